//! The one stepping path: a scene's solver stepped up to an event (an output, a monitor
//! sample, a gate, a viewer frame, the end) in batches of `Solver::advance` (a CUDA graph on
//! the GPU), reading the clock once per batch. The run driver, the benchmarks, validation,
//! stability maps, charts and the viewer all step through `Stepper`.
//!
//! A batch opens the gates whose time came, then takes half the estimated number of steps
//! to the next event (from the last batch's mean dt; one step when there is no estimate),
//! at most `MAX_BATCH`, and never past a gate: so the last steps before an event are taken
//! one at a time and an event is met at the first step boundary at or past its time, as
//! with single steps. The particles' health (`Solver::check`) is checked every
//! `CHECK_EVERY` steps of the solver's count, whatever the batches.

use std::time::Instant;

use crate::solver::{Fault, Solver};

/// Health checks (`Solver::check`) run every this many steps.
pub const CHECK_EVERY: u64 = 10;

/// Most steps between two read-backs of the clock.
pub const MAX_BATCH: u64 = 32;

/// Whether the clock `t` [T] has reached `target` [T]: within a relative 1e-9, so that a
/// fixed step that lands on an output time by rounding counts as there.
pub fn reached(t: f64, target: f64) -> bool {
    t >= target - 1e-9 * target.abs()
}

/// A scene's removable walls, (group, opening time [T]), opened in time order.
#[derive(Clone, Debug, Default)]
pub struct Gates {
    pending: Vec<(u32, f64)>,
}

impl Gates {
    pub fn new(mut gates: Vec<(u32, f64)>) -> Gates {
        gates.sort_by(|a, b| a.1.total_cmp(&b.1));
        Gates { pending: gates }
    }

    /// The opening time of the next gate, if any is left.
    pub fn next_time(&self) -> Option<f64> {
        self.pending.first().map(|g| g.1)
    }

    /// Remove the groups whose opening time the clock `t` has reached; returns (group,
    /// particles removed) for each.
    pub fn open_due(&mut self, solver: &mut dyn Solver, t: f64) -> Vec<(u32, usize)> {
        let due = self.pending.iter().take_while(|g| reached(t, g.1)).count();
        self.pending
            .drain(..due)
            .map(|(group, _)| (group, solver.remove_group(group)))
            .collect()
    }
}

/// What one batch did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Batch {
    /// Steps taken.
    pub steps: u64,
    /// The gates opened before it: (group, particles removed).
    pub opened: Vec<(u32, usize)>,
}

/// Steps one scene's solver: its gates, the dt estimate that sizes the batches, and the
/// wall time spent stepping.
#[derive(Clone, Debug, Default)]
pub struct Stepper {
    gates: Gates,
    /// [T] mean dt of the last batch (0: none yet).
    dt_estimate: f64,
    /// [s] wall time inside `batch`.
    stepping_seconds: f64,
}

impl Stepper {
    /// A stepper for a scene's gates (`Scene::gates`).
    pub fn new(gates: Vec<(u32, f64)>) -> Stepper {
        Stepper {
            gates: Gates::new(gates),
            ..Stepper::default()
        }
    }

    /// [s] wall time spent stepping so far (gates, steps and health checks; the clock read
    /// included).
    pub fn stepping_seconds(&self) -> f64 {
        self.stepping_seconds
    }

    /// One batch towards the event at `t_event` [T], of at most `max_steps` steps (at least
    /// one step unless `max_steps` is 0). See the module docs.
    pub fn batch(
        &mut self,
        solver: &mut dyn Solver,
        t_event: f64,
        max_steps: u64,
    ) -> Result<Batch, Fault> {
        let started = Instant::now();
        let t = solver.time();
        let opened = self.gates.open_due(solver, t);
        let event = t_event.min(self.gates.next_time().unwrap_or(f64::INFINITY));
        let mut n = if self.dt_estimate > 0.0 && event.is_finite() {
            ((event - t) / self.dt_estimate * 0.5).floor().max(1.0) as u64
        } else if self.dt_estimate > 0.0 {
            MAX_BATCH
        } else {
            1
        };
        n = n.min(MAX_BATCH).min(max_steps);
        let mut left = n;
        while left > 0 {
            // Up to the next health check, as one batch (a CUDA graph on the GPU).
            let k = left.min(CHECK_EVERY - solver.steps() % CHECK_EVERY);
            solver.advance(k);
            left -= k;
            if solver.steps() % CHECK_EVERY == 0 {
                solver.check()?;
            }
        }
        if n > 0 {
            self.dt_estimate = (solver.time() - t) / n as f64;
        }
        self.stepping_seconds += started.elapsed().as_secs_f64();
        Ok(Batch { steps: n, opened })
    }

    /// Step until the clock reaches `t_end` [T] (the last step may pass it by less than one
    /// dt), then check the particles' health.
    pub fn advance_to(&mut self, solver: &mut dyn Solver, t_end: f64) -> Result<(), Fault> {
        while !reached(solver.time(), t_end) {
            self.batch(solver, t_end, u64::MAX)?;
        }
        solver.check()
    }

    /// Take `steps` steps (a viewer frame), opening gates on time; the health is checked as
    /// in every batch.
    pub fn advance_steps(&mut self, solver: &mut dyn Solver, steps: u64) -> Result<(), Fault> {
        let mut left = steps;
        while left > 0 {
            left -= self.batch(solver, f64::INFINITY, left)?.steps;
        }
        Ok(())
    }
}
