//! The problem a solve takes: a periodic forcing on the bins and the drag of the particle
//! mix.

use std::f64::consts::PI;

use sim::Scene;

use crate::error::{Result, SolverError};

/// A periodic forcing to solve for.
#[derive(Debug, Clone)]
pub struct ProfileProblem {
    /// Streaming velocity at the bin centres (a/time), the datasets' `u_inf`.
    pub u_inf: Vec<f64>,
    /// Streaming velocity averaged over each bin (a/time): what the drag and Delta_v read.
    /// The simulation's drag acts on each particle at its own `u_inf(y)`, and its Delta_v
    /// averages `u_inf` over the bin's particles (docs/physics.md section 6); where the
    /// forcing curves within a bin (a sharp band: 0.0729 at the centre, 0.0638 averaged, in
    /// the first bin of plugs_000) the centre value overstates the simulated drag by 17 %.
    pub u_inf_mean: Vec<f64>,
    /// Bin width (a).
    pub bin_width: f64,
    /// Global volume fraction.
    pub phi: f64,
    /// Fluid viscosity.
    pub eta: f64,
    /// `c = 6 pi eta <a> / <V_p>`: drag density per unit volume fraction and velocity lag.
    pub drag_coefficient: f64,
}

impl ProfileProblem {
    /// The scene's forcing `u_inf(y)` at its bin centres and averaged over its bins, with the
    /// drag coefficient `c = 6 pi eta <a> / <V_p>` of its particle mix (Stokes drag per
    /// particle over mean particle volume, thesis eq 3.5). A scene of homogeneous shear has
    /// no forcing profile and is refused, and so is a Brownian scene, whose rheology lies
    /// outside the closures' domain (they are of non-Brownian runs).
    pub fn from_scene(scene: &Scene) -> Result<Self> {
        if scene.shear_rate().is_some() {
            return Err(SolverError::InvalidArgument(
                "homogeneous shear (fluid.shear_rate) has no forcing profile to solve for; \
                 the solver takes scenes with fluid.profile"
                    .to_owned(),
            ));
        }
        if let Some(thermal) = &scene.thermal {
            return Err(SolverError::InvalidArgument(format!(
                "the scene has Brownian forces (fluid.kT = {}, tau_B = {:.3e}): the closures \
                 are learned from and fitted to non-Brownian runs, outside whose domain its \
                 rheology lies; simulate it instead",
                thermal.kt, thermal.tau_b
            )));
        }
        let f = &scene.file;
        let width = f.run.bin_width;
        let u_inf = bin_centres(scene.n_bins, width)
            .map(|y| scene.profile.u(y))
            .collect();
        let u_inf_mean = (0..scene.n_bins)
            .map(|k| scene.profile.mean(k as f64 * width, (k + 1) as f64 * width))
            .collect();
        let (mut radius_sum, mut volume_sum) = (0.0, 0.0);
        for (&a, &count) in f.particles.radii.iter().zip(&scene.counts) {
            radius_sum += count as f64 * a;
            volume_sum += count as f64 * 4.0 / 3.0 * PI * a.powi(3);
        }
        Ok(ProfileProblem {
            u_inf,
            u_inf_mean,
            bin_width: width,
            phi: f.particles.phi,
            eta: f.fluid.eta,
            drag_coefficient: 6.0 * PI * f.fluid.eta * radius_sum / volume_sum,
        })
    }

    /// Number of bins.
    pub fn n_bins(&self) -> usize {
        self.u_inf.len()
    }

    /// The bin centres `y_k = (k + 1/2) w` (a).
    pub fn bin_centres(&self) -> Vec<f64> {
        bin_centres(self.n_bins(), self.bin_width).collect()
    }
}

/// `y_k = (k + 1/2) w` for `k < n`.
fn bin_centres(n: usize, width: f64) -> impl Iterator<Item = f64> {
    (0..n).map(move |k| (k as f64 + 0.5) * width)
}
