//! Provides `libxgboost.so` for linking.
//!
//! By default the library is the one in the pinned PyPI wheel `xgboost-cpu`, installed on
//! first build with `python3 -m pip install --no-deps --target <data>/suspflow/xgboost-cpu-<version>`,
//! `<data>` the per-user data directory `$XDG_DATA_HOME` (default `~/.local/share`). It lives
//! outside any checkout and target directory, so that a binary installed with `cargo install`
//! keeps finding it after `cargo clean` or when the checkout moves (the binaries carry its
//! absolute path as their rpath); every checkout of the same pin shares one copy. Without a
//! home directory it goes under the workspace's `target/xgboost`. The wheel's layout is kept
//! intact: `libxgboost.so` finds its own bundled libgomp through its `$ORIGIN`-relative rpath.
//!
//! The interpreter is `$PYO3_PYTHON` when set (maturin sets it to the one it builds for),
//! else `python3`; inside pip's isolated build it finds pip because `python/pyproject.toml`
//! lists pip among the build requirements.
//!
//! `XGBOOST_LIB_DIR`, when set, names a directory already holding a `libxgboost.so` to use
//! instead; nothing is installed then.
//!
//! The chosen directory is published as link metadata (`DEP_XGBOOST_LIB_DIR` in the build
//! scripts of direct dependents), which they turn into an rpath for their executables.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The wheel that provides the library (the CPU build; the plain `xgboost` wheel is CUDA's).
const WHEEL: &str = "xgboost-cpu";
/// Pinned: saved models must load in the Python package of the same version.
const WHEEL_VERSION: &str = "3.2.0";

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=XGBOOST_LIB_DIR");
    println!("cargo:rerun-if-env-changed=XDG_DATA_HOME");
    println!("cargo:rerun-if-env-changed=HOME");
    let lib_dir = match env::var_os("XGBOOST_LIB_DIR") {
        Some(dir) => PathBuf::from(dir),
        None => wheel_lib_dir(),
    };
    let library = lib_dir.join("libxgboost.so");
    if !library.is_file() {
        panic!(
            "{} does not exist: point XGBOOST_LIB_DIR at a directory holding libxgboost.so",
            library.display()
        );
    }
    println!("cargo:rerun-if-changed={}", library.display());
    println!("cargo:rustc-link-search=native={}", lib_dir.display());
    println!("cargo:rustc-link-lib=dylib=xgboost");
    println!("cargo:lib_dir={}", lib_dir.display());
}

/// The `lib/` directory of the pinned wheel under [`install_prefix`], installing the wheel
/// first when that version is not there yet.
fn wheel_lib_dir() -> PathBuf {
    let prefix = install_prefix();
    if !is_installed(&prefix) {
        install_wheel(&prefix);
    }
    prefix.join("xgboost").join("lib")
}

/// `$XDG_DATA_HOME/suspflow/xgboost-cpu-<version>` (`~/.local/share` when `XDG_DATA_HOME`
/// is unset or relative), else `<workspace>/target/xgboost` when there is no home directory.
fn install_prefix() -> PathBuf {
    let absolute = |v: std::ffi::OsString| Some(PathBuf::from(v)).filter(|p| p.is_absolute());
    let data_home = env::var_os("XDG_DATA_HOME")
        .and_then(absolute)
        .or_else(|| env::var_os("HOME").and_then(absolute).map(|h| h.join(".local").join("share")));
    match data_home {
        Some(data) => data.join("suspflow").join(format!("{WHEEL}-{WHEEL_VERSION}")),
        None => {
            let manifest_dir = PathBuf::from(
                env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"),
            );
            // This crate lives in `<workspace>/vendor/xgboost_lib-sys`.
            let workspace = manifest_dir
                .parent()
                .and_then(Path::parent)
                .expect("xgboost_lib-sys sits two levels below the workspace root");
            workspace.join("target").join("xgboost")
        }
    }
}

/// Whether `prefix` holds the pinned wheel version with its shared library.
fn is_installed(prefix: &Path) -> bool {
    let dist_info = format!("{}-{WHEEL_VERSION}.dist-info", WHEEL.replace('-', "_"));
    prefix.join(dist_info).is_dir()
        && prefix
            .join("xgboost")
            .join("lib")
            .join("libxgboost.so")
            .is_file()
}

/// Installs the wheel into a staging directory, then moves it to `prefix` in one rename, so
/// that an interrupted or concurrent build never leaves a half-written `prefix` behind.
fn install_wheel(prefix: &Path) {
    let parent = prefix.parent().expect("prefix has a parent");
    fs::create_dir_all(parent)
        .unwrap_or_else(|e| panic!("cannot create {}: {e}", parent.display()));
    let staging = parent.join(format!("xgboost.partial-{}", std::process::id()));
    // Left over from an interrupted build with the same process id, if any.
    let _ = fs::remove_dir_all(&staging);
    let requirement = format!("{WHEEL}=={WHEEL_VERSION}");
    let python = env::var_os("PYO3_PYTHON").unwrap_or_else(|| "python3".into());
    let output = Command::new(&python)
        .args(["-m", "pip", "install", "--no-deps", "--no-input", "--disable-pip-version-check", "--target"])
        .arg(&staging)
        .arg(&requirement)
        .output()
        .unwrap_or_else(|e| {
            panic!("cannot run `{} -m pip` to install {requirement}: {e}; install Python 3 with pip, or set XGBOOST_LIB_DIR", python.to_string_lossy())
        });
    if !output.status.success() {
        panic!(
            "`{} -m pip install {requirement}` failed (Python 3 with pip is needed, or XGBOOST_LIB_DIR):\n{}\n{}",
            python.to_string_lossy(),
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
    }
    // An older pin or a broken install.
    let _ = fs::remove_dir_all(prefix);
    if let Err(e) = fs::rename(&staging, prefix) {
        let _ = fs::remove_dir_all(&staging);
        // A concurrent build may have installed it in the meantime.
        if !is_installed(prefix) {
            panic!(
                "cannot move {} to {}: {e}",
                staging.display(),
                prefix.display()
            );
        }
    }
}
