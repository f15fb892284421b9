//! `suspflow train --data FILE.csv --out DIR`: fits the surrogate mappings of SPEC
//! section 8 and saves each as XGBoost JSON plus a sidecar.
use anyhow::Context;
use std::path::PathBuf;
use std::time::Instant;
use surrogate::{Dataset, HyperParameters, Mapping, Samples, TrainedModel, MAPPINGS};

#[derive(clap::Args)]
pub struct Args {
    /// Training table (one row per bin per simulation, SPEC section 8 columns).
    #[arg(long)]
    data: PathBuf,
    /// Directory for `<mapping>.json` and `<mapping>.meta.json`.
    #[arg(long, default_value = "models")]
    out: PathBuf,
    /// Mappings to train (mu, theta, dv); all three when absent.
    #[arg(long = "mapping")]
    mappings: Vec<String>,
}

pub fn run(args: Args) -> anyhow::Result<()> {
    let dataset = Dataset::read_csv(&args.data)?;
    let mappings: Vec<&Mapping> = if args.mappings.is_empty() {
        MAPPINGS.iter().collect()
    } else {
        args.mappings.iter().map(|m| Mapping::by_name(m)).collect::<Result<_, _>>()?
    };
    let params = HyperParameters::default();
    let started = Instant::now();
    for mapping in mappings {
        let t = Instant::now();
        let model = TrainedModel::train(mapping, &dataset, &params)?;
        let train_s = t.elapsed().as_secs_f64();
        model.save(&args.out).with_context(|| format!("saving the {} model", mapping.name))?;
        let fit = model.evaluate(&Samples::from_dataset(&dataset, mapping)?)?;
        let errors: Vec<String> =
            mapping.outputs.iter().zip(&fit).map(|(o, e)| format!("{o} {:.2} %", 100.0 * e)).collect();
        println!(
            "{}: ({}) -> ({}), {} rows, trained in {:.3} s; training-set relative L2 error {}",
            mapping.name,
            mapping.features.join(", "),
            mapping.outputs.join(", "),
            dataset.n_rows(),
            train_s,
            errors.join(", ")
        );
    }
    println!("models in {} ({:.3} s in all)", args.out.display(), started.elapsed().as_secs_f64());
    Ok(())
}
