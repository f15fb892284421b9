//! Build script of the `suspflow` package: the rpath to `libxgboost.so` and the commit stamp.

#[path = "rpath.rs"]
mod rpath;
#[path = "stamp.rs"]
mod stamp;

fn main() {
    rpath::main();
    stamp::main();
}
