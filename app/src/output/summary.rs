//! `summary.json`: what ran, on what, how fast, and how it ended.

use serde::{Deserialize, Serialize};

use crate::analysis::bodies::BodySummary;
use meshfree_core::measure::monitor::MonitorSummary;
use meshfree_core::measure::voids::VoidSummary;
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::Counts;
use meshfree_core::solver::{Diagnostics, Fault};

/// How the run ended (`Running` while it runs: a run killed outright leaves that).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RunStatus {
    Running,
    Completed,
    /// A blow-up (`fault` says which particle and why).
    Failed,
    /// Stopped by a signal or the caller's flag (`interrupted_by`); the last frame holds
    /// the state it reached.
    Interrupted,
}

/// The JSON summary of a run (also what `run::run` returns).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    pub scene: String,
    /// The scene file path, or `builtin:<name>`.
    pub scene_source: String,
    pub dimension: u32,
    pub backend: String,
    pub device: String,
    /// Initial particle numbers by kind.
    pub particles: Counts,
    pub steps: u64,
    /// \[T\]
    pub simulated_time: f64,
    pub wall_seconds: f64,
    /// Particles x steps / wall seconds (particles counted at the start).
    pub particle_steps_per_second: f64,
    /// Number of outputs (frames) written.
    pub outputs: usize,
    pub output_dir: String,
    /// The particle files' format.
    pub output_format: OutputFormat,
    /// Bytes of particle files written.
    pub output_bytes: u64,
    /// How the wall time split.
    pub timing: Timing,
    pub final_diagnostics: Option<Diagnostics>,
    /// Connected clusters of fluid particles (links under 1.5 dx,
    /// `analysis::clusters`) at the last output: droplets. Counted where the scene's
    /// `[output] clusters` asks.
    #[serde(default)]
    pub fluid_clusters: Option<usize>,
    /// The void metric over the outputs (`meshfree_core::measure::voids`): the share of the fluid
    /// region's cells of side dx with no particle, and the largest empty circle (sphere) in
    /// dx. Measured where the scene's `[output] voids` asks.
    #[serde(default)]
    pub voids: Option<VoidSummary>,
    pub status: RunStatus,
    /// The blow-up that stopped a failed run.
    pub fault: Option<Fault>,
    /// The output index of the frame that holds the failing state (a failed run's last
    /// frame: `particles_NNNNN` with that number).
    #[serde(default)]
    pub fault_frame: Option<usize>,
    /// What stopped a failed run other than a blow-up: a file that could not be written, or
    /// an internal error.
    #[serde(default)]
    pub error: Option<String>,
    /// The signal that stopped an interrupted run (`SIGINT`, `SIGTERM`, `SIGHUP`).
    #[serde(default)]
    pub interrupted_by: Option<String>,
    /// The scene's force monitors: Strouhal number, mean Cd, rms Cl, blockage ratio.
    #[serde(default)]
    pub monitors: Vec<MonitorSummary>,
    /// The elastic bodies (solid groups): largest |omega|, worst change of size (area or
    /// volume) and of radius of gyration over the outputs (`analysis::bodies`).
    #[serde(default)]
    pub bodies: Vec<BodySummary>,
    /// The open boundaries (`[[open_boundaries]]`' order): the particles and mass \[M\] in
    /// and out through each since the run began (over every part of a resumed run).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub open_boundaries: Vec<meshfree_core::physics::open::OpenTally>,
    /// The simulated time \[T\] of the last checkpoint (`checkpoint.bin`, from which `meshfree
    /// run --resume` continues); none where the run wrote none.
    #[serde(default)]
    pub checkpoint_time: Option<f64>,
    /// The run's files in its directory besides its frames, series and checkpoint (the
    /// scene copy, the summary, the CSV files): what `--overwrite` removes with those
    /// (`output::files`).
    #[serde(default)]
    pub files: Vec<String>,
    /// The times \[T\] of the checkpoints this run was resumed from, in order (empty for a
    /// run in one go). The counts and timings cover the whole run, every part of it.
    #[serde(default)]
    pub resumed_from: Vec<f64>,
}

/// How a run's wall time split \[s\]. The writer works while the solver steps, so
/// `setup + stepping + output_wait` is the part of `total` the outputs could not hide, and
/// `writer` (its busy time) overlaps `stepping`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Timing {
    /// Scene set-up: reading its surface files (`mesh`, `polygon`, `inside`) and building
    /// their trees, particle generation, the backend's start (on a GPU: context, modules,
    /// upload), up to the first step.
    pub setup_seconds: f64,
    /// Stepping, as the `Stepper` clocked it (health checks included).
    pub stepping_seconds: f64,
    /// Time the stepping waited for the output: starting the copies, a full writer queue,
    /// and the last frames' writing after the last step.
    pub output_wait_seconds: f64,
    /// The writer thread's busy time: downloads, encoding, files (overlapped).
    pub writer_seconds: f64,
    /// The part of `writer_seconds` spent waiting for the frames' copies (the downloads).
    #[serde(default)]
    pub writer_download_seconds: f64,
    pub total_seconds: f64,
}

impl RunSummary {
    /// Take the writer's counts: frames, bytes, busy time, clusters, bodies, the last
    /// checkpoint.
    pub fn absorb(&mut self, w: &super::writer::Report) {
        if let Some((t, _)) = w.checkpoint {
            self.checkpoint_time = Some(t);
        }
        self.outputs = w.frames;
        self.output_bytes = w.bytes;
        self.timing.writer_seconds = w.busy_seconds;
        self.timing.writer_download_seconds = w.download_seconds;
        self.fluid_clusters = w.last_clusters;
        self.voids = w.voids.clone();
        self.bodies = w.bodies.clone();
    }

    pub fn write(&self, path: &std::path::Path) -> std::io::Result<()> {
        let mut text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        text.push('\n');
        super::write_atomic(path, text.as_bytes())
    }
}
