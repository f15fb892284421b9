//! The figures of `suspflow flow-curves`: `eta_r(phi)` and `mu(J)` per seed beside the
//! seeds' law and the fit, and `eta_r(Pe)` with its parts at each volume fraction; and the
//! names of the states and curves they share with the summary.
use crate::plots::data_and_laws::{self, Points};
use crate::plots::loglog::Line;
use rheometry::PARTS;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use surrogate::{over_seeds, Curve, JammingLaw, State, StatePoint, SEEDS_LAW};

/// A state's name in the tables; its density only where `densities` (the runs hold more
/// than one, [`several_densities`]).
pub fn label(state: &State, densities: bool) -> String {
    let more = curve_suffix(state.curve(), densities);
    if state.peclet.is_finite() {
        format!("mu_p = {}, Pe = {:.3e}{more}", state.mu_p, state.peclet)
    } else {
        format!("mu_p = {}, non-Brownian{more}", state.mu_p)
    }
}

/// `, alpha = a` for a mixture's grain share `a`, then `, rho = r` where `densities`, then
/// the time step where it is not the automatic one: `, dt = d` (fixed) or `, dt x f` (a
/// multiple of the automatic step); nothing for one-species runs at the grid's one density
/// and the automatic step.
pub fn curve_suffix((_, alpha, rho, step): Curve, densities: bool) -> String {
    let mut suffix = alpha.map_or_else(String::new, |a| format!(", alpha = {a}"));
    if densities {
        let _ = write!(suffix, ", rho = {rho}");
    }
    match step.dt {
        Some(dt) => {
            let _ = write!(suffix, ", dt = {dt:.3e}");
        }
        None if step.dt_factor != 1.0 => {
            let _ = write!(suffix, ", dt x {:.3}", step.dt_factor);
        }
        None => {}
    }
    suffix
}

/// Whether the runs were made at more than one particle density (e.g. a scan of the
/// inertia-diffusion ratio, grids/brownian_inertia.toml).
pub fn several_densities(points: &[StatePoint]) -> bool {
    points.iter().any(|p| p.state.rho != points[0].state.rho)
}

/// File name of the `eta_r(Pe)` figure at volume fraction `phi`.
pub fn peclet_figure(phi: f64) -> String {
    format!("eta_r_Pe_phi{phi:.3}.svg")
}

/// `eta_r(Pe)` at volume fraction `phi`: the total (pair stresslets) for each friction
/// coefficient, mixture composition and particle density, and the [`PARTS`] of the
/// frictionless (or least frictional; the first composition, the lightest) runs; log-log, non-positive values (a negative part)
/// left out.
pub fn draw_peclet_figure(path: &Path, phi: f64, points: &[StatePoint]) -> anyhow::Result<()> {
    let at_phi: Vec<&StatePoint> = points.iter().filter(|p| p.phi == phi).collect();
    // One curve per friction coefficient, mixture composition and density.
    let mut kinds: Vec<Curve> = Vec::new();
    for p in &at_phi {
        if !kinds.contains(&p.state.curve()) {
            kinds.push(p.state.curve());
        }
    }
    kinds.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
    let of_kind = |kind: Curve| -> Vec<&StatePoint> {
        at_phi
            .iter()
            .copied()
            .filter(|p| p.state.curve() == kind)
            .collect()
    };
    let densities = several_densities(points);
    let name = |curve: Curve| format!("mu_p = {}{}", curve.0, curve_suffix(curve, densities));
    let mut series = Vec::new();
    for &kind in &kinds {
        series.push(Points {
            name: format!("eta_r (contact + lubrication), {}", name(kind)),
            points: over_seeds(&of_kind(kind), |p| p.eta_r),
        });
    }
    if let Some(&kind) = kinds.first() {
        let sel = of_kind(kind);
        for (q, (_, legend, _)) in PARTS.iter().enumerate() {
            series.push(Points {
                name: format!("{legend}, {}", name(kind)),
                points: over_seeds(&sel, |p| p.parts[q]),
            });
        }
    }
    data_and_laws::draw(
        path,
        &format!("Homogeneous shear at phi = {phi}: eta_r against the Peclet number"),
        ("Pe", "eta_r"),
        true,
        &series,
        &[],
    )
}

/// The points of each seed, in grid order.
fn by_seed(points: &[StatePoint]) -> BTreeMap<u64, Vec<&StatePoint>> {
    let mut seeds: BTreeMap<u64, Vec<&StatePoint>> = BTreeMap::new();
    for p in points {
        seeds.entry(p.seed).or_default().push(p);
    }
    seeds
}

/// One marker series per seed of `(x, y, standard error of y)` taken from each point.
fn per_seed(points: &[StatePoint], value: fn(&StatePoint) -> (f64, f64, f64)) -> Vec<Points> {
    by_seed(points)
        .iter()
        .map(|(s, sel)| Points {
            name: format!("seed {s}"),
            points: sel.iter().map(|p| value(p)).collect(),
        })
        .collect()
}

/// `eta_r(phi)` and `mu(J)`, one marker colour per seed, beside the seeds' law and the fit
/// (box convention). In the `mu(J)` plane a law is drawn at each measured point's `J` as
/// `mu = J eta_r(phi)`, since `eta_r = mu / J`.
pub fn draw_figures(
    out: &Path,
    points: &[StatePoint],
    fitted: Option<&JammingLaw>,
) -> anyhow::Result<()> {
    let mut laws = vec![(
        format!(
            "seeds' law, phi_J = {}, lambda = {}",
            SEEDS_LAW.phi_j, SEEDS_LAW.lambda
        ),
        SEEDS_LAW,
    )];
    if let Some(fitted) = fitted {
        laws.push((
            format!(
                "fit, phi_J = {:.3}, lambda = {:.2}",
                fitted.phi_j, fitted.lambda
            ),
            *fitted,
        ));
    }
    let eta_points = per_seed(points, |p| (p.phi_actual, p.eta_r.0, p.eta_r.1));
    let phi_grid: Vec<f64> = (0..=60).map(|k| 0.44 + 0.0025 * k as f64).collect();
    let eta_curves: Vec<Line> = laws
        .iter()
        .map(|(name, law)| Line {
            name: name.clone(),
            points: phi_grid.iter().map(|&p| (p, law.eta_r(p))).collect(),
        })
        .collect();
    data_and_laws::draw(
        &out.join("eta_r.svg"),
        "Homogeneous shear: relative viscosity (pair stresslets)",
        ("phi", "eta_r"),
        false,
        &eta_points,
        &eta_curves,
    )?;
    let mu_points = per_seed(points, |p| (p.j.0, p.mu.0, p.mu.1));
    let mut by_j: Vec<&StatePoint> = points.iter().collect();
    by_j.sort_by(|a, b| a.j.0.total_cmp(&b.j.0));
    let mu_curves: Vec<Line> = laws
        .iter()
        .map(|(name, law)| Line {
            name: format!("{name} at the measured J"),
            points: by_j
                .iter()
                .map(|p| {
                    let j = p.j.0;
                    (j, j * law.eta_r(p.phi_actual))
                })
                .collect(),
        })
        .collect();
    data_and_laws::draw(
        &out.join("mu_J.svg"),
        "Homogeneous shear: mu(J) (pair stresslets)",
        ("J", "mu"),
        true,
        &mu_points,
        &mu_curves,
    )
}
