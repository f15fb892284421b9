//! Raw bindings to the XGBoost C API (`xgboost/c_api.h`).
//!
//! `bindings.rs` was generated once with bindgen 0.71.1 from the `c_api.h` bundled in
//! crates.io's `xgboost_lib-sys` 3.4.0 (XGBoost 3.4 header), with the same options as that
//! crate's build script: `allowlist_function("XG.*")`, `allowlist_type("bst_.*|.*Handle")`,
//! include paths `include/` and `dmlc-core/include/`. Every function it declares is exported
//! by the `libxgboost.so` of the pinned `xgboost-cpu` wheel (checked with `nm -D`).
//! Regenerate only when moving to a new header, and re-check the exports then.
#![allow(non_upper_case_globals)]
#![allow(non_camel_case_types)]
#![allow(non_snake_case)]

include!("bindings.rs");
