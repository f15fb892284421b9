//! `suspflow predict --model DIR/<mapping> --input FILE.csv`: a trained mapping's
//! predictions for every row of a table of its feature columns. The trees are evaluated
//! by `surrogate::Predictor`, which does not load the XGBoost library's model: a profile
//! takes milliseconds end to end (`suspflow bench-predict`). Every row is checked against
//! the model's training domain (`surrogate::training_domain`): the `in_domain` column says
//! whether it lies inside, `domain_distance` how far it is from the nearest training rows in
//! units of the domain's threshold (<= 1 is near enough), and the rows outside are counted.
use anyhow::Context;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;
use surrogate::{Dataset, Predictor};

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
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let started = Instant::now();
    let name = args
        .model
        .file_name()
        .and_then(|n| n.to_str())
        .map(|n| n.trim_end_matches(".meta.json").trim_end_matches(".json"))
        .with_context(|| format!("--model {}: expected DIR/<mapping>", args.model.display()))?;
    let dir = args.model.parent().map(PathBuf::from).unwrap_or_default();
    let model = Predictor::load(&dir, name)?;
    let dataset = Dataset::read_csv(&args.input)?;
    let predicted = model.predict(&dataset)?;
    let domain = model.check_domain(&dataset)?;
    let elapsed = started.elapsed();
    let meta = model.meta();
    let mut out = String::new();
    let mut header: Vec<String> = meta.features.clone();
    header.extend(meta.outputs.iter().map(|o| format!("{o}_pred")));
    header.extend(["in_domain".to_owned(), "domain_distance".to_owned()]);
    let _ = writeln!(out, "{}", header.join(","));
    let names: Vec<&str> = meta.features.iter().map(String::as_str).collect();
    let features = dataset.matrix(&names)?;
    for ((row, pred), check) in features
        .rows()
        .into_iter()
        .zip(predicted.rows())
        .zip(&domain)
    {
        let mut cells: Vec<String> = row
            .iter()
            .chain(pred.iter())
            .map(|x| format!("{x:e}"))
            .collect();
        cells.push(check.inside().to_string());
        cells.push(format!("{:e}", check.distance));
        let _ = writeln!(out, "{}", cells.join(","));
    }
    match &args.out {
        Some(path) => {
            std::fs::write(path, out).with_context(|| format!("writing {}", path.display()))?
        }
        None => print!("{out}"),
    }
    eprintln!(
        "{} rows predicted by `{}` in {:.2} ms (load + read + predict + domain check)",
        dataset.n_rows(),
        name,
        elapsed.as_secs_f64() * 1e3
    );
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
