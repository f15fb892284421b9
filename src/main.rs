//! `suspflow`: dense-suspension rheology under inhomogeneous flow.
mod cmd_bench;
mod cmd_simulate;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "suspflow", version, about = "Dense-suspension rheology under inhomogeneous flow")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene to its steady state and write the binned profile.
    Simulate(cmd_simulate::Args),
    /// Measure particle-steps per second of the force + integration loop.
    Bench(cmd_bench::Args),
}

/// Runs `f` on a pool of `threads` threads (0 = all cores).
pub fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> anyhow::Result<T> {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
    Ok(pool.install(f))
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Simulate(args) => cmd_simulate::run(args),
        Command::Bench(args) => cmd_bench::run(args),
    }
}
