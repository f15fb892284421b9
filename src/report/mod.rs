//! The sections of `suspflow report`: simulation error against run time
//! (`convergence_report`, measured by `sim::studies::convergence`), surrogate error against
//! training time (`surrogate_cost`), the two side by side (`side_by_side`), the stability
//! sweep (`plots::stability_map`, run by `sim::studies::stability_sweep`) and Theta against
//! Delta_v (`descriptor_noise`); and the reports of other commands: `cross-validate`'s
//! (`cross_validation`), `validate`'s tables (`validation`), `solve --compare`'s
//! (`solve_comparison`) and `flow-curves`' (`flow_curves`).

pub mod convergence_report;
pub mod cross_validation;
pub mod descriptor_noise;
pub mod flow_curves;
pub mod side_by_side;
pub mod solve_comparison;
pub mod surrogate_cost;
pub mod validation;
