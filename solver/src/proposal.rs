//! Which simulations to run next: candidate scenes ranked by how wide the bands of their
//! solved profiles are (`suspflow propose`), and the top ones written as a grid `generate`
//! runs.
//!
//! Each candidate (one scene of a grid file, its replicas aside) is solved from its forcing
//! with one closure and banded at a level ([`Closures::bands`]); its score is the mean over
//! u, phi_loc and mu of the band's mean width relative to the profile's mean |value|
//! ([`crate::bands::ProfileBands::relative_widths`]). A candidate the closure cannot solve
//! ranks above every banded one: the models cannot say anything there.
//!
//! The batch to simulate is not simply the widest few: candidates whose solved states lie
//! together (the same phi, neighbouring (J, Delta_v)) are narrowed by the same new data, so
//! a batch of them buys one candidate's worth of information several times (measured:
//! reports/proposal/README.md, where the four widest, all at one phi, narrowed the bands no
//! more than four random candidates). A simulated scene informs the states near its own, so
//! the batch is chosen greedily to cover the widest bands of *all* candidates
//! ([`Proposal::batch`]): a bin of candidate `c` is covered by candidate `k` when `k`'s
//! solved profile has a bin of the same phi within the closure's training-domain threshold
//! (the distance at which a training simulation's bins lie from the nearest other
//! simulation's, [`surrogate::TrainingDomain`]); each pick adds the most uncovered band, each
//! bin of `c` weighted by `c`'s score over its bins (a coverage objective, submodular, so the
//! greedy batch is within `1 - 1/e` of the best). Stalled candidates come first.
//!
//! The written grid sets every field of each chosen scene in its own case, so it runs the
//! very scenes that were ranked.

use rayon::prelude::*;
use serde::Serialize;
use sim::{Grid, GridRun};
use toml::{Table, Value};

use crate::closure_kind::ClosureKind;
use crate::closures::{Bands, Closures};
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
    /// Each bin of the solved profile in the closure's training-domain coordinates (empty
    /// for a stalled solve).
    #[serde(skip)]
    states: Vec<Vec<f64>>,
}

/// Candidates ranked, widest bands first.
#[derive(Debug, Clone, Serialize)]
pub struct Proposal {
    pub closure: &'static str,
    pub level: f64,
    pub candidates: Vec<Candidate>,
    /// The closure's training-domain threshold: states closer than it inform each other.
    pub threshold: f64,
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
        let solved = scenes
            .par_iter()
            .map(|(run, seeds)| {
                let f = &run.scene.file;
                let (outcome, states) = candidate_outcome(closures, kind, &run.scene, level)
                    .map_err(|e| SolverError::InvalidArgument(format!("{}: {e}", run.id)))?;
                let candidate = Candidate {
                    id: run.id.clone(),
                    profile: f.fluid.profile.clone(),
                    l_y: f.box_.l_y,
                    phi: f.particles.phi,
                    seeds: seeds.clone(),
                    outcome,
                    file: f.clone(),
                    states: states.as_ref().map_or_else(Vec::new, |s| s.0.clone()),
                };
                Ok((candidate, states.map(|s| s.1)))
            })
            .collect::<Result<Vec<_>>>()?;
        let threshold = solved.iter().find_map(|(_, t)| *t).unwrap_or(0.0);
        let mut candidates: Vec<Candidate> = solved.into_iter().map(|(c, _)| c).collect();
        let key = |c: &Candidate| match c.outcome {
            Outcome::Stalled(_) => f64::INFINITY,
            Outcome::Banded { score, .. } => score,
        };
        candidates.sort_by(|a, b| key(b).total_cmp(&key(a)));
        Ok(Proposal {
            closure: kind.name(),
            level,
            candidates,
            threshold,
        })
    }

    /// The indices (into `candidates`) of a batch of `top`, in the order picked: the stalled
    /// candidates first, then greedily the candidate that covers the most not yet covered
    /// band of all candidates (module doc; ties go to the higher ranked).
    pub fn batch(&self, top: usize) -> Vec<usize> {
        let n = self.candidates.len();
        let mut picked: Vec<usize> = (0..n)
            .filter(|&k| matches!(self.candidates[k].outcome, Outcome::Stalled(_)))
            .take(top)
            .collect();
        // covers[k][c][b]: whether candidate k's states cover bin b of candidate c.
        let covers: Vec<Vec<Vec<bool>>> = (0..n)
            .map(|k| (0..n).map(|c| self.covered_bins(k, c)).collect())
            .collect();
        let weight: Vec<f64> = self
            .candidates
            .iter()
            .map(|c| match c.outcome {
                Outcome::Banded { score, .. } if !c.states.is_empty() => {
                    score / c.states.len() as f64
                }
                _ => 0.0,
            })
            .collect();
        let mut covered: Vec<Vec<bool>> = self
            .candidates
            .iter()
            .map(|c| vec![false; c.states.len()])
            .collect();
        for &k in &picked {
            mark(&mut covered, &covers[k]);
        }
        while picked.len() < top.min(n) {
            let gain = |k: usize| -> f64 {
                (0..n)
                    .map(|c| {
                        let newly = covers[k][c]
                            .iter()
                            .zip(&covered[c])
                            .filter(|(&by_k, &already)| by_k && !already)
                            .count();
                        weight[c] * newly as f64
                    })
                    .sum()
            };
            let best = (0..n)
                .filter(|k| !picked.contains(k))
                .map(|k| (k, gain(k)))
                // Ranked order breaks ties: the first of equal gains wins.
                .fold(None, |best: Option<(usize, f64)>, (k, g)| match best {
                    Some((_, bg)) if bg >= g => best,
                    _ => Some((k, g)),
                });
            let Some((k, _)) = best else { break };
            mark(&mut covered, &covers[k]);
            picked.push(k);
        }
        picked
    }

    /// Which bins of candidate `c` a simulation of candidate `k` informs: those with a bin of
    /// `k` at the same phi within the threshold.
    fn covered_bins(&self, k: usize, c: usize) -> Vec<bool> {
        let (ck, cc) = (&self.candidates[k], &self.candidates[c]);
        if ck.phi != cc.phi {
            return vec![false; cc.states.len()];
        }
        let r2 = self.threshold * self.threshold;
        cc.states
            .iter()
            .map(|b| {
                ck.states
                    .iter()
                    .any(|q| b.iter().zip(q).map(|(x, y)| (x - y) * (x - y)).sum::<f64>() <= r2)
            })
            .collect()
    }

    /// A grid named `name` of the candidates `batch` (indices, [`Proposal::batch`]), one
    /// case each setting every field of its scene (its replicas' seeds as `seed = [...]`),
    /// in that order.
    pub fn grid_toml(&self, name: &str, batch: &[usize]) -> Result<String> {
        let mut text = format!(
            "# Proposed by `suspflow propose`: {} of {} candidates, picked one by one to \
             cover the widest\n# {:.0} % bands of the {} closure over all candidates (mean \
             relative width of u, phi_loc\n# and mu; stalled solves first), in the order \
             picked.\n",
            batch.len(),
            self.candidates.len(),
            100.0 * self.level,
            self.closure
        );
        for &k in batch {
            let c = &self.candidates[k];
            text += &format!("#   {}: {}\n", c.id, describe(&c.outcome));
        }
        let mut grid = Table::new();
        grid.insert("name".into(), Value::String(name.to_owned()));
        let cases = batch
            .iter()
            .map(|&k| case_of(&self.candidates[k]).map(Value::Table))
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

/// A solved candidate's bins in the closure's training-domain coordinates, and that
/// domain's threshold.
type States = (Vec<Vec<f64>>, f64);

/// Marks as covered the bins `by` covers, candidate by candidate.
fn mark(covered: &mut [Vec<bool>], by: &[Vec<bool>]) {
    for (c, b) in covered.iter_mut().zip(by) {
        for (x, &y) in c.iter_mut().zip(b) {
            *x |= y;
        }
    }
}

/// Solves and bands one candidate; when banded, its bins in the closure's training-domain
/// coordinates and that domain's threshold.
fn candidate_outcome(
    closures: &Closures,
    kind: ClosureKind,
    scene: &sim::Scene,
    level: f64,
) -> Result<(Outcome, Option<States>)> {
    let problem = ProfileProblem::from_scene(scene)?;
    let solution = match problem.solve(closures.get(kind)?, Some(&closures.local), START_PRESSURE) {
        Ok(s) => s,
        Err(e @ (SolverError::NotConverged { .. } | SolverError::ContinuationStalled { .. })) => {
            return Ok((Outcome::Stalled(e.to_string()), None))
        }
        Err(e) => return Err(e),
    };
    match closures.bands(kind, &problem, &solution, level)? {
        Bands::Calibrated(calibrated) => {
            let widths = calibrated.0.relative_widths(&solution);
            let states = closures.domain_coordinates(kind, problem.phi, &solution)?;
            Ok((
                Outcome::Banded {
                    relative_widths: widths,
                    score: widths.iter().sum::<f64>() / 3.0,
                },
                Some(states),
            ))
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
                states: Vec::new(),
            });
        }
        assert_eq!(candidates.len(), 4);
        // Rank the last two scenes first.
        candidates.reverse();
        let proposal = Proposal {
            closure: "learned",
            level: 0.9,
            candidates,
            threshold: 0.1,
        };
        let text = proposal.grid_toml("next", &[0, 1]).unwrap();
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

    /// Candidates of the grid with the given phi, score and bins (one coordinate each).
    fn banded(specs: &[(f64, f64, &[f64])]) -> Vec<Candidate> {
        let grid = Grid::from_toml(GRID, false).unwrap();
        let file = grid.runs[0].scene.file.clone();
        specs
            .iter()
            .enumerate()
            .map(|(k, &(phi, score, bins))| Candidate {
                id: format!("c{k}"),
                profile: String::new(),
                l_y: 40.0,
                phi,
                seeds: vec![1],
                outcome: Outcome::Banded {
                    relative_widths: [score; 3],
                    score,
                },
                file: file.clone(),
                states: bins.iter().map(|&x| vec![x]).collect(),
            })
            .collect()
    }

    /// A batch covers different states: a near copy of the widest candidate adds nothing
    /// once it is picked, so the next pick is where uncovered bands remain.
    #[test]
    fn the_batch_skips_candidates_whose_states_the_picked_ones_cover() {
        let candidates = banded(&[
            // c0, c1: the widest two, at one phi and the same states.
            (0.57, 0.5, &[0.0, 0.05, 0.1]),
            (0.57, 0.45, &[0.0, 0.05, 0.12]),
            // c2: other states at that phi; c3: the same states at another phi.
            (0.57, 0.3, &[0.5, 0.55, 0.6]),
            (0.5, 0.2, &[0.0, 0.05, 0.1]),
        ]);
        let proposal = Proposal {
            closure: "learned",
            level: 0.9,
            candidates,
            threshold: 0.03,
        };
        // Own width alone would pick c0, c1, c2.
        assert_eq!(proposal.batch(3), vec![0, 2, 3]);
        // c0 and c1 cover each other's bins (0.12 lies 0.02 from 0.1): a tie of 0.95 that
        // the higher ranked c0 wins.
        assert_eq!(proposal.batch(1), vec![0]);
        // A stalled candidate comes first.
        let mut stalled = proposal.clone();
        stalled.candidates[3].outcome = Outcome::Stalled("no".to_owned());
        stalled.candidates[3].states.clear();
        assert_eq!(stalled.batch(2), vec![3, 0]);
    }
}
