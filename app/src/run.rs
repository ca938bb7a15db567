//! The run driver: scene -> solver -> output directory. Used by the CLI, the tests and
//! the viewer.
//!
//! Order of work: apply overrides and validate, generate particles, build the solver, and
//! only then create the output directory (a scene that fails validation writes nothing).
//! Then: output at t = 0; loop { one batch of `meshfree_core::step::Stepper` towards the
//! next output or monitor sample (it opens the gates on time and checks the health every
//! `step::CHECK_EVERY` steps); a health check and an output at each output time }; a last
//! output at the end.
//!
//! An output never stalls the stepping for long: the main thread reads the diagnostics,
//! starts the frame's copy (`Solver::capture`: on the GPU a device-side copy that a second
//! stream downloads) and queues it for the writer thread (`output::writer`), which writes
//! the particle file (`[output] format` and `fields`: binary VTU with `particles.pvd`,
//! zlib VTU, CSV or none), the row of `diagnostics.csv`, `clusters.csv` where `[output]
//! clusters` asks, and, in a scene with elastic bodies, a row per body to `bodies.csv`.
//! Force monitors (`crate::monitors`) sample at t = 0 and every `interval` after it (a step
//! boundary at or past the time) into `<name>.csv`; probes and gauges (`crate::probes`)
//! likewise into `probes.csv` and `gauges.csv`, sampled on the device. `summary.json` is written at the end,
//! also after a blow-up, with the timing split (set-up, stepping, output waits, the
//! writer's busy time), the cluster count of the last output and each body's extremes.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Instant;

use meshfree_core::backend::{self, BackendChoice};
use meshfree_core::frame::{Field, Fields};
use meshfree_core::named::Named;
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::{paper_exact, Counts, Overrides, Scene, SceneSource};
use meshfree_core::solver::{Diagnostics, Fault, Solver};
use meshfree_core::step::{reached, Stepper};

use crate::analysis::bodies::BodyTracker;
use crate::analysis::clusters;
use crate::monitors::Monitors;
use crate::output::writer::{self, Writer};
use crate::output::{RunStatus, RunSummary, Timing};
use crate::probes::Probes;
use meshfree_core::voids::VoidMeter;

pub use crate::output::writer::Frame;
pub use crate::run_error::RunError;

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

/// The output directory of a scene when none is given: `out/<file stem>` for a scene file
/// (a copy of a built-in keeps its `name`, not its directory), `out/<name>` otherwise;
/// `-paper-exact` appended for the paper's form (`Scene::with_paper_exact`).
pub fn default_out_dir(scene: &Scene) -> PathBuf {
    let stem = match &scene.source {
        SceneSource::File(p) => p.file_stem().map(|s| s.to_string_lossy().into_owned()),
        _ => None,
    };
    let Some(mut stem) = stem else {
        return Path::new("out").join(scene.name());
    };
    if scene.name().ends_with(paper_exact::NAME_SUFFIX) {
        stem.push_str(paper_exact::NAME_SUFFIX);
    }
    Path::new("out").join(stem)
}

/// The files a run writes into its directory: particle files, the series, CSVs, JSON, the
/// scene copy and temporaries of the atomic writes.
fn is_run_file(name: &str) -> bool {
    name == "scene.toml"
        || [".vtu", ".pvd", ".csv", ".json", ".tmp", ".png", ".bin"]
            .iter()
            .any(|e| name.ends_with(e))
}

/// Make `dir` ready for a run: refuse an earlier run's output unless `overwrite`, and then
/// remove only files a run writes (a directory with anything else is refused either way).
fn prepare_out_dir(dir: &Path, overwrite: bool) -> Result<(), RunError> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(io_err(dir)(e)),
    };
    let (mut ours, mut others) = (Vec::new(), Vec::new());
    for entry in entries {
        let entry = entry.map_err(io_err(dir))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let file = entry.file_type().map(|t| t.is_file()).unwrap_or(false);
        if file && is_run_file(&name) {
            ours.push(entry.path());
        } else {
            others.push(name);
        }
    }
    let run_there = ours.iter().any(|p| {
        p.file_name()
            .is_some_and(|n| n == "summary.json" || n == "scene.toml" || n == "particles.pvd")
    });
    if !run_there {
        return Ok(());
    }
    if !overwrite {
        return Err(RunError::OutputInUse {
            dir: dir.to_path_buf(),
            reason: format!(
                "holds an earlier run's output ({} files: summary.json, frames, CSVs); pass \
                 --overwrite to replace it, or --out to write elsewhere",
                ours.len()
            ),
        });
    }
    if !others.is_empty() {
        others.sort();
        return Err(RunError::OutputInUse {
            dir: dir.to_path_buf(),
            reason: format!(
                "--overwrite clears only a run's own files, and this directory also holds {} \
                 (`{}`{}): move them or choose another --out",
                others.len(),
                others[0],
                if others.len() > 1 { ", ..." } else { "" }
            ),
        });
    }
    for path in ours {
        std::fs::remove_file(&path).map_err(io_err(&path))?;
    }
    Ok(())
}

/// The run's solver: one domain, `decompose` subdomains, one per GPU, or one per MPI
/// process.
fn create_solver(
    scene: &Scene,
    setup: meshfree_core::solver::Setup,
    options: &RunOptions,
) -> Result<Box<dyn Solver>, RunError> {
    if options.mpi {
        #[cfg(feature = "mpi")]
        return Ok(crate::mpi::lead(scene, setup, options.backend)?);
        #[cfg(not(feature = "mpi"))]
        return Err(
            backend::BackendError::Launch("this build has the `mpi` feature off".into()).into(),
        );
    }
    let _ = scene;
    Ok(match (options.gpus, options.decompose) {
        (Some(g), _) => backend::create(BackendChoice::Cuda, backend::Layout::Gpus(g), setup)?,
        (None, Some(n)) => backend::create(options.backend, backend::Layout::Threads(n), setup)?,
        (None, None) => backend::create(options.backend, backend::Layout::One, setup)?,
    })
}

/// Run `scene` to its end time (or `max_steps`), writing output. See the module docs.
pub fn run(scene: &Scene, options: &RunOptions) -> Result<RunSummary, RunError> {
    run_observed(scene, options, &mut |_| {})
}

/// `run`, calling `observer` on the writer thread at each output, once its files landed.
pub fn run_observed(
    scene: &Scene,
    options: &RunOptions,
    observer: writer::Observer,
) -> Result<RunSummary, RunError> {
    drive(scene, options, observer, None)
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
    drive(&scene, &options, &mut |_| {}, Some(r))
}

/// A run from the start (`resume` None) or from a checkpoint.
fn drive(
    scene: &Scene,
    options: &RunOptions,
    observer: writer::Observer,
    resume: Option<crate::resume::Resume>,
) -> Result<RunSummary, RunError> {
    let started = Instant::now();
    let scene = scene.with_overrides(&Overrides {
        t_end: options.t_end,
        output_interval: options.output_interval,
    })?;
    scene.check_size(options.max_particles)?;
    let setup = scene.setup()?;
    let counts = Counts::of(&setup.particles);
    let with_solids = setup.has_solids();
    let bodies = BodyTracker::new(&setup.particles, scene.file.dimension);
    let voids = scene
        .file
        .output
        .voids
        .then(|| VoidMeter::new(&scene.file, &setup.particles));
    let mut masses = Vec::new();
    if !bodies.is_empty() {
        masses = vec![0.0f32; setup.particles.len()];
        for q in &setup.particles {
            if let Some(m) = masses.get_mut(q.id as usize) {
                *m = q.mass;
            }
        }
    }
    let out_dir = options
        .out_dir
        .clone()
        .unwrap_or_else(|| default_out_dir(&scene));
    match &resume {
        None => prepare_out_dir(&out_dir, options.overwrite)?,
        Some(r) => crate::resume::rollback(&out_dir, r)?,
    }
    let mut solver = create_solver(&scene, setup, options)?;
    let info = solver.info();
    let mut stepper = Stepper::new(scene.gates()).with_end(scene.file.time.end);
    if let Some(r) = &resume {
        stepper.resume(&r.run.stepper, &mut *solver);
        r.solver
            .restore_into(&mut *solver)
            .map_err(|reason| RunError::Checkpoint {
                path: out_dir.join(crate::output::checkpoint::FILE),
                reason: format!("does not fit the scene: {reason}"),
            })?;
    }
    let before = resume.as_ref().map(|r| r.run.timing).unwrap_or_default();
    let setup_seconds = before.setup_seconds + started.elapsed().as_secs_f64();

    let spec = &scene.file.output;
    let format = options.format.unwrap_or(spec.format);
    let fields = spec.fields(with_solids);
    let cluster_radius = spec
        .clusters
        .then_some(clusters::DEFAULT_FACTOR * scene.file.discretisation.spacing as f32);
    // What the writer's analysis needs besides the written fields.
    let mut capture = if format == OutputFormat::None {
        Fields::NONE
    } else {
        fields
    };
    if cluster_radius.is_some() || voids.is_some() || !bodies.is_empty() {
        capture = capture.union(Fields::of(&[
            Field::Position,
            Field::Velocity,
            Field::Density,
            Field::Kind,
            Field::Id,
            Field::Group,
        ]));
    }

    std::fs::create_dir_all(&out_dir).map_err(io_err(&out_dir))?;
    if resume.is_none() {
        let scene_copy = out_dir.join("scene.toml");
        std::fs::write(&scene_copy, &scene.text).map_err(io_err(&scene_copy))?;
    }
    let writer = Writer::create(
        writer::Config {
            dir: out_dir.clone(),
            format,
            fields,
            cluster_radius,
            voids,
            bodies,
            masses,
        },
        observer,
        resume.as_ref().map(|r| &r.run.writer),
    )?;
    let mut monitors =
        Monitors::create(&scene, &out_dir, resume.as_ref().map(|r| &r.run.monitors))?;
    let mut probes = Probes::create(&scene, &out_dir, resume.as_ref().map(|r| &r.run.probes))?;

    let t_end = scene.file.time.end;
    let interval = scene.file.time.output_interval;
    let mut report = Reporter::new(options.progress, t_end, options.max_steps);
    if let Some(r) = &resume {
        report.line(&format!(
            "meshfree: resuming {} from its checkpoint at t = {} (step {}, written by {} on build {})",
            out_dir.display(),
            r.solver.clock().time,
            r.solver.clock().steps,
            r.run.backend,
            r.run.build
        ));
    }
    report.line(&format!(
        "meshfree: {} ({}) on {} ({}): {} particles ({} fluid, {} solid, {} boundary) -> {} ({}, set-up {:.2} s)",
        scene.name(),
        scene.origin(),
        info.backend,
        info.device,
        counts.total,
        counts.fluid,
        counts.solid,
        counts.boundary,
        out_dir.display(),
        format.name(),
        setup_seconds,
    ));

    let mut summary = RunSummary {
        scene: scene.name().to_string(),
        scene_source: scene.origin(),
        dimension: scene.file.dimension,
        backend: info.backend.clone(),
        device: info.device.clone(),
        particles: counts,
        steps: 0,
        simulated_time: 0.0,
        wall_seconds: 0.0,
        particle_steps_per_second: 0.0,
        outputs: 0,
        output_dir: out_dir.display().to_string(),
        output_format: format,
        output_bytes: 0,
        timing: Timing::default(),
        final_diagnostics: None,
        fluid_clusters: None,
        voids: None,
        status: RunStatus::Running,
        fault: None,
        interrupted_by: None,
        fault_frame: None,
        monitors: Vec::new(),
        bodies: Vec::new(),
        checkpoint_time: resume.as_ref().map(|r| r.solver.clock().time),
        resumed_from: resume.as_ref().map_or_else(Vec::new, |r| {
            let mut v = r.run.resumed_from.clone();
            v.push(r.solver.clock().time);
            v
        }),
    };

    // A run killed outright (kill -9, power) leaves `running` behind, not an older status.
    let summary_path = out_dir.join("summary.json");
    summary
        .write(&summary_path)
        .map_err(io_err(&summary_path))?;
    let interrupted = || options.interrupt.is_some_and(|f| f.load(Ordering::SeqCst));
    let mut stopped = false;
    let mut fault_frame = None;

    let first_step = solver.steps();
    let mut out = Outputs {
        jobs: None,
        capture,
        wait_seconds: before.output_wait_seconds,
        taken: resume.as_ref().map_or(0, |r| r.run.writer.frames),
        warned: false,
    };
    // What each checkpoint records of the run besides the solver (`crate::resume`).
    let run_state = crate::resume::RunState {
        build: meshfree_core::build_info::COMMIT.to_string(),
        backend: info.backend.clone(),
        scene_digest: crate::resume::digest(&scene.text),
        t_end,
        output_interval: interval,
        format,
        next_output: interval,
        next_checkpoint: spec.checkpoint_interval,
        stepper: Default::default(),
        monitors: Default::default(),
        probes: Default::default(),
        writer: Default::default(),
        timing: Timing::default(),
        resumed_from: summary.resumed_from.clone(),
    };
    let checkpoint_path = out_dir.join(crate::output::checkpoint::FILE);

    let (result, written) = std::thread::scope(|scope| {
        let (tx, rx) = mpsc::sync_channel::<writer::Job>(1);
        let thread = std::thread::Builder::new()
            .name("meshfree-writer".into())
            .spawn_scoped(scope, move || writer.serve(rx))
            .expect("spawning the writer thread");
        out.jobs = Some(tx);
        let result = (|| -> Result<(), RunFailure> {
            solver.check().map_err(RunFailure::Fault)?;
            let mut last = match &resume {
                // The checkpoint's outputs and samples are on the disk already.
                Some(_) => solver.diagnostics(),
                None => {
                    let d = out.take(&mut *solver, &report)?;
                    monitors.sample_due(&mut *solver)?;
                    probes.sample_due(&mut *solver)?;
                    d
                }
            };
            let mut next_output = resume.as_ref().map_or(interval, |r| r.run.next_output);
            let mut next_checkpoint = match &resume {
                Some(r) => r.run.next_checkpoint,
                None => spec.checkpoint_interval,
            };
            // A checkpoint of the run as it stands (after this step's output and samples).
            let checkpoint = |solver: &mut dyn Solver,
                              out: &mut Outputs,
                              stepper: &Stepper,
                              monitors: &Monitors,
                              probes: &Probes,
                              next_output: f64,
                              next_checkpoint: Option<f64>|
             -> Result<(), RunFailure> {
                let mut state = run_state.clone();
                state.next_output = next_output;
                state.next_checkpoint = next_checkpoint;
                state.stepper = stepper.state();
                state.monitors = monitors.state()?;
                state.probes = probes.state()?;
                state.timing = Timing {
                    setup_seconds,
                    stepping_seconds: stepper.stepping_seconds(),
                    output_wait_seconds: out.wait_seconds,
                    total_seconds: before.total_seconds + started.elapsed().as_secs_f64(),
                    ..Timing::default()
                };
                let waited = Instant::now();
                out.send(crate::resume::checkpoint_job(
                    checkpoint_path.clone(),
                    crate::output::checkpoint::Saved::of(solver),
                    state,
                ))?;
                out.wait_seconds += waited.elapsed().as_secs_f64();
                Ok(())
            };
            loop {
                let t = solver.time();
                let taken = solver.steps() - first_step;
                if reached(t, t_end) || options.max_steps.is_some_and(|n| taken >= n) {
                    break;
                }
                if interrupted() {
                    stopped = true;
                    break;
                }
                let next_event = next_output
                    .min(t_end)
                    .min(next_checkpoint.unwrap_or(f64::INFINITY))
                    .min(monitors.next_time().unwrap_or(f64::INFINITY))
                    .min(probes.next_time().unwrap_or(f64::INFINITY));
                let budget = options.max_steps.map_or(u64::MAX, |n| n - taken);
                let batch = stepper
                    .batch(&mut *solver, next_event, budget)
                    .map_err(RunFailure::Fault)?;
                for (group, n) in batch.opened {
                    report.line(&format!(
                        "t = {t:.4}: gate (group {group}) removed, {n} particles"
                    ));
                }
                let t_new = solver.time();
                if reached(t_new, next_output) {
                    solver.check().map_err(RunFailure::Fault)?;
                    last = out.take(&mut *solver, &report)?;
                    next_output = ((t_new / interval + 1e-9).floor() + 1.0) * interval;
                }
                monitors.sample_due(&mut *solver)?;
                probes.sample_due(&mut *solver)?;
                if let (Some(at), Some(every)) = (next_checkpoint, spec.checkpoint_interval) {
                    if reached(t_new, at) && !reached(t_new, t_end) {
                        solver.check().map_err(RunFailure::Fault)?;
                        next_checkpoint = Some(((t_new / every + 1e-9).floor() + 1.0) * every);
                        checkpoint(
                            &mut *solver,
                            &mut out,
                            &stepper,
                            &monitors,
                            &probes,
                            next_output,
                            next_checkpoint,
                        )?;
                    }
                }
                report.progress(t_new, solver.steps() - first_step, &last);
            }
            // A checkpoint wherever the run stops short of a blow-up (its end, --steps, a
            // signal), and the state it reached as a last frame where no output took it.
            // The checkpoint comes first: a resumed run removes that off-schedule frame and
            // goes on as the run in one go would have.
            let unsaved = last.step != solver.steps();
            if unsaved {
                solver.check().map_err(RunFailure::Fault)?;
            }
            checkpoint(
                &mut *solver,
                &mut out,
                &stepper,
                &monitors,
                &probes,
                next_output,
                next_checkpoint,
            )?;
            if unsaved {
                out.take(&mut *solver, &report)?;
            }
            Ok(())
        })();
        // At a blow-up, the failing state is the last frame (its values may be non-finite:
        // that is what it shows).
        if let Err(RunFailure::Fault(_)) = &result {
            // (A fault is found by a health check, which comes before the output of its step.)
            if out.take(&mut *solver, &report).is_ok() {
                fault_frame = Some(out.taken - 1);
            }
        }
        // Closing the channel lets the writer finish the frames it holds.
        out.jobs = None;
        let drained = Instant::now();
        let written = thread.join().expect("the writer thread panicked");
        out.wait_seconds += drained.elapsed().as_secs_f64();
        (result, written)
    });

    // The whole run, every part of it where it was resumed.
    let steps = solver.steps();
    summary.steps = steps;
    summary.simulated_time = solver.time();
    summary.wall_seconds = before.total_seconds + started.elapsed().as_secs_f64();
    let step_seconds = stepper.stepping_seconds();
    summary.particle_steps_per_second = if step_seconds > 0.0 {
        counts.total as f64 * steps as f64 / step_seconds
    } else {
        0.0
    };
    summary.final_diagnostics = Some(solver.diagnostics());
    summary.monitors = monitors.summaries();
    let failure = match (result, written) {
        // A failed write first: it is why the stepping stopped.
        (_, Err(f)) => return Err(f.into()),
        (Err(RunFailure::Io(e)), _) => return Err(e),
        (Ok(()), Ok(w)) => {
            summary.absorb(&w);
            if stopped {
                summary.status = RunStatus::Interrupted;
                summary.interrupted_by = Some(crate::interrupt::signal_name().to_string());
            } else {
                summary.status = RunStatus::Completed;
            }
            None
        }
        (Err(RunFailure::Fault(f)), Ok(w)) => {
            summary.absorb(&w);
            summary.status = RunStatus::Failed;
            summary.fault = Some(f.clone());
            summary.fault_frame = fault_frame;
            Some(f)
        }
    };
    summary.timing = Timing {
        setup_seconds,
        stepping_seconds: step_seconds,
        output_wait_seconds: out.wait_seconds,
        writer_seconds: summary.timing.writer_seconds,
        writer_download_seconds: summary.timing.writer_download_seconds,
        total_seconds: summary.wall_seconds,
    };
    summary
        .write(&summary_path)
        .map_err(io_err(&summary_path))?;
    report.finish(&summary);
    match failure {
        None if stopped => Err(RunError::Interrupted {
            signal: crate::interrupt::signal_name().to_string(),
            out_dir,
            summary: Box::new(summary),
        }),
        None => Ok(summary),
        Some(fault) => Err(RunError::BlowUp {
            fault: Box::new(fault),
            out_dir,
            summary: Box::new(summary),
        }),
    }
}

enum RunFailure {
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

/// The stepping side of the outputs: starts each frame's copy and hands it to the writer.
struct Outputs {
    /// The writer's queue (None once closed).
    jobs: Option<mpsc::SyncSender<writer::Job>>,
    /// The fields each capture copies.
    capture: Fields,
    /// [s] time the stepping waited for the writer (a full queue, a staging set in use, the
    /// final drain).
    wait_seconds: f64,
    taken: usize,
    warned: bool,
}

impl Outputs {
    /// Queue a job for the writer. A writer that stopped (a failed write) is reported by
    /// the join.
    fn send(&mut self, job: writer::Job) -> Result<(), RunError> {
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

    /// One output: diagnostics, the frame's copy started, the job queued. Returns the
    /// diagnostics. A writer that stopped (a failed write) is reported by the join.
    fn take(
        &mut self,
        solver: &mut dyn Solver,
        report: &Reporter,
    ) -> Result<Diagnostics, RunError> {
        let d = solver.diagnostics();
        let waited = Instant::now();
        let frame = solver.capture(self.capture);
        self.send(writer::Job::Frame(writer::FrameJob {
            diagnostics: d.clone(),
            frame,
        }))?;
        let waited = waited.elapsed().as_secs_f64();
        self.wait_seconds += waited;
        self.taken += 1;
        if waited > 0.5 && !self.warned {
            self.warned = true;
            report.line(&format!(
                "meshfree: output {} waited {waited:.2} s for the writer (the disk is slower than the \
                 outputs): fewer [output] fields, a longer output interval or format = \"vtu\" \
                 (uncompressed) help; summary.json's timing says how much in all",
                self.taken - 1
            ));
        }
        Ok(d)
    }
}

/// Progress on stderr: an indicatif bar on a terminal, else a line per tenth of the run.
struct Reporter {
    bar: Option<indicatif::ProgressBar>,
    lines: bool,
    t_end: f64,
    max_steps: Option<u64>,
    next_tenth: u32,
}

impl Reporter {
    fn new(mode: Progress, t_end: f64, max_steps: Option<u64>) -> Reporter {
        let terminal = std::io::stderr().is_terminal();
        let (bar, lines) = match mode {
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
        Reporter {
            bar,
            lines,
            t_end,
            max_steps,
            next_tenth: 1,
        }
    }

    fn line(&self, text: &str) {
        if let Some(bar) = &self.bar {
            bar.println(text);
        } else if self.lines {
            eprintln!("{text}");
        }
    }

    fn progress(&mut self, t: f64, steps: u64, d: &Diagnostics) {
        let mut frac = t / self.t_end;
        if let Some(n) = self.max_steps {
            frac = frac.max(steps as f64 / n.max(1) as f64);
        }
        let frac = frac.clamp(0.0, 1.0);
        if let Some(bar) = &self.bar {
            bar.set_position((frac * 1000.0) as u64);
            if steps % 10 == 0 {
                bar.set_message(format!(
                    "t = {t:.4} step {steps} max|v| = {:.3}",
                    d.max_speed
                ));
            }
        } else if self.lines && frac * 10.0 >= self.next_tenth as f64 {
            while frac * 10.0 >= self.next_tenth as f64 {
                self.next_tenth += 1;
            }
            eprintln!(
                "  {:>3.0}%  t = {t:.4}  step {steps}  (at last output: max|v| = {:.4}, density error = {:.4})",
                frac * 100.0,
                d.max_speed,
                d.density_error
            );
        }
    }

    fn finish(&self, s: &RunSummary) {
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
             stepping {:.2} s, waiting for output {:.2} s (writer busy {:.2} s alongside); {} outputs, \
             {:.1} MB in {}",
            s.steps,
            s.simulated_time,
            s.wall_seconds,
            s.particle_steps_per_second,
            t.setup_seconds,
            t.stepping_seconds,
            t.output_wait_seconds,
            t.writer_seconds,
            s.outputs,
            s.output_bytes as f64 / 1e6,
            s.output_dir
        ));
        for m in &s.monitors {
            self.line(&m.to_string());
        }
    }
}
