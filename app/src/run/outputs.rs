//! The outputs event: at each output time a health check, the diagnostics, and the frame's
//! copy started (`Solver::capture`) and queued for the writer thread (`output::writer`),
//! which writes the files.

use std::time::Instant;

use meshfree_core::solver::frame::Fields;
use meshfree_core::solver::Diagnostics;

use super::context::{Ctx, RunFailure};
use super::event::Event;
use super::RunError;
use crate::output::writer;
use crate::resume::RunState;

/// The stepping side of the outputs.
pub(super) struct Outputs {
    /// The fields each capture copies.
    capture: Fields,
    /// [T] the output interval.
    interval: f64,
    /// [T] the next output's time (0 for a fresh run: its first output).
    next: f64,
    /// Frames taken so far, every part of the run.
    taken: usize,
    /// Whether a slow output was reported (once a run).
    warned: bool,
}

impl Outputs {
    /// The outputs every `interval` [T] from `next`, `taken` of them already written.
    pub fn new(capture: Fields, interval: f64, next: f64, taken: usize) -> Outputs {
        Outputs {
            capture,
            interval,
            next,
            taken,
            warned: false,
        }
    }

    /// One output: diagnostics, the frame's copy started, the job queued. Returns the
    /// diagnostics. A writer that stopped (a failed write) is reported by the join.
    pub fn take(&mut self, ctx: &mut Ctx) -> Result<Diagnostics, RunError> {
        let d = ctx.solver.diagnostics();
        let waited = Instant::now();
        let frame = ctx.solver.capture(self.capture);
        ctx.queue.send(writer::Job::Frame(writer::FrameJob {
            diagnostics: d.clone(),
            frame,
        }))?;
        let waited = waited.elapsed().as_secs_f64();
        ctx.queue.wait_seconds += waited;
        self.taken += 1;
        if waited > 0.5 && !self.warned {
            self.warned = true;
            ctx.lines.line(&format!(
                "meshfree: output {} waited {waited:.2} s for the writer (the disk is slower than the \
                 outputs): format = \"vtu-lz4\" (compressed, fast), fewer [output] fields or a \
                 longer output interval help; the run's end line and summary.json say how much in all",
                self.taken - 1
            ));
        }
        Ok(d)
    }

    /// After a blow-up: the failing state as the last frame (a fault is found by a health
    /// check, which comes before the output of its step). Returns its output index.
    pub fn fault_frame(&mut self, ctx: &mut Ctx) -> Option<usize> {
        self.take(ctx).ok().map(|_| self.taken - 1)
    }
}

impl Event for Outputs {
    fn next_time(&self) -> Option<f64> {
        Some(self.next)
    }

    fn fire(&mut self, ctx: &mut Ctx) -> Result<(), RunFailure> {
        ctx.check()?;
        ctx.last = self.take(ctx)?;
        let t = ctx.solver.time();
        self.next = ((t / self.interval + 1e-9).floor() + 1.0) * self.interval;
        Ok(())
    }

    fn save(&self, state: &mut RunState) -> Result<(), RunFailure> {
        state.next_output = self.next;
        Ok(())
    }
}
