//! `suspflow`: dense-suspension rheology under inhomogeneous flow. The command line only:
//! each command lives in `suspflow::commands`.
use suspflow::commands;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "suspflow",
    version = suspflow::CODE_VERSION,
    about = "Dense-suspension rheology under inhomogeneous flow"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene to its steady state and write the binned profile.
    Simulate(commands::simulate::Args),
    /// Run every scene of a grid (resumably, in parallel) into one dataset.
    Generate(commands::generate::Args),
    /// Flow curves of a homogeneous-shear grid run by `generate`: fit of phi_J and lambda,
    /// figures, and the local-versus-homogeneous viscosity.
    FlowCurves(commands::flow_curves::Args),
    /// Green-Kubo Brownian viscosity of an unsheared Brownian scene.
    GreenKubo(commands::green_kubo::Args),
    /// Combine datasets of distinct scenes (e.g. the shards of a grid) into one.
    Merge(commands::merge::Args),
    /// Plot every scene of a dataset along y (u, phi_loc, mu, J, Theta, Delta_v) as SVG.
    Plot(commands::plot::Args),
    /// Write a report (reports/<name>/report.md): simulation and surrogate error against run time,
    /// side by side, stability on stiff and extreme cases, Theta against Delta_v.
    Report(commands::report::Args),
    /// Compare two binned profiles: squared z-scores and relative differences per observable.
    Compare(commands::compare::Args),
    /// The effect of each observable convention on finished runs, from their snapshot sums.
    Conventions(commands::conventions::Args),
    /// Draw the datasets' rows in the (J, phi_loc) and (J, Theta) planes; tabulate column ranges.
    Coverage(commands::coverage::Args),
    /// Measure particle-steps per second of the force + integration loop.
    Bench(commands::bench::Args),
    /// Train the surrogate mappings on a dataset.
    Train(commands::train::Args),
    /// Predict a profile with a trained mapping.
    Predict(commands::predict::Args),
    /// Predict a scene's steady profile from its forcing alone (momentum balance + closure).
    Solve(commands::solve::Args),
    /// Rank candidate scenes by the width of their solved profiles' bands; write the widest as a grid.
    Propose(commands::propose::Args),
    /// Compare XGBoost, the physics backbone and both, leaving one profile family out at a time.
    CrossValidate(commands::cross_validate::Args),
    /// Measure the trained mappings on unseen flow profiles; write the figures.
    Validate(commands::validate::Args),
    /// Time loading a model, reading a 50-bin profile and predicting it.
    BenchPredict(commands::bench_predict::Args),
}

/// Runs the command; its error is printed and told by the exit status
/// (`suspflow::exit_status`: bad input, runs failed, interrupted).
fn main() -> std::process::ExitCode {
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // The message and its causes only: `{e:?}` would add a stack backtrace wherever
            // RUST_BACKTRACE is set, and an error here is the user's input, not a bug.
            eprintln!("Error: {e}");
            for cause in e.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            std::process::ExitCode::from(suspflow::exit_status::of(&e))
        }
    }
}

fn run() -> anyhow::Result<()> {
    // XGBoost's OpenMP threads otherwise spin between parallel regions and stall next to
    // busy threads; set before any thread starts (see .cargo/config.toml).
    if std::env::var_os("OMP_WAIT_POLICY").is_none() {
        std::env::set_var("OMP_WAIT_POLICY", "PASSIVE");
    }
    match Cli::parse().command {
        Command::Simulate(args) => commands::simulate::run(args),
        Command::Generate(args) => commands::generate::run(args),
        Command::FlowCurves(args) => commands::flow_curves::run(args),
        Command::GreenKubo(args) => commands::green_kubo::run(args),
        Command::Merge(args) => commands::merge::run(args),
        Command::Plot(args) => commands::plot::run(args),
        Command::Report(args) => commands::report::run(args),
        Command::Compare(args) => commands::compare::run(args),
        Command::Conventions(args) => commands::conventions::run(args),
        Command::Coverage(args) => commands::coverage::run(args),
        Command::Bench(args) => commands::bench::run(args),
        Command::Train(args) => commands::train::run(args),
        Command::Predict(args) => commands::predict::run(args),
        Command::Solve(args) => commands::solve::run(args),
        Command::Propose(args) => commands::propose::run(args),
        Command::CrossValidate(args) => commands::cross_validate::run(args),
        Command::Validate(args) => commands::validate::run(args),
        Command::BenchPredict(args) => commands::bench_predict::run(args),
    }
}
