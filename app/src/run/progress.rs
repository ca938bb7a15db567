//! The progress event on stderr: an indicatif bar on a terminal, else a line per tenth of
//! the run; and the reporter that makes it with the run's lines (`lines.rs`).

use std::io::IsTerminal;

use super::context::{Ctx, RunFailure};
use super::event::Event;
use super::lines::Lines;
use super::Progress;

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
