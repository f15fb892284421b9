//! What a solve returns.

use schema::Observable;

/// A solved profile, one entry per bin, and how the solve went.
#[derive(Debug, Clone, Default)]
pub struct ProfileSolution {
    pub u: Vec<f64>,
    /// Centred difference of `u` (1/time).
    pub gdot: Vec<f64>,
    /// Shear stress of the bin (positive in compression): the mean of the closure's stresses
    /// `-sign(gdot) mu P` at its two faces, where the momentum balance holds. Where the
    /// stress changes sign inside a bin (a plug's centre) it is the balance's value near
    /// zero, not the closure's at a shear rate near zero.
    pub sigma_xy: Vec<f64>,
    /// Uniform pressure.
    pub pressure: f64,
    pub phi_loc: Vec<f64>,
    pub j: Vec<f64>,
    /// `|sigma_xy| / P`, of the bin's stress above.
    pub mu: Vec<f64>,
    pub delta_v: Vec<f64>,
    /// Drag density `c phi_loc (u_inf - u)`.
    pub f_x: Vec<f64>,
    /// The suspension temperature (eq 6.1) where the closure solves its balance (the
    /// nonlocal closure); empty otherwise.
    pub theta: Vec<f64>,
    /// Each bin's distance (units a) to the nearest velocity extremum of `u`
    /// (`surrogate::extremum_distances`), the extremum closure's input.
    pub d_ext: Vec<f64>,
    /// Newton iterations taken (fresh Jacobians, the local law's included; steps on a kept
    /// Jacobian are not counted).
    pub iterations: usize,
    /// Largest scaled residual at the end.
    pub residual: f64,
    /// Whether Newton's method stalled from `u = u_inf` and the solve followed the
    /// continuation from the local law ([`crate::ProfileProblem::solve`]).
    pub continued: bool,
}

impl ProfileSolution {
    /// The solved values of observable `o` along y; `None` for those a solve does not give
    /// per bin (P is uniform; count is not solved for, Theta only by the nonlocal closure).
    pub fn column(&self, o: Observable) -> Option<&[f64]> {
        match o {
            Observable::U => Some(&self.u),
            Observable::Gdot => Some(&self.gdot),
            Observable::SigmaXy => Some(&self.sigma_xy),
            Observable::PhiLoc => Some(&self.phi_loc),
            Observable::J => Some(&self.j),
            Observable::Mu => Some(&self.mu),
            Observable::DeltaV => Some(&self.delta_v),
            Observable::FX => Some(&self.f_x),
            Observable::Theta if !self.theta.is_empty() => Some(&self.theta),
            Observable::P | Observable::Theta | Observable::Count => None,
        }
    }
}
