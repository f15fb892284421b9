//! `suspflow solve --compare`: each solution beside a simulated profile of the same scene,
//! as relative L2 errors with their part beyond the simulation's noise, the bins inside the
//! bands, and the figure `compare.svg`.
use crate::plots::profile_panels::{profile_panels, Panel, Series};
use anyhow::{bail, Context};
use ndarray::Array2;
use schema::columns as col;
use schema::Observable;
use sim::input::scene::Scene;
use solver::{ClosureKind, ProfileBands, ProfileProblem, ProfileSolution, BANDED};
use std::path::Path;
use surrogate::{beyond_noise, relative_l2_error, Dataset};

/// Relative L2 errors of u, phi_loc and mu of each solution against the simulated rows of
/// the scene in `path`, with their part beyond the simulation's own noise (`||se|| / ||y||`)
/// where the file has standard errors, and the fraction of the bins inside the first
/// solution's `bands`; printed, and the figure `compare.svg` in `out`: the three along y,
/// simulated (one standard error bars where the file has them), solved, and the bands.
pub fn compare(
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
