//! A run's events, in the spirit of TrixiParticles' callbacks: the outputs, the force
//! monitors, the probes and gauges, the checkpoints and the progress report. Each says
//! when it next has something to do (the batches step to the earliest), fires when due
//! after a batch, and tells its part of a checkpoint's run state and of the summary.

use super::checkpoints::Checkpoints;
use super::context::{Ctx, RunFailure};
use super::event::Event;
use super::outputs::Outputs;
use super::progress::ProgressReport;
use super::setup::Setup;
use super::RunError;
use crate::monitors::Monitors;
use crate::output::RunSummary;
use crate::probes::Probes;
use crate::resume::{Resume, RunState};

/// A run's events, fired in this order after each batch.
pub(super) struct Events {
    pub outputs: Outputs,
    monitors: Monitors,
    probes: Probes,
    checkpoints: Checkpoints,
    progress: ProgressReport,
}

impl Events {
    /// The events of the run `set` up: a fresh run's first output and samples at t = 0, a
    /// resumed one's where its checkpoint left them (their files opened at their ends);
    /// a checkpoint every `wall` seconds of wall time besides (`RunOptions::checkpoint_wall`).
    pub fn new(
        set: &Setup,
        progress: ProgressReport,
        resume: Option<&Resume>,
        wall: Option<f64>,
    ) -> Result<Events, RunError> {
        let run = resume.map(|r| &r.run);
        let interval = set.scene.file.time.output_interval;
        Ok(Events {
            outputs: match run {
                Some(r) => Outputs::new(set.capture, interval, r.next_output, r.writer.frames),
                None => Outputs::new(set.capture, interval, 0.0, 0),
            },
            monitors: Monitors::create(&set.scene, &set.out_dir, run.map(|r| &r.monitors))?,
            probes: Probes::create(&set.scene, &set.out_dir, run.map(|r| &r.probes))?,
            checkpoints: Checkpoints::new(set, resume, wall),
            progress,
        })
    }

    /// The files the monitors and probes write into the run's directory.
    pub fn file_names(&self) -> Vec<String> {
        let mut names = self.monitors.file_names();
        names.extend(self.probes.file_names());
        names
    }

    fn all(&mut self) -> [&mut dyn Event; 5] {
        [
            &mut self.outputs,
            &mut self.monitors,
            &mut self.probes,
            &mut self.checkpoints,
            &mut self.progress,
        ]
    }

    fn each(&self) -> [&dyn Event; 5] {
        [
            &self.outputs,
            &self.monitors,
            &self.probes,
            &self.checkpoints,
            &self.progress,
        ]
    }

    /// [T] the earliest event's time.
    pub fn next_time(&self) -> Option<f64> {
        (self.each().iter())
            .filter_map(|e| e.next_time())
            .min_by(f64::total_cmp)
    }

    /// Fire every event that is due, in order; then save the run where one asked
    /// (`Ctx::save_due`: a checkpoint, after the round's output and samples).
    pub fn fire_due(&mut self, ctx: &mut Ctx) -> Result<(), RunFailure> {
        for e in self.all() {
            if e.due(ctx) {
                e.fire(ctx)?;
            }
        }
        if std::mem::take(&mut ctx.save_due) {
            self.save(ctx)?;
        }
        Ok(())
    }

    /// A checkpoint of the run as it stands: every event's part of the run state.
    pub fn save(&self, ctx: &mut Ctx) -> Result<(), RunFailure> {
        let mut state = self.checkpoints.base();
        for e in self.each() {
            e.save(&mut state)?;
        }
        self.checkpoints.write(ctx, state)
    }

    /// Where the run stops short of a blow-up (its end, --steps, a signal): a checkpoint,
    /// and the state it reached as a last frame where no output took it. The checkpoint
    /// comes first: a resumed run removes that off-schedule frame and goes on as the run
    /// in one go would have.
    pub fn stop(&mut self, ctx: &mut Ctx) -> Result<(), RunFailure> {
        let unsaved = ctx.last.step != ctx.solver.steps();
        if unsaved {
            ctx.check()?;
        }
        self.save(ctx)?;
        if unsaved {
            self.outputs.take(ctx)?;
        }
        Ok(())
    }

    /// Every event's part of the summary.
    pub fn summarise(&self, summary: &mut RunSummary) {
        for e in self.each() {
            e.summarise(summary);
        }
    }
}

impl Event for Monitors {
    fn next_time(&self) -> Option<f64> {
        Monitors::next_time(self)
    }

    fn fire(&mut self, ctx: &mut Ctx) -> Result<(), RunFailure> {
        Ok(self.sample_due(&mut *ctx.solver)?)
    }

    fn save(&self, state: &mut RunState) -> Result<(), RunFailure> {
        state.monitors = self.state()?;
        Ok(())
    }

    fn summarise(&self, summary: &mut RunSummary) {
        summary.monitors = self.summaries();
    }
}

impl Event for Probes {
    fn next_time(&self) -> Option<f64> {
        Probes::next_time(self)
    }

    fn fire(&mut self, ctx: &mut Ctx) -> Result<(), RunFailure> {
        Ok(self.sample_due(&mut *ctx.solver)?)
    }

    fn save(&self, state: &mut RunState) -> Result<(), RunFailure> {
        state.probes = self.state()?;
        Ok(())
    }
}
