//! The run driver: scene -> solver -> output directory. Used by the CLI, the tests and
//! the viewer.
//!
//! Order of work: apply overrides and validate, generate particles, build the solver, and
//! only then create the output directory (a scene that fails validation writes nothing):
//! `setup.rs`. Then the run is a loop of `meshfree_core::solver::step::Stepper` batches, each to the
//! earliest of the run's events and its end (the stepper opens the gates on time and checks
//! the health every `step::CHECK_EVERY` steps); after each batch every event that is due
//! fires, in a fixed order (`events.rs`): the outputs (`outputs.rs`: a health check and an
//! output at each output time), the force monitors, the probes and gauges, the checkpoints
//! (`checkpoints.rs`) and the progress report (`progress.rs`). What the events act on, the
//! solver, its stepper, the writer's queue and the clock, is `context.rs`'s `Ctx`; how the
//! run ended, `ending.rs`. A fresh run fires its events once at t = 0 (the first output and
//! samples); where it stops, it writes a checkpoint and the state it reached as a last frame.
//!
//! An output never stalls the stepping for long: the main thread reads the diagnostics,
//! starts the frame's copy (`Solver::capture`: on the GPU a device-side copy that a second
//! stream downloads) and queues it for the writer thread (`output::writer`), which writes
//! the particle file (`[output] format` and `fields`: binary VTU with `particles.pvd`,
//! zlib VTU, CSV or none), the row of `diagnostics.csv`, `clusters.csv` where `[output]
//! clusters` asks, and, in a scene with elastic bodies, a row per body to `bodies.csv`.
//! Force monitors (`crate::monitors`) sample at t = 0 and every `interval` after it (a step
//! boundary at or past the time) into `<name>.csv`; probes and gauges (`crate::probes`)
//! likewise into `probes.csv` and `gauges.csv`, sampled on the device. `summary.json` is
//! written at the start (status `running`) and at the end, also after a blow-up, each part
//! filling the fields it owns: the set-up the scene, backend and particles, the context
//! the steps and the timing split (set-up, stepping, output waits), the writer the frames,
//! the cluster count of the last output and each body's extremes, the monitors their
//! statistics, the ending the status.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::mpsc;

use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::Scene;

use crate::output::{files, writer};
use crate::output::{RunStatus, RunSummary};
use crate::resume::Resume;

mod checkpoints;
mod context;
mod ending;
mod event;
mod events;
mod lines;
mod out_dir;
mod outputs;
mod progress;
mod setup;

use context::{Ctx, RunFailure};
use ending::{Ending, Stop};
use events::Events;
use setup::Setup;

pub use crate::output::writer::Frame;
pub use crate::run_error::RunError;
pub use out_dir::default_out_dir;

/// How to report progress on stderr.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Progress {
    /// A progress bar when stderr is a terminal, else plain lines.
    #[default]
    Auto,
    /// Plain lines: the start, each tenth of the run, the end.
    Lines,
    /// Nothing.
    Quiet,
}

/// Options of one run. `Default` runs on `auto` into `default_out_dir`.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    pub backend: BackendChoice,
    /// Default `default_out_dir(scene)`.
    pub out_dir: Option<PathBuf>,
    /// Refuse a scene whose estimate holds more particles (`Scene::check_size`; the
    /// machine's available memory is checked either way).
    pub max_particles: Option<u64>,
    /// Replace an earlier run's output in `out_dir` (else the run refuses the directory).
    pub overwrite: bool,
    /// Raised to stop the run at the next batch with a last frame and an `interrupted`
    /// summary (`crate::interrupt::install` gives the one the signals raise).
    pub interrupt: Option<&'static AtomicBool>,
    /// Replaces the scene's `time.end`.
    pub t_end: Option<f64>,
    /// Stop after this many steps (also before `t_end`).
    pub max_steps: Option<u64>,
    /// Replaces the scene's `time.output_interval`.
    pub output_interval: Option<f64>,
    pub progress: Progress,
    /// Replaces the scene's `[output] format`.
    pub format: Option<OutputFormat>,
    /// Step in this many subdomains (`meshfree_core::exchange`: slabs along the longest
    /// axis, one thread each, halos exchanged every step), on `backend`; the particles come
    /// out as in one domain. None: one domain.
    pub decompose: Option<usize>,
    /// One subdomain on each of this many GPUs, through NCCL (`backend::Layout::Gpus`);
    /// None: `decompose` or one domain.
    pub gpus: Option<usize>,
    /// \[s\] of wall time between checkpoints besides those of `[output]
    /// checkpoint_interval` and the stop's (`run --checkpoint-every`); None: none by wall
    /// time.
    pub checkpoint_wall: Option<f64>,
    /// This process is rank 0 of an MPI run (`crate::mpi`, `run --mpi`): one subdomain per
    /// process.
    pub mpi: bool,
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |e| RunError::Io {
        path: path.to_path_buf(),
        reason: e.to_string(),
    }
}

/// Run `scene` to its end time (or `max_steps`), writing output. See the module docs.
pub fn run(scene: &Scene, options: &RunOptions) -> Result<RunSummary, RunError> {
    drive(scene, options, None, None)
}

/// `run`, calling `observer` on the writer thread at each output, once its files landed.
pub fn run_observed(
    scene: &Scene,
    options: &RunOptions,
    observer: writer::Observer,
) -> Result<RunSummary, RunError> {
    drive(scene, options, Some(observer), None)
}

/// Continue the run in `dir` from its checkpoint (`crate::resume`) to its end time, or to
/// `options.t_end` where given (a later one extends a finished run). The run's own output
/// interval and format hold (`options.output_interval`, `format`, `out_dir` and `overwrite`
/// are not used); the backend is `options.backend`, which may differ from the run's (then
/// the result is not bit for bit the uninterrupted run's: the other backend rounds its
/// sums differently).
pub fn resume(dir: &Path, options: &RunOptions) -> Result<RunSummary, RunError> {
    let r = crate::resume::load(dir)?;
    // Without --t-end a finished run's checkpoint (at or just past its end) has nothing to
    // do: the run completes at once.
    let t = r.solver.clock().time;
    let t_end = options.t_end.unwrap_or(r.run.t_end.max(t));
    if t_end < t {
        return Err(RunError::Checkpoint {
            path: dir.join(crate::output::checkpoint::FILE),
            reason: format!("--t-end {t_end} is before the checkpoint's time {t}"),
        });
    }
    let options = RunOptions {
        t_end: Some(t_end),
        output_interval: Some(r.run.output_interval),
        format: Some(r.run.format),
        out_dir: Some(dir.to_path_buf()),
        ..options.clone()
    };
    let scene = r.scene.clone();
    drive(&scene, &options, None, Some(r))
}

/// A run from the start (`resume` None) or from a checkpoint: the set-up, the writer
/// thread, the batches to the events (`step_through`), and the summary. An `observer` sees
/// frames that carry every field an analysis may want (`Setup::new`).
fn drive(
    scene: &Scene,
    options: &RunOptions,
    observer: Option<writer::Observer>,
    resume: Option<Resume>,
) -> Result<RunSummary, RunError> {
    let set = Setup::new(scene, options, observer, resume.as_ref())?;
    let t_end = set.t_end();
    let (lines, progress) = progress::reporter(options.progress, t_end, options.max_steps);
    let mut events = Events::new(&set, progress, resume.as_ref(), options.checkpoint_wall)?;
    set.announce(&lines, resume.as_ref());
    let mut summary = set.summary();
    summary.files = [files::SCENE, files::SUMMARY]
        .into_iter()
        .chain(set.writer.csv_names())
        .map(String::from)
        .chain(set.surfaces.iter().cloned())
        .chain(events.file_names())
        .collect();
    // A run killed outright (kill -9, power) leaves `running` behind, not an older status.
    let summary_path = set.out_dir.join(files::SUMMARY);
    (summary.write(&summary_path)).map_err(io_err(&summary_path))?;
    let (writer, out_dir, _lock) = (set.writer, set.out_dir, set._lock);
    let mut ctx = Ctx::new(set.solver, set.stepper, set.clock, lines, options, t_end);
    let (stepped, written) = std::thread::scope(|scope| {
        let (tx, rx) = mpsc::sync_channel::<writer::Job>(1);
        let thread = std::thread::Builder::new()
            .name("meshfree-writer".into())
            .spawn_scoped(scope, move || writer.serve(rx))
            .expect("spawning the writer thread");
        ctx.queue.open(tx);
        // A panic in the stepping (a bug) must still close the queue, or the writer waits
        // for ever and the scope never joins (issue #52).
        let stepped = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let result = step_through(&mut ctx, &mut events, resume.is_some());
            // At a blow-up, the failing state is the last frame (its values may be
            // non-finite: that is what it shows).
            let fault_frame = match &result {
                Err(RunFailure::Fault(_)) => events.outputs.fault_frame(&mut ctx),
                _ => None,
            };
            (result, fault_frame)
        }));
        // Closing the queue lets the writer finish the frames it holds.
        let written = ctx.queue.drain(thread);
        (stepped, written)
    });
    let (result, fault_frame) = match stepped {
        Ok(stepped) => stepped,
        Err(panic) => {
            // The solver's state is not to be trusted: the summary says what happened, and
            // the panic goes on (its message is printed already; exit 101).
            summary.status = RunStatus::Failed;
            summary.error = Some(format!(
                "internal error (a bug: please report it): {}",
                panic_message(&*panic)
            ));
            let _ = summary.write(&summary_path);
            std::panic::resume_unwind(panic);
        }
    };
    // The whole run, every part of it where it was resumed.
    ctx.summarise(&mut summary);
    events.summarise(&mut summary);
    let (ending, written) = match (result, written) {
        // A failed write first: it is why the stepping stopped. The summary says so where
        // it can still be written.
        (_, Err(f)) => return Err(failed(summary, &summary_path, f.into())),
        (Err(RunFailure::Io(e)), _) => return Err(failed(summary, &summary_path, e)),
        (Ok(stop), Ok(w)) => (Ending::of(stop), w),
        (Err(RunFailure::Fault(f)), Ok(w)) => (Ending::Failed(f, fault_frame), w),
    };
    summary.absorb(&written);
    ending.summarise(&mut summary);
    (summary.write(&summary_path)).map_err(io_err(&summary_path))?;
    ctx.lines.finish(&summary);
    ending.into_result(summary, out_dir)
}

/// `error` after the summary records it (status `failed`, the reason), where the disk
/// still takes it.
fn failed(mut summary: RunSummary, path: &Path, error: RunError) -> RunError {
    summary.status = RunStatus::Failed;
    summary.error = Some(error.to_string());
    let _ = summary.write(path);
    error
}

/// A panic's message, where it is text.
fn panic_message(panic: &(dyn std::any::Any + Send)) -> &str {
    (panic.downcast_ref::<&str>().copied())
        .or_else(|| panic.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("(no message)")
}

/// The run's batches: the events at t = 0 of a fresh run (a resumed one's are on the disk
/// already), then a batch to the earliest event or the end and the events it made due,
/// until the run stops (`Ctx::stopping`); then the stop's checkpoint and last frame.
fn step_through(ctx: &mut Ctx, events: &mut Events, resumed: bool) -> Result<Stop, RunFailure> {
    if resumed {
        ctx.check()?;
        ctx.last = ctx.solver.diagnostics();
    } else {
        events.fire_due(ctx)?;
    }
    let stop = loop {
        if let Some(stop) = ctx.stopping() {
            break stop;
        }
        ctx.batch(events.next_time())?;
        events.fire_due(ctx)?;
    };
    events.stop(ctx)?;
    Ok(stop)
}
