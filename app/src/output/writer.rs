//! The output writer thread: everything an output does after the solver has started the
//! frame's copy (`Solver::capture`), off the stepping path.
//!
//! For each frame, in order: wait for the copy (`PendingFrame::wait`: on the GPU, the
//! download on the second stream), write the particle file (`[output] format`) and then
//! rewrite `particles.pvd`, append the row of `diagnostics.csv`, count the fluid clusters
//! into `clusters.csv` where `[output] clusters` asks, measure the void metric into
//! `voids.csv` where `[output] voids` asks (`meshfree_core::measure::voids`, on the host from the
//! frame), measure the elastic bodies into `bodies.csv`, and call the run's observer. The channel holds one frame: a run whose
//! writer falls behind waits at the next output (the run reports that wait as output wait).
//! The first failure (a full disk, an unwritable directory) stops the thread; the run sees
//! it at its next output or at the end, with the path and the reason, and every frame
//! written before it stays readable.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::Instant;

use meshfree_core::measure::voids::{VoidMeter, VoidSummary};
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::solver::frame::{Fields, FrameData, PendingFrame};
use meshfree_core::solver::Diagnostics;
use serde::{Deserialize, Serialize};

use super::vtk::{Compression, VtuWriter};
use super::{BodiesCsv, DiagnosticsCsv, PvdSeries};
use crate::analysis::bodies::{BodySummary, BodyTracker};
use crate::analysis::clusters;

use super::files::{self, BODIES, CLUSTERS, DIAGNOSTICS, VOIDS};

/// What an observer sees at each output (on the writer thread, after the files landed).
pub struct Frame<'a> {
    pub index: usize,
    pub diagnostics: &'a Diagnostics,
    /// The captured fields, in storage order (`FrameData::particles` orders them by id).
    pub data: &'a FrameData,
}

/// An observer of the frames.
pub type Observer<'a> = &'a mut (dyn FnMut(&Frame) + Send);

/// One output for the writer.
pub struct FrameJob {
    pub diagnostics: Diagnostics,
    pub frame: Box<dyn PendingFrame>,
}

/// A checkpoint's last part: given the writer's state (after every frame queued before
/// it landed), write the file (`crate::resume`). Returns its simulated time \[T\] and its
/// size in bytes.
pub type CheckpointJob = Box<dyn FnOnce(WriterState) -> Result<(f64, u64), Failure> + Send>;

/// What the writer does next, in queue order.
pub enum Job {
    Frame(FrameJob),
    Checkpoint(CheckpointJob),
}

/// The writer's part of a checkpoint: its counts, the series and the bodies' extremes so
/// far, and the length of each CSV file it appends to (a resumed run cuts them back).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct WriterState {
    pub frames: usize,
    pub bytes: u64,
    pub busy_seconds: f64,
    pub download_seconds: f64,
    #[serde(default)]
    pub encode_seconds: f64,
    #[serde(default)]
    pub write_seconds: f64,
    pub last_clusters: Option<usize>,
    /// `particles.pvd`'s entries: (time \[T\], file).
    pub series: Vec<(f64, String)>,
    pub bodies: Vec<BodySummary>,
    /// The void metric so far, where measured.
    #[serde(default)]
    pub voids: Option<VoidSummary>,
    /// (file name in the run directory, bytes).
    pub files: Vec<(String, u64)>,
}

/// What the writer needs to know, fixed for a run.
pub struct Config {
    pub dir: PathBuf,
    pub format: OutputFormat,
    /// The fields the particle files carry.
    pub fields: Fields,
    /// \[L\] the cluster count's link radius, where the scene asks for clusters.
    pub cluster_radius: Option<f32>,
    /// The void metric's cells and fluid region, where the scene asks for it.
    pub voids: Option<VoidMeter>,
    /// The elastic bodies (empty without solids).
    pub bodies: BodyTracker,
    /// \[M\] every particle's mass by id (the bodies' measures weigh by mass; frames carry
    /// no mass). Empty without bodies.
    pub masses: Vec<f32>,
}

/// What the writer did, at the end of the run.
#[derive(Debug, Default)]
pub struct Report {
    pub frames: usize,
    /// Bytes of particle files.
    pub bytes: u64,
    /// \[s\] time the writer spent waiting for copies, encoding and writing (overlapped with
    /// the stepping).
    pub busy_seconds: f64,
    /// \[s\] the part of `busy_seconds` spent waiting for the frames' copies (on a GPU, the
    /// downloads).
    pub download_seconds: f64,
    /// \[s\] the part of `busy_seconds` spent building and compressing the particle files'
    /// arrays (VTU).
    pub encode_seconds: f64,
    /// \[s\] the part of `busy_seconds` spent writing the particle files (handing their bytes
    /// to the system: the disk's own writing may go on after).
    pub write_seconds: f64,
    /// The cluster count of the last output, where counted.
    pub last_clusters: Option<usize>,
    pub bodies: Vec<BodySummary>,
    /// The void metric over the outputs, where measured.
    pub voids: Option<VoidSummary>,
    /// The last checkpoint written: its simulated time \[T\] and size in bytes.
    pub checkpoint: Option<(f64, u64)>,
}

/// Why the writer stopped: the file and the reason.
#[derive(Debug)]
pub struct Failure {
    pub path: PathBuf,
    pub reason: String,
}

/// The writer's state on its thread.
pub struct Writer<'o> {
    cfg: Config,
    pvd: PvdSeries,
    diagnostics: DiagnosticsCsv,
    clusters: Option<std::io::BufWriter<std::fs::File>>,
    voids: Option<std::io::BufWriter<std::fs::File>>,
    bodies_csv: Option<BodiesCsv>,
    /// The VTU encoder (its cells kept between frames), for the VTU formats.
    vtu: Option<VtuWriter>,
    observer: Option<Observer<'o>>,
    report: Report,
}

fn fail(path: &Path) -> impl FnOnce(std::io::Error) -> Failure + '_ {
    move |e| Failure {
        path: path.to_path_buf(),
        reason: e.to_string(),
    }
}

impl<'o> Writer<'o> {
    /// Create the CSV files (before the run's first step: an unwritable directory stops the
    /// run before it starts), or, continuing a run from a checkpoint (`resume`: the
    /// writer's state there), open them at their ends and carry on its counts.
    pub fn create(
        mut cfg: Config,
        observer: Option<Observer<'o>>,
        resume: Option<&WriterState>,
    ) -> Result<Writer<'o>, Failure> {
        let append = resume.is_some();
        let d = cfg.dir.join(DIAGNOSTICS);
        let diagnostics = DiagnosticsCsv::open(&d, append).map_err(fail(&d))?;
        let clusters = match cfg.cluster_radius {
            Some(_) => {
                let path = cfg.dir.join(CLUSTERS);
                let f = super::open_csv(&path, "step,time,fluid_clusters", append)
                    .map_err(fail(&path))?;
                Some(f)
            }
            None => None,
        };
        let voids = match cfg.voids {
            Some(_) => {
                let path = cfg.dir.join(VOIDS);
                let f = super::open_csv(&path, "step,time,empty_fraction,largest_void_dx", append)
                    .map_err(fail(&path))?;
                Some(f)
            }
            None => None,
        };
        let bodies_csv = if cfg.bodies.is_empty() {
            None
        } else {
            let path = cfg.dir.join(BODIES);
            Some(BodiesCsv::open(&path, append).map_err(fail(&path))?)
        };
        let mut report = Report::default();
        let pvd = cfg.dir.join(files::SERIES);
        let pvd = match resume {
            None => PvdSeries::new(pvd),
            Some(w) => {
                cfg.bodies.resume(&w.bodies).map_err(|reason| Failure {
                    path: cfg.dir.join(super::checkpoint::FILE),
                    reason,
                })?;
                report.frames = w.frames;
                report.bytes = w.bytes;
                report.busy_seconds = w.busy_seconds;
                report.download_seconds = w.download_seconds;
                report.encode_seconds = w.encode_seconds;
                report.write_seconds = w.write_seconds;
                report.last_clusters = w.last_clusters;
                report.voids = w.voids.clone();
                PvdSeries::with_entries(pvd, w.series.clone())
            }
        };
        Ok(Writer {
            pvd,
            vtu: Compression::of(cfg.format).map(VtuWriter::new),
            cfg,
            diagnostics,
            clusters,
            voids,
            bodies_csv,
            observer,
            report,
        })
    }

    /// The CSV files it appends to.
    pub fn csv_names(&self) -> Vec<&'static str> {
        let mut csv = vec![DIAGNOSTICS];
        if self.clusters.is_some() {
            csv.push(CLUSTERS);
        }
        if self.voids.is_some() {
            csv.push(VOIDS);
        }
        if self.bodies_csv.is_some() {
            csv.push(BODIES);
        }
        csv
    }

    /// The writer's part of a checkpoint (every frame before it written and flushed).
    fn state(&self) -> Result<WriterState, Failure> {
        let mut files = Vec::new();
        for name in self.csv_names() {
            let path = self.cfg.dir.join(name);
            let len = std::fs::metadata(&path).map_err(fail(&path))?.len();
            files.push((name.to_string(), len));
        }
        Ok(WriterState {
            frames: self.report.frames,
            bytes: self.report.bytes,
            busy_seconds: self.report.busy_seconds,
            download_seconds: self.report.download_seconds,
            encode_seconds: self.report.encode_seconds,
            write_seconds: self.report.write_seconds,
            last_clusters: self.report.last_clusters,
            series: self.pvd.entries().to_vec(),
            bodies: self.cfg.bodies.summaries(),
            voids: self.report.voids.clone(),
            files,
        })
    }

    /// Write every job until the channel closes or a write fails.
    pub fn serve(mut self, jobs: mpsc::Receiver<Job>) -> Result<Report, Failure> {
        for job in jobs {
            let started = Instant::now();
            match job {
                Job::Frame(f) => self.write(f)?,
                Job::Checkpoint(write) => {
                    let state = self.state()?;
                    self.report.checkpoint = Some(write(state)?);
                }
            }
            self.report.busy_seconds += started.elapsed().as_secs_f64();
        }
        self.report.bodies = self.cfg.bodies.summaries();
        Ok(self.report)
    }

    fn write(&mut self, job: FrameJob) -> Result<(), Failure> {
        let dir = self.cfg.dir.clone();
        let waited = Instant::now();
        let data = job.frame.wait().map_err(|reason| Failure {
            path: dir.clone(),
            reason,
        })?;
        self.report.download_seconds += waited.elapsed().as_secs_f64();
        let index = self.report.frames;
        let d = &job.diagnostics;
        let fields = self.cfg.fields;
        let file = match self.cfg.format {
            OutputFormat::Vtu | OutputFormat::VtuZlib | OutputFormat::VtuLz4 => {
                let name = files::frame_file(index as u64, "vtu");
                let path = dir.join(&name);
                let vtu = self.vtu.as_mut().expect("a VTU format has its writer");
                let (bytes, times) = vtu.write(&path, &data, fields).map_err(fail(&path))?;
                self.report.bytes += bytes;
                self.report.encode_seconds += times.encode_seconds;
                self.report.write_seconds += times.write_seconds;
                Some(name)
            }
            OutputFormat::Csv => {
                let path = dir.join(files::frame_file(index as u64, "csv"));
                let written = Instant::now();
                self.report.bytes +=
                    super::write_particles_csv(&path, &data, fields).map_err(fail(&path))?;
                self.report.write_seconds += written.elapsed().as_secs_f64();
                None
            }
            OutputFormat::None => None,
        };
        if let Some(name) = file {
            self.pvd.add(d.time, &name).map_err(fail(self.pvd.path()))?;
        }
        let path = dir.join(DIAGNOSTICS);
        self.diagnostics.write(d).map_err(fail(&path))?;
        let needs_particles = self.cfg.cluster_radius.is_some()
            || self.cfg.voids.is_some()
            || self.bodies_csv.is_some();
        if needs_particles {
            let mut particles = data.particles();
            for q in &mut particles {
                q.mass = self.cfg.masses.get(q.id as usize).copied().unwrap_or(0.0);
            }
            if let (Some(r), Some(csv)) = (self.cfg.cluster_radius, self.clusters.as_mut()) {
                let n = clusters::count_fluid_clusters(&particles, r);
                self.report.last_clusters = Some(n);
                let path = dir.join(CLUSTERS);
                writeln!(csv, "{},{},{n}", d.step, d.time)
                    .and_then(|_| csv.flush())
                    .map_err(fail(&path))?;
            }
            if let (Some(meter), Some(csv)) = (self.cfg.voids.as_ref(), self.voids.as_mut()) {
                let s = meter.measure(&particles, d.time);
                let sum = self.report.voids.get_or_insert_with(|| VoidSummary {
                    region_cells: meter.region_cells(),
                    ..VoidSummary::default()
                });
                sum.add(s);
                let path = dir.join(VOIDS);
                writeln!(
                    csv,
                    "{},{},{},{}",
                    d.step, d.time, s.empty_fraction, s.largest_void_dx
                )
                .and_then(|_| csv.flush())
                .map_err(fail(&path))?;
            }
            if let Some(csv) = self.bodies_csv.as_mut() {
                let rows = self.cfg.bodies.sample(&particles);
                let path = dir.join(BODIES);
                csv.write(d.step, d.time, &rows).map_err(fail(&path))?;
            }
        }
        if let Some(observer) = self.observer.as_mut() {
            observer(&Frame {
                index,
                diagnostics: d,
                data: &data,
            });
        }
        self.report.frames += 1;
        Ok(())
    }
}
