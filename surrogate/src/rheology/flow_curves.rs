//! The flow curves of a grid of homogeneous-shear runs by state (docs/physics.md sections
//! 10 and 11): the runs grouped into states (friction coefficient, Peclet number, a
//! mixture's composition), means
//! over seeds with standard errors from their spread, the jamming law fitted per state
//! under each stress convention, and the seeds' Pe -> 0 estimate, the hydrodynamic
//! viscosity plus the Green-Kubo Brownian one. Plain numbers in: the caller reads the runs.
//!
//! Every `eta_r` is a relative viscosity `-sigma_xy / (eta gdot)` (dimensionless), given as
//! `(mean, standard error)`.

use crate::error::{Result, SurrogateError};
use crate::rheology::flow_curve_fit::{FlowCurvePoint, SeededJammingFit};
use crate::rheology::jamming_bootstrap::PointWithError;
use crate::rheology::jamming_law::SEEDS_LAW;
use crate::rheology::statistics::mean_and_standard_error;

/// A state of the flow curves: friction coefficient, Peclet number (infinite without
/// Brownian forces), for a colloid-grain mixture its grain share of the solid volume
/// `alpha` (docs/physics.md section 13), and the particle density `rho`, which with the
/// thermal energy sets the inertia-diffusion ratio `tau_I / tau_B = rho kT / (eta^2 a)`
/// (section 11): runs of two compositions or two densities are two curves even at one
/// volume fraction. So are runs at two time steps (a step-convergence grid): their means
/// are never pooled as if they were seeds.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct State {
    pub mu_p: f64,
    pub peclet: f64,
    pub alpha: Option<f64>,
    pub rho: f64,
    pub step: StepSetting,
}

/// How a run's time step was set: the scene's `run.dt` (a fixed step, in time units) when it
/// has one, else `run.dt_factor` times the automatic step.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct StepSetting {
    pub dt: Option<f64>,
    pub dt_factor: f64,
}

impl StepSetting {
    /// The automatic step, as chosen.
    pub const AUTOMATIC: StepSetting = StepSetting {
        dt: None,
        dt_factor: 1.0,
    };
}

/// What names a curve over the Peclet number: friction coefficient, composition, density,
/// time step.
pub type Curve = (f64, Option<f64>, f64, StepSetting);

impl State {
    /// The curve over the Peclet number this state lies on.
    pub fn curve(&self) -> Curve {
        (self.mu_p, self.alpha, self.rho, self.step)
    }
}

/// Index in [`StatePoint::parts`] of the hydrodynamic (lubrication) part.
const HYDRODYNAMIC: usize = 1;
/// Index of the one-body drag part.
const DRAG: usize = 2;
/// Index of the structural Brownian part.
const BROWNIAN: usize = 3;

/// One finished run on the flow curves.
#[derive(Clone, Copy, Debug)]
pub struct StatePoint {
    pub state: State,
    /// The grid's volume fraction (the realised one is `phi_actual`).
    pub phi: f64,
    pub seed: u64,
    /// Realised volume fraction.
    pub phi_actual: f64,
    /// `eta_r` of the box's pair stresslets (contact + lubrication).
    pub eta_r: (f64, f64),
    /// `eta_r` of the bins' `sigma_xy` (the scene's stress convention), [`bin_viscosity`].
    ///
    /// [`bin_viscosity`]: crate::rheology::flow_curve_fit::bin_viscosity
    pub eta_r_bins: (f64, f64),
    /// The parts of `eta_r` ([`part_viscosity`]), in the order contact, hydrodynamic
    /// (lubrication), one-body drag, structural Brownian; NaN where the run has none.
    pub parts: [(f64, f64); 4],
    /// The box's friction coefficient `mu = sigma_xy / P` and viscous number `J`.
    pub mu: (f64, f64),
    pub j: (f64, f64),
    /// The Green-Kubo Brownian viscosity over eta at this volume fraction, when given.
    pub green_kubo: Option<(f64, f64)>,
}

/// `eta_r = -sigma_xy / (eta gdot)` of a stress part `sigma_xy` (mean, standard error) at
/// `eta_gdot`, the fluid viscosity times the imposed shear rate.
pub fn part_viscosity(mean: f64, se: f64, eta_gdot: f64) -> (f64, f64) {
    // `+ 0.0` turns the -0 of a zero part (no Brownian forces) into 0.
    (-mean / eta_gdot + 0.0, se / eta_gdot)
}

impl StatePoint {
    /// The seeds' low-Pe estimate (paper section 4, Fig. 6a): the hydrodynamic viscosity
    /// (lubrication and one-body drag) plus the Green-Kubo Brownian viscosity of the
    /// unsheared suspension at the same volume fraction, errors added in quadrature; NaN
    /// without one.
    pub fn eta_r_hydrodynamic_green_kubo(&self) -> (f64, f64) {
        let Some((gk, gk_se)) = self.green_kubo else {
            return (f64::NAN, f64::NAN);
        };
        let (hd, hd_se) = self.eta_r_hydrodynamic_drag();
        (hd + gk, hd_se.hypot(gk_se))
    }

    /// The hydrodynamic viscosity: lubrication plus one-body drag, errors in quadrature.
    pub fn eta_r_hydrodynamic_drag(&self) -> (f64, f64) {
        let ((h, h_se), (d, d_se)) = (self.parts[HYDRODYNAMIC], self.parts[DRAG]);
        (h + d, h_se.hypot(d_se))
    }

    /// `eta_r` with the structural Brownian stress added (the seeds' low-Pe fit adds a
    /// Brownian viscosity to the hydrodynamic one), errors added in quadrature.
    pub fn eta_r_with_brownian(&self) -> (f64, f64) {
        let (b, b_se) = self.parts[BROWNIAN];
        (self.eta_r.0 + b, self.eta_r.1.hypot(b_se))
    }
}

/// Largest difference of realised volume fractions for a Green-Kubo result to belong to
/// a flow-curve point (the same box and phi give the same count of spheres).
const GREEN_KUBO_PHI_MATCH: f64 = 1e-3;

/// The Green-Kubo Brownian viscosity (in units of the fluid's) at the realised volume
/// fraction `phi_actual`, from `replicas` of `(phi_actual, eta_B / eta, its error)`: the
/// [`seed_mean`] of those within [`GREEN_KUBO_PHI_MATCH`] (the spread of independent
/// replicas; one run's block error when it is alone), `None` without any.
pub fn green_kubo_at(replicas: &[(f64, f64, f64)], phi_actual: f64) -> Option<(f64, f64)> {
    let here: Vec<(f64, f64)> = replicas
        .iter()
        .filter(|(phi, _, _)| green_kubo_matches(*phi, phi_actual))
        .map(|&(_, eta, se)| (eta, se))
        .collect();
    (!here.is_empty()).then(|| seed_mean(&here))
}

/// Whether a Green-Kubo run at the realised volume fraction `replica_phi` is of a point at
/// `phi_actual` (within [`GREEN_KUBO_PHI_MATCH`]).
pub fn green_kubo_matches(replica_phi: f64, phi_actual: f64) -> bool {
    (replica_phi - phi_actual).abs() < GREEN_KUBO_PHI_MATCH
}

/// Keeps the Green-Kubo viscosity of each point only at the lowest Peclet number of its
/// curve (the points of equal friction, composition and density): the seeds' construction
/// ([`StatePoint::eta_r_hydrodynamic_green_kubo`]) is a Pe -> 0 estimate, the
/// hydrodynamic viscosity at the lowest Pe plus the unsheared suspension's Brownian one,
/// and means nothing beside the sheared stress of higher Peclet numbers.
pub fn keep_green_kubo_at_lowest_peclet(points: &mut [StatePoint]) {
    let lowest: Vec<f64> = points
        .iter()
        .map(|p| {
            points
                .iter()
                .filter(|q| q.state.curve() == p.state.curve())
                .map(|q| q.state.peclet)
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    for (p, lowest) in points.iter_mut().zip(lowest) {
        if p.state.peclet > lowest {
            p.green_kubo = None;
        }
    }
}

/// A stress convention: its name, and the `eta_r` of a point under it.
pub type Convention = (&'static str, fn(&StatePoint) -> (f64, f64));

/// The stress conventions the jamming law is fitted under.
pub const CONVENTIONS: [Convention; 4] = [
    ("pair stresslets (box)", |p| p.eta_r),
    ("bins, scene's stress convention", |p| p.eta_r_bins),
    (
        "pair stresslets + structural Brownian",
        StatePoint::eta_r_with_brownian,
    ),
    (
        "hydrodynamic + drag + Green-Kubo Brownian (the seeds' Pe -> 0)",
        StatePoint::eta_r_hydrodynamic_green_kubo,
    ),
];

/// The distinct states of `points`, ordered by friction, then Peclet number, composition
/// and density.
pub fn states(points: &[StatePoint]) -> Vec<State> {
    let mut states: Vec<State> = Vec::new();
    for p in points {
        if !states.contains(&p.state) {
            states.push(p.state);
        }
    }
    states.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    states
}

/// The grid's distinct volume fractions, ascending.
pub fn volume_fractions(points: &[StatePoint]) -> Vec<f64> {
    let mut phis: Vec<f64> = points.iter().map(|p| p.phi).collect();
    phis.sort_by(f64::total_cmp);
    phis.dedup();
    phis
}

/// The mean over seeds of `values` (mean, standard error), with the standard error of that
/// mean from their spread, `sqrt(s^2 / n)`; a single run's own value and error when there
/// is one.
pub fn seed_mean(values: &[(f64, f64)]) -> (f64, f64) {
    match values {
        [one] => *one,
        _ => mean_and_standard_error(&values.iter().map(|v| v.0).collect::<Vec<_>>()),
    }
}

/// [`seed_mean`] of `value` at each Peclet number of the points `sel`: `(Pe, mean,
/// standard error)`, ascending in Pe, non-finite left out.
pub fn over_seeds(
    sel: &[&StatePoint],
    value: impl Fn(&StatePoint) -> (f64, f64),
) -> Vec<(f64, f64, f64)> {
    let mut by_pe: Vec<(f64, Vec<(f64, f64)>)> = Vec::new();
    for p in sel {
        let v = value(p);
        match by_pe.iter_mut().find(|(pe, _)| *pe == p.state.peclet) {
            Some((_, vs)) => vs.push(v),
            None => by_pe.push((p.state.peclet, vec![v])),
        }
    }
    by_pe.sort_by(|a, b| a.0.total_cmp(&b.0));
    by_pe
        .into_iter()
        .filter(|(pe, _)| pe.is_finite())
        .map(|(pe, vs)| {
            let (m, se) = seed_mean(&vs);
            (pe, m, se)
        })
        .filter(|(_, m, se)| m.is_finite() && se.is_finite())
        .collect()
}

/// The jamming law of one state under each of the [`CONVENTIONS`] (an error where its
/// points cannot be fitted, e.g. fewer than three volume fractions).
pub struct StateFits {
    pub state: State,
    pub fits: Vec<Result<SeededJammingFit>>,
}

impl StateFits {
    /// The jamming law `eta_r = (1 - phi/phi_J)^(-lambda)` fitted to the points of `state`
    /// at their realised volume fractions, under each convention: to every point and to
    /// each seed's points ([`SeededJammingFit`]).
    pub fn fit(points: &[StatePoint], state: State) -> Self {
        let sel: Vec<&StatePoint> = points.iter().filter(|p| p.state == state).collect();
        let fits = CONVENTIONS
            .iter()
            .map(|(_, value)| {
                let points: Vec<FlowCurvePoint> = sel
                    .iter()
                    .map(|p| FlowCurvePoint {
                        seed: p.seed,
                        phi: p.phi_actual,
                        eta_r: value(p).0,
                    })
                    .collect();
                SeededJammingFit::fit(&points)
            })
            .collect();
        StateFits { state, fits }
    }
}

/// The seeds' Pe -> 0 points of `state` ([`StatePoint::eta_r_hydrodynamic_green_kubo`]),
/// one per volume fraction with a Green-Kubo viscosity: the [`seed_mean`] of the
/// hydrodynamic + drag viscosity, with the error of the seeds' spread, plus the Green-Kubo
/// viscosity, which all those seeds share, errors in quadrature. For
/// [`crate::rheology::jamming_bootstrap::JammingBootstrap`]: the seeds' spread alone misses
/// the shared error. An error where the runs of one volume fraction do not all carry the
/// same Green-Kubo viscosity (runs at realised volume fractions matched to different
/// Green-Kubo results, or only some with one).
pub fn green_kubo_points(points: &[StatePoint], state: State) -> Result<Vec<PointWithError>> {
    let mut out = Vec::new();
    for phi in volume_fractions(points) {
        let sel: Vec<&StatePoint> = points
            .iter()
            .filter(|p| p.state == state && p.phi == phi)
            .collect();
        let Some(first) = sel.first() else {
            continue;
        };
        if sel.iter().any(|p| p.green_kubo != first.green_kubo) {
            return Err(SurrogateError::InvalidArgument(format!(
                "the runs at phi = {phi} carry different Green-Kubo viscosities ({:?}): give \
                 one Green-Kubo result (or replicas) per volume fraction",
                sel.iter().map(|p| p.green_kubo).collect::<Vec<_>>()
            )));
        }
        let Some((gk, gk_se)) = first.green_kubo else {
            continue;
        };
        let hydrodynamic = seed_mean(
            &sel.iter()
                .map(|p| p.eta_r_hydrodynamic_drag())
                .collect::<Vec<_>>(),
        );
        out.push(PointWithError {
            phi: seed_mean(&sel.iter().map(|p| (p.phi_actual, 0.0)).collect::<Vec<_>>()).0,
            eta_r: hydrodynamic.0 + gk,
            se: hydrodynamic.1.hypot(gk_se),
        });
    }
    Ok(out)
}

/// One state at one volume fraction, each value the [`seed_mean`] of its runs.
pub struct StateRow {
    /// Realised volume fraction.
    pub phi: f64,
    /// Number of runs (seeds).
    pub seeds: usize,
    pub eta_r: (f64, f64),
    pub eta_r_bins: (f64, f64),
    /// The [`StatePoint::parts`].
    pub parts: [(f64, f64); 4],
    pub mu: (f64, f64),
    pub j: (f64, f64),
    /// The seeds' law ([`SEEDS_LAW`]) at `phi`.
    pub seeds_law: f64,
}

/// The rows of `state`, one per volume fraction of `points` that it has runs at.
pub fn state_rows(points: &[StatePoint], state: State) -> Vec<StateRow> {
    let at_state: Vec<&StatePoint> = points.iter().filter(|p| p.state == state).collect();
    volume_fractions(points)
        .into_iter()
        .filter_map(|phi| {
            let sel: Vec<&StatePoint> = at_state.iter().copied().filter(|p| p.phi == phi).collect();
            if sel.is_empty() {
                return None;
            }
            let col = |f: &dyn Fn(&StatePoint) -> (f64, f64)| {
                seed_mean(&sel.iter().map(|p| f(p)).collect::<Vec<_>>())
            };
            let phi = col(&|p| (p.phi_actual, 0.0)).0;
            Some(StateRow {
                phi,
                seeds: sel.len(),
                eta_r: col(&|p| p.eta_r),
                eta_r_bins: col(&|p| p.eta_r_bins),
                parts: std::array::from_fn(|q| col(&|p| p.parts[q])),
                mu: col(&|p| p.mu),
                j: col(&|p| p.j),
                seeds_law: SEEDS_LAW.eta_r(phi),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(peclet: f64, seed: u64, eta_r: f64) -> StatePoint {
        StatePoint {
            state: State {
                mu_p: 0.0,
                peclet,
                alpha: None,
                rho: 1.0,
                step: StepSetting::AUTOMATIC,
            },
            phi: 0.5,
            seed,
            phi_actual: 0.5,
            eta_r: (eta_r, 0.1),
            eta_r_bins: (eta_r, 0.1),
            parts: [(1.0, 0.3), (2.0, 0.4), (0.5, 0.0), (0.25, 0.0)],
            mu: (0.1, 0.0),
            j: (0.01, 0.0),
            green_kubo: None,
        }
    }

    #[test]
    fn one_seed_keeps_its_own_error_and_two_their_spread() {
        assert_eq!(seed_mean(&[(2.0, 0.1)]), (2.0, 0.1));
        let (m, se) = seed_mean(&[(2.0, 0.1), (4.0, 0.1)]);
        assert_eq!((m, se), (3.0, 1.0));
        let points = [
            point(10.0, 1, 2.0),
            point(10.0, 2, 4.0),
            point(f64::INFINITY, 1, 5.0),
        ];
        let sel: Vec<&StatePoint> = points.iter().collect();
        assert_eq!(over_seeds(&sel, |p| p.eta_r), vec![(10.0, 3.0, 1.0)]);
        assert_eq!(states(&points).len(), 2);
    }

    /// Two compositions at one volume fraction, friction and Pe are two states, ordered by
    /// alpha, and a one-species run a third (as reports/mixtures/collapse needs).
    #[test]
    fn mixtures_of_two_compositions_are_two_states() {
        let with = |alpha: Option<f64>| StatePoint {
            state: State {
                alpha,
                ..point(1.0, 1, 2.0).state
            },
            ..point(1.0, 1, 2.0)
        };
        let points = [
            with(Some(0.5)),
            with(Some(0.0)),
            with(None),
            with(Some(0.5)),
        ];
        let got: Vec<Option<f64>> = states(&points).iter().map(|s| s.alpha).collect();
        assert_eq!(got, vec![None, Some(0.0), Some(0.5)]);
    }

    /// Two particle densities at one volume fraction, friction and Pe (two inertia-diffusion
    /// ratios) are two states, ordered by density.
    #[test]
    fn runs_at_two_densities_are_two_states() {
        let with = |rho: f64, seed: u64, eta_r: f64| StatePoint {
            state: State {
                rho,
                ..point(1.0, seed, eta_r).state
            },
            ..point(1.0, seed, eta_r)
        };
        let points = [
            with(0.5, 1, 4.0),
            with(0.05, 1, 4.4),
            with(0.5, 2, 4.2),
            with(0.05, 2, 4.6),
        ];
        let got: Vec<f64> = states(&points).iter().map(|s| s.rho).collect();
        assert_eq!(got, vec![0.05, 0.5]);
    }

    /// Runs of one seed at the automatic step, at a third of it and at a fixed step (a
    /// step-convergence grid) are three states, each with its one run, not one state of
    /// three "seeds" whose mean mixes the steps.
    #[test]
    fn runs_at_three_steps_are_three_states() {
        let with = |dt: Option<f64>, dt_factor: f64, eta_r: f64| StatePoint {
            state: State {
                step: StepSetting { dt, dt_factor },
                ..point(1.0, 1, eta_r).state
            },
            ..point(1.0, 1, eta_r)
        };
        let points = [
            with(None, 1.0, 4.0),
            with(None, 1.0 / 3.0, 3.0),
            with(Some(1e-3), 1.0, 3.5),
        ];
        let found = states(&points);
        assert_eq!(found.len(), 3);
        let automatic: Vec<&StatePoint> = points
            .iter()
            .filter(|p| p.state.step == StepSetting::AUTOMATIC)
            .collect();
        // One run alone: its own value and block error, nothing of the other steps.
        assert_eq!(over_seeds(&automatic, |p| p.eta_r), vec![(1.0, 4.0, 0.1)]);
    }

    #[test]
    fn the_green_kubo_viscosity_stays_at_each_curves_lowest_peclet_number() {
        let mut points: Vec<StatePoint> = [0.1, 1.0, 0.1]
            .into_iter()
            .map(|pe| {
                let mut p = point(pe, 1, 5.0);
                p.green_kubo = Some((3.0, 0.5));
                p
            })
            .collect();
        // A curve of its own (another density) whose lowest Pe is 1.
        points.push(StatePoint {
            state: State {
                rho: 0.05,
                ..points[1].state
            },
            ..points[1]
        });
        keep_green_kubo_at_lowest_peclet(&mut points);
        let kept: Vec<bool> = points.iter().map(|p| p.green_kubo.is_some()).collect();
        assert_eq!(kept, [true, false, true, true]);
        assert!(points[1].eta_r_hydrodynamic_green_kubo().0.is_nan());
    }

    #[test]
    fn green_kubo_replicas_of_one_volume_fraction_are_averaged_over_their_spread() {
        let replicas = [(0.4496, 6.0, 1.0), (0.4496, 10.0, 3.0), (0.4997, 9.0, 2.0)];
        // Two replicas: their mean, with sqrt(s^2 / n) = |10 - 6| / 2 as its error (not
        // the block errors 1 and 3).
        let (eta, se) = green_kubo_at(&replicas, 0.4497).unwrap();
        assert!(
            (eta - 8.0).abs() < 1e-12 && (se - 2.0).abs() < 1e-12,
            "{eta} {se}"
        );
        // One replica: its own value and block error.
        assert_eq!(green_kubo_at(&replicas, 0.4997), Some((9.0, 2.0)));
        assert_eq!(green_kubo_at(&replicas, 0.55), None);
    }

    #[test]
    fn the_green_kubo_estimate_adds_hydrodynamic_drag_and_brownian() {
        let mut p = point(10.0, 1, 2.0);
        assert!(p.eta_r_hydrodynamic_green_kubo().0.is_nan());
        p.green_kubo = Some((1.0, 0.3));
        let (eta, se) = p.eta_r_hydrodynamic_green_kubo();
        assert_eq!(eta, 3.5);
        assert!((se - 0.5).abs() < 1e-15);
        assert_eq!(p.eta_r_with_brownian(), (2.25, 0.1));
        assert_eq!(part_viscosity(0.0, 0.0, 2.0).0.to_bits(), 0.0f64.to_bits());
    }

    #[test]
    fn green_kubo_points_add_the_shared_error_to_the_seeds_spread() {
        // Two seeds whose hydrodynamic + drag viscosities are 2.5 and 2.9 (spread: standard
        // error 0.2), one Green-Kubo value 7 +- 0.5 for both; a third run at another phi
        // without Green-Kubo is left out.
        let mut runs: Vec<StatePoint> = [(1, 2.0), (2, 2.4)]
            .into_iter()
            .map(|(seed, h)| {
                let mut p = point(0.1, seed, 5.0);
                p.parts[HYDRODYNAMIC].0 = h;
                p.green_kubo = Some((7.0, 0.5));
                p
            })
            .collect();
        let mut other = point(0.1, 1, 5.0);
        (other.phi, other.phi_actual) = (0.55, 0.55);
        runs.push(other);
        let got = green_kubo_points(&runs, runs[0].state).unwrap();
        assert_eq!(got.len(), 1);
        assert!((got[0].eta_r - 9.7).abs() < 1e-12, "{got:?}");
        // Not the seeds' spread of the per-run sums (0.2): the shared 0.5 stays.
        assert!((got[0].se - 0.2f64.hypot(0.5)).abs() < 1e-12, "{got:?}");
        // Seeds of one volume fraction with different Green-Kubo values are refused.
        runs[1].green_kubo = Some((8.0, 0.5));
        let e = green_kubo_points(&runs, runs[0].state).unwrap_err();
        assert!(e.to_string().contains("different Green-Kubo"), "{e}");
    }
}
