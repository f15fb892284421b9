//! Stage 1, the data: datasets read from CSV, the mappings that turn their rows into
//! samples, the outputs' scaling and physical ranges, and the training domain.

pub mod dataset;
pub mod extremum_distance;
pub(crate) mod files;
pub mod mapping;
pub mod physical_range;
pub mod samples;
pub mod scaling;
pub mod table_kind;
pub mod training_domain;
