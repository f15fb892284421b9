//! Section 5 of the report: Theta against Delta_v as the non-local descriptor. The
//! surrogate's side (validation error of the `theta` and `dv` mappings per profile, and
//! each descriptor's share of its model's gain), and the data's side: per validation
//! profile, how much each descriptor varies along y and how noisy it is (batch-means
//! standard error), drawn along y in `descriptors_along_y.svg`.
use crate::plots::profile_panels::{profile_panels, Panel, Series};
use anyhow::Context;
use schema::columns as col;
use std::fmt::Write as _;
use std::path::Path;
use surrogate::{
    beyond_noise, gain_shares, theta_vs_dv, Dataset, DescriptorStats, Lower, Mapping, TrainedModel,
    Validation,
};

/// Writes the figure into `dir` and returns the section, from the validation set and the
/// `theta` and `dv` models in `models`.
pub fn section(validate: &Path, models: &Path, dir: &Path) -> anyhow::Result<String> {
    let data = Dataset::read_csv(validate)?;
    let mut md = String::from("## 5. Theta against Delta_v\n\n");
    md.push_str("Surrogate: relative L2 validation error (eq 6.6) of the mapping that reads Theta and of the one that \
        reads Delta_v, with the same J and phi inputs and the same outputs; in brackets the part beyond the targets' \
        own noise, `sqrt(max(0, error^2 - noise^2))`.\n\n| profile | output | theta mapping | dv mapping | noise | lower |\n|---|---|---|---|---|---|\n");
    let load = |name: &str| {
        TrainedModel::load(models, name)
            .with_context(|| format!("loading the {name} model from {}", models.display()))
    };
    let (theta, dv) = (load("theta")?, load("dv")?);
    let (vt, vd) = (
        Validation::run(&theta, &data)?,
        Validation::run(&dv, &data)?,
    );
    for row in theta_vs_dv(&vt, &vd, Mapping::by_name("theta")?.outputs) {
        let lower = match row.lower() {
            Lower::Theta => "Theta",
            Lower::Dv => "Delta_v",
            Lower::Tie => "tie",
        };
        let cell = |e: f64| match row.noise {
            Some(n) => format!("{:.2} % ({:.2} %)", 100.0 * e, 100.0 * beyond_noise(e, n)),
            None => format!("{:.2} %", 100.0 * e),
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {lower} |",
            row.profile,
            row.output,
            cell(row.theta),
            cell(row.dv),
            row.noise
                .map_or_else(|| "-".to_owned(), |n| format!("{:.2} %", 100.0 * n))
        );
    }
    let share = |m: &TrainedModel, feature: &str| -> anyhow::Result<f64> {
        let gains = m.feature_importance()?;
        Ok(gain_shares(&gains)
            .iter()
            .find(|g| g.0 == feature)
            .map_or(0.0, |g| g.1))
    };
    let _ = writeln!(md, "\nShare of the model's gain: Theta {:.1} % of the theta mapping, Delta_v {:.1} % of the dv mapping.\n",
        100.0 * share(&theta, "Theta")?, 100.0 * share(&dv, "Delta_v")?);

    md.push_str("Data: per validation profile, variation along y (standard deviation over mean), noise (standard error \
        relative to the value, median and largest over bins) and their ratio (standard deviation along y over the rms \
        standard error: how many noise widths the profile spans).\n\n\
        | profile | descriptor | variation along y | median relative SE | largest relative SE | signal / noise |\n|---|---|---|---|---|---|\n");
    let ids = data.group_keys()?;
    let mut unique: Vec<&String> = Vec::new();
    for id in ids {
        if !unique.contains(&id) {
            unique.push(id);
        }
    }
    let y = data.column("y")?;
    let mut panels: Vec<Panel> = [
        "Theta",
        "Delta_v",
        "Theta SE / Theta",
        "Delta_v SE / Delta_v",
    ]
    .iter()
    .map(|q| Panel {
        quantity: q.to_string(),
        series: Vec::new(),
    })
    .collect();
    let mut notes = Vec::new();
    for id in unique {
        let rows: Vec<usize> = (0..ids.len()).filter(|&r| &ids[r] == id).collect();
        let mut medians = [f64::NAN; 2];
        for (d, name) in ["Theta", "Delta_v"].iter().enumerate() {
            let pick = |c: &str| -> anyhow::Result<Vec<f64>> {
                let col = data.column(c)?;
                Ok(rows.iter().map(|&r| col[r]).collect())
            };
            let (v, se) = (pick(name)?, pick(&col::standard_error(name))?);
            let s = DescriptorStats::of(&v, &se);
            medians[d] = s.median_relative_se;
            let _ = writeln!(
                md,
                "| {id} | {name} | {:.2} | {:.2} % | {:.1} % | {:.1} |",
                s.variation,
                100.0 * s.median_relative_se,
                100.0 * s.max_relative_se,
                s.signal_to_noise
            );
            let ys: Vec<f64> = rows.iter().map(|&r| y[r]).collect();
            panels[d].series.push(Series {
                name: id.clone(),
                points: ys.iter().copied().zip(v.iter().copied()).collect(),
                errors: Some(se.clone()),
            });
            panels[d + 2].series.push(Series {
                name: id.clone(),
                points: ys
                    .iter()
                    .zip(v.iter().zip(&se))
                    .map(|(&y, (v, s))| (y, s / v.abs()))
                    .collect(),
                errors: None,
            });
        }
        let (u_inf, dv, dv_se) = (
            data.column(col::U_INF)?,
            data.column("Delta_v")?,
            data.column(&col::standard_error(col::DELTA_V))?,
        );
        let worst = rows
            .iter()
            .copied()
            .filter(|&r| (dv_se[r] / dv[r].abs()).is_finite())
            .max_by(|&a, &b| (dv_se[a] / dv[a].abs()).total_cmp(&(dv_se[b] / dv[b].abs())));
        let u_max = rows.iter().map(|&r| u_inf[r].abs()).fold(0.0, f64::max);
        let at = worst.map_or(String::new(), |r| {
            format!(
                " Its noisiest bin is at y = {:.0}, where |u_inf| = {:.3} \
            (largest |u_inf| {u_max:.3}): Delta_v divides by |u_inf|.",
                y[r],
                u_inf[r].abs()
            )
        });
        notes.push(format!("- {id}: Delta_v's median relative standard error is {:.1} times Theta's, so the same relative \
            precision takes {:.1} times the averaging.{at}", medians[1] / medians[0], (medians[1] / medians[0]).powi(2)));
    }
    md.push('\n');
    md.push_str(&notes.join("\n"));
    md.push_str("\n\nDelta_v needs only the mean velocity profile (e.g. from PIV in an experiment), Theta the velocity \
        fluctuations of individual particles; the table shows what each costs in averaging time in a simulation.\n");
    profile_panels(
        &dir.join("descriptors_along_y.svg"),
        "Theta and Delta_v along y (validation profiles, 1 SE bars)",
        &panels,
    )?;
    md.push_str("\n![Theta and Delta_v along y](descriptors_along_y.svg)\n\n");
    Ok(md)
}
