//! `suspflow predict --model DIR/<mapping> --input FILE.csv`: a trained mapping's
//! predictions for every row of a table of its feature columns. The trees are evaluated
//! by `surrogate::Predictor`, which does not load the XGBoost library's model: a profile
//! takes milliseconds end to end (`suspflow bench-predict`). Every row is checked against
//! the model's training domain (`surrogate::training_domain`): the `in_domain` column says
//! whether it lies inside, `domain_distance` how far it is from the nearest training rows in
//! units of the domain's threshold (<= 1 is near enough), and the rows outside are counted.
//! Predictions are clipped into their physical range (`surrogate::physical_range`: 0 <
//! phi_loc < 0.74, mu >= 0), and the clipped values are counted too.
use anyhow::{bail, Context};
use schema::columns as col;
use std::path::PathBuf;
use std::time::Instant;
use surrogate::{Dataset, DomainCheck, Predictor};

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
    let (predicted, clipped) = model.predict_counting_clips(&dataset)?;
    let domain = model.check_domain(&dataset)?;
    let elapsed = started.elapsed();
    let predicted: Vec<Vec<f64>> = predicted.rows().into_iter().map(|r| r.to_vec()).collect();
    let out = with_predictions(&dataset, &model.meta().outputs, &predicted, &domain)?;
    match &args.out {
        Some(path) => schema::write_atomic(path, out.as_bytes())?,
        None => print!("{out}"),
    }
    eprintln!(
        "{} rows predicted by `{}` in {:.2} ms (load + read + predict + domain check)",
        dataset.n_rows(),
        name,
        elapsed.as_secs_f64() * 1e3
    );
    if clipped > 0 {
        eprintln!(
            "warning: {clipped} predicted values of `{name}` left their physical range \
             (0 < phi_loc < {}, mu >= 0) and were clipped to its edge",
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

/// The input table, every column as read, followed by one column `<output>_pred` per output
/// and the training-domain columns `in_domain`, `domain_distance` (CSV quoted where a cell
/// needs it).
fn with_predictions(
    dataset: &Dataset,
    outputs: &[String],
    predicted: &[Vec<f64>],
    domain: &[DomainCheck],
) -> anyhow::Result<String> {
    let names = dataset.column_names();
    let added: Vec<String> = outputs
        .iter()
        .map(|o| format!("{o}{}", col::PREDICTED_SUFFIX))
        .chain([col::IN_DOMAIN.to_owned(), col::DOMAIN_DISTANCE.to_owned()])
        .collect();
    if let Some(taken) = added.iter().find(|a| names.contains(a)) {
        bail!(
            "{} already has a column `{taken}` (the output of an earlier predict?): the \
             predictions would repeat its name; give the table without it",
            dataset.source_name()
        );
    }
    let columns = names
        .iter()
        .map(|n| dataset.text(n))
        .collect::<Result<Vec<_>, _>>()?;
    let mut writer = csv::Writer::from_writer(Vec::new());
    let header = names.iter().chain(&added);
    writer.write_record(header)?;
    for (row, (pred, check)) in predicted.iter().zip(domain).enumerate() {
        let cells = columns
            .iter()
            .map(|c| c[row].clone())
            .chain(pred.iter().map(|x| format!("{x:e}")))
            .chain([check.inside().to_string(), format!("{:e}", check.distance)]);
        writer.write_record(cells)?;
    }
    Ok(String::from_utf8(writer.into_inner()?)?)
}
