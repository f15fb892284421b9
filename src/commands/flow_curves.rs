//! `suspflow flow-curves GRID.toml --runs WORK --out DIR`: the flow curves of a grid of
//! homogeneous-shear scenes (docs/physics.md section 10) that `suspflow generate` has run
//! (resumably, with progress) into the work directory `WORK`: per scene the box totals,
//! the fit of `phi_J` and `lambda` of the jamming law with uncertainties from the scatter
//! between seeds, SVG figures of `eta_r(phi)` and `mu(J)` beside the seeds' law, and a
//! markdown summary; with `--local DATA.csv`, the local `mu / J` of the sheared bins of an
//! inhomogeneous-flow dataset against the homogeneous curve at the same volume fraction.
//!
//! Two stress conventions are fitted: the box's pair stresslets (contact and lubrication,
//! as the thesis' LAMMPS runs report), and the bins' `sigma_xy` under the scene's
//! `[observables] stress` convention (the same pair stresslets by default; with the
//! one-body drag stresslet under `pairs+drag`, as the shipped datasets were made).
use crate::local_viscosity::{self, LocalBand};
use crate::plots::data_and_laws::{self, Points};
use crate::plots::loglog::Line;
use crate::scene_work::{Recorded, SceneStatus, SceneWork};
use anyhow::{bail, Context};
use sim::input::grid::Grid;
use sim::output::atomic_write::write_atomic;
use sim::sampling::shear_rheology::ShearRheology;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use surrogate::{
    bin_viscosity, mean_and_standard_error, Dataset, FlowCurvePoint, JammingLaw, SeededJammingFit,
    SEEDS_LAW,
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
    /// Output directory: flow_curves.csv, eta_r.svg, mu_J.svg, README.md.
    #[arg(long)]
    out: PathBuf,
    /// Replace the files of an earlier run in `--out`.
    #[arg(long)]
    force: bool,
}

/// The fields of a homogeneous-shear scene's summary.json this command reads.
#[derive(serde::Deserialize)]
struct ShearSummary {
    n_particles: usize,
    phi_actual: f64,
    strain_to_steady: f64,
    mean_overlap: f64,
    shear: Option<ShearRheology>,
}

/// One finished scene.
struct FlowPoint {
    id: String,
    /// The grid's volume fraction (the realised one is in the summary).
    phi: f64,
    seed: u64,
    summary: ShearSummary,
    rheology: ShearRheology,
    /// `eta_r` of the bins' `sigma_xy` (the scene's stress convention): mean over the bins of
    /// `-sigma_xy / (eta gdot)`, with its standard error.
    eta_r_bins: (f64, f64),
}

/// The two stress conventions: name, and `(eta_r, standard error)` of a point.
type Convention = (&'static str, fn(&FlowPoint) -> (f64, f64));

const CONVENTIONS: [Convention; 2] = [
    ("pair stresslets (box)", |p| {
        (p.rheology.eta_r.mean, p.rheology.eta_r.se)
    }),
    ("bins, scene's stress convention", |p| p.eta_r_bins),
];

pub fn run(args: Args) -> anyhow::Result<()> {
    let grid = Grid::from_path(&args.grid, false)?;
    crate::output_guard::out_dir(&args.out)?;
    let mut points = Vec::new();
    let mut missing = Vec::new();
    for gs in &grid.runs {
        let Some(gdot) = gs.scene.shear_rate() else {
            bail!(
                "{}: scene {} has no fluid.shear_rate; flow curves need homogeneous shear",
                args.grid.display(),
                gs.id
            );
        };
        let work = SceneWork::new(&args.runs, &gs.label());
        if !matches!(work.status()?, SceneStatus::Done(_)) {
            missing.push(gs.label());
            continue;
        }
        if work.recorded_scene(&gs.scene.file)? != Recorded::Same {
            bail!(
                "{}: the run there was not made for scene {} of {} (another shear rate, \
                 volume fraction or setting, or no scene.toml): --runs must be the work \
                 directory in which `suspflow generate` ran this grid",
                work.dir.display(),
                gs.id,
                args.grid.display()
            );
        }
        let path = work.dir.join("summary.json");
        let bytes = std::fs::read(&path).with_context(|| format!("reading {}", path.display()))?;
        let summary: ShearSummary = serde_json::from_slice(&bytes)
            .with_context(|| format!("reading {}", path.display()))?;
        let rheology = summary
            .shear
            .with_context(|| format!("{}: no `shear` box totals", path.display()))?;
        let eta_r_bins = bin_viscosity(
            &Dataset::read_csv(work.profile_csv())?,
            gs.scene.file.fluid.eta * gdot,
        )?;
        points.push(FlowPoint {
            id: gs.id.clone(),
            phi: gs.scene.file.particles.phi,
            seed: gs.scene.file.seed,
            summary,
            rheology,
            eta_r_bins,
        });
    }
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
    let fits: Vec<SeededJammingFit> = CONVENTIONS
        .iter()
        .map(|(_, value)| fit(&points, *value))
        .collect::<anyhow::Result<_>>()?;
    let local = match &args.local {
        Some(path) => Some(local_viscosity::bands(path, &LOCAL_BANDS)?),
        None => None,
    };
    let written =
        ["README.md", "flow_curves.csv", "eta_r.svg", "mu_J.svg"].map(|f| args.out.join(f));
    crate::output_guard::refuse_any_unless_force(
        &written,
        args.force,
        "an earlier flow-curve result",
        "choose another --out",
    )?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    write_table(&args.out.join("flow_curves.csv"), &points)?;
    draw_figures(&args.out, &points, &fits[0].all)?;
    let text = summary_text(&args, &points, &fits, local.as_deref());
    let readme = args.out.join("README.md");
    write_atomic(&readme, text.as_bytes())?;
    print!("{text}");
    eprintln!("wrote {}", args.out.display());
    Ok(())
}

/// The points of each seed, in grid order.
fn by_seed(points: &[FlowPoint]) -> BTreeMap<u64, Vec<&FlowPoint>> {
    let mut seeds: BTreeMap<u64, Vec<&FlowPoint>> = BTreeMap::new();
    for p in points {
        seeds.entry(p.seed).or_default().push(p);
    }
    seeds
}

/// One marker series per seed of `(x, y, standard error of y)` taken from each point.
fn per_seed(points: &[FlowPoint], value: fn(&FlowPoint) -> (f64, f64, f64)) -> Vec<Points> {
    by_seed(points)
        .iter()
        .map(|(s, sel)| Points {
            name: format!("seed {s}"),
            points: sel.iter().map(|p| value(p)).collect(),
        })
        .collect()
}

/// The jamming law fitted to every point and to each seed's points, with `eta_r` from
/// `value`.
fn fit(
    points: &[FlowPoint],
    value: fn(&FlowPoint) -> (f64, f64),
) -> anyhow::Result<SeededJammingFit> {
    let points: Vec<FlowCurvePoint> = points
        .iter()
        .map(|p| FlowCurvePoint {
            seed: p.seed,
            phi: p.summary.phi_actual,
            eta_r: value(p).0,
        })
        .collect();
    Ok(SeededJammingFit::fit(&points)?)
}

fn write_table(path: &Path, points: &[FlowPoint]) -> anyhow::Result<()> {
    let mut out = String::from(
        "scene_id,seed,n_particles,phi_actual,strain_to_steady,mean_overlap,shear_rate,\
         sigma_xy,sigma_xy_se,P,P_se,eta_r,eta_r_se,mu,mu_se,J,J_se,eta_r_bins,eta_r_bins_se\n",
    );
    for p in points {
        let r = &p.rheology;
        let _ = write!(
            out,
            "{},{},{},{},{},{},{}",
            p.id,
            p.seed,
            p.summary.n_particles,
            p.summary.phi_actual,
            p.summary.strain_to_steady,
            p.summary.mean_overlap,
            r.shear_rate
        );
        for e in [r.sigma_xy, r.p, r.eta_r, r.mu, r.j] {
            let _ = write!(out, ",{},{}", e.mean, e.se);
        }
        let _ = writeln!(out, ",{},{}", p.eta_r_bins.0, p.eta_r_bins.1);
    }
    Ok(write_atomic(path, out.as_bytes())?)
}

/// `eta_r(phi)` and `mu(J)`, one marker colour per seed, beside the seeds' law and the fit
/// (box convention). In the `mu(J)` plane a law is drawn at each measured point's `J` as
/// `mu = J eta_r(phi)`, since `eta_r = mu / J`.
fn draw_figures(out: &Path, points: &[FlowPoint], fitted: &JammingLaw) -> anyhow::Result<()> {
    let laws = [
        (
            format!(
                "seeds' law, phi_J = {}, lambda = {}",
                SEEDS_LAW.phi_j, SEEDS_LAW.lambda
            ),
            SEEDS_LAW,
        ),
        (
            format!(
                "fit, phi_J = {:.3}, lambda = {:.2}",
                fitted.phi_j, fitted.lambda
            ),
            *fitted,
        ),
    ];
    let eta_points = per_seed(points, |p| {
        (
            p.summary.phi_actual,
            p.rheology.eta_r.mean,
            p.rheology.eta_r.se,
        )
    });
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
    let mu_points = per_seed(points, |p| {
        (p.rheology.j.mean, p.rheology.mu.mean, p.rheology.mu.se)
    });
    let mut by_j: Vec<&FlowPoint> = points.iter().collect();
    by_j.sort_by(|a, b| a.rheology.j.mean.total_cmp(&b.rheology.j.mean));
    let mu_curves: Vec<Line> = laws
        .iter()
        .map(|(name, law)| Line {
            name: format!("{name} at the measured J"),
            points: by_j
                .iter()
                .map(|p| {
                    let j = p.rheology.j.mean;
                    (j, j * law.eta_r(p.summary.phi_actual))
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
    points: &[FlowPoint],
    fits: &[SeededJammingFit],
    local: Option<&[LocalBand]>,
) -> String {
    let mut s = String::from("# Flow curves of homogeneous simple shear\n\n");
    let _ = writeln!(
        s,
        "Frictionless bidisperse spheres sheared between Lees-Edwards images \
         (docs/physics.md section 10), {} scenes of `{}`. Produced by\n\n```\n\
         suspflow generate {} --out {}/bins.csv --work {} --jobs 2 --threads 1\n\
         suspflow flow-curves {} --runs {}{} --out {}\n```\n",
        points.len(),
        args.grid.display(),
        args.grid.display(),
        args.out.display(),
        args.runs.display(),
        args.grid.display(),
        args.runs.display(),
        args.local
            .as_ref()
            .map_or(String::new(), |l| format!(" --local {}", l.display())),
        args.out.display()
    );
    s.push_str(
        "Per volume fraction, the mean over seeds (standard error from their spread); `eta_r` \
         of the pair stresslets over the box, and of the bins' `sigma_xy` (with the drag \
         stresslet, as in the datasets):\n\n\
         | phi | seeds | eta_r (pairs) | eta_r (bins) | seeds' law | pairs / law | mu | J |\n\
         |---|---|---|---|---|---|---|---|\n",
    );
    let mut by_phi: BTreeMap<String, Vec<&FlowPoint>> = BTreeMap::new();
    for p in points {
        by_phi.entry(format!("{:.4}", p.phi)).or_default().push(p);
    }
    for sel in by_phi.values() {
        let col = |f: fn(&FlowPoint) -> f64| {
            mean_and_standard_error(&sel.iter().map(|p| f(p)).collect::<Vec<_>>())
        };
        let phi = col(|p| p.summary.phi_actual).0;
        let (eta, eta_se) = col(|p| p.rheology.eta_r.mean);
        let (bins, bins_se) = col(|p| p.eta_r_bins.0);
        let (mu, mu_se) = col(|p| p.rheology.mu.mean);
        let (j, j_se) = col(|p| p.rheology.j.mean);
        let law = SEEDS_LAW.eta_r(phi);
        let _ = writeln!(
            s,
            "| {phi:.4} | {} | {eta:.2} ± {eta_se:.2} | {bins:.2} ± {bins_se:.2} | {law:.2} | {:.2} | {mu:.3} ± {mu_se:.3} | {j:.4} ± {j_se:.4} |",
            sel.len(),
            eta / law
        );
    }
    s.push_str(
        "\nFit of `eta_r = (1 - phi/phi_J)^(-lambda)` (least squares in `ln eta_r`, all \
         points; standard errors from the seeds' separate fits), beside the seeds' \
         `phi_J = 0.642`, `lambda = 1.5`:\n\n\
         | stress | phi_J | lambda | per seed (phi_J, lambda) |\n|---|---|---|---|\n",
    );
    for ((name, _), f) in CONVENTIONS.iter().zip(fits) {
        let seeds: Vec<String> = f
            .per_seed
            .iter()
            .map(|(s, l)| format!("seed {s}: {:.4}, {:.3}", l.phi_j, l.lambda))
            .collect();
        let _ = writeln!(
            s,
            "| {name} | {:.4} ± {:.4} | {:.3} ± {:.3} | {} |",
            f.all.phi_j,
            f.phi_j_se,
            f.all.lambda,
            f.lambda_se,
            seeds.join("; ")
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
            let (pairs, bins) = (&fits[0].all, &fits[1].all);
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
    s.push_str("\nFigures: `eta_r.svg` (eta_r against phi), `mu_J.svg` (mu against J); data in `flow_curves.csv`.\n");
    s
}
