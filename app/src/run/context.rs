//! What a run's events act on (`Ctx`): the solver and its stepper, the writer's queue, the
//! lines on stderr, the clock, and the diagnostics of the last output; with the batches
//! that step it and the summary's fields it owns (the steps and the timing split).

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::thread::ScopedJoinHandle;
use std::time::Instant;

use meshfree_core::solver::step::{reached, Stepper};
use meshfree_core::solver::{Diagnostics, Fault, Solver};

use super::ending::Stop;
use super::lines::Lines;
use super::{RunError, RunOptions};
use crate::output::writer::{self, Failure, Report};
use crate::output::{RunSummary, Timing};

/// Why the stepping stopped short: a blow-up, or a failed write (or set-up of a file).
pub(super) enum RunFailure {
    Fault(Fault),
    Io(RunError),
}

impl From<RunError> for RunFailure {
    fn from(e: RunError) -> Self {
        RunFailure::Io(e)
    }
}

impl From<(PathBuf, std::io::Error)> for RunFailure {
    fn from((path, e): (PathBuf, std::io::Error)) -> Self {
        RunFailure::Io(RunError::Io {
            path,
            reason: e.to_string(),
        })
    }
}

/// The run's wall clock: every part of it where it was resumed.
pub(super) struct Clock {
    pub started: Instant,
    /// The timings of the parts before this one (zero for a run in one go).
    pub before: Timing,
    /// [s] the set-up's, this part's included.
    pub setup_seconds: f64,
}

impl Clock {
    /// [s] the whole run's wall time so far.
    pub fn total_seconds(&self) -> f64 {
        self.before.total_seconds + self.started.elapsed().as_secs_f64()
    }
}

/// The writer thread's queue, from the stepping side.
pub(super) struct Queue {
    /// None before the thread starts and once closed.
    jobs: Option<mpsc::SyncSender<writer::Job>>,
    /// [s] time the stepping waited for the writer (a full queue, a staging set in use, the
    /// final drain).
    pub wait_seconds: f64,
}

impl Queue {
    pub fn open(&mut self, jobs: mpsc::SyncSender<writer::Job>) {
        self.jobs = Some(jobs);
    }

    /// Queue a job for the writer. A writer that stopped (a failed write) is reported by
    /// the join.
    pub fn send(&mut self, job: writer::Job) -> Result<(), RunError> {
        let sent = self.jobs.as_ref().is_some_and(|tx| tx.send(job).is_ok());
        if !sent {
            // The writer stopped on an error: stop the run; the join reports which.
            self.jobs = None;
            return Err(RunError::Io {
                path: PathBuf::from("(output)"),
                reason: "the output writer stopped".into(),
            });
        }
        Ok(())
    }

    /// Close the queue, which lets the writer finish the frames it holds, and wait for it.
    pub fn drain(
        &mut self,
        thread: ScopedJoinHandle<'_, Result<Report, Failure>>,
    ) -> Result<Report, Failure> {
        self.jobs = None;
        let drained = Instant::now();
        // A panic on the writer thread (a bug) stops the run as a failed write would.
        let written = thread.join().unwrap_or_else(|_| {
            Err(Failure {
                path: PathBuf::from("(output)"),
                reason: "the output writer failed (an internal error: please report it)".into(),
            })
        });
        self.wait_seconds += drained.elapsed().as_secs_f64();
        written
    }
}

/// The run as it stands, which its events act on.
pub(super) struct Ctx {
    pub solver: Box<dyn Solver>,
    pub stepper: Stepper,
    pub queue: Queue,
    pub lines: Lines,
    pub clock: Clock,
    /// The diagnostics of the last output (a resumed run's state, before its first).
    pub last: Diagnostics,
    /// Raised by an event (a checkpoint's time) for the run to be saved once the events
    /// due have fired (`Events::fire_due`).
    pub save_due: bool,
    /// [T] the run's end.
    t_end: f64,
    /// The solver's step count at the start (a resumed run's steps so far).
    first_step: u64,
    max_steps: Option<u64>,
    interrupt: Option<&'static AtomicBool>,
}

impl Ctx {
    pub fn new(
        solver: Box<dyn Solver>,
        stepper: Stepper,
        clock: Clock,
        lines: Lines,
        options: &RunOptions,
        t_end: f64,
    ) -> Ctx {
        Ctx {
            first_step: solver.steps(),
            queue: Queue {
                jobs: None,
                wait_seconds: clock.before.output_wait_seconds,
            },
            solver,
            stepper,
            lines,
            clock,
            last: Diagnostics::default(),
            save_due: false,
            t_end,
            max_steps: options.max_steps,
            interrupt: options.interrupt,
        }
    }

    /// [T] the run's end.
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// Steps taken by this part of the run.
    pub fn steps_taken(&self) -> u64 {
        self.solver.steps() - self.first_step
    }

    /// The particles' health now (a fault stops the run).
    pub fn check(&mut self) -> Result<(), RunFailure> {
        self.solver.check().map_err(RunFailure::Fault)
    }

    /// Whether the run stops before another batch: its end or `--steps` reached, or the
    /// interrupt raised.
    pub fn stopping(&mut self) -> Option<Stop> {
        let taken = self.steps_taken();
        if reached(self.solver.time(), self.t_end) || self.max_steps.is_some_and(|n| taken >= n) {
            return Some(Stop::End);
        }
        let raised = self.interrupt.is_some_and(|f| f.load(Ordering::SeqCst));
        raised.then_some(Stop::Interrupted)
    }

    /// One batch of steps towards the earliest event `next` [T] or the end, within
    /// `--steps`; the gates it opened are reported.
    pub fn batch(&mut self, next: Option<f64>) -> Result<(), RunFailure> {
        // The binary's fault tests (`tests/binary_faults.rs`) stand in for a bug in the
        // stepping here; debug builds only.
        #[cfg(debug_assertions)]
        if std::env::var_os("MESHFREE_TEST_PANIC_IN_STEP").is_some() {
            panic!("MESHFREE_TEST_PANIC_IN_STEP: a panic in the stepping");
        }
        let t = self.solver.time();
        let to = next.unwrap_or(f64::INFINITY).min(self.t_end);
        let budget = self.max_steps.map_or(u64::MAX, |n| n - self.steps_taken());
        let batch = (self.stepper)
            .batch(&mut *self.solver, to, budget)
            .map_err(RunFailure::Fault)?;
        for (group, n) in batch.opened {
            self.lines.line(&format!(
                "t = {t:.4}: gate (group {group}) removed, {n} particles"
            ));
        }
        Ok(())
    }

    /// The timing split so far (the writer's busy time is the writer's to tell).
    pub fn timing(&self) -> Timing {
        Timing {
            setup_seconds: self.clock.setup_seconds,
            stepping_seconds: self.stepper.stepping_seconds(),
            output_wait_seconds: self.queue.wait_seconds,
            total_seconds: self.clock.total_seconds(),
            ..Timing::default()
        }
    }

    /// The summary's fields the run's state owns: the steps, the time reached, the wall
    /// time and its split, the rate and the final diagnostics.
    pub fn summarise(&mut self, s: &mut RunSummary) {
        let steps = self.solver.steps();
        s.steps = steps;
        s.simulated_time = self.solver.time();
        s.wall_seconds = self.clock.total_seconds();
        let step_seconds = self.stepper.stepping_seconds();
        s.particle_steps_per_second = if step_seconds > 0.0 {
            s.particles.total as f64 * steps as f64 / step_seconds
        } else {
            0.0
        };
        s.final_diagnostics = Some(self.solver.diagnostics());
        s.open_boundaries = self.solver.open_tally();
        s.timing = Timing {
            total_seconds: s.wall_seconds,
            ..self.timing()
        };
    }
}
