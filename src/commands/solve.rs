//! `suspflow solve SCENE.toml --models DIR --out DIR`: the steady profile of a scene from
//! its forcing alone (u_inf(y), phi, box, particle sizes), by the momentum balance closed
//! with the learned `dv` mapping, with the local rheology, or nonlocally with the learned
//! `theta` mapping and the Theta balance (the `solver` crate).
//! Writes `DIR/profile.csv` (the dataset's columns that the solve determines, no standard
//! errors, and the bands `<u|phi_loc|mu>_lower`, `_upper` at `--level`, 90 % by default,
//! calibrated on families the models did not see: `solver::bands`), `DIR/summary.json`
//! (which closure, the fitted Theta balance, the bands' margins) and `DIR/scene.toml`, all
//! by `solver::SolvedProfile`; `--compare FILE.csv` puts a simulated profile of the same
//! scene beside the solutions of every closure.
use crate::output_guard;
use crate::plots::profile_panels::{profile_panels, Panel, Series};
use anyhow::{bail, Context};
use ndarray::Array2;
use schema::columns as col;
use schema::Observable;
use sim::input::scene::Scene;
use solver::{
    Bands, ClosureKind, Closures, ProfileBands, ProfileProblem, ProfileSolution, SolvedProfile,
    SolverError, BANDED,
};
use std::path::{Path, PathBuf};
use std::time::Instant;
use surrogate::{beyond_noise, relative_l2_error, Dataset};

use crate::surrogate_text::percent;

/// Starting pressure of the Newton iterations (units eta/time; the training scenes have
/// 0.03-0.2).
const START_PRESSURE: f64 = 0.1;

/// `--closure NAME`: one of the solver's closures.
fn parse_closure(name: &str) -> Result<ClosureKind, String> {
    ClosureKind::from_name(name).map_err(|e| e.to_string())
}

#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML): profile, phi, box, particle sizes, bin width.
    scene: PathBuf,
    /// Directory of the trained models (reads the `dv` and `theta` mappings).
    #[arg(long, default_value = "models")]
    models: PathBuf,
    /// Closure of the momentum balance: learned (the `dv` mapping), local (mu = A J^b and
    /// eq 6.7, fitted on the training data), nonlocal (the `theta` mapping with the Theta
    /// balance l^2 Theta'' = Theta - c J^beta) or extremum (the `ext` mapping, whose input
    /// d_ext is the distance to the nearest velocity extremum of the solved profile).
    #[arg(long, default_value = "learned", value_parser = parse_closure)]
    closure: ClosureKind,
    /// Training dataset of the fits every closure uses: the local rheology (the local closure,
    /// and the start of the learned and nonlocal closures' continuation) with its training
    /// domain, and the Theta balance (the nonlocal closure). Default: the file the `dv`
    /// model's sidecar names, relative to the folder holding --models (so from any directory).
    #[arg(long)]
    train: Option<PathBuf>,
    /// Output directory for profile.csv and summary.json.
    #[arg(long)]
    out: PathBuf,
    /// Replace an earlier solution in --out.
    #[arg(long)]
    force: bool,
    /// A simulated profile of this scene (`profile.csv` of `simulate`, or a dataset holding
    /// the scene's rows under its name): relative L2 errors of every closure, their part
    /// beyond the simulation's own noise, and the coverage of this closure's bands.
    #[arg(long)]
    compare: Option<PathBuf>,
    /// Level of the bands (a probability in (0, 1)).
    #[arg(long, default_value_t = surrogate::DEFAULT_LEVEL)]
    level: f64,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let scene = Scene::from_path(&args.scene, false)?;
    let problem = ProfileProblem::from_scene(&scene)
        .with_context(|| format!("{}: nothing to solve", args.scene.display()))?;
    let profile_csv = args.out.join("profile.csv");
    let _lock = output_guard::claim_dir(&args.out, "`suspflow solve`")?;
    output_guard::refuse_unless_force(
        &profile_csv,
        args.force,
        "an earlier solution",
        "choose another --out",
    )?;
    surrogate::check_level(args.level)?;
    let closures = Closures::load(&args.models, args.train.as_deref()).with_context(|| {
        format!(
            "loading the closures from {} and their training data",
            args.models.display()
        )
    })?;
    let started = Instant::now();
    let solution = problem
        .solve(
            closures.get(args.closure)?,
            Some(&closures.local),
            START_PRESSURE,
        )
        .map_err(|e| with_hint(e, args.closure))
        .with_context(|| {
            format!(
                "solving {} with the {} closure",
                args.scene.display(),
                args.closure.name()
            )
        })?;
    let bands = closures.bands(args.closure, &problem, &solution, args.level)?;
    let wall_ms = started.elapsed().as_secs_f64() * 1e3;
    let checks = closures.domain_checks(args.closure, scene.file.particles.phi, &solution)?;
    let (profile_bands, band_summary) = match bands {
        Bands::Calibrated(calibrated) => {
            let (b, summary) = *calibrated;
            (Some(b), Some(summary))
        }
        Bands::Missing(why) => {
            eprintln!("warning: the profile has no bands: {why}");
            (None, None)
        }
    };
    let solved = SolvedProfile {
        scene: &scene,
        problem: &problem,
        solution: &solution,
        checks: &checks,
        bands: profile_bands.as_ref(),
    };
    let summary = solved.summary(
        args.closure,
        closures.theta_fit,
        band_summary,
        wall_ms,
        crate::CODE_VERSION,
    );
    solved.write(&args.out, &summary)?;
    let outside = summary.bins_outside_domain;
    println!(
        "{}: {} closure, {} bins, {} Newton iterations{}, residual {:.1e}, P {:.4}, {:.1} ms -> {}",
        scene.file.name,
        args.closure.name(),
        summary.bins,
        solution.iterations,
        if solution.continued {
            " (by continuation from the local law)"
        } else {
            ""
        },
        solution.residual,
        solution.pressure,
        wall_ms,
        profile_csv.display()
    );
    if let Some(b) = &summary.bands {
        println!(
            "  {:.0} % bands (columns <u|phi_loc|mu>_lower, _upper), mean width relative to the \
             profile: u {}, phi_loc {}, mu {}; on held-out families the 90 % bands covered u {}, \
             phi_loc {}, mu {} of the bins",
            100.0 * b.level,
            percent(b.relative_widths[0]),
            percent(b.relative_widths[1]),
            percent(b.relative_widths[2]),
            percent(b.held_out_coverage[0]),
            percent(b.held_out_coverage[1]),
            percent(b.held_out_coverage[2])
        );
    }
    if outside > 0 {
        eprintln!(
            "warning: {outside} of {} bins lie outside the training domain of the {} closure \
             (largest domain distance {:.2}, 1 = the threshold): their closure values are \
             extrapolations (profile.csv column in_domain = false)",
            summary.bins,
            args.closure.name(),
            summary.largest_domain_distance
        );
    }
    if let Some(path) = &args.compare {
        let others: Vec<(ClosureKind, ProfileSolution)> = ClosureKind::ALL
            .into_iter()
            .filter(|&kind| kind != args.closure)
            .filter_map(|kind| {
                let solved = closures
                    .get(kind)
                    .and_then(|c| problem.solve(c, Some(&closures.local), START_PRESSURE));
                match solved {
                    Ok(s) => Some((kind, s)),
                    Err(e) => {
                        println!("{} closure left out of the comparison: {e}", kind.name());
                        None
                    }
                }
            })
            .collect();
        let mut solutions = vec![(args.closure, &solution)];
        solutions.extend(others.iter().map(|(kind, s)| (*kind, s)));
        compare(
            path,
            &args.out,
            &scene,
            &problem,
            &solutions,
            profile_bands.as_ref(),
        )?;
    }
    Ok(())
}

/// A solve that stalls is an error that points to the other closures (never to the one that
/// failed): each is a different model of the same flow.
fn with_hint(e: SolverError, closure: ClosureKind) -> anyhow::Error {
    match e {
        SolverError::NotConverged { .. } | SolverError::ContinuationStalled { .. } => {
            let others: Vec<String> = ClosureKind::ALL
                .into_iter()
                .filter(|&kind| kind != closure)
                .map(|kind| format!("--closure {}", kind.name()))
                .collect();
            anyhow::anyhow!("{e} (try {})", others.join(" or "))
        }
        e => e.into(),
    }
}

/// Relative L2 errors of u, phi_loc and mu of each solution against the simulated rows of
/// the scene in `path`, with their part beyond the simulation's own noise (`||se|| / ||y||`)
/// where the file has standard errors, and the fraction of the bins inside the first
/// solution's `bands`; printed, and the figure `compare.svg` in `out`: the three along y,
/// simulated (one standard error bars where the file has them), solved, and the bands.
fn compare(
    path: &Path,
    out: &Path,
    scene: &Scene,
    problem: &ProfileProblem,
    solutions: &[(ClosureKind, &ProfileSolution)],
    bands: Option<&ProfileBands>,
) -> anyhow::Result<()> {
    let data = Dataset::read_csv(path)?;
    let ids = data.text(col::SCENE_ID)?;
    let rows: Vec<usize> = (0..data.n_rows())
        .filter(|&r| ids[r] == scene.file.name)
        .collect();
    if rows.len() != scene.n_bins {
        bail!(
            "{} holds {} rows of scene `{}`, the scene has {} bins",
            path.display(),
            rows.len(),
            scene.file.name,
            scene.n_bins
        );
    }
    let y = problem.bin_centres();
    println!(
        "against {} (relative L2 error, unscaled; in brackets its part beyond the simulation's \
         own noise, sqrt(max(0, error^2 - noise^2))):",
        path.display()
    );
    println!(
        "  {:<8} {:>18} {:>18} {:>18}",
        "closure",
        col::U,
        col::PHI_LOC,
        col::MU
    );
    let mut noise_line = format!("  {:<8}", "noise");
    let mut coverage_line = format!("  {:<8}", "in band");
    let mut panels = Vec::new();
    let mut lines: Vec<String> = solutions
        .iter()
        .map(|(kind, _)| format!("  {:<8}", kind.name()))
        .collect();
    for observable in [Observable::U, Observable::PhiLoc, Observable::Mu] {
        let name = observable.name();
        let c = data.column(name)?;
        let simulated = Array2::from_shape_fn((rows.len(), 1), |(k, _)| c[rows[k]]);
        let se_name = col::standard_error(name);
        let errors: Option<Vec<f64>> = match data.column(&se_name) {
            Ok(se) => Some(rows.iter().map(|&r| se[r]).collect()),
            Err(_) => None,
        };
        let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
        let noise = errors
            .as_ref()
            .map(|se| norm(&mut se.iter().copied()) / norm(&mut rows.iter().map(|&r| c[r])));
        noise_line += &format!(
            " {:>18}",
            noise.map_or_else(|| "-".to_owned(), |n| format!("{:.2}%", 100.0 * n))
        );
        let mut series = vec![Series {
            name: "simulated".to_owned(),
            points: rows.iter().zip(&y).map(|(&r, &y)| (y, c[r])).collect(),
            errors,
        }];
        for ((kind, s), line) in solutions.iter().zip(&mut lines) {
            let solved = s
                .column(observable)
                .with_context(|| format!("a solve gives no {name} per bin"))?;
            let column = Array2::from_shape_fn((rows.len(), 1), |(k, _)| solved[k]);
            let error = relative_l2_error(simulated.view(), column.view())?[0];
            let beyond = noise.map_or_else(
                || " ".repeat(9),
                |n| format!(" ({:>5.2}%)", 100.0 * beyond_noise(error, n)),
            );
            *line += &format!(" {:>8}{beyond}", format!("{:.2}%", 100.0 * error));
            series.push(Series {
                name: format!("solved, {} closure", kind.name()),
                points: y.iter().copied().zip(solved.iter().copied()).collect(),
                errors: None,
            });
        }
        if let Some(b) = bands {
            let i = BANDED.iter().position(|o| *o == observable).unwrap_or(0);
            let inside = (0..rows.len())
                .filter(|&k| b.lower[i][k] <= c[rows[k]] && c[rows[k]] <= b.upper[i][k])
                .count();
            coverage_line += &format!(
                " {:>18}",
                format!("{:.1}%", 100.0 * inside as f64 / rows.len() as f64)
            );
            for (end, values) in [("lower", &b.lower[i]), ("upper", &b.upper[i])] {
                series.push(Series {
                    name: format!(
                        "{:.0} % band, {}, {end}",
                        100.0 * b.level,
                        solutions[0].0.name()
                    ),
                    points: y.iter().copied().zip(values.iter().copied()).collect(),
                    errors: None,
                });
            }
        }
        panels.push(Panel {
            quantity: name.to_owned(),
            series,
        });
    }
    for line in lines {
        println!("{line}");
    }
    println!("{noise_line}");
    if let Some(b) = bands {
        println!(
            "{coverage_line}   (bins inside the {:.0} % bands of the {} closure)",
            100.0 * b.level,
            solutions[0].0.name()
        );
    }
    let figure = out.join("compare.svg");
    let title = format!(
        "{}: u_inf = {}, L_y = {}, phi = {}",
        scene.file.name, scene.file.fluid.profile, scene.file.box_.l_y, scene.file.particles.phi
    );
    profile_panels(&figure, &title, &panels)?;
    println!("figure: {}", figure.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use solver::Stall;

    #[test]
    fn a_stalled_solve_suggests_every_other_closure_and_never_its_own() {
        for closure in ClosureKind::ALL {
            let stalled = SolverError::NotConverged {
                stall: Stall::SingularJacobian,
                iterations: 3,
                residual: 1.0,
                tolerance: 1e-8,
            };
            let message = with_hint(stalled, closure).to_string();
            for kind in ClosureKind::ALL {
                let hint = format!("--closure {}", kind.name());
                assert_eq!(
                    message.contains(&hint),
                    kind != closure,
                    "{closure:?}: {message}"
                );
            }
        }
        let other = with_hint(SolverError::InvalidArgument("x".into()), ClosureKind::Local);
        assert!(!other.to_string().contains("--closure"), "{other}");
    }
}
