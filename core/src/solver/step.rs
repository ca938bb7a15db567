//! The one stepping path: a scene's solver stepped up to an event (an output, a monitor
//! sample, a gate, a viewer frame, the end) in batches of `Solver::advance` (a CUDA graph on
//! the GPU), reading the clock once per batch. The run driver, the benchmarks, validation,
//! stability maps, charts and the viewer all step through `Stepper`.
//!
//! A batch opens the gates whose time came, then takes half the estimated number of steps
//! to the next event (from the last batch's mean dt; one step when there is no estimate),
//! at most `MAX_BATCH`, and never past a gate: so the last steps before an event are taken
//! one at a time and an event is met at the first step boundary at or past its time, as
//! with single steps. The particles' health is checked every `CHECK_EVERY` steps of the
//! solver's count, whatever the batches (`Solver::queue_check`); a backend may report a
//! check's fault at the end of the batch (`Solver::queued_fault`: the CUDA backend keeps it
//! on the device and reads it with the clock), with the step, time and particle of the
//! check that found it, so that a blow-up stops a run at most `MAX_BATCH` steps after that
//! check, and at most `CHECK_EVERY + MAX_BATCH` steps after it began.

use std::time::Instant;

use crate::solver::{Fault, Solver};

/// Health checks (`Solver::check`) run every this many steps.
pub const CHECK_EVERY: u64 = 10;

/// Most steps between two read-backs of the clock.
pub const MAX_BATCH: u64 = 32;

/// [-] A run stops with a fault when a batch's mean time step falls below this fraction of
/// the end time (`Stepper::with_end`): 1e12 steps to go is a run that never ends (a step
/// collapsed by a huge viscosity or acceleration), not a slow one.
pub const DT_FLOOR: f64 = 1e-12;

/// Whether the clock `t` \[T\] has reached `target` \[T\]: within a relative 1e-9, so that a
/// fixed step that lands on an output time by rounding counts as there.
pub fn reached(t: f64, target: f64) -> bool {
    t >= target - 1e-9 * target.abs()
}

/// A scene's removable walls, (group, opening time \[T\]), opened in time order.
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

/// The fault of a time step under the floor: which term of eq. (19) and its limits took it
/// there (the sound-speed term h / (c + |v|), the acceleration term sqrt(h / |a|), the
/// viscous term), named at the fastest particle (a read-back: this ends the run).
fn collapsed_step(solver: &mut dyn Solver, dt: f64, floor: f64) -> Fault {
    let p = *solver.params();
    let d = solver.diagnostics();
    let fastest = solver
        .particles()
        .into_iter()
        .filter(|q| q.kind != crate::physics::particle::Kind::Boundary)
        .max_by(|a, b| {
            let s = |q: &crate::physics::particle::Particle| {
                q.velocity.iter().map(|v| v * v).sum::<f32>()
            };
            s(a).total_cmp(&s(b))
        });
    let c = p.c0.max(if d.solid > 0 {
        p.sound_speed(crate::physics::params::MF_KIND_SOLID as u8)
    } else {
        0.0
    }) as f64;
    let (h, courant) = (p.h as f64, p.courant as f64);
    let sound = courant * h / (c + d.max_speed as f64);
    let term = if p.dt > 0.0 {
        format!("the scene's fixed time.dt = {}", p.dt)
    } else if p.viscosity > 0.0
        && crate::consts::MF_VISCOUS_DT * h * h / (p.viscosity as f64) < 2.0 * dt
    {
        format!(
            "the viscous term {} h^2 / nu (nu = {})",
            crate::consts::MF_VISCOUS_DT,
            p.viscosity
        )
    } else if sound < 2.0 * dt {
        format!(
            "the sound-speed term courant h / (c + |v|max): |v|max = {}",
            d.max_speed
        )
    } else {
        // dt = courant sqrt(h / a): the acceleration it implies.
        let a = h * (courant / dt).powi(2);
        format!(
            "the acceleration term courant sqrt(h / |a|max): |a|max ~ {a:.3e} (a huge alpha, \
             beta, viscosity or wall strength, or particles almost on top of each other)"
        )
    };
    Fault {
        step: solver.steps(),
        time: solver.time(),
        particle: fastest.as_ref().map_or(u32::MAX, |q| q.id),
        kind: fastest.map_or("none".into(), |q| q.kind.name().into()),
        quantity: "time step".into(),
        value: dt,
        reason: format!(
            "below {floor:.3e} ({DT_FLOOR:e} of the end time, or of the time stepped to): set \
             by {term}; the particle named is the fastest"
        ),
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

/// What a `Stepper` carries from batch to batch, for a run that continues from a
/// checkpoint (`Stepper::state`, `Stepper::resume`): a run resumed with it opens the same
/// gates and sizes its batches as the saved run would have.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepperState {
    /// The gates not yet opened: (group, opening time \[T\]).
    pub pending_gates: Vec<(u32, f64)>,
    /// \[T\] mean dt of the last batch (0: none yet).
    pub dt_estimate: f64,
    /// \[s\] wall time spent stepping so far.
    pub stepping_seconds: f64,
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
    /// [T] a batch's mean dt below this is a fault (0: `DT_FLOOR` of the batch's event time
    /// only, so that a step collapsed to 0 stops every loop that steps to a time).
    dt_floor: f64,
}

impl Stepper {
    /// A stepper for a scene's gates (`Scene::gates`).
    pub fn new(gates: Vec<(u32, f64)>) -> Stepper {
        Stepper {
            gates: Gates::new(gates),
            ..Stepper::default()
        }
    }

    /// The same, stopping with a fault when a batch's mean step falls under `DT_FLOOR` of
    /// the end time `t_end` \[T\].
    pub fn with_end(mut self, t_end: f64) -> Stepper {
        self.dt_floor = DT_FLOOR * t_end;
        self
    }

    /// What a resumed run needs of this stepper.
    pub fn state(&self) -> StepperState {
        StepperState {
            pending_gates: self.gates.pending.clone(),
            dt_estimate: self.dt_estimate,
            stepping_seconds: self.stepping_seconds,
        }
    }

    /// The stepper of a run continued from `state`; the solver's gates that `state` lists as
    /// opened (`opened`) are removed from it first, as the saved run removed them: the
    /// groups of `gates` (`Scene::gates`) not pending in `state`. Returns them.
    pub fn resume(&mut self, state: &StepperState, solver: &mut dyn Solver) -> Vec<u32> {
        let pending = &state.pending_gates;
        let opened: Vec<u32> = self
            .gates
            .pending
            .iter()
            .filter(|g| !pending.iter().any(|p| p.0 == g.0))
            .map(|g| g.0)
            .collect();
        for &g in &opened {
            solver.remove_group(g);
        }
        self.gates.pending.clone_from(pending);
        self.dt_estimate = state.dt_estimate;
        self.stepping_seconds = state.stepping_seconds;
        opened
    }

    /// \[s\] wall time spent stepping so far (gates, steps and health checks; the clock read
    /// included).
    pub fn stepping_seconds(&self) -> f64 {
        self.stepping_seconds
    }

    /// One batch towards the event at `t_event` \[T\], of at most `max_steps` steps (at least
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
            if solver.steps().is_multiple_of(CHECK_EVERY) {
                solver.queue_check()?;
            }
        }
        if n > 0 {
            self.dt_estimate = (solver.time() - t) / n as f64;
        }
        solver.queued_fault()?;
        self.stepping_seconds += started.elapsed().as_secs_f64();
        // Without an end time (`with_end`) the event's time sets the floor: a step that has
        // collapsed to 0 would otherwise step towards it for ever.
        let floor = match event.is_finite() {
            true => self.dt_floor.max(DT_FLOOR * event),
            false => self.dt_floor,
        };
        if n > 0 && self.dt_estimate < floor {
            return Err(collapsed_step(solver, self.dt_estimate, floor));
        }
        Ok(Batch { steps: n, opened })
    }

    /// Step until the clock reaches `t_end` \[T\] (the last step may pass it by less than one
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
