//! What a solve returns.

/// A solved profile, one entry per bin, and how the solve went.
#[derive(Debug, Clone, Default)]
pub struct ProfileSolution {
    pub u: Vec<f64>,
    /// Centred difference of `u` (1/time).
    pub gdot: Vec<f64>,
    /// Shear stress at the bin centre, `-sign(gdot) mu P` (positive in compression).
    pub sigma_xy: Vec<f64>,
    /// Uniform pressure.
    pub pressure: f64,
    pub phi_loc: Vec<f64>,
    pub j: Vec<f64>,
    pub mu: Vec<f64>,
    pub delta_v: Vec<f64>,
    /// Drag density `c phi_loc (u_inf - u)`.
    pub f_x: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Largest scaled residual at the end.
    pub residual: f64,
}
