//! The Green-Kubo run at rest (docs/physics.md section 11): an unsheared Brownian scene
//! from its initial packing, a warm-up, then the structural Brownian shear stress of the
//! box ([`shell_shear_stress`]) sampled every few steps over a span, and its Green-Kubo
//! integral ([`GreenKubo`]). A finished run extends to a longer span.
use crate::error::SimError;
use crate::input::run_cost::RunCost;
use crate::input::scene::{Scene, SceneFile};
use crate::input::thermal_scales::ThermalScales;
use crate::integrate::simulation::{Simulation, SystemState};
use crate::run::job::{Job, Sampled};
use crate::run::steady::same_scene;
use crate::run::{driver, Phase, Progress, RunOptions};
use crate::sampling::green_kubo::{check_length, shell_shear_stress, GreenKubo};
use serde::{Deserialize, Serialize};

/// How long an equilibrium Green-Kubo run is, in Brownian times `tau_B`, and how its
/// integral is taken.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct GreenKuboRun {
    pub warmup_tau_b: f64,
    pub span_tau_b: f64,
    /// Steps between two samples of the stress.
    pub every: u64,
    /// Largest lag of the correlation (its integral's upper limit).
    pub max_lag_tau_b: f64,
    /// Consecutive parts of the series for the standard error.
    pub blocks: usize,
}

/// The Green-Kubo run's own progress: the stress sampled so far.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct GreenKuboState {
    scene: SceneFile,
    run: GreenKuboRun,
    warmed_up: bool,
    /// The structural Brownian shear stress of the box at every sample (energy / volume).
    series: Vec<f64>,
}

/// A Green-Kubo run of a scene.
pub struct GreenKuboJob<'a> {
    scene: &'a Scene,
    run: GreenKuboRun,
}

impl<'a> GreenKuboJob<'a> {
    /// The run `run` of `scene`.
    pub fn new(scene: &'a Scene, run: GreenKuboRun) -> Self {
        GreenKuboJob { scene, run }
    }

    /// The scene's Brownian scales; an error for a scene without Brownian forces.
    fn thermal(&self) -> Result<ThermalScales, SimError> {
        self.scene.thermal.ok_or_else(|| {
            SimError::field(
                "fluid.kT",
                "the Green-Kubo viscosity needs Brownian forces (fluid.kT > 0)",
            )
        })
    }

    /// Steps per Brownian time `tau_B`.
    fn steps_per_tau_b(&self) -> f64 {
        self.scene.thermal.map_or(f64::NAN, |t| t.tau_b) / self.scene.timestep.dt
    }

    /// Steps of `tau` Brownian times (saturating: [`GreenKuboJob::cost`] refuses a run of
    /// that many before it starts).
    fn steps(&self, tau: f64) -> u64 {
        (tau * self.steps_per_tau_b()).round() as u64
    }

    /// What the run costs: the warm-up's and the span's particle-steps at the rate of a
    /// Brownian scene here. [`Job::check`] refuses a run that cannot finish; the warning of
    /// a long one is the caller's to show.
    pub fn cost(&self) -> RunCost {
        let per_tau_b = self.steps_per_tau_b();
        RunCost::of_steps(
            per_tau_b,
            self.scene.n_particles(),
            [
                self.run.warmup_tau_b * per_tau_b,
                self.run.span_tau_b * per_tau_b,
            ],
            true,
        )
    }

    fn every(&self) -> u64 {
        self.run.every.max(1)
    }

    /// Samples of the span.
    fn samples(&self) -> usize {
        (self.steps(self.run.span_tau_b) / self.every()) as usize
    }

    /// Time between two samples.
    fn sample_dt(&self) -> f64 {
        self.scene.timestep.dt * self.every() as f64
    }

    /// The largest lag, in samples.
    fn max_lag(&self) -> usize {
        let tau_b = self.scene.thermal.map_or(f64::NAN, |t| t.tau_b);
        (self.run.max_lag_tau_b * tau_b / self.sample_dt()).round() as usize
    }
}

impl Job for GreenKuboJob<'_> {
    type State = GreenKuboState;
    type Outcome = GreenKubo;

    fn check(&self) -> Result<(), SimError> {
        self.thermal()?;
        if self.scene.gdot_max() > 0.0 {
            return Err(SimError::field(
                "fluid",
                "the Green-Kubo viscosity is of the unsheared suspension: give no \
                 fluid.shear_rate, fluid.profile or fluid.peclet",
            ));
        }
        let lengths = [
            ("warm-up", self.run.warmup_tau_b, true),
            ("span", self.run.span_tau_b, false),
            ("largest lag", self.run.max_lag_tau_b, false),
        ];
        for (what, tau, zero_allowed) in lengths {
            if !(tau.is_finite() && (tau > 0.0 || (zero_allowed && tau == 0.0))) {
                return Err(SimError::GreenKubo(format!(
                    "the {what} of {tau} tau_B is not a {} number of Brownian times",
                    if zero_allowed {
                        "non-negative"
                    } else {
                        "positive"
                    }
                )));
            }
        }
        self.cost()
            .check_levers("shorten the warm-up or the span (in tau_B), or lengthen the step")
            .map_err(SimError::GreenKubo)?;
        check_length(self.samples(), self.max_lag(), self.run.blocks)?;
        if self.max_lag() < 2 {
            return Err(SimError::GreenKubo(format!(
                "the largest lag is {} sample interval(s) of {:.3e} time: its extrapolation \
                 needs at least 2 (3 lags); lengthen the largest lag or sample more often",
                self.max_lag(),
                self.sample_dt()
            )));
        }
        Ok(())
    }

    fn fresh(&self) -> GreenKuboState {
        GreenKuboState {
            scene: self.scene.file.clone(),
            run: self.run,
            warmed_up: false,
            series: Vec::new(),
        }
    }

    fn resume(
        &self,
        mut st: GreenKuboState,
        _system: &SystemState,
    ) -> Result<GreenKuboState, String> {
        if !same_scene(&st.scene, &self.scene.file) {
            return Err("was written for a different scene".into());
        }
        let (old, new) = (st.run, self.run);
        if (old.warmup_tau_b, old.every) != (new.warmup_tau_b, new.every) {
            return Err(format!(
                "was written for a warm-up of {} tau_B and a sample every {} steps, not {} and {}",
                old.warmup_tau_b, old.every, new.warmup_tau_b, new.every
            ));
        }
        if st.series.len() > self.samples() {
            return Err(format!(
                "holds {} samples, more than the span of {} tau_B has ({}): an extension \
                 only lengthens the span",
                st.series.len(),
                new.span_tau_b,
                self.samples()
            ));
        }
        st.run = new;
        Ok(st)
    }

    fn interval(&self, st: &GreenKuboState) -> u64 {
        if st.warmed_up {
            self.every()
        } else {
            self.steps(self.run.warmup_tau_b)
        }
    }

    fn sample(
        &mut self,
        st: &mut GreenKuboState,
        sim: &mut Simulation,
    ) -> Result<Sampled, SimError> {
        if st.warmed_up {
            st.series.push(shell_shear_stress(sim));
        } else {
            st.warmed_up = true;
        }
        Ok(if self.finished(st) {
            Sampled::Finished
        } else {
            Sampled::Continue
        })
    }

    fn finished(&self, st: &GreenKuboState) -> bool {
        st.warmed_up && st.series.len() >= self.samples()
    }

    fn progress(&self, st: &GreenKuboState, sim: &Simulation) -> Progress {
        Progress {
            phase: if st.series.is_empty() {
                Phase::Equilibrating
            } else {
                Phase::Averaging
            },
            strain: self.scene.clock_rate() * sim.time,
            clock: self.scene.clock(),
            max_strain: self.run.warmup_tau_b,
            snapshots: st.series.len(),
            snapshots_target: self.samples(),
            step: sim.step,
            samples: st.series.len() as u64,
        }
    }

    fn finish(
        &self,
        st: GreenKuboState,
        _sim: &Simulation,
        _wall_s: f64,
    ) -> Result<GreenKubo, SimError> {
        let thermal = self.thermal()?;
        let volume = self.scene.box_len.iter().product();
        GreenKubo::of_series(
            &st.series,
            self.sample_dt(),
            (volume, thermal.kt),
            self.max_lag(),
            self.run.blocks,
        )
    }
}

/// Runs the unsheared Brownian `scene` (it needs `fluid.kT > 0` and no flow) from its
/// initial packing (or `opts`' checkpoint): `warmup_tau_b`, then samples
/// [`shell_shear_stress`] every `every` steps over `span_tau_b`, and integrates it.
/// `progress` is called after every sample.
pub fn equilibrium_viscosity(
    scene: &Scene,
    run: GreenKuboRun,
    opts: &RunOptions,
    progress: &mut dyn FnMut(&Progress, &Simulation),
) -> Result<GreenKubo, SimError> {
    driver::drive(scene, &mut GreenKuboJob::new(scene, run), opts, progress)
}
