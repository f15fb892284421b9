//! The box over which a learned closure's trees are averaged (docs/physics.md section 8):
//! trees are piecewise constant, their average over a box is continuous, so Newton's method
//! can differentiate it.

/// Relative half-width of the box over which a learned closure is averaged, for J and its
/// second feature (Delta_v, Theta or d_ext).
pub const SMOOTHING: f64 = 0.3;

/// Least half-width (units a) of the box in d_ext: the distance to a velocity extremum goes
/// to 0 at the faces beside it, where a relative box would shrink to the trees' sharp
/// splits as the extremum moves.
pub const EXTREMUM_SMOOTHING_FLOOR: f64 = 0.5;
