//! What finished runs measure (docs/physics.md sections 10 and 11), above the simulator
//! (`sim`, which runs them) and the fits (`surrogate::rheology`): the Green-Kubo
//! viscosity of a run at rest with its extrapolation ([`GreenKuboResult`]), and the points
//! of the flow curves of a grid of homogeneous-shear runs, read from the runs' folders
//! ([`FlowRuns`], one [`FlowCurveRow`] each in `flow_curves.csv`) and fitted
//! ([`FlowCurves`]); and the tables of a grid's
//! runs, dataset, run table and ensemble table ([`sweep_tables`]). Each result is written
//! by one writer and read back by the same type; the command line and Python render them.

pub mod error;
pub mod flow_curves;
pub mod flow_points;
pub mod green_kubo;
pub mod sweep_tables;

pub use error::{Result, RheometryError};
pub use flow_curves::{read_green_kubo_replicas, FlowCurveSource, FlowCurves};
pub use flow_points::{FlowCurveRow, FlowPoint, FlowRuns, PARTS};
pub use green_kubo::GreenKuboResult;
pub use surrogate::EnsembleSummary;
