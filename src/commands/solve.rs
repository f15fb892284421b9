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
use crate::report::solve_comparison::compare;
use anyhow::Context;
use sim::input::scene::Scene;
use solver::{
    Bands, ClosureKind, Closures, ProfileProblem, ProfileSolution, SolvedProfile, SolverError,
};
use std::path::PathBuf;
use std::time::Instant;

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
