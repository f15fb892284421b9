//! Calibrating the bands of solved profiles ([`crate::bands`]) on the training scenes, one
//! profile family left out at a time: each family's scenes are solved from their forcing
//! alone with models, intervals, local law and Theta balance made without that family, and
//! every bin scores `|simulated - solved| / scale` per observable.
//!
//! The fold models take the shipped models' hyper-parameters; their intervals take the
//! scores of the other families' rows from the shipped models' own interval studies
//! ([`IntervalStudy::calibration_without`]), so that no family's rows calibrate its own
//! solve. The coverage of the bands is measured cross-conformally as for the rows: a
//! family's bins get the margin of the other families' scores.

use rayon::prelude::*;
use schema::columns as col;
use sim::{Scene, SceneFile};
use surrogate::{
    family_names, fraction, Dataset, HyperParameters, IntervalStudy, Mapping, Predictor, Samples,
    TrainedModel, DEFAULT_LEVEL, MIN_TUNING_FAMILIES, PROFILE_COLUMN,
};

use crate::bands::{BandCalibration, BandScales, ClosureBands, ProfileBands, BANDED};
use crate::closure::{Closure, ExtremumClosure, LearnedClosure, NonlocalClosure};
use crate::closure_kind::ClosureKind;
use crate::error::{Result, SolverError};
use crate::local_fit::fit_local_rheology;
use crate::problem::ProfileProblem;
use crate::theta_balance::ThetaBalance;

/// Starting pressure of the calibration solves (as `suspflow solve`'s).
const START_PRESSURE: f64 = 0.1;

/// Box edges across the flow (units a) of the scenes rebuilt from the table: the solver reads
/// only the forcing, phi, the bins and the particle sizes, so any box of the training grids'
/// will do.
const BOX_EDGE: f64 = 17.0;

/// A shipped model's mapping, hyper-parameters and interval study.
pub struct ShippedModel<'a> {
    pub mapping: &'static Mapping,
    pub params: &'a HyperParameters,
    pub study: &'a IntervalStudy,
}

/// One solved calibration scene: its family's index and each bin's scores.
struct Scored {
    family: usize,
    scores: [Vec<f64>; 3],
    relative_width_at_one: [f64; 3],
}

/// One closure's scenes over all folds.
#[derive(Default)]
struct ClosureScenes {
    scored: Vec<Scored>,
    failed: usize,
}

/// Solves every family of `train` with the models of the fold that held it out and returns
/// the calibration of every closure's bands; `models` must hold `dv` and `theta` (and `ext`
/// for the extremum closure). `done` is called with each family as its fold finishes; the
/// folds run in parallel on rayon's pool.
pub fn calibrate_bands(
    train: &Dataset,
    models: &[ShippedModel],
    code_version: &str,
    done: &(dyn Fn(&str) + Sync),
) -> Result<BandCalibration> {
    let find = |name: &str| models.iter().find(|m| m.mapping.name == name);
    if find("dv").is_none() || find("theta").is_none() {
        return Err(SolverError::InvalidArgument(
            "the bands' calibration needs the `dv` and `theta` models".to_owned(),
        ));
    }
    let kinds: Vec<ClosureKind> = ClosureKind::ALL
        .into_iter()
        .filter(|k| k.mapping().is_none_or(|m| find(m).is_some()))
        .collect();
    let families = family_names(&Samples::from_dataset(train, find("dv").unwrap().mapping)?)?;
    if families.len() < MIN_TUNING_FAMILIES {
        return Err(SolverError::InvalidArgument(format!(
            "the bands are calibrated leaving one profile family out: {} holds {} famil{}, \
             at least {MIN_TUNING_FAMILIES} are needed",
            train.source_name(),
            families.len(),
            if families.len() == 1 { "y" } else { "ies" }
        )));
    }
    let row_families = train.text(PROFILE_COLUMN)?;
    let per_fold = families
        .par_iter()
        .enumerate()
        .map(|(f, family)| {
            let result = solve_family(train, row_families, family, f, models, &kinds);
            done(family);
            result.map_err(|e| {
                SolverError::InvalidArgument(format!("holding out family `{family}`: {e}"))
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let closures = kinds
        .iter()
        .enumerate()
        .map(|(c, kind)| {
            let mut scenes = ClosureScenes::default();
            for fold in &per_fold {
                scenes.failed += fold[c].failed;
            }
            scenes.scored = per_fold
                .iter()
                .flat_map(|fold| &fold[c].scored)
                .map(|s| Scored {
                    family: s.family,
                    scores: s.scores.clone(),
                    relative_width_at_one: s.relative_width_at_one,
                })
                .collect();
            summarise(kind.name(), &scenes, families.len())
        })
        .collect();
    Ok(BandCalibration {
        training_fnv1a_64: train.fingerprint(),
        models: models
            .iter()
            .map(|m| (m.mapping.name.to_owned(), m.params.clone()))
            .collect(),
        held_out: "profile families".to_owned(),
        folds: families.len(),
        closures,
        code_version: code_version.to_owned(),
    })
}

/// The fold that holds out `family` (index `f`): its models and fits, and the scores of its
/// scenes for each closure of `kinds`, in that order.
fn solve_family(
    train: &Dataset,
    row_families: &[String],
    family: &str,
    f: usize,
    models: &[ShippedModel],
    kinds: &[ClosureKind],
) -> Result<Vec<ClosureScenes>> {
    let (test_rows, train_rows): (Vec<usize>, Vec<usize>) =
        (0..train.n_rows()).partition(|&r| same_family(&row_families[r], family));
    let rest = train.select_rows(&train_rows)?;
    let predictor = |name: &str| -> Result<Option<Predictor>> {
        let Some(m) = models.iter().find(|m| m.mapping.name == name) else {
            return Ok(None);
        };
        let samples = Samples::from_dataset(&rest, m.mapping)?;
        let model = TrainedModel::fit(m.mapping, &samples, m.params)?;
        let trees = model.fit_quantile_trees(&samples, m.params)?;
        let calibration = m.study.calibration_without(family, model.meta())?;
        Ok(Some(Predictor::of(
            &model.with_intervals(trees, calibration)?,
        )?))
    };
    let local = fit_local_rheology(&rest)?;
    let learned = LearnedClosure::new(predictor("dv")?.expect("checked by the caller"))?;
    let nonlocal = NonlocalClosure::new(
        predictor("theta")?.expect("checked by the caller"),
        ThetaBalance::fit(&rest)?.balance,
    )?;
    let extremum = predictor("ext")?.map(ExtremumClosure::new).transpose()?;
    let closure = |kind: ClosureKind| -> &dyn Closure {
        match kind {
            ClosureKind::Learned => &learned,
            ClosureKind::Local => &local,
            ClosureKind::Nonlocal => &nonlocal,
            ClosureKind::Extremum => extremum.as_ref().expect("listed only with its model"),
        }
    };
    let mut out: Vec<ClosureScenes> = kinds.iter().map(|_| ClosureScenes::default()).collect();
    for rows in scenes(train, &test_rows)? {
        let problem = problem_of(train, &rows)?;
        let truth = BANDED
            .iter()
            .map(|o| {
                let c = train.column(o.name())?;
                Ok(rows.iter().map(|&r| c[r]).collect::<Vec<f64>>())
            })
            .collect::<Result<Vec<_>>>()?;
        for (kind, scenes) in kinds.iter().zip(&mut out) {
            let c = closure(*kind);
            let Ok(solution) = problem.solve(c, Some(&local), START_PRESSURE) else {
                scenes.failed += 1;
                continue;
            };
            let scales = problem.band_scales(c, &solution, DEFAULT_LEVEL)?;
            scenes.scored.push(score(&solution, &scales, &truth, f));
        }
    }
    Ok(out)
}

/// Whether two profile texts name one family (they differ at most in whitespace).
fn same_family(a: &str, b: &str) -> bool {
    a.chars()
        .filter(|c| !c.is_whitespace())
        .eq(b.chars().filter(|c| !c.is_whitespace()))
}

/// The rows of `rows` grouped by scene, each group in order of `y`.
fn scenes(data: &Dataset, rows: &[usize]) -> Result<Vec<Vec<usize>>> {
    let ids = data.group_keys()?;
    let y = data.column(col::Y)?;
    let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
    for &r in rows {
        match groups.iter_mut().find(|(id, _)| *id == ids[r]) {
            Some((_, g)) => g.push(r),
            None => groups.push((ids[r].clone(), vec![r])),
        }
    }
    Ok(groups
        .into_iter()
        .map(|(_, mut g)| {
            g.sort_by(|&a, &b| y[a].total_cmp(&y[b]));
            g
        })
        .collect())
}

/// The problem of the scene whose rows (one per bin, in order of y) are `rows`: its forcing,
/// L_y and phi from the table, equal bins filling L_y, the default particles and fluid.
fn problem_of(data: &Dataset, rows: &[usize]) -> Result<ProfileProblem> {
    let first = rows[0];
    let name = &data.group_keys()?[first];
    let profile = &data.text(PROFILE_COLUMN)?[first];
    let (l_y, phi) = (data.column(col::L_Y)?[first], data.column(col::PHI)?[first]);
    let mut file = SceneFile::with_defaults(name, [BOX_EDGE, l_y, BOX_EDGE], phi, profile);
    file.run.bin_width = l_y / rows.len() as f64;
    let scene = Scene::from_file(file, false).map_err(|e| {
        SolverError::InvalidArgument(format!("rebuilding scene `{name}` from its rows: {e}"))
    })?;
    ProfileProblem::from_scene(&scene)
}

/// The scores `|truth - solved| / scale` of every bin where the table defines the truth (an
/// empty cell, mu where the bin's pressure was not positive, has none), and the band widths
/// at a margin of 1.
fn score(
    solution: &crate::solution::ProfileSolution,
    scales: &BandScales,
    truth: &[Vec<f64>],
    family: usize,
) -> Scored {
    let scores = std::array::from_fn(|i| {
        let solved = solution
            .column(BANDED[i])
            .expect("u, phi_loc and mu per bin");
        solved
            .iter()
            .zip(&truth[i])
            .zip(&scales.per_observable[i])
            .filter(|((_, t), _)| t.is_finite())
            .map(|((&s, &t), &scale)| (t - s).abs() / scale.max(f64::MIN_POSITIVE))
            .collect()
    });
    let unit = ProfileBands::new(solution, scales, [1.0; 3], DEFAULT_LEVEL);
    Scored {
        family,
        scores,
        relative_width_at_one: unit.relative_widths(solution),
    }
}

/// One closure's calibration: all scores sorted, and the cross-conformal coverage and
/// relative width at [`DEFAULT_LEVEL`].
fn summarise(name: &str, scenes: &ClosureScenes, n_families: usize) -> ClosureBands {
    let all = |i: usize, keep: &dyn Fn(usize) -> bool| -> Vec<f64> {
        let mut v: Vec<f64> = scenes
            .scored
            .iter()
            .filter(|s| keep(s.family))
            .flat_map(|s| s.scores[i].iter().copied())
            .collect();
        v.sort_by(f64::total_cmp);
        v
    };
    let margins_without: Vec<[f64; 3]> = (0..n_families)
        .map(|f| {
            std::array::from_fn(|i| {
                surrogate::conformal_quantile(&all(i, &|g| g != f), DEFAULT_LEVEL)
            })
        })
        .collect();
    let coverage = std::array::from_fn(|i| {
        fraction(scenes.scored.iter().flat_map(|s| {
            s.scores[i]
                .iter()
                .map(|&x| x <= margins_without[s.family][i])
        }))
    });
    let relative_width = std::array::from_fn(|i| {
        let n = scenes.scored.len().max(1) as f64;
        scenes
            .scored
            .iter()
            .map(|s| s.relative_width_at_one[i] * margins_without[s.family][i])
            .sum::<f64>()
            / n
    });
    ClosureBands {
        closure: name.to_owned(),
        scores: std::array::from_fn(|i| all(i, &|_| true)),
        scenes: scenes.scored.len() + scenes.failed,
        failed: scenes.failed,
        fold_coverage: coverage,
        fold_relative_width: relative_width,
    }
}
