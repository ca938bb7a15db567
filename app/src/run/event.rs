//! What a run's event is (`Event`): it says when it next has something to do, fires when
//! due after a batch, and tells its part of a checkpoint's run state and of the summary.
//! The events themselves and their order are `events.rs`'s.

use meshfree_core::solver::step::reached;

use super::context::{Ctx, RunFailure};
use crate::output::RunSummary;
use crate::resume::RunState;

/// Something a run does at its times.
pub(super) trait Event {
    /// [T] when it next has something to do; None: nothing (it bounds no batch).
    fn next_time(&self) -> Option<f64>;

    /// Whether it fires after the batch that brought the run to where `ctx` stands: by
    /// default where the clock reached its next time (`step::reached`).
    fn due(&self, ctx: &mut Ctx) -> bool {
        (self.next_time()).is_some_and(|next| reached(ctx.solver.time(), next))
    }

    /// Do what is due, and set the next time.
    fn fire(&mut self, ctx: &mut Ctx) -> Result<(), RunFailure>;

    /// Its part of a checkpoint's run state (`crate::resume::RunState`).
    fn save(&self, _state: &mut RunState) -> Result<(), RunFailure> {
        Ok(())
    }

    /// Its part of the summary.
    fn summarise(&self, _summary: &mut RunSummary) {}
}
