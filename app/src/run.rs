//! The run driver: scene -> solver -> output directory. Used by the CLI, the tests and
//! the viewer.
//!
//! Order of work: apply overrides and validate, generate particles, build the solver, and
//! only then create the output directory (a scene that fails validation writes nothing).
//! Then: output at t = 0; loop { one batch of `meshfree_core::step::Stepper` towards the
//! next output or monitor sample (it opens the gates on time and checks the health every
//! `step::CHECK_EVERY` steps); a health check and an output at each output time }; a last
//! output at the end. Each output writes `particles_NNNNN.vtu`, rewrites `particles.pvd`, appends a
//! row to `diagnostics.csv` and one to `clusters.csv` (the number of connected fluid
//! clusters, `analysis::clusters`) and, in a scene with elastic bodies, a row per body to
//! `bodies.csv` (centroid, velocity, angular velocity, size and spread against t = 0,
//! `analysis::bodies`). Force monitors (`crate::monitors`) sample at t = 0 and
//! every `interval` after it (a step boundary at or past the time) into `<name>.csv`.
//! `summary.json` is written at the end, also after a blow-up, with the cluster count of
//! the last output and each body's extremes.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use meshfree_core::backend::{self, BackendChoice, BackendError};
use meshfree_core::particle::Particle;
use meshfree_core::scene::{Counts, Overrides, Scene, SceneError};
use meshfree_core::solver::{Diagnostics, Fault, Solver};
use meshfree_core::step::{reached, Stepper};

use crate::analysis::bodies::BodyTracker;
use crate::analysis::clusters;
use crate::monitors::Monitors;
use crate::output::{self, BodiesCsv, DiagnosticsCsv, PvdSeries, RunStatus, RunSummary};
use crate::probes::Probes;

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

/// Options of one run. `Default` runs on `auto` into `out/<scene name>`.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    pub backend: BackendChoice,
    /// Default `out/<scene name>`.
    pub out_dir: Option<PathBuf>,
    /// Replaces the scene's `time.end`.
    pub t_end: Option<f64>,
    /// Stop after this many steps (also before `t_end`).
    pub max_steps: Option<u64>,
    /// Replaces the scene's `time.output_interval`.
    pub output_interval: Option<f64>,
    pub progress: Progress,
    /// Also write each output as a plain particle CSV (`particles_NNNNN.csv`).
    pub particle_csv: bool,
}

/// Why a run did not complete.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A blow-up: output written so far is kept, `summary.json` holds the fault.
    #[error("{fault} (output so far in {})", out_dir.display())]
    BlowUp {
        fault: Box<Fault>,
        out_dir: PathBuf,
        summary: Box<RunSummary>,
    },
}

/// What an observer sees at each output.
pub struct Frame<'a> {
    pub index: usize,
    pub diagnostics: &'a Diagnostics,
    /// Ordered by id.
    pub particles: &'a [Particle],
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |source| RunError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Run `scene` to its end time (or `max_steps`), writing output. See the module docs.
pub fn run(scene: &Scene, options: &RunOptions) -> Result<RunSummary, RunError> {
    run_observed(scene, options, &mut |_| {})
}

/// `run`, calling `observer` at each output with the particles just written.
pub fn run_observed(
    scene: &Scene,
    options: &RunOptions,
    observer: &mut dyn FnMut(&Frame),
) -> Result<RunSummary, RunError> {
    let started = Instant::now();
    let scene = scene.with_overrides(&Overrides {
        t_end: options.t_end,
        output_interval: options.output_interval,
    })?;
    let setup = scene.setup()?;
    let counts = Counts::of(&setup.particles);
    let with_stress = setup.has_solids();
    let bodies = BodyTracker::new(&setup.particles, scene.file.dimension);
    let out_dir = options
        .out_dir
        .clone()
        .unwrap_or_else(|| Path::new("out").join(scene.name()));
    let mut solver = backend::create(options.backend, setup)?;
    let info = solver.info();

    std::fs::create_dir_all(&out_dir).map_err(io_err(&out_dir))?;
    let scene_copy = out_dir.join("scene.toml");
    std::fs::write(&scene_copy, &scene.text).map_err(io_err(&scene_copy))?;
    let csv_path = out_dir.join("diagnostics.csv");
    let clusters_path = out_dir.join("clusters.csv");
    let mut clusters_csv = std::fs::File::create(&clusters_path).map_err(io_err(&clusters_path))?;
    writeln!(clusters_csv, "step,time,fluid_clusters").map_err(io_err(&clusters_path))?;
    let bodies_path = out_dir.join("bodies.csv");
    let bodies_csv = if bodies.is_empty() {
        None
    } else {
        Some(BodiesCsv::create(&bodies_path).map_err(io_err(&bodies_path))?)
    };
    let mut out = Writer {
        clusters_csv,
        bodies,
        bodies_csv,
        cluster_radius: clusters::DEFAULT_FACTOR * scene.file.discretisation.spacing as f32,
        last_clusters: None,
        dir: out_dir.clone(),
        pvd: PvdSeries::new(out_dir.join("particles.pvd")),
        csv: DiagnosticsCsv::create(&csv_path).map_err(io_err(&csv_path))?,
        frames: 0,
        with_stress,
        particle_csv: options.particle_csv,
    };
    let mut monitors = Monitors::create(&scene, &out_dir)
        .map_err(|(path, source)| RunError::Io { path, source })?;
    let mut probes =
        Probes::create(&scene, &out_dir).map_err(|(path, source)| RunError::Io { path, source })?;

    let t_end = scene.file.time.end;
    let interval = scene.file.time.output_interval;
    let mut report = Reporter::new(options.progress, t_end, options.max_steps);
    report.line(&format!(
        "meshfree: {} ({}) on {} ({}): {} particles ({} fluid, {} solid, {} boundary) -> {}",
        scene.name(),
        scene.origin(),
        info.backend,
        info.device,
        counts.total,
        counts.fluid,
        counts.solid,
        counts.boundary,
        out_dir.display()
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
        final_diagnostics: None,
        fluid_clusters: None,
        status: RunStatus::Completed,
        fault: None,
        monitors: Vec::new(),
        bodies: Vec::new(),
    };

    let mut stepper = Stepper::new(scene.gates());
    let first_step = solver.steps();

    let result = (|| -> Result<(), RunFailure> {
        solver.check().map_err(RunFailure::Fault)?;
        let mut last = out.output(&mut *solver, observer)?;
        monitors.sample_due(&mut *solver)?;
        probes.sample_due(&mut *solver)?;
        let mut next_output = interval;
        loop {
            let t = solver.time();
            let taken = solver.steps() - first_step;
            if reached(t, t_end) || options.max_steps.is_some_and(|n| taken >= n) {
                break;
            }
            let next_event = next_output
                .min(t_end)
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
                last = out.output(&mut *solver, observer)?;
                next_output = ((t_new / interval + 1e-9).floor() + 1.0) * interval;
            }
            monitors.sample_due(&mut *solver)?;
            probes.sample_due(&mut *solver)?;
            report.progress(t_new, solver.steps() - first_step, &last);
        }
        if last.step != solver.steps() {
            solver.check().map_err(RunFailure::Fault)?;
            out.output(&mut *solver, observer)?;
        }
        Ok(())
    })();

    let steps = solver.steps() - first_step;
    summary.steps = steps;
    summary.simulated_time = solver.time();
    summary.outputs = out.frames;
    summary.wall_seconds = started.elapsed().as_secs_f64();
    let step_seconds = stepper.stepping_seconds();
    summary.particle_steps_per_second = if step_seconds > 0.0 {
        counts.total as f64 * steps as f64 / step_seconds
    } else {
        0.0
    };
    summary.final_diagnostics = Some(solver.diagnostics());
    summary.fluid_clusters = out.last_clusters;
    summary.monitors = monitors.summaries();
    summary.bodies = out.bodies.summaries();
    let failure = match result {
        Ok(()) => None,
        Err(RunFailure::Fault(f)) => {
            summary.status = RunStatus::Failed;
            summary.fault = Some(f.clone());
            Some(f)
        }
        Err(RunFailure::Io(e)) => return Err(e),
    };
    let summary_path = out_dir.join("summary.json");
    summary
        .write(&summary_path)
        .map_err(io_err(&summary_path))?;
    report.finish(&summary);
    match failure {
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
    fn from((path, source): (PathBuf, std::io::Error)) -> Self {
        RunFailure::Io(RunError::Io { path, source })
    }
}

struct Writer {
    dir: PathBuf,
    clusters_csv: std::fs::File,
    /// [L] link radius of the cluster count.
    cluster_radius: f32,
    last_clusters: Option<usize>,
    /// The elastic bodies and `bodies.csv` (None in a scene without solids).
    bodies: BodyTracker,
    bodies_csv: Option<BodiesCsv>,
    pvd: PvdSeries,
    csv: DiagnosticsCsv,
    frames: usize,
    with_stress: bool,
    particle_csv: bool,
}

impl Writer {
    /// One output: VTK file, pvd, CSV row. Returns the diagnostics written.
    fn output(
        &mut self,
        solver: &mut dyn Solver,
        observer: &mut dyn FnMut(&Frame),
    ) -> Result<Diagnostics, RunError> {
        let d = solver.diagnostics();
        let particles = solver.particles();
        let name = format!("particles_{:05}.vtu", self.frames);
        let path = self.dir.join(&name);
        output::write_vtu(&path, &particles, self.with_stress).map_err(io_err(&path))?;
        if self.particle_csv {
            let path = self.dir.join(format!("particles_{:05}.csv", self.frames));
            output::write_particles_csv(&path, &particles).map_err(io_err(&path))?;
        }
        self.pvd
            .add(d.time, &name)
            .map_err(io_err(self.pvd.path()))?;
        self.csv
            .write(&d)
            .map_err(io_err(&self.dir.join("diagnostics.csv")))?;
        let n = clusters::count_fluid_clusters(&particles, self.cluster_radius);
        self.last_clusters = Some(n);
        writeln!(self.clusters_csv, "{},{},{n}", d.step, d.time)
            .map_err(io_err(&self.dir.join("clusters.csv")))?;
        if let Some(csv) = self.bodies_csv.as_mut() {
            let rows = self.bodies.sample(&particles);
            csv.write(d.step, d.time, &rows)
                .map_err(io_err(&self.dir.join("bodies.csv")))?;
        }
        observer(&Frame {
            index: self.frames,
            diagnostics: &d,
            particles: &particles,
        });
        self.frames += 1;
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
        };
        self.line(&format!(
            "{status}: {} steps to t = {:.4} in {:.2} s ({:.3e} particle-steps/s), {} outputs in {}",
            s.steps, s.simulated_time, s.wall_seconds, s.particle_steps_per_second, s.outputs, s.output_dir
        ));
        for m in &s.monitors {
            self.line(&m.to_string());
        }
    }
}
