//! `suspflow predict --model DIR/<mapping> --input FILE.csv`: a trained mapping's
//! predictions for every row of a table of its feature columns. The trees are evaluated
//! by `surrogate::Predictor`, which does not load the XGBoost library's model: a profile
//! takes milliseconds end to end (`suspflow bench-predict`). Every row is checked against
//! the model's training domain (`surrogate::training_domain`): the `in_domain` column says
//! whether it lies inside, `domain_distance` how far it is from the nearest training rows in
//! units of the domain's threshold (<= 1 is near enough), and the rows outside are counted.
//! Predictions are clipped into their physical range (`surrogate::physical_range`: 0 <
//! phi_loc < 0.74, mu >= 0), and the clipped values are counted too. Each prediction comes
//! with an interval, `<output>_lower` to `<output>_upper`, at `--level` (90 % by default):
//! conformalised quantile trees calibrated on profile families the model did not see
//! (`surrogate::models::intervals`).
use anyhow::Context;
use std::path::PathBuf;
use std::time::Instant;
use surrogate::{Dataset, PredictionTable, Predictor};

use crate::surrogate_text::errors_by_output;

#[derive(clap::Args)]
pub struct Args {
    /// Model, as `DIR/<mapping>` (reads `DIR/<mapping>.json` and `DIR/<mapping>.meta.json`).
    #[arg(long)]
    model: PathBuf,
    /// Table with the mapping's feature columns (other columns are copied through).
    #[arg(long)]
    input: PathBuf,
    /// Output table; standard output when absent.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Replace an existing `--out`.
    #[arg(long)]
    force: bool,
    /// Level of the intervals `<output>_lower`, `<output>_upper` (a probability in (0, 1)).
    #[arg(long, default_value_t = surrogate::DEFAULT_LEVEL)]
    level: f64,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let started = Instant::now();
    if let Some(out) = &args.out {
        anyhow::ensure!(
            out != &args.input,
            "--out {} is the --input; write the predictions to a new file",
            out.display()
        );
        crate::output_guard::refuse_unless_force(
            out,
            args.force,
            "an earlier table",
            "choose another --out",
        )?;
    }
    let name = args
        .model
        .file_name()
        .and_then(|n| n.to_str())
        .map(|n| n.trim_end_matches(".meta.json").trim_end_matches(".json"))
        .with_context(|| format!("--model {}: expected DIR/<mapping>", args.model.display()))?;
    let dir = args.model.parent().map(PathBuf::from).unwrap_or_default();
    let model = Predictor::load(&dir, name)?;
    let dataset = Dataset::read_csv(&args.input)?;
    let prediction = model.predict_with_intervals(&dataset, args.level)?;
    let domain = model.check_domain(&dataset)?;
    let elapsed = started.elapsed();
    let table = PredictionTable {
        dataset: &dataset,
        outputs: &model.meta().outputs,
        prediction: &prediction,
        domain: &domain,
    };
    let out = table.to_csv()?;
    match &args.out {
        Some(path) => schema::write_atomic(path, out.as_bytes())?,
        None => print!("{out}"),
    }
    eprintln!(
        "{} rows predicted by `{}` in {:.2} ms (load + read + predict + intervals + domain check)",
        dataset.n_rows(),
        name,
        elapsed.as_secs_f64() * 1e3
    );
    match model.intervals() {
        Some(i) => eprintln!(
            "intervals: {:.0} % (columns <output>_lower, <output>_upper) of {}, calibrated on \
             {} folds leaving one of the {} out, which they covered at 90 %: {}",
            100.0 * args.level,
            if prediction.with_target_noise {
                "a target with the table's standard error (<output>_se)"
            } else {
                "the true mean (the table gives no <output>_se)"
            },
            i.calibration.folds,
            i.calibration.held_out,
            errors_by_output(&i.calibration.outputs, &i.calibration.fold_coverage)
        ),
        None => eprintln!(
            "warning: `{name}` was saved without intervals (a training that could not leave \
             rows out to calibrate them): predictions without error bars"
        ),
    }
    if prediction.clipped > 0 {
        eprintln!(
            "warning: {} predicted values of `{name}` left their physical range \
             (0 < phi_loc < {}, mu >= 0) and were clipped to its edge",
            prediction.clipped,
            surrogate::PHI_LOC_MAX
        );
    }
    let outside = domain.iter().filter(|c| !c.inside()).count();
    if outside > 0 {
        let out_of_range = domain.iter().filter(|c| !c.in_range).count();
        eprintln!(
            "warning: {outside} of {} rows lie outside the training domain of `{name}` \
             ({out_of_range} beyond a feature's training range, the others farther from every \
             training simulation than the threshold): their predictions are extrapolations \
             (column in_domain = false)",
            dataset.n_rows()
        );
    }
    Ok(())
}
