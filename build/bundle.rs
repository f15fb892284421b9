//! Build script of the Python extension (`python/`): copies `libxgboost.so` (published by
//! `xgboost_lib-sys` as `DEP_XGBOOST_LIB_DIR`) into the package, `python/suspflow/_xgboost/`,
//! and gives the extension the rpath `$ORIGIN/_xgboost/xgboost/lib`, so that the wheel carries
//! the library and the installed package needs neither the checkout nor its `target/`.
//!
//! The copy keeps the pinned wheel's layout (`xgboost/lib/libxgboost.so` beside
//! `xgboost_cpu.libs/`, the libgomp it bundles), which the library's own `$ORIGIN/../..`
//! rpath expects. A library named by `XGBOOST_LIB_DIR` without that sibling folder is copied
//! alone and loads its OpenMP runtime from the system. maturin puts every file under
//! `python/suspflow/` into the wheel; `.gitignore` keeps the copy out of git.
use std::fs;
use std::path::{Path, PathBuf};

/// The package folder the library is copied to, relative to the extension module.
const BUNDLE: &str = "_xgboost";

pub fn main() {
    println!("cargo:rerun-if-env-changed=DEP_XGBOOST_LIB_DIR");
    let lib_dir = PathBuf::from(std::env::var_os("DEP_XGBOOST_LIB_DIR").expect(
        "DEP_XGBOOST_LIB_DIR is unset: this package must depend directly on xgboost_lib-sys",
    ));
    let manifest_dir =
        PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let bundle = manifest_dir.join("suspflow").join(BUNDLE);
    copy_into(
        &lib_dir.join("libxgboost.so"),
        &bundle.join("xgboost").join("lib"),
    );
    // The wheel's `xgboost_cpu.libs/`, two levels above `xgboost/lib/`.
    if let Some(libs) = lib_dir.parent().and_then(Path::parent) {
        let libs = libs.join("xgboost_cpu.libs");
        if let Ok(entries) = fs::read_dir(&libs) {
            for entry in entries.flatten() {
                copy_into(&entry.path(), &bundle.join("xgboost_cpu.libs"));
            }
        }
    }
    println!("cargo:rerun-if-changed={}", bundle.display());
    println!("cargo:rustc-link-arg=-Wl,-rpath,$ORIGIN/{BUNDLE}/xgboost/lib");
}

/// Copies `file` into `dir` unless a file of the same name and size is there already.
fn copy_into(file: &Path, dir: &Path) {
    let name = file.file_name().expect("a file name");
    let target = dir.join(name);
    let size = |p: &Path| fs::metadata(p).map(|m| m.len()).ok();
    if size(&target).is_some() && size(&target) == size(file) {
        return;
    }
    fs::create_dir_all(dir).unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    fs::copy(file, &target).unwrap_or_else(|e| {
        panic!(
            "cannot copy {} to {}: {e}",
            file.display(),
            target.display()
        )
    });
}
