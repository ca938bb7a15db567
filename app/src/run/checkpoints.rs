//! The checkpoints event: every `[output] checkpoint_interval` of simulated time and every
//! `RunOptions::checkpoint_wall` seconds of wall time (not at the end, whose checkpoint the
//! stop writes; the wall clock bounds no batch, so the stepping is the same with it or
//! without), a health check and a save of the run
//! (`Events::save`): the solver's state (`output::checkpoint::Saved`) and the run's
//! (`crate::resume::RunState`), written to `checkpoint.bin` on the writer thread after the
//! frames queued before it.

use std::path::PathBuf;
use std::time::Instant;

use meshfree_core::solver::step::reached;

use super::context::{Ctx, RunFailure};
use super::event::Event;
use super::setup::Setup;
use crate::output::checkpoint::{self, Saved};
use crate::resume::{Resume, RunState};

pub(super) struct Checkpoints {
    /// [T] the next checkpoint's time, if any.
    next: Option<f64>,
    /// [T] the interval (`[output] checkpoint_interval`), if any.
    every: Option<f64>,
    /// What every checkpoint records of the run besides the events' parts: its build,
    /// backend, scene, end, output interval and format, and where it was resumed from.
    base: RunState,
    path: PathBuf,
    /// [s] the wall time between checkpoints, if any, and when the last was written.
    wall: Option<f64>,
    last: Instant,
}

impl Checkpoints {
    pub fn new(set: &Setup, resume: Option<&Resume>, wall: Option<f64>) -> Checkpoints {
        let every = set.scene.file.output.checkpoint_interval;
        let interval = set.scene.file.time.output_interval;
        Checkpoints {
            next: resume.map_or(every, |r| r.run.next_checkpoint),
            every,
            base: RunState {
                build: meshfree_core::build_info::COMMIT.to_string(),
                backend: set.info.backend.clone(),
                // Of the copy in the directory, which a resume compares (a resumed run's
                // overrides are not written into it again).
                scene_digest: crate::resume::digest(
                    resume.map_or(&set.scene.text, |r| &r.scene.text),
                ),
                t_end: set.t_end(),
                output_interval: interval,
                format: set.format,
                next_output: interval,
                next_checkpoint: every,
                stepper: Default::default(),
                monitors: Default::default(),
                probes: Default::default(),
                writer: Default::default(),
                timing: Default::default(),
                resumed_from: set.resumed_from.clone(),
            },
            path: set.out_dir.join(checkpoint::FILE),
            wall,
            last: Instant::now(),
        }
    }

    /// The run's state besides the events' parts, for them to fill (`Event::save`).
    pub fn base(&self) -> RunState {
        self.base.clone()
    }

    /// Queue the checkpoint of `ctx`'s solver and the run's `state` (the events' parts
    /// filled): the stepper's state and the timing so far are added here.
    pub fn write(&self, ctx: &mut Ctx, mut state: RunState) -> Result<(), RunFailure> {
        state.stepper = ctx.stepper.state();
        state.timing = ctx.timing();
        let waited = Instant::now();
        ctx.queue.send(crate::resume::checkpoint_job(
            self.path.clone(),
            Saved::of(&mut *ctx.solver),
            state,
        ))?;
        ctx.queue.wait_seconds += waited.elapsed().as_secs_f64();
        Ok(())
    }
}

impl Event for Checkpoints {
    fn next_time(&self) -> Option<f64> {
        self.next
    }

    /// At its time or once the wall time is up, short of the end (the stop writes that
    /// one).
    fn due(&self, ctx: &mut Ctx) -> bool {
        let t = ctx.solver.time();
        let simulated = self.every.is_some() && self.next.is_some_and(|at| reached(t, at));
        let wall = (self.wall).is_some_and(|w| self.last.elapsed().as_secs_f64() >= w);
        (simulated || wall) && !reached(t, ctx.t_end())
    }

    fn fire(&mut self, ctx: &mut Ctx) -> Result<(), RunFailure> {
        ctx.check()?;
        let t = ctx.solver.time();
        if let Some(every) = self
            .every
            .filter(|_| self.next.is_some_and(|at| reached(t, at)))
        {
            self.next = Some(((t / every + 1e-9).floor() + 1.0) * every);
        }
        self.last = Instant::now();
        ctx.save_due = true;
        Ok(())
    }

    fn save(&self, state: &mut RunState) -> Result<(), RunFailure> {
        state.next_checkpoint = self.next;
        Ok(())
    }
}
