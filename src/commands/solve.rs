//! `suspflow solve SCENE.toml --models DIR --out DIR`: the steady profile of a scene from
//! its forcing alone (u_inf(y), phi, box, particle sizes), by the momentum balance closed
//! with the learned `dv` mapping or with the local rheology (the `solver` crate).
//! Writes `DIR/profile.csv` (the dataset's columns that the solve determines; no standard
//! errors) and `DIR/summary.json`; `--compare FILE.csv` puts a simulated profile of the same
//! scene beside the solutions of both closures.
use crate::output_guard;
use crate::plots::profile_panels::{profile_panels, Panel, Series};
use anyhow::{bail, Context};
use ndarray::Array2;
use schema::columns as col;
use schema::Observable;
use serde::Serialize;
use sim::input::scene::Scene;
use solver::{fit_local_rheology, LearnedClosure, ProfileProblem, ProfileSolution, SolverError};
use std::path::{Path, PathBuf};
use std::time::Instant;
use surrogate::{
    relative_l2_error, Dataset, DomainCheck, Mapping, Predictor, Samples, TrainingDomain,
};

/// Starting pressure of the Newton iterations (units eta/time; the training scenes have
/// 0.03-0.2).
const START_PRESSURE: f64 = 0.1;

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ClosureKind {
    /// The trained `dv` mapping, (J, Delta_v, phi) -> (phi_loc, mu).
    Learned,
    /// mu = A J^b and phi_loc by eq 6.7, fitted on the training data.
    Local,
}

#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML): profile, phi, box, particle sizes, bin width.
    scene: PathBuf,
    /// Directory of the trained models (reads the `dv` mapping).
    #[arg(long, default_value = "models")]
    models: PathBuf,
    /// Closure of the momentum balance.
    #[arg(long, value_enum, default_value_t = ClosureKind::Learned)]
    closure: ClosureKind,
    /// Training dataset the local rheology is fitted on (default: the `dv` model's own).
    #[arg(long)]
    train: Option<PathBuf>,
    /// Output directory for profile.csv and summary.json.
    #[arg(long)]
    out: PathBuf,
    /// Replace an earlier solution in --out.
    #[arg(long)]
    force: bool,
    /// A simulated profile of this scene (`profile.csv` of `simulate`, or a dataset holding
    /// the scene's rows under its name): relative L2 errors of both closures.
    #[arg(long)]
    compare: Option<PathBuf>,
}

#[derive(Serialize)]
struct Summary<'a> {
    scene: &'a str,
    closure: ClosureKind,
    bins: usize,
    iterations: usize,
    /// Largest balance residual, in units of the forcing's drag density.
    residual: f64,
    pressure: f64,
    /// Bins outside the closure's training domain (columns `in_domain`, `domain_distance`
    /// of profile.csv): their closure values are extrapolations.
    bins_outside_domain: usize,
    /// Largest `domain_distance` over the bins (<= 1 is near enough the training rows).
    largest_domain_distance: f64,
    wall_ms: f64,
    code_version: &'a str,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let scene = Scene::from_path(&args.scene, false)?;
    let problem = ProfileProblem::from_scene(&scene)
        .with_context(|| format!("{}: nothing to solve", args.scene.display()))?;
    let profile_csv = args.out.join("profile.csv");
    output_guard::out_dir(&args.out)?;
    output_guard::refuse_unless_force(
        &profile_csv,
        args.force,
        "an earlier solution",
        "choose another --out",
    )?;
    let predictor = Predictor::load(&args.models, "dv")
        .with_context(|| format!("loading model `dv` from {}", args.models.display()))?;
    let train = args
        .train
        .clone()
        .unwrap_or_else(|| PathBuf::from(&predictor.meta().training_data.source));
    let train_data =
        Dataset::read_csv(&train).context("reading the training data for the local rheology")?;
    let law = fit_local_rheology(&train_data)?;
    let domain = match args.closure {
        ClosureKind::Learned => predictor.domain().clone(),
        ClosureKind::Local => TrainingDomain::fit(&Samples::from_dataset(
            &train_data,
            Mapping::by_name("dv")?,
        )?)?,
    };
    let features = predictor.meta().features.clone();
    let learned = LearnedClosure::new(predictor)?;
    let started = Instant::now();
    let solution = match args.closure {
        ClosureKind::Learned => problem.solve(&learned, START_PRESSURE),
        ClosureKind::Local => problem.solve(&law, START_PRESSURE),
    }
    .map_err(|e| with_hint(e, args.closure))
    .with_context(|| {
        format!(
            "solving {} with the {:?} closure",
            args.scene.display(),
            args.closure
        )
    })?;
    let wall_ms = started.elapsed().as_secs_f64() * 1e3;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let checks = domain_checks(&domain, &features, scene.file.particles.phi, &solution)?;
    write_profile(&profile_csv, &scene, &problem, &solution, &checks)?;
    let outside = checks.iter().filter(|c| !c.inside()).count();
    let summary = Summary {
        scene: &scene.file.name,
        closure: args.closure,
        bins: problem.n_bins(),
        iterations: solution.iterations,
        residual: solution.residual,
        pressure: solution.pressure,
        bins_outside_domain: outside,
        largest_domain_distance: checks.iter().map(|c| c.distance).fold(0.0, f64::max),
        wall_ms,
        code_version: crate::CODE_VERSION,
    };
    std::fs::write(
        args.out.join("summary.json"),
        serde_json::to_string_pretty(&summary)?,
    )?;
    println!(
        "{}: {:?} closure, {} bins, {} Newton iterations, residual {:.1e}, P {:.4}, {:.1} ms -> {}",
        scene.file.name,
        args.closure,
        summary.bins,
        solution.iterations,
        solution.residual,
        solution.pressure,
        wall_ms,
        profile_csv.display()
    );
    if outside > 0 {
        eprintln!(
            "warning: {outside} of {} bins lie outside the training domain of the {:?} closure \
             (largest domain distance {:.2}, 1 = the threshold): their closure values are \
             extrapolations (profile.csv column in_domain = false)",
            summary.bins, args.closure, summary.largest_domain_distance
        );
    }
    if let Some(path) = &args.compare {
        let (other, other_solution) = match args.closure {
            ClosureKind::Learned => (ClosureKind::Local, problem.solve(&law, START_PRESSURE)),
            ClosureKind::Local => (
                ClosureKind::Learned,
                problem.solve(&learned, START_PRESSURE),
            ),
        };
        let mut solutions = vec![(args.closure, &solution)];
        match &other_solution {
            Ok(s) => solutions.push((other, s)),
            Err(e) => println!("{other:?} closure left out of the comparison: {e}"),
        }
        compare(path, &args.out, &scene, &problem, &solutions)?;
    }
    Ok(())
}

/// A learned solve that stalls is an error that points to the other closure.
fn with_hint(e: SolverError, closure: ClosureKind) -> anyhow::Error {
    match e {
        SolverError::NotConverged { .. } if closure == ClosureKind::Learned => {
            anyhow::anyhow!("{e} (try --closure local)")
        }
        e => e.into(),
    }
}

/// Where each solved bin lies relative to the closure's training rows, in the features of
/// the `dv` mapping (`features`, its order): J and Delta_v of the solution, the scene's phi.
/// The learned closure's domain is the model's own; the local closure's is fitted on its
/// training file (the law is fitted on those rows).
fn domain_checks(
    domain: &TrainingDomain,
    features: &[String],
    phi: f64,
    s: &ProfileSolution,
) -> anyhow::Result<Vec<DomainCheck>> {
    let columns = features
        .iter()
        .map(
            |name| match Observable::from_name(name).and_then(|o| s.column(o)) {
                Some(values) => Ok(values.to_vec()),
                None if name == col::PHI => Ok(vec![phi; s.j.len()]),
                None => bail!("a solve gives no `{name}` per bin for the training-domain check"),
            },
        )
        .collect::<anyhow::Result<Vec<_>>>()?;
    let rows = Array2::from_shape_fn((s.j.len(), columns.len()), |(k, f)| columns[f][k]);
    Ok(domain.check(rows.view())?)
}

/// Writes the solution with the dataset's column names and the bins' training-domain check
/// (`in_domain`, `domain_distance`, as `predict` writes them); standard errors are left out.
fn write_profile(
    path: &Path,
    scene: &Scene,
    problem: &ProfileProblem,
    s: &ProfileSolution,
    checks: &[DomainCheck],
) -> anyhow::Result<()> {
    let mut w =
        csv::Writer::from_path(path).with_context(|| format!("writing {}", path.display()))?;
    w.write_record([
        col::SCENE_ID,
        col::PROFILE,
        col::L_Y,
        col::PHI,
        col::Y,
        col::U_INF,
        col::U,
        col::GDOT,
        col::SIGMA_XY,
        col::P,
        col::PHI_LOC,
        col::J,
        col::MU,
        col::DELTA_V,
        col::F_X,
        col::IN_DOMAIN,
        col::DOMAIN_DISTANCE,
    ])?;
    let f = &scene.file;
    for (k, y) in problem.bin_centres().into_iter().enumerate() {
        let numbers = [
            y,
            problem.u_inf[k],
            s.u[k],
            s.gdot[k],
            s.sigma_xy[k],
            s.pressure,
            s.phi_loc[k],
            s.j[k],
            s.mu[k],
            s.delta_v[k],
            s.f_x[k],
        ];
        let mut record = vec![
            f.name.clone(),
            f.fluid.profile.clone(),
            format!("{:e}", f.box_.l_y),
            format!("{:e}", f.particles.phi),
        ];
        record.extend(numbers.iter().map(|x| format!("{x:e}")));
        record.extend([
            checks[k].inside().to_string(),
            format!("{:e}", checks[k].distance),
        ]);
        w.write_record(&record)?;
    }
    w.flush()?;
    Ok(())
}

/// Relative L2 errors of u, phi_loc and mu of each solution against the simulated rows of
/// the scene in `path`, printed, and the figure `compare.svg` in `out`: the three along y,
/// simulated (one standard error bars where the file has them) and solved.
fn compare(
    path: &Path,
    out: &Path,
    scene: &Scene,
    problem: &ProfileProblem,
    solutions: &[(ClosureKind, &ProfileSolution)],
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
    println!("against {} (relative L2 error, unscaled):", path.display());
    println!(
        "  {:<8} {:>8} {:>8} {:>8}",
        "closure",
        col::U,
        col::PHI_LOC,
        col::MU
    );
    let mut panels = Vec::new();
    let mut lines: Vec<String> = solutions
        .iter()
        .map(|(kind, _)| format!("  {:<8}", format!("{kind:?}").to_lowercase()))
        .collect();
    for observable in [Observable::U, Observable::PhiLoc, Observable::Mu] {
        let name = observable.name();
        let c = data.column(name)?;
        let simulated = Array2::from_shape_fn((rows.len(), 1), |(k, _)| c[rows[k]]);
        let se_name = col::standard_error(name);
        let errors = match data.column(&se_name) {
            Ok(se) => Some(rows.iter().map(|&r| se[r]).collect()),
            Err(_) => None,
        };
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
            *line += &format!(" {:>7.2}%", 100.0 * error);
            series.push(Series {
                name: format!("solved, {} closure", format!("{kind:?}").to_lowercase()),
                points: y.iter().copied().zip(solved.iter().copied()).collect(),
                errors: None,
            });
        }
        panels.push(Panel {
            quantity: name.to_owned(),
            series,
        });
    }
    for line in lines {
        println!("{line}");
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
