//! `suspflow plot DATA.csv --out DIR`: one SVG per scene of a dataset (or a `profile.csv`,
//! or an ensemble table) with u (and u_inf), phi_loc, mu, J, Theta and Delta_v along y, each
//! bin's value with one standard error, like the thesis' figure 6.1; the replicas (seeds) of
//! a scene are drawn as one series each.
use crate::plots::profile_panels::{profile_panels, Panel, Series};
use anyhow::Context;
use schema::columns as col;
use std::path::PathBuf;
use surrogate::Dataset;

/// Observables drawn, one panel each.
const QUANTITIES: [&str; 6] = [
    col::U,
    col::PHI_LOC,
    col::MU,
    col::J,
    col::THETA,
    col::DELTA_V,
];

#[derive(clap::Args)]
pub struct Args {
    /// Dataset or profile table (docs/physics.md section 8 columns).
    data: PathBuf,
    /// Directory for `<scene_id>.svg`.
    #[arg(long)]
    out: PathBuf,
    /// Replace figures of the same scenes already in `--out`.
    #[arg(long)]
    force: bool,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let data = Dataset::read_csv(&args.data)?;
    let _lock = crate::output_guard::claim_dir(&args.out, "`suspflow plot`")?;
    let ids = data.group_keys()?;
    let scenes = scene_order(ids, &data)?;
    let figure = |id: &str| args.out.join(format!("{id}.svg"));
    crate::output_guard::refuse_any_unless_force(
        &scenes.iter().map(|id| figure(id)).collect::<Vec<_>>(),
        args.force,
        "a figure of `suspflow plot`",
        "choose another --out",
    )?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let (profile, l_y, phi) = (
        data.text(col::PROFILE)?,
        data.text(col::L_Y)?,
        data.text(col::PHI)?,
    );
    let (y, u_inf) = (
        data.defined_column(col::Y)?,
        data.defined_column(col::U_INF)?,
    );
    let seeds = data.text(col::SEED).ok();
    for id in scenes {
        let rows: Vec<usize> = (0..data.n_rows()).filter(|&r| ids[r] == id).collect();
        let replicas = replica_rows(&rows, seeds);
        let mut panels = Vec::new();
        for q in QUANTITIES {
            let (v, se) = (
                data.defined_column(q)?,
                data.defined_column(&col::standard_error(q))?,
            );
            let mut series: Vec<Series> = replicas
                .iter()
                .map(|(name, rows)| Series {
                    name: name.clone(),
                    points: rows.iter().map(|&r| (y[r], v[r])).collect(),
                    errors: Some(rows.iter().map(|&r| se[r]).collect()),
                })
                .collect();
            if q == "u" {
                series.push(Series {
                    name: "u_inf".into(),
                    points: rows.iter().map(|&r| (y[r], u_inf[r])).collect(),
                    errors: None,
                });
            }
            panels.push(Panel {
                quantity: q.into(),
                series,
            });
        }
        let r0 = rows[0];
        let title = format!(
            "{id}: u_inf = {}, L_y = {}, phi = {}",
            profile[r0], l_y[r0], phi[r0]
        );
        let path = figure(id);
        profile_panels(&path, &title, &panels)?;
        println!("{}", path.display());
    }
    Ok(())
}

/// The rows of one scene split by seed, named `seed <s>`, in order of first appearance; all
/// of them as `simulated` when the table has no seed column or the scene one seed.
fn replica_rows(rows: &[usize], seeds: Option<&[String]>) -> Vec<(String, Vec<usize>)> {
    let mut replicas: Vec<(String, Vec<usize>)> = Vec::new();
    for &row in rows {
        let seed = seeds.map_or("", |s| s[row].as_str());
        match replicas.iter_mut().find(|(s, _)| s == seed) {
            Some((_, rows)) => rows.push(row),
            None => replicas.push((seed.to_string(), vec![row])),
        }
    }
    if replicas.len() == 1 {
        replicas[0].0 = "simulated".into();
    } else {
        for (name, _) in &mut replicas {
            *name = format!("seed {name}");
        }
    }
    replicas
}

/// The scenes of `ids` (one per row) in file order. Each id names an SVG file, so it must
/// follow the safe-name rule; a scene whose rows are not contiguous (two runs of one id, or
/// files concatenated) is refused rather than drawn into one SVG.
fn scene_order<'a>(ids: &'a [String], data: &Dataset) -> anyhow::Result<Vec<&'a str>> {
    let mut scenes: Vec<&str> = Vec::new();
    for (row, id) in ids.iter().enumerate() {
        if scenes.last() == Some(&id.as_str()) {
            continue;
        }
        schema::scene_name::check(id).map_err(|m| {
            anyhow::anyhow!(
                "{}: data row {}, column `scene_id`: {m}",
                data.source_name(),
                row + 1
            )
        })?;
        if scenes.contains(&id.as_str()) {
            anyhow::bail!(
                "{}: data row {}: scene `{id}` appears again after other scenes; \
                 its rows must be together (one run per scene id)",
                data.source_name(),
                row + 1
            );
        }
        scenes.push(id);
    }
    Ok(scenes)
}
