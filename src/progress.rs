//! Progress of a run on standard error: a bar on a terminal, and off a terminal (a batch
//! job's log, nohup) a line every [`LINE_PERCENT`] percent of a phase or every
//! [`LINE_EVERY`], whichever comes first.
use indicatif::{ProgressBar, ProgressStyle};
use sim::run::progress::ProgressLines;
use sim::run::Progress;
use std::time::Duration;

/// Percent of a phase between two progress lines off a terminal.
pub const LINE_PERCENT: f64 = 10.0;
/// Longest time between two progress lines off a terminal.
pub const LINE_EVERY: Duration = Duration::from_secs(300);

/// A run's bar (hidden off a terminal).
pub fn bar() -> anyhow::Result<ProgressBar> {
    let bar = ProgressBar::new(1000);
    bar.set_style(ProgressStyle::with_template(
        "{spinner} [{elapsed_precise}] {bar:30} {msg} (ETA {eta})",
    )?);
    Ok(bar)
}

/// The line schedule off a terminal.
pub fn lines() -> ProgressLines {
    ProgressLines::new(LINE_PERCENT, LINE_EVERY)
}

/// Shows `p` on `bar`, or as a line (`label` first) when the bar is hidden and one is due.
pub fn show(bar: &ProgressBar, lines: &mut ProgressLines, p: &Progress, label: &str) {
    if bar.is_hidden() {
        if let Some(line) = lines.line(p) {
            eprintln!("{label}{line}");
        }
        return;
    }
    bar.set_position((1000.0 * p.fraction()) as u64);
    bar.set_message(format!("{label}{}", p.describe()));
}
