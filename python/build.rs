//! Build script of the Python extension: the bundled `libxgboost.so` and its rpath, and the
//! commit stamp.

#[path = "../build/bundle.rs"]
mod bundle;
#[path = "../build/stamp.rs"]
mod stamp;

fn main() {
    bundle::main();
    stamp::main();
}
