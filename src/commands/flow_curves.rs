//! `suspflow flow-curves GRID.toml --runs WORK --out DIR`: the flow curves of a grid of
//! homogeneous-shear scenes (docs/physics.md section 10) that `suspflow generate` has run
//! (resumably, with progress) into the work directory `WORK`: per scene the box totals,
//! the fit of `phi_J` and `lambda` of the jamming law with uncertainties from the scatter
//! between seeds, SVG figures of `eta_r(phi)` and `mu(J)` beside the seeds' law, and a
//! markdown summary; with `--local DATA.csv`, the local `mu / J` of the sheared bins of an
//! inhomogeneous-flow dataset against the homogeneous curve at the same volume fraction.
//!
//! Grids over the Peclet number (`fluid.peclet`, Brownian scenes, docs/physics.md section
//! 11) and the friction coefficient are fitted per state `(mu_p, Pe)`, and each volume
//! fraction gets a figure of `eta_r(Pe)` with the parts of the stress (contact,
//! lubrication, and the structural Brownian stress beside them).
//!
//! Two stress conventions are fitted: the box's pair stresslets (contact and lubrication,
//! as the thesis' LAMMPS runs report), and the bins' `sigma_xy` under the scene's
//! `[observables] stress` convention (the same pair stresslets by default; with the
//! one-body drag stresslet under `pairs+drag`, as the shipped datasets were made).
use crate::plots::data_and_laws::{self, Points};
use crate::plots::loglog::Line;
use anyhow::Context;
use rheometry::{FlowCurveRow, FlowRuns, GreenKuboResult, PARTS};
use schema::write_atomic;
use sim::input::grid::Grid;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use surrogate::rheology::local_viscosity::{self, LocalBand};
use surrogate::{
    green_kubo_points, keep_green_kubo_at_lowest_peclet, over_seeds, state_rows, states,
    volume_fractions, Curve, Dataset, JammingBootstrap, JammingLaw, Quantiles, State, StateFits,
    StatePoint, CONVENTIONS, MIN_VOLUME_FRACTIONS, PHI_J_MAX, SEEDS_LAW, SEEDS_LOW_PECLET_PHI_J,
};

/// Centres of the `phi_loc` bands of the local-versus-homogeneous table.
const LOCAL_BANDS: [f64; 7] = [0.44, 0.46, 0.48, 0.50, 0.52, 0.54, 0.56];

#[derive(clap::Args)]
pub struct Args {
    /// Grid of homogeneous-shear scenes (e.g. grids/flow_curves.toml).
    grid: PathBuf,
    /// Work directory in which `suspflow generate` ran the grid (its `--work`, by default
    /// `<out>.work`).
    #[arg(long)]
    runs: PathBuf,
    /// Inhomogeneous-flow dataset whose sheared bins are compared with the flow curve
    /// (e.g. datasets/train.csv).
    #[arg(long)]
    local: Option<PathBuf>,
    /// Output directories of `suspflow green-kubo` (one or more replicas per volume
    /// fraction): adds the fit of the seeds' Pe -> 0 estimate, the hydrodynamic viscosity
    /// (lubrication and drag) at each curve's lowest Peclet number plus the Green-Kubo
    /// Brownian viscosity at the same volume fraction (the mean over its replicas, with the
    /// standard error from their spread; one run's block error when it is alone).
    #[arg(long, num_args = 1..)]
    green_kubo: Vec<PathBuf>,
    /// Output directory: flow_curves.csv, eta_r.svg, mu_J.svg, README.md.
    #[arg(long)]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    force: bool,
}

/// A state's name in the tables; its density only where `densities` (the runs hold more
/// than one, [`several_densities`]).
fn label(state: &State, densities: bool) -> String {
    let more = curve_suffix(state.alpha, state.rho, densities);
    if state.peclet.is_finite() {
        format!("mu_p = {}, Pe = {:.3e}{more}", state.mu_p, state.peclet)
    } else {
        format!("mu_p = {}, non-Brownian{more}", state.mu_p)
    }
}

/// `, alpha = a` for a mixture's grain share `a`, then `, rho = r` where `densities`;
/// nothing for one-species runs at the grid's one density.
fn curve_suffix(alpha: Option<f64>, rho: f64, densities: bool) -> String {
    let mut suffix = alpha.map_or_else(String::new, |a| format!(", alpha = {a}"));
    if densities {
        let _ = write!(suffix, ", rho = {rho}");
    }
    suffix
}

/// Whether the runs were made at more than one particle density (e.g. a scan of the
/// inertia-diffusion ratio, grids/brownian_inertia.toml).
fn several_densities(points: &[StatePoint]) -> bool {
    points.iter().any(|p| p.state.rho != points[0].state.rho)
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let grid = Grid::from_path(&args.grid, false)?;
    crate::output_guard::out_dir(&args.out)?;
    let green_kubo = args
        .green_kubo
        .iter()
        .map(|d| GreenKuboResult::read(d))
        .collect::<Result<Vec<_>, _>>()?;
    let FlowRuns { points, missing } = FlowRuns::read(&grid, &args.runs, &green_kubo)?;
    if !missing.is_empty() {
        eprintln!(
            "warning: {} of {} runs not finished in {} (run `suspflow generate {} --out ... --work {}`): {}",
            missing.len(),
            grid.runs.len(),
            args.runs.display(),
            args.grid.display(),
            args.runs.display(),
            missing.join(", ")
        );
    }
    let mut curve: Vec<StatePoint> = points.iter().map(|p| p.point).collect();
    keep_green_kubo_at_lowest_peclet(&mut curve);
    let fits: Vec<StateFits> = states(&curve)
        .into_iter()
        .map(|state| StateFits::fit(&curve, state))
        .collect();
    let local = match &args.local {
        Some(path) => Some(local_viscosity::bands(
            &Dataset::read_csv(path).with_context(|| format!("reading {}", path.display()))?,
            &LOCAL_BANDS,
        )?),
        None => None,
    };
    let phis = volume_fractions(&curve);
    let brownian = curve.iter().any(|p| p.state.peclet.is_finite());
    let mut written: Vec<PathBuf> = ["README.md", "flow_curves.csv", "eta_r.svg", "mu_J.svg"]
        .iter()
        .map(|f| args.out.join(f))
        .collect();
    if brownian {
        written.extend(phis.iter().map(|&phi| args.out.join(peclet_figure(phi))));
    }
    crate::output_guard::refuse_any_unless_force(
        &written,
        args.force,
        "an earlier flow-curve result",
        "choose another --out",
    )?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    FlowCurveRow::write_all(&args.out.join("flow_curves.csv"), &points)?;
    let first_fit = fits
        .iter()
        .find_map(|f| f.fits[0].as_ref().ok())
        .map(|f| f.all);
    draw_figures(&args.out, &curve, first_fit.as_ref())?;
    if brownian {
        for &phi in &phis {
            draw_peclet_figure(&args.out.join(peclet_figure(phi)), phi, &curve)?;
        }
    }
    let text = summary_text(&args, &curve, &fits, local.as_deref());
    let readme = args.out.join("README.md");
    write_atomic(&readme, text.as_bytes())?;
    print!("{text}");
    eprintln!("wrote {}", args.out.display());
    Ok(())
}

/// File name of the `eta_r(Pe)` figure at volume fraction `phi`.
fn peclet_figure(phi: f64) -> String {
    format!("eta_r_Pe_phi{phi:.3}.svg")
}

/// `eta_r(Pe)` at volume fraction `phi`: the total (pair stresslets) for each friction
/// coefficient, mixture composition and particle density, and the [`PARTS`] of the
/// frictionless (or least frictional; the first composition, the lightest) runs; log-log, non-positive values (a negative part)
/// left out.
fn draw_peclet_figure(path: &Path, phi: f64, points: &[StatePoint]) -> anyhow::Result<()> {
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
    let name =
        |(mu_p, alpha, rho): Curve| format!("mu_p = {mu_p}{}", curve_suffix(alpha, rho, densities));
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
fn draw_figures(
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

fn summary_text(
    args: &Args,
    points: &[StatePoint],
    fits: &[StateFits],
    local: Option<&[LocalBand]>,
) -> String {
    let densities = several_densities(points);
    let mut s = String::from("# Flow curves of homogeneous simple shear\n\n");
    let _ = writeln!(
        s,
        "Bidisperse spheres sheared between Lees-Edwards images \
         (docs/physics.md sections 10 and 11), {} runs of `{}`. Produced by\n\n```\n\
         suspflow generate {} --out DATASET.csv --work {} --jobs 2 --threads 1\n\
         suspflow flow-curves {} --runs {}{} --out {}\n```\n",
        points.len(),
        args.grid.display(),
        args.grid.display(),
        args.runs.display(),
        args.grid.display(),
        args.runs.display(),
        args.local
            .as_ref()
            .map_or(String::new(), |l| format!(" --local {}", l.display()))
            + &args
                .green_kubo
                .iter()
                .map(|d| format!(" --green-kubo {}", d.display()))
                .collect::<String>(),
        args.out.display()
    );
    s.push_str(
        "Per state and volume fraction, the mean over seeds (standard error from their \
         spread; a single run's own batch-means error when there is one seed); `eta_r` of the pair stresslets over the box (contact + hydrodynamic, i.e. \
         lubrication), of the bins' `sigma_xy` (the scene's stress convention), the parts, \
         and the structural Brownian stress (thesis eq 3.54) beside them:\n\n\
         | state | phi | seeds | eta_r (pairs) | eta_r (bins) | contact | hydrodynamic | drag | structural Brownian | seeds' law | pairs / law | mu | J |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for f in fits {
        for row in state_rows(points, f.state) {
            let show = |(m, se): (f64, f64)| format!("{m:.2} ± {se:.2}");
            let (phi, (eta, eta_se), (mu, mu_se), (j, j_se)) = (row.phi, row.eta_r, row.mu, row.j);
            let parts: Vec<String> = row.parts.iter().map(|&p| show(p)).collect();
            let _ = writeln!(
                s,
                "| {} | {phi:.4} | {} | {eta:.2} ± {eta_se:.2} | {} | {} | {:.2} | {:.2} | {mu:.3} ± {mu_se:.3} | {j:.4} ± {j_se:.4} |",
                label(&f.state, densities),
                row.seeds,
                show(row.eta_r_bins),
                parts.join(" | "),
                row.seeds_law,
                eta / row.seeds_law
            );
        }
    }
    let fit_header = format!(
        "\nFit of `eta_r = (1 - phi/phi_J)^(-lambda)` per state (least squares in `ln eta_r`, \
         all points; standard errors from the seeds' separate fits), beside the seeds' \
         `phi_J = {}`, `lambda = {}` (frictionless, high Pe) and `phi_J = \
         {SEEDS_LOW_PECLET_PHI_J}` (Pe -> 0, hydrodynamic + Green-Kubo Brownian viscosity):\n\n\
         | state | stress | phi_J | lambda | per seed (phi_J, lambda) |\n|---|---|---|---|---|\n",
        SEEDS_LAW.phi_j, SEEDS_LAW.lambda
    );
    let mut rows = String::new();
    let mut unfitted = Vec::new();
    let mut unavailable = false;
    for f in fits {
        let of_state: Vec<StatePoint> = points
            .iter()
            .filter(|p| p.state == f.state)
            .copied()
            .collect();
        if volume_fractions(&of_state).len() < MIN_VOLUME_FRACTIONS {
            unfitted.push(label(&f.state, densities));
            continue;
        }
        for ((name, value), fit) in CONVENTIONS.iter().zip(&f.fits) {
            if of_state.iter().all(|p| value(p).0.is_nan()) {
                unavailable = true;
                continue;
            }
            match fit {
                Ok(fit) => {
                    let seeds: Vec<String> = fit
                        .per_seed
                        .iter()
                        .map(|(s, l)| format!("seed {s}: {:.4}, {:.3}", l.phi_j, l.lambda))
                        .collect();
                    let _ = writeln!(
                        rows,
                        "| {} | {name} | {:.4} ± {:.4} | {:.3} ± {:.3} | {} |",
                        label(&f.state, densities),
                        fit.all.phi_j,
                        fit.phi_j_se,
                        fit.all.lambda,
                        fit.lambda_se,
                        seeds.join("; ")
                    );
                }
                Err(e) => {
                    let _ = writeln!(
                        rows,
                        "| {} | {name} | not fitted: {e} | | |",
                        label(&f.state, densities)
                    );
                }
            }
        }
    }
    if !rows.is_empty() {
        s.push_str(&fit_header);
        s.push_str(&rows);
    }
    green_kubo_bootstrap(&mut s, points, fits, densities);
    if unavailable {
        s.push_str(
            "\nStresses not measured for a state (the Green-Kubo Brownian viscosity without \
             `--green-kubo`, or above a curve's lowest Peclet number) have no row.\n",
        );
    }
    if !unfitted.is_empty() {
        let _ = writeln!(
            s,
            "\nNot fitted, fewer than {MIN_VOLUME_FRACTIONS} volume fractions: {}.",
            unfitted.join("; ")
        );
    }
    if let Some(bands) = local {
        let _ = writeln!(
            s,
            "\nLocal `eta_r = mu / J` of the sheared bins (|gdot| >= {} of the scene's largest) \
             of `{}`, in bands of phi_loc ± {}, against the seeds' law and the homogeneous \
             fits at the same volume fraction (medians over the band of each bin's ratio at \
             its own phi_loc):\n\n\
             | phi_loc | bins | local mu/J | seeds' law | local / law | homogeneous (pairs) | local / homogeneous (pairs) | homogeneous (bins) | local / homogeneous (bins) |\n\
             |---|---|---|---|---|---|---|---|---|",
            local_viscosity::SHEARED_FRACTION,
            args.local.as_ref().map_or(String::new(), |p| p.display().to_string()),
            0.5 * local_viscosity::BAND_WIDTH
        );
        for b in bands {
            let (Some(Ok(pairs)), Some(Ok(bins))) = (
                fits.first().map(|f| &f.fits[0]),
                fits.first().map(|f| &f.fits[1]),
            ) else {
                continue;
            };
            let (pairs, bins) = (&pairs.all, &bins.all);
            let _ = writeln!(
                s,
                "| {:.2} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} |",
                b.phi,
                b.bins.len(),
                b.eta_r(),
                SEEDS_LAW.eta_r(b.phi),
                b.ratio(|p| SEEDS_LAW.eta_r(p)),
                pairs.eta_r(b.phi),
                b.ratio(|p| pairs.eta_r(p)),
                bins.eta_r(b.phi),
                b.ratio(|p| bins.eta_r(p)),
            );
        }
    }
    s.push_str("\nFigures: `eta_r.svg` (eta_r against phi), `mu_J.svg` (mu against J)");
    if points.iter().any(|p| p.state.peclet.is_finite()) {
        s.push_str(", `eta_r_Pe_phi*.svg` (eta_r and its parts against Pe, per phi)");
    }
    s.push_str("; data in `flow_curves.csv`.\n");
    s
}

/// Draws of the Green-Kubo points within their errors for the jamming law's bootstrap.
const BOOTSTRAP_DRAWS: usize = 1000;

/// Per state with Green-Kubo points at enough volume fractions, the jamming law refitted
/// to those points moved within their errors, the Green-Kubo one that the seeds share
/// included (`surrogate::JammingBootstrap`), which the seeds' spread in the table misses.
fn green_kubo_bootstrap(
    s: &mut String,
    points: &[StatePoint],
    fits: &[StateFits],
    densities: bool,
) {
    let near_seeds = SEEDS_LOW_PECLET_PHI_J + 0.015;
    let mut lines = Vec::new();
    for f in fits {
        let state = label(&f.state, densities);
        let drawn = green_kubo_points(points, f.state).and_then(|gk| {
            if gk.len() < MIN_VOLUME_FRACTIONS {
                return Ok(None);
            }
            JammingBootstrap::run(&gk, BOOTSTRAP_DRAWS, 1).map(|b| Some((gk, b)))
        });
        let line = match drawn {
            Ok(None) => continue,
            Ok(Some((gk, b))) => {
                let values: Vec<String> = gk
                    .iter()
                    .map(|p| format!("{:.2} ± {:.2} at {:.3}", p.eta_r, p.se, p.phi))
                    .collect();
                let value = |v: f64, digits: usize| {
                    if v.is_finite() {
                        format!("{v:.digits$}")
                    } else {
                        format!("> {PHI_J_MAX}")
                    }
                };
                let range = |q: Option<Quantiles>, digits: usize| {
                    q.map_or_else(
                        || "-".to_owned(),
                        |q| {
                            format!(
                                "{} ({} to {})",
                                value(q.median, digits),
                                value(q.p16, digits),
                                value(q.p84, digits)
                            )
                        },
                    )
                };
                format!(
                    "| {state} | {} | {} | {} | {} / {} / {} | {:.0} % |",
                    values.join("; "),
                    range(b.phi_j, 4),
                    range(b.lambda, 3),
                    b.diverging,
                    b.beyond_edge,
                    b.invalid,
                    100.0 * b.share_at_most(near_seeds)
                )
            }
            Err(e) => format!("| {state} | not drawn: {e} | | | | |"),
        };
        lines.push(line);
    }
    if lines.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "\nThe hydrodynamic + drag + Green-Kubo fit within the points' errors: {BOOTSTRAP_DRAWS} \
         draws (seed 1) of every point at `eta_r + se z` (z standard normal; se the seeds' \
         spread of the hydrodynamic + drag part and the Green-Kubo error, which all seeds of \
         a volume fraction share, in quadrature), each refitted. phi_J: median (16th to 84th \
         percentile) over all draws, `> {PHI_J_MAX}` for the draws whose points do not \
         diverge below the search's edge; lambda: the same over the draws that diverge. \
         Draws: diverging / not diverging below {PHI_J_MAX} / not fittable (a point drawn at \
         eta_r <= 1); and the share of all draws with phi_J <= {near_seeds:.3}, within 0.015 \
         of the seeds' Pe -> 0 value {SEEDS_LOW_PECLET_PHI_J}:\n\n\
         | state | points (eta_r ± se at phi) | phi_J | lambda | draws | phi_J <= {near_seeds:.3} |\n\
         |---|---|---|---|---|---|\n{}",
        lines.join("\n")
    );
}
