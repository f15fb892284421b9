//! Particle simulator for dense non-Brownian suspensions under inhomogeneous flow.
//! Physics: `../shared/SPEC.md`; equation numbers are the thesis' (chapter 3 and 6).

pub mod error;
pub mod flow_profile;
pub mod packing;
