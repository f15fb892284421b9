//! Ctrl-C, SIGTERM (what a batch scheduler sends at its time limit) and SIGHUP: one flag
//! for the process, which the runs look at every few hundred steps; they stop with their
//! checkpoint saved.
use anyhow::Context;
use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The flag the runs of this process look at.
pub fn flag() -> &'static AtomicBool {
    &INTERRUPTED
}

/// Sets the flag on Ctrl-C, SIGTERM and SIGHUP.
pub fn install() -> anyhow::Result<()> {
    ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst))
        .context("installing the Ctrl-C handler")
}
