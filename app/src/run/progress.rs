//! Progress on stderr: the lines of a run (its start, gates opened, slow outputs, its end)
//! and the progress event, an indicatif bar on a terminal, else a line per tenth of the run.

use std::io::IsTerminal;

use super::context::{Ctx, RunFailure};
use super::events::Event;
use super::Progress;
use crate::output::{RunStatus, RunSummary};

/// The run's lines on stderr: above the bar where there is one, else plain, or none.
#[derive(Clone)]
pub(super) struct Lines {
    bar: Option<indicatif::ProgressBar>,
    plain: bool,
}

/// The progress event: fires after every batch, bounds none.
pub(super) struct ProgressReport {
    bar: Option<indicatif::ProgressBar>,
    plain: bool,
    t_end: f64,
    max_steps: Option<u64>,
    next_tenth: u32,
}

/// The lines and the progress event of a run to `t_end` [T] (or `max_steps`), in `mode`.
pub(super) fn reporter(
    mode: Progress,
    t_end: f64,
    max_steps: Option<u64>,
) -> (Lines, ProgressReport) {
    let terminal = std::io::stderr().is_terminal();
    let (bar, plain) = match mode {
        Progress::Quiet => (None, false),
        Progress::Lines => (None, true),
        Progress::Auto if terminal => {
            let bar = indicatif::ProgressBar::new(1000);
            bar.set_style(
                indicatif::ProgressStyle::with_template(
                    "{elapsed_precise} [{bar:40}] {percent:>3}% eta {eta} {msg}",
                )
                .expect("progress template")
                .progress_chars("=> "),
            );
            (Some(bar), false)
        }
        Progress::Auto => (None, true),
    };
    let lines = Lines {
        bar: bar.clone(),
        plain,
    };
    let report = ProgressReport {
        bar,
        plain,
        t_end,
        max_steps,
        next_tenth: 1,
    };
    (lines, report)
}

impl Lines {
    pub fn line(&self, text: &str) {
        if let Some(bar) = &self.bar {
            bar.println(text);
        } else if self.plain {
            crate::errln!("{text}");
        }
    }

    /// The bar cleared, and the run's last lines: how it ended, its timing split, its
    /// monitors' statistics.
    pub fn finish(&self, s: &RunSummary) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        let status = match s.status {
            RunStatus::Completed => "completed".to_string(),
            RunStatus::Failed => "FAILED".to_string(),
            RunStatus::Interrupted => format!(
                "INTERRUPTED ({})",
                s.interrupted_by.as_deref().unwrap_or("signal")
            ),
            RunStatus::Running => "running".to_string(),
        };
        let t = &s.timing;
        self.line(&format!(
            "{status}: {} steps to t = {:.4} in {:.2} s ({:.3e} particle-steps/s); set-up {:.2} s, \
             stepping {:.2} s, waiting for output {:.2} s (writer busy {:.2} s alongside); {} outputs, \
             {:.1} MB in {}",
            s.steps,
            s.simulated_time,
            s.wall_seconds,
            s.particle_steps_per_second,
            t.setup_seconds,
            t.stepping_seconds,
            t.output_wait_seconds,
            t.writer_seconds,
            s.outputs,
            s.output_bytes as f64 / 1e6,
            s.output_dir
        ));
        for m in &s.monitors {
            self.line(&m.to_string());
        }
    }
}

impl Event for ProgressReport {
    fn next_time(&self) -> Option<f64> {
        None
    }

    /// After every batch.
    fn due(&self, _ctx: &mut Ctx) -> bool {
        true
    }

    /// The bar's position (the larger of the time's and the steps' share of the run), or a
    /// line at each tenth, with the last output's diagnostics.
    fn fire(&mut self, ctx: &mut Ctx) -> Result<(), RunFailure> {
        let (t, steps, d) = (ctx.solver.time(), ctx.steps_taken(), &ctx.last);
        // Shown: the run's step count, a resumed run's counted from its start as its last
        // line counts them (the share of `--steps` counts this part's).
        let step = ctx.solver.steps();
        let mut frac = t / self.t_end;
        if let Some(n) = self.max_steps {
            frac = frac.max(steps as f64 / n.max(1) as f64);
        }
        let frac = frac.clamp(0.0, 1.0);
        if let Some(bar) = &self.bar {
            bar.set_position((frac * 1000.0) as u64);
            if steps.is_multiple_of(10) {
                bar.set_message(format!(
                    "t = {t:.4} step {step} max|v| = {:.3}",
                    d.max_speed
                ));
            }
        } else if self.plain && frac * 10.0 >= self.next_tenth as f64 {
            while frac * 10.0 >= self.next_tenth as f64 {
                self.next_tenth += 1;
            }
            crate::errln!(
                "  {:>3.0}%  t = {t:.4}  step {step}  (at last output: max|v| = {:.4}, density error = {:.4})",
                frac * 100.0,
                d.max_speed,
                d.density_error
            );
        }
        Ok(())
    }
}
