//! Which simulations to run next: candidate scenes ranked by how wide the bands of their
//! solved profiles are (`suspflow propose`), and the top ones written as a grid `generate`
//! runs.
//!
//! Each candidate (one scene of a grid file, its replicas aside) is solved from its forcing
//! with one closure and banded at a level ([`Closures::bands`]); its score is the mean over
//! u, phi_loc and mu of the band's mean width relative to the profile's mean |value|
//! ([`ProfileBands::relative_widths`]). A candidate the closure cannot solve ranks above
//! every banded one: the models cannot say anything there. The written grid sets every field
//! of each chosen scene in its own case, so it runs the very scenes that were ranked.

use rayon::prelude::*;
use serde::Serialize;
use sim::{Grid, GridRun};
use toml::{Table, Value};

use crate::closures::{Bands, ClosureKind, Closures};
use crate::error::{Result, SolverError};
use crate::problem::ProfileProblem;

/// Starting pressure of the candidates' solves (as `suspflow solve`'s).
const START_PRESSURE: f64 = 0.1;

/// How one candidate's solve went.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// Solved and banded: the relative band widths of u, phi_loc and mu, and their mean.
    Banded {
        relative_widths: [f64; 3],
        score: f64,
    },
    /// The closure did not solve it (the reason).
    Stalled(String),
}

/// One candidate scene and how it ranked.
#[derive(Debug, Clone, Serialize)]
pub struct Candidate {
    /// The scene's id in the candidate grid, its forcing, L_y, phi and replica seeds.
    pub id: String,
    pub profile: String,
    pub l_y: f64,
    pub phi: f64,
    pub seeds: Vec<u64>,
    pub outcome: Outcome,
    /// The scene's file (the first replica's), every field set.
    #[serde(skip)]
    file: sim::SceneFile,
}

/// Candidates ranked, widest bands first.
#[derive(Debug, Clone, Serialize)]
pub struct Proposal {
    pub closure: &'static str,
    pub level: f64,
    pub candidates: Vec<Candidate>,
}

impl Proposal {
    /// Solves and bands every scene of `grid` with the closure `kind` at `level`, in
    /// parallel on rayon's pool, and ranks them; the models must carry their bands'
    /// calibration.
    pub fn rank(closures: &Closures, kind: ClosureKind, grid: &Grid, level: f64) -> Result<Self> {
        let mut scenes: Vec<(&GridRun, Vec<u64>)> = Vec::new();
        for run in &grid.runs {
            match scenes.iter_mut().find(|(r, _)| r.id == run.id) {
                Some((_, seeds)) => seeds.push(run.seed()),
                None => scenes.push((run, vec![run.seed()])),
            }
        }
        let mut candidates = scenes
            .par_iter()
            .map(|(run, seeds)| {
                let f = &run.scene.file;
                let outcome = candidate_outcome(closures, kind, &run.scene, level)
                    .map_err(|e| SolverError::InvalidArgument(format!("{}: {e}", run.id)))?;
                Ok(Candidate {
                    id: run.id.clone(),
                    profile: f.fluid.profile.clone(),
                    l_y: f.box_.l_y,
                    phi: f.particles.phi,
                    seeds: seeds.clone(),
                    outcome,
                    file: f.clone(),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let key = |c: &Candidate| match c.outcome {
            Outcome::Stalled(_) => f64::INFINITY,
            Outcome::Banded { score, .. } => score,
        };
        candidates.sort_by(|a, b| key(b).total_cmp(&key(a)));
        Ok(Proposal {
            closure: kind.name(),
            level,
            candidates,
        })
    }

    /// A grid named `name` of the first `top` candidates, one case each setting every field
    /// of its scene (its replicas' seeds as `seed = [...]`), in rank order.
    pub fn grid_toml(&self, name: &str, top: usize) -> Result<String> {
        let mut text = format!(
            "# Proposed by `suspflow propose`: the {} of {} candidates whose {:.0} % bands \
             of the {} closure are widest\n# (mean relative width of u, phi_loc and mu; \
             stalled solves first), widest first.\n",
            top.min(self.candidates.len()),
            self.candidates.len(),
            100.0 * self.level,
            self.closure
        );
        for c in self.candidates.iter().take(top) {
            text += &format!("#   {}: {}\n", c.id, describe(&c.outcome));
        }
        let mut grid = Table::new();
        grid.insert("name".into(), Value::String(name.to_owned()));
        let cases = self
            .candidates
            .iter()
            .take(top)
            .map(|c| case_of(c).map(Value::Table))
            .collect::<Result<Vec<_>>>()?;
        grid.insert("cases".into(), Value::Array(cases));
        let body = toml::to_string(&grid)
            .map_err(|e| SolverError::InvalidArgument(format!("writing the grid: {e}")))?;
        Ok(text + &body)
    }
}

/// A candidate's outcome in a line.
pub fn describe(outcome: &Outcome) -> String {
    match outcome {
        Outcome::Banded {
            relative_widths: w,
            score,
        } => format!(
            "score {:.4} (relative widths u {:.4}, phi_loc {:.4}, mu {:.4})",
            score, w[0], w[1], w[2]
        ),
        Outcome::Stalled(why) => format!("not solved: {why}"),
    }
}

/// Solves and bands one candidate.
fn candidate_outcome(
    closures: &Closures,
    kind: ClosureKind,
    scene: &sim::Scene,
    level: f64,
) -> Result<Outcome> {
    let problem = ProfileProblem::from_scene(scene)?;
    let solution = match problem.solve(closures.get(kind)?, Some(&closures.local), START_PRESSURE) {
        Ok(s) => s,
        Err(e @ (SolverError::NotConverged { .. } | SolverError::ContinuationStalled { .. })) => {
            return Ok(Outcome::Stalled(e.to_string()))
        }
        Err(e) => return Err(e),
    };
    match closures.bands(kind, &problem, &solution, level)? {
        Bands::Calibrated(calibrated) => {
            let widths = calibrated.0.relative_widths(&solution);
            Ok(Outcome::Banded {
                relative_widths: widths,
                score: widths.iter().sum::<f64>() / 3.0,
            })
        }
        Bands::Missing(why) => Err(SolverError::InvalidArgument(format!(
            "no bands to rank by: {why}"
        ))),
    }
}

/// The case of one candidate: every field of its scene file as a dotted key, its name left
/// to the grid and its seeds as a list.
fn case_of(c: &Candidate) -> Result<Table> {
    let table = Table::try_from(&c.file)
        .map_err(|e| SolverError::InvalidArgument(format!("{}: {e}", c.id)))?;
    let mut case = Table::new();
    flatten("", &table, &mut case);
    case.remove("name");
    let seeds = c.seeds.iter().map(|&s| Value::Integer(s as i64)).collect();
    case.insert("seed".into(), Value::Array(seeds));
    Ok(case)
}

/// `table`'s leaves as `prefix.key.key = value` entries of `out`.
fn flatten(prefix: &str, table: &Table, out: &mut Table) {
    for (key, value) in table {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        match value {
            Value::Table(inner) => flatten(&path, inner, out),
            leaf => {
                out.insert(path, leaf.clone());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GRID: &str = r#"
        name = "candidates"
        [scene]
        seed = [4, 5]
        box = { l_x = 10.0, l_z = 10.0 }
        particles = { stokes = 0.09 }
        run = { max_strain = 12.0, window_strain = 1.0 }
        [vary]
        "particles.phi" = [0.5, 0.57]
        [[cases]]
        "fluid.profile" = "0.2*sin(2*pi*y/L)"
        "box.l_y" = 40.0
        [[cases]]
        "fluid.profile" = "0.1*tanh(2*sin(4*pi*y/L))"
        "box.l_y" = 60.0
    "#;

    /// The written grid runs the very scenes that were ranked, with their seeds, in rank order.
    #[test]
    fn the_proposed_grid_reads_back_as_the_chosen_scenes() {
        let grid = Grid::from_toml(GRID, false).unwrap();
        let mut candidates: Vec<Candidate> = Vec::new();
        for run in &grid.runs {
            if let Some(c) = candidates.iter_mut().find(|c| c.id == run.id) {
                c.seeds.push(run.seed());
                continue;
            }
            let f = &run.scene.file;
            candidates.push(Candidate {
                id: run.id.clone(),
                profile: f.fluid.profile.clone(),
                l_y: f.box_.l_y,
                phi: f.particles.phi,
                seeds: vec![run.seed()],
                outcome: Outcome::Banded {
                    relative_widths: [0.1; 3],
                    score: 0.1,
                },
                file: f.clone(),
            });
        }
        assert_eq!(candidates.len(), 4);
        // Rank the last two scenes first.
        candidates.reverse();
        let proposal = Proposal {
            closure: "learned",
            level: 0.9,
            candidates,
        };
        let text = proposal.grid_toml("next", 2).unwrap();
        let back = Grid::from_toml(&text, false).unwrap();
        assert_eq!(back.scene_count(), 2);
        assert_eq!(back.runs.len(), 4);
        for (k, chosen) in proposal.candidates[..2].iter().enumerate() {
            let runs: Vec<&GridRun> = back.runs.iter().filter(|r| r.index == k).collect();
            assert_eq!(
                runs.iter().map(|r| r.seed()).collect::<Vec<_>>(),
                chosen.seeds
            );
            let mut file = runs[0].scene.file.clone();
            file.name = chosen.file.name.clone();
            assert_eq!(
                Table::try_from(&file).unwrap(),
                Table::try_from(&chosen.file).unwrap(),
                "{}",
                chosen.id
            );
        }
        assert!(text.contains("candidates_003: score 0.1000"), "{text}");
    }
}
