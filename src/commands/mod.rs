//! One module per `suspflow` command, each with its clap `Args` and its `run`. Commands do
//! not import from each other: what two of them share lives in a module of its own.

pub mod bench;
pub mod bench_predict;
pub mod compare;
pub mod conventions;
pub mod coverage;
pub mod cross_validate;
pub mod flow_curves;
pub mod generate;
pub mod green_kubo;
pub mod merge;
pub mod plot;
pub mod predict;
pub mod propose;
pub mod report;
pub mod simulate;
pub mod solve;
pub mod train;
pub mod validate;
