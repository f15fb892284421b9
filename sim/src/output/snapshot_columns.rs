//! Vector columns of a snapshot row: each component in the shortest decimal that reads back
//! to the same `f64`, so a frame holds the simulator's state exactly.
use crate::state::Vec3;
use std::fmt::Write as _;

/// Appends ` x y z` for each of `vectors` to `row`.
pub fn push_vectors(row: &mut String, vectors: &[Vec3]) {
    for v in vectors {
        let _ = write!(row, " {} {} {}", v.x, v.y, v.z);
    }
}
