//! The markdown summary (`README.md`) of `suspflow flow-curves`.
use crate::plots::flow_curves::{label, several_densities};
use rheometry::FlowCurveSource;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use surrogate::rheology::local_viscosity::{self, LocalBand};
use surrogate::{
    green_kubo_points, state_rows, volume_fractions, JammingBootstrap, Quantiles, StateFits,
    StatePoint, CONVENTIONS, MIN_VOLUME_FRACTIONS, PHI_J_MAX, SEEDS_LAW, SEEDS_LOW_PECLET_PHI_J,
};

/// What the command was given, for the summary's record of how it was made.
pub struct Command<'a> {
    pub grid: &'a Path,
    pub source: FlowCurveSource<'a>,
    pub local: Option<&'a Path>,
    pub green_kubo: &'a [PathBuf],
    pub out: &'a Path,
}

/// The `generate` command line(s) that ran `grid` into the work directories `runs`: one,
/// or one per part of a grid run in parts, or (`again`) of the runs run again.
fn generate_lines(grid: &Path, runs: &[PathBuf], again: bool) -> String {
    let grid = grid.display();
    if let ([one], false) = (runs, again) {
        return format!(
            "suspflow generate {grid} --out DATASET.csv --work {} --jobs 2 --threads 1\n",
            one.display()
        );
    }
    let folders: String = runs
        .iter()
        .map(|r| format!("#   {}\n", r.display()))
        .collect();
    let what = if again {
        "the runs replaced, run again (`--shard I/N`, N the grid's runs, I each run's index)"
    } else {
        "the grid's runs in parts (`--shard I/N`, one or more parts per folder)"
    };
    format!(
        "# {what}, into these work folders:\n{folders}\
         suspflow generate {grid} --shard I/N --out DATASET_I.csv --work FOLDER --jobs 1 \
         --threads 1\n"
    )
}

/// The work directories `runs`, separated by spaces.
pub fn folder_list(runs: &[PathBuf]) -> String {
    runs.iter()
        .map(|r| r.display().to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The markdown summary of the flow curves: how `cmd` produced them, the state points per
/// state and volume fraction, the fits, the Green-Kubo bootstrap and the local table.
pub fn summary_text(
    cmd: &Command,
    points: &[StatePoint],
    fits: &[StateFits],
    local: Option<&[LocalBand]>,
) -> String {
    let densities = several_densities(points);
    let mut s = String::from("# Flow curves of homogeneous simple shear\n\n");
    let options = cmd
        .local
        .as_ref()
        .map_or(String::new(), |l| format!(" --local {}", l.display()))
        + &cmd
            .green_kubo
            .iter()
            .map(|d| format!(" --green-kubo {}", d.display()))
            .collect::<String>();
    let grid = cmd.grid.display();
    let made = match cmd.source {
        FlowCurveSource::Runs(runs) => format!(
            "{}suspflow flow-curves {grid} --runs {}{options} --out {}\n```\n",
            generate_lines(cmd.grid, runs, false),
            folder_list(runs),
            cmd.out.display()
        ),
        FlowCurveSource::Table(table) => format!(
            "suspflow flow-curves {grid} --table {}{options} --out {}\n```\n\n\
             from the table that `suspflow flow-curves {grid} --runs ...` wrote earlier.\n",
            table.display(),
            cmd.out.display()
        ),
        FlowCurveSource::Updated { table, runs } => {
            let folders = folder_list(runs);
            format!(
                "{}suspflow flow-curves {grid} --table {} --runs {folders}{options} --out {}\n\
                 ```\n\nfrom the table that `suspflow flow-curves {grid} --runs ...` wrote \
                 earlier, with the runs finished in {folders} in place of its lines of the same \
                 scenes (each line's `code_version` names the code that made it).\n",
                generate_lines(cmd.grid, runs, true),
                table.display(),
                cmd.out.display(),
            )
        }
    };
    let _ = writeln!(
        s,
        "Bidisperse spheres sheared between Lees-Edwards images \
         (docs/physics.md sections 10 and 11), {} runs of `{grid}`. Produced by\n\n```\n{made}",
        points.len(),
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
            cmd.local.as_ref().map_or(String::new(), |p| p.display().to_string()),
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
