//! Embeds an rpath to the directory of `libxgboost.so` (published by `xgboost_lib-sys` as
//! `DEP_XGBOOST_LIB_DIR`) into this package's binaries and test executables, so that they run
//! without `LD_LIBRARY_PATH`. Cargo passes `rustc-link-arg` only to the package whose build
//! script prints it, so `surrogate` and `solver` use this same script
//! (`build = "../build/rpath.rs"`); the `suspflow` package runs it from `build/suspflow.rs`.

pub fn main() {
    println!("cargo:rerun-if-env-changed=DEP_XGBOOST_LIB_DIR");
    match std::env::var("DEP_XGBOOST_LIB_DIR") {
        Ok(dir) => println!("cargo:rustc-link-arg=-Wl,-rpath,{dir}"),
        Err(_) => panic!(
            "DEP_XGBOOST_LIB_DIR is unset: this package must depend directly on xgboost_lib-sys"
        ),
    }
}
