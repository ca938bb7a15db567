//! The run's lines on stderr (its start, gates opened, slow outputs, its end): above the
//! progress bar where there is one (`progress.rs`), else plain, or none; written through
//! `errln!`, so a closed or hung-up stderr never stops a run.

use crate::output::{RunStatus, RunSummary};

/// The run's lines on stderr: above the bar where there is one, else plain, or none.
#[derive(Clone)]
pub(super) struct Lines {
    pub(super) bar: Option<indicatif::ProgressBar>,
    pub(super) plain: bool,
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
             stepping {:.2} s, waiting for output {:.2} s (writer busy {:.2} s alongside{}); {} outputs, \
             {:.1} MB in {}",
            s.steps,
            s.simulated_time,
            s.wall_seconds,
            s.particle_steps_per_second,
            t.setup_seconds,
            t.stepping_seconds,
            t.output_wait_seconds,
            t.writer_seconds,
            s.writer_mb_per_second
                .map_or(String::new(), |r| format!(", {r:.0} MB/s")),
            s.outputs,
            s.output_bytes as f64 / 1e6,
            s.output_dir
        ));
        if let Some(advice) = &s.output_advice {
            self.line(&format!("note: {advice}"));
        }
        for m in &s.monitors {
            self.line(&m.to_string());
        }
    }
}
