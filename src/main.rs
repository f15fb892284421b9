//! `suspflow`: dense-suspension rheology under inhomogeneous flow.
mod cmd_bench;
mod cmd_bench_predict;
mod cmd_compare;
mod cmd_generate;
mod cmd_merge;
mod cmd_plot;
mod cmd_predict;
mod cmd_report;
mod cmd_simulate;
mod cmd_solve;
mod cmd_train;
mod cmd_validate;
mod convergence;
mod convergence_report;
mod dataset_file;
mod descriptor_noise;
mod file_lock;
mod loglog_plot;
mod output_guard;
mod plot;
mod report;
mod scene_work;
mod side_by_side;
mod stability_map;
mod stability_sweep;
mod surrogate_cost;
mod training_overlap;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "suspflow",
    version,
    about = "Dense-suspension rheology under inhomogeneous flow"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene to its steady state and write the binned profile.
    Simulate(cmd_simulate::Args),
    /// Run every scene of a grid (resumably, in parallel) into one dataset.
    Generate(cmd_generate::Args),
    /// Combine datasets of distinct scenes (e.g. the shards of a grid) into one.
    Merge(cmd_merge::Args),
    /// Plot every scene of a dataset along y (u, phi_loc, mu, J, Theta, Delta_v) as SVG.
    Plot(cmd_plot::Args),
    /// Write a report (reports/<name>/report.md): simulation and surrogate error against run time,
    /// side by side, stability on stiff and extreme cases, Theta against Delta_v.
    Report(cmd_report::Args),
    /// Compare two binned profiles: squared z-scores and relative differences per observable.
    Compare(cmd_compare::Args),
    /// Measure particle-steps per second of the force + integration loop.
    Bench(cmd_bench::Args),
    /// Train the surrogate mappings on a dataset.
    Train(cmd_train::Args),
    /// Predict a profile with a trained mapping.
    Predict(cmd_predict::Args),
    /// Predict a scene's steady profile from its forcing alone (momentum balance + closure).
    Solve(cmd_solve::Args),
    /// Measure the trained mappings on unseen flow profiles; write the figures.
    Validate(cmd_validate::Args),
    /// Time loading a model, reading a 50-bin profile and predicting it.
    BenchPredict(cmd_bench_predict::Args),
}

/// Runs `f` on a pool of `threads` threads (0 = all cores).
pub fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> anyhow::Result<T> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()?;
    Ok(pool.install(f))
}

fn main() -> anyhow::Result<()> {
    // XGBoost's OpenMP threads otherwise spin between parallel regions and stall next to
    // busy threads; set before any thread starts (see .cargo/config.toml).
    if std::env::var_os("OMP_WAIT_POLICY").is_none() {
        std::env::set_var("OMP_WAIT_POLICY", "PASSIVE");
    }
    match Cli::parse().command {
        Command::Simulate(args) => cmd_simulate::run(args),
        Command::Generate(args) => cmd_generate::run(args),
        Command::Merge(args) => cmd_merge::run(args),
        Command::Plot(args) => cmd_plot::run(args),
        Command::Report(args) => cmd_report::run(args),
        Command::Compare(args) => cmd_compare::run(args),
        Command::Bench(args) => cmd_bench::run(args),
        Command::Train(args) => cmd_train::run(args),
        Command::Predict(args) => cmd_predict::run(args),
        Command::Solve(args) => cmd_solve::run(args),
        Command::Validate(args) => cmd_validate::run(args),
        Command::BenchPredict(args) => cmd_bench_predict::run(args),
    }
}
