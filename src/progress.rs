//! Progress of a run, or of a batch of runs, on standard error: bars on a terminal, and off a terminal (a batch
//! job's log, nohup) a line every few percent of a phase or minutes
//! ([`ProgressLines::for_logs`]).
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use sim::input::grid::GridRun;
use sim::output::run_summary::RunOutcome;
use sim::run::batch::BatchWatch;
use sim::run::progress::ProgressLines;
use sim::run::run_folder::Ended;
use sim::run::Progress;
use std::sync::Mutex;

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
    ProgressLines::for_logs()
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

/// The bars of a batch on a terminal (an overall one, one per worker), and off a terminal
/// its lines: each run's start and end, and its progress every few percent or minutes.
pub struct BatchBars {
    multi: MultiProgress,
    /// Counts the runs done.
    pub overall: ProgressBar,
    workers: Vec<ProgressBar>,
    lines: Vec<Mutex<ProgressLines>>,
}

impl BatchBars {
    /// Bars for `runs` runs on `jobs` workers.
    pub fn new(runs: usize, jobs: usize) -> anyhow::Result<BatchBars> {
        let multi = MultiProgress::new();
        let overall = multi.add(ProgressBar::new(runs as u64));
        overall.set_style(ProgressStyle::with_template(
            "[{elapsed_precise}] {bar:30} {pos}/{len} runs {msg}",
        )?);
        let workers = (0..jobs)
            .map(|_| {
                let bar = multi.add(ProgressBar::new(1000));
                bar.set_style(ProgressStyle::with_template("  {msg}").expect("static template"));
                bar
            })
            .collect();
        Ok(BatchBars {
            multi,
            overall,
            workers,
            lines: (0..jobs).map(|_| Mutex::new(lines())).collect(),
        })
    }

    fn log(&self, line: String) {
        if self.multi.is_hidden() {
            eprintln!("{line}");
        } else {
            let _ = self.multi.println(line);
        }
    }

    /// Clears the bars.
    pub fn finish(&self) {
        for bar in &self.workers {
            bar.finish_and_clear();
        }
        self.overall.finish_and_clear();
    }
}

impl BatchWatch for BatchBars {
    fn started(&self, worker: usize, gs: &GridRun, resuming: bool) {
        if let Ok(mut schedule) = self.lines[worker].lock() {
            *schedule = lines();
        }
        self.log(format!(
            "{} start{}: N = {}, L_y = {}, phi = {}, `{}`",
            gs.label(),
            if resuming { " (resuming)" } else { "" },
            gs.scene.n_particles(),
            gs.scene.box_len[1],
            gs.scene.file.particles.phi,
            gs.scene.profile.expr()
        ));
    }

    fn progress(&self, worker: usize, gs: &GridRun, p: &Progress) {
        let label = format!("{}: ", gs.label());
        if let Ok(mut lines) = self.lines[worker].lock() {
            crate::progress::show(&self.workers[worker], &mut lines, p, &label);
        }
    }

    fn ended(&self, gs: &GridRun, ended: &Ended<RunOutcome>, seconds: f64) {
        let label = gs.label();
        self.log(match ended {
            Ended::Finished(outcome) => {
                let s = &outcome.summary;
                format!(
                    "{label} done in {seconds:.0} s: steady at strain {:.2}, momentum residual {:.4}",
                    s.strain_to_steady,
                    s.momentum_residual.unwrap_or(f64::NAN)
                )
            }
            Ended::Interrupted { step } => format!(
                "{label} interrupted at step {step}; checkpoint saved (the same command resumes it)"
            ),
            Ended::InterruptedPacking => format!(
                "{label} interrupted during its initial packing; nothing to save (the same \
                 command starts it again from its seed)"
            ),
            Ended::Failed(reason) => format!("{label} FAILED: {reason}"),
        });
    }
}
