//! A run's set-up: the scene's overrides and validation, the particles, the output
//! directory made ready (or rolled back to a checkpoint), the solver (restored from the
//! checkpoint where resumed) and its stepper, the writer, the lines that open the run, and
//! the summary's fields that it owns.

use std::io::Write as _;
use std::time::Instant;

use meshfree_core::backend;
use meshfree_core::measure::voids::VoidMeter;
use meshfree_core::named::Named;
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::{Counts, Overrides, Scene};
use meshfree_core::solver::frame::{Field, Fields};
use meshfree_core::solver::step::Stepper;
use meshfree_core::solver::{BackendInfo, Solver};

use super::context::Clock;
use super::lines::Lines;
use super::out_dir::{default_out_dir, prepare_out_dir};
use super::{io_err, RunError, RunOptions};
use crate::analysis::bodies::BodyTracker;
use crate::analysis::clusters;
use crate::output::files::{self, DirLock};
use crate::output::writer::{self, Writer};
use crate::output::{RunStatus, RunSummary, Timing};
use crate::resume::Resume;

/// A run set up, before its first step.
pub(super) struct Setup<'o> {
    /// The scene with the run's overrides (`--t-end`, `--output-interval`), naming its
    /// surfaces' copies in the run's directory.
    pub scene: Scene,
    /// The names of those copies and of its motion series' (`surface-N.<ext>`,
    /// `motion-N.csv`).
    pub surfaces: Vec<String>,
    pub out_dir: std::path::PathBuf,
    pub solver: Box<dyn Solver>,
    pub info: BackendInfo,
    pub stepper: Stepper,
    pub counts: Counts,
    /// The particle files' format (the scene's, or `--format`).
    pub format: OutputFormat,
    /// The fields each output's capture copies: the written ones and what the writer's
    /// analyses need besides.
    pub capture: Fields,
    pub writer: Writer<'o>,
    pub clock: Clock,
    /// The checkpoint times [T] this run was resumed from, in order (this one last).
    pub resumed_from: Vec<f64>,
    /// [T] the time of the checkpoint it continues from.
    pub checkpoint_time: Option<f64>,
    /// The directory's lock, for a fresh run (a resumed one's is the `Resume`'s).
    pub _lock: Option<DirLock>,
}

impl<'o> Setup<'o> {
    /// Set up `scene` for a run with `options`, from the start or from `resume`.
    pub fn new(
        scene: &Scene,
        options: &RunOptions,
        observer: Option<writer::Observer<'o>>,
        resume: Option<&Resume>,
    ) -> Result<Setup<'o>, RunError> {
        let started = Instant::now();
        let scene = scene.with_overrides(&Overrides {
            t_end: options.t_end,
            output_interval: options.output_interval,
        })?;
        scene.check_size(options.max_particles)?;
        // A fresh run copies its surfaces' and series' files into its directory and its
        // copy of the scene names them there; a resumed run's scene already does.
        let (scene, surface_copies) = match resume {
            None => scene.with_surface_copies()?,
            Some(_) => (scene, Vec::new()),
        };
        let surfaces: Vec<String> = meshfree_core::scene::geometry::surfaces(&scene.file)
            .into_iter()
            .filter_map(|p| p.outline.file.clone())
            .filter(|f| meshfree_core::run_files::surface_index(f).is_some())
            .chain(
                meshfree_core::scene::motion_series::series_of(&scene.file)
                    .into_iter()
                    .chain(meshfree_core::scene::motion_series::inlet_series_of(
                        &scene.file,
                    ))
                    .map(|(_, r)| r.file.clone())
                    .filter(|f| {
                        meshfree_core::run_files::motion_index(f).is_some()
                            || meshfree_core::run_files::inflow_index(f).is_some()
                    }),
            )
            .collect();
        let setup = scene.setup()?;
        let counts = Counts::of(&setup.particles);
        let mut fields = scene.file.output.fields(&setup.particles);
        let format = options.format.unwrap_or(scene.file.output.format);
        // A CSV frame is ordered by id, and other codes' files are compared with it by id:
        // its default fields keep it.
        if format == OutputFormat::Csv && scene.file.output.fields.is_none() {
            fields = fields.with(Field::Id);
        }
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
        let mut solver = create_solver(&scene, setup, options)?;
        let info = solver.info();
        let mut stepper = Stepper::new(scene.gates()).with_end(scene.file.time.end);
        if let Some(r) = resume {
            stepper.resume(&r.run.stepper, &mut *solver);
            r.solver
                .restore_into(&mut *solver)
                .map_err(|reason| RunError::Checkpoint {
                    path: out_dir.join(crate::output::checkpoint::FILE),
                    reason: format!("does not fit the scene: {reason}"),
                })?;
        }
        let before = resume.map(|r| r.run.timing).unwrap_or_default();
        let clock = Clock {
            started,
            // Reading the scene's surface files happened with the scene, before this.
            setup_seconds: before.setup_seconds
                + scene.surfaces_seconds()
                + started.elapsed().as_secs_f64(),
            before,
        };

        let spec = &scene.file.output;
        let cluster_radius = spec
            .clusters
            .then_some(clusters::DEFAULT_FACTOR * scene.file.discretisation.spacing as f32);
        // What the writer's analysis needs besides the written fields.
        let mut capture = if format == OutputFormat::None {
            Fields::NONE
        } else {
            fields
        };
        // An observer (`run::run_observed`: validation, tests) follows particles by id and
        // tells them apart by kind and group, whatever the files carry.
        if cluster_radius.is_some() || voids.is_some() || !bodies.is_empty() || observer.is_some() {
            capture = capture.union(Fields::of(&[
                Field::Position,
                Field::Velocity,
                Field::Density,
                Field::Kind,
                Field::Id,
                Field::Group,
            ]));
        }

        // Everything that can refuse the run has been checked: only now is the directory
        // touched, under its lock (a resume took it before reading the checkpoint).
        std::fs::create_dir_all(&out_dir).map_err(io_err(&out_dir))?;
        let lock = match resume {
            Some(_) => None,
            None => Some(DirLock::take(&out_dir)?),
        };
        match resume {
            None => {
                let monitors: Vec<String> =
                    scene.file.monitors.iter().map(|m| m.name.clone()).collect();
                prepare_out_dir(&out_dir, options.overwrite, &monitors)?;
                for copy in &surface_copies {
                    let path = out_dir.join(&copy.name);
                    (files::create_new(&path))
                        .and_then(|mut f| f.write_all(&copy.bytes))
                        .map_err(io_err(&path))?;
                }
                let scene_copy = out_dir.join(files::SCENE);
                (files::create_new(&scene_copy))
                    .and_then(|mut f| f.write_all(scene.text.as_bytes()))
                    .map_err(io_err(&scene_copy))?;
            }
            Some(r) => crate::resume::rollback(&out_dir, r)?,
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
            resume.map(|r| &r.run.writer),
        )?;
        Ok(Setup {
            scene,
            surfaces,
            out_dir,
            solver,
            info,
            stepper,
            counts,
            format,
            capture,
            writer,
            clock,
            resumed_from: resume.map_or_else(Vec::new, |r| {
                let mut v = r.run.resumed_from.clone();
                v.push(r.solver.clock().time);
                v
            }),
            checkpoint_time: resume.map(|r| r.solver.clock().time),
            _lock: lock,
        })
    }

    /// [T] the run's end (the scene's, or `--t-end`).
    pub fn t_end(&self) -> f64 {
        self.scene.file.time.end
    }

    /// The lines that open the run: where a resumed one continues from, and what runs
    /// where.
    pub fn announce(&self, lines: &Lines, resume: Option<&Resume>) {
        if let Some(r) = resume {
            lines.line(&format!(
                "meshfree: resuming {} from its checkpoint at t = {} (step {}, written by {} on build {})",
                self.out_dir.display(),
                r.solver.clock().time,
                r.solver.clock().steps,
                r.run.backend,
                r.run.build
            ));
        }
        let (scene, counts, info) = (&self.scene, &self.counts, &self.info);
        lines.line(&format!(
            "meshfree: {} ({}) on {} ({}): {} particles ({} fluid, {} solid, {} boundary) -> {} ({}, set-up {:.2} s)",
            scene.name(),
            scene.origin(),
            info.backend,
            info.device,
            counts.total,
            counts.fluid,
            counts.solid,
            counts.boundary,
            self.out_dir.display(),
            self.format.name(),
            self.clock.setup_seconds,
        ));
    }

    /// The summary as the run starts (`running`): the fields the set-up owns (the scene,
    /// the backend, the particles, the output, where it was resumed from), the others
    /// empty until the parts that own them fill them at the end.
    pub fn summary(&self) -> RunSummary {
        RunSummary {
            scene: self.scene.name().to_string(),
            scene_source: self.scene.origin(),
            dimension: self.scene.file.dimension,
            backend: self.info.backend.clone(),
            device: self.info.device.clone(),
            particles: self.counts,
            steps: 0,
            simulated_time: 0.0,
            wall_seconds: 0.0,
            particle_steps_per_second: 0.0,
            outputs: 0,
            output_dir: self.out_dir.display().to_string(),
            output_format: self.format,
            output_bytes: 0,
            writer_mb_per_second: None,
            output_advice: None,
            timing: Timing::default(),
            final_diagnostics: None,
            fluid_clusters: None,
            voids: None,
            status: RunStatus::Running,
            fault: None,
            interrupted_by: None,
            error: None,
            files: Vec::new(),
            fault_frame: None,
            monitors: Vec::new(),
            bodies: Vec::new(),
            open_boundaries: Vec::new(),
            checkpoint_time: self.checkpoint_time,
            resumed_from: self.resumed_from.clone(),
        }
    }
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
        (Some(g), _) => backend::create(
            backend::BackendChoice::Cuda,
            backend::Layout::Gpus(g),
            setup,
        )?,
        (None, Some(n)) => backend::create(options.backend, backend::Layout::Threads(n), setup)?,
        (None, None) => backend::create(options.backend, backend::Layout::One, setup)?,
    })
}
