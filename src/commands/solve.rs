//! `suspflow solve SCENE.toml --models DIR --out DIR`: the steady profile of a scene from
//! its forcing alone (u_inf(y), phi, box, particle sizes), by the momentum balance closed
//! with the learned `dv` mapping or with the local rheology (`surrogate::profile_solver`).
//! Writes `DIR/profile.csv` (the dataset's columns that the solve determines; no standard
//! errors) and `DIR/summary.json`; `--compare FILE.csv` puts a simulated profile of the same
//! scene beside the solutions of both closures.
use crate::output_guard;
use crate::plots::profile_panels::{profile_panels, Panel, Series};
use anyhow::{bail, Context};
use ndarray::Array2;
use serde::Serialize;
use sim::input::scene::Scene;
use sim::output::dataset_columns as col;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::time::Instant;
use surrogate::{
    relative_l2_error, Dataset, LearnedClosure, LocalRheology, Predictor, ProfileProblem,
    ProfileSolution,
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
    wall_ms: f64,
    code_version: &'a str,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let scene = Scene::from_path(&args.scene, false)?;
    if scene.shear_rate().is_some() {
        anyhow::bail!(
            "{}: homogeneous shear (fluid.shear_rate) has no forcing profile to solve for; \
             solve takes scenes with fluid.profile",
            args.scene.display()
        );
    }
    let profile_csv = args.out.join("profile.csv");
    output_guard::out_dir(&args.out)?;
    output_guard::refuse_unless_force(
        &profile_csv,
        args.force,
        "an earlier solution",
        "choose another --out",
    )?;
    let problem = problem(&scene);
    let predictor = Predictor::load(&args.models, "dv")
        .with_context(|| format!("loading model `dv` from {}", args.models.display()))?;
    let train = args
        .train
        .clone()
        .unwrap_or_else(|| PathBuf::from(&predictor.meta().training_data.source));
    let learned = LearnedClosure::new(predictor)?;
    let law = local_rheology(&train)?;
    let started = Instant::now();
    let solution = match args.closure {
        ClosureKind::Learned => problem.solve(&learned, START_PRESSURE),
        ClosureKind::Local => problem.solve(&law, START_PRESSURE),
    }
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
    write_profile(&profile_csv, &scene, &problem, &solution)?;
    let summary = Summary {
        scene: &scene.file.name,
        closure: args.closure,
        bins: problem.u_inf.len(),
        iterations: solution.iterations,
        residual: solution.residual,
        pressure: solution.pressure,
        wall_ms,
        code_version: sim::CODE_VERSION,
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

/// The scene's forcing at its bin centres, with the drag coefficient of its particle mix.
fn problem(scene: &Scene) -> ProfileProblem {
    let f = &scene.file;
    let width = f.run.bin_width;
    let u_inf = (0..scene.n_bins)
        .map(|k| scene.profile.u((k as f64 + 0.5) * width))
        .collect();
    let (mut radius_sum, mut volume_sum) = (0.0, 0.0);
    for (&a, &count) in f.particles.radii.iter().zip(&scene.counts) {
        radius_sum += count as f64 * a;
        volume_sum += count as f64 * 4.0 / 3.0 * PI * a.powi(3);
    }
    ProfileProblem {
        u_inf,
        bin_width: width,
        phi: f.particles.phi,
        eta: f.fluid.eta,
        drag_coefficient: 6.0 * PI * f.fluid.eta * radius_sum / volume_sum,
    }
}

/// mu = A J^b and eq 6.7 fitted on every row of `path` with J, phi_loc and mu.
fn local_rheology(path: &Path) -> anyhow::Result<LocalRheology> {
    let data =
        Dataset::read_csv(path).context("reading the training data for the local rheology")?;
    let rows = data.complete_rows(&[col::J, col::PHI_LOC, col::MU])?;
    let column = |name: &str| -> anyhow::Result<Vec<f64>> {
        let c = data.column(name)?;
        Ok(rows.iter().map(|&r| c[r]).collect())
    };
    Ok(LocalRheology::fit(
        &column(col::J)?,
        &column(col::PHI_LOC)?,
        &column(col::MU)?,
    )?)
}

/// Writes the solution with the dataset's column names; standard errors are left out.
fn write_profile(
    path: &Path,
    scene: &Scene,
    problem: &ProfileProblem,
    s: &ProfileSolution,
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
    ])?;
    let f = &scene.file;
    for k in 0..problem.u_inf.len() {
        let y = (k as f64 + 0.5) * problem.bin_width;
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
    let y: Vec<f64> = (0..scene.n_bins)
        .map(|k| (k as f64 + 0.5) * problem.bin_width)
        .collect();
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
    for name in [col::U, col::PHI_LOC, col::MU] {
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
            let solved = solved_column(s, name);
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

/// The solved values of observable `name` (u, phi_loc or mu).
fn solved_column<'a>(s: &'a ProfileSolution, name: &str) -> &'a [f64] {
    match name {
        col::U => &s.u,
        col::PHI_LOC => &s.phi_loc,
        _ => &s.mu,
    }
}
