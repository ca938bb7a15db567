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
    /// \[MB/s\] the writer's rate on the particle files: their bytes over its time encoding
    /// and writing them (`Timing::writer_mb_per_second`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub writer_mb_per_second: Option<f64>,
    /// What to change where the stepping waited for the output more than a tenth of its time
    /// (`RunSummary::absorb`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output_advice: Option<String>,
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
    /// The part of `writer_seconds` spent building and compressing the particle files' arrays.
    #[serde(default)]
    pub writer_encode_seconds: f64,
    /// The part of `writer_seconds` spent handing the particle files' bytes to the system
    /// (the disk may write them later: the page cache takes them first).
    #[serde(default)]
    pub writer_write_seconds: f64,
    pub total_seconds: f64,
}

impl Timing {
    /// \[MB/s\] `bytes` over the writer's time on them: encoding and writing (not the
    /// downloads). None before any was spent.
    pub fn writer_mb_per_second(&self, bytes: u64) -> Option<f64> {
        let t = self.writer_encode_seconds + self.writer_write_seconds;
        (t > 0.0).then(|| bytes as f64 / 1e6 / t)
    }

    /// The share of the stepping that the stepping spent waiting for the output.
    pub fn output_wait_share(&self) -> f64 {
        self.output_wait_seconds / self.stepping_seconds.max(1e-9)
    }

    /// Where the stepping waited for the output more than 10 % of its time: by how much, and
    /// what would cut the wait (`outputs` frames of `bytes` in all, in `format`).
    pub fn advice(&self, format: OutputFormat, outputs: usize, bytes: u64) -> Option<String> {
        let share = self.output_wait_share();
        if share <= 0.1 || outputs == 0 {
            return None;
        }
        let lz4 = match format {
            OutputFormat::Vtu | OutputFormat::VtuZlib | OutputFormat::Csv => {
                "`[output] format = \"vtu-lz4\"` (compressed, and fast to write), "
            }
            OutputFormat::VtuLz4 | OutputFormat::None => "",
        };
        Some(format!(
            "the stepping waited {:.0} % of its time for the output ({:.2} s: {outputs} frames, \
             {:.1} MB a frame{}); {lz4}fewer `[output] fields` or a longer \
             `time.output_interval` would cut the wait",
            share * 100.0,
            self.output_wait_seconds,
            bytes as f64 / 1e6 / outputs as f64,
            self.writer_mb_per_second(bytes)
                .map_or(String::new(), |r| format!(", written at {r:.0} MB/s")),
        ))
    }
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
        self.timing.writer_encode_seconds = w.encode_seconds;
        self.timing.writer_write_seconds = w.write_seconds;
        self.writer_mb_per_second = self.timing.writer_mb_per_second(w.bytes);
        self.output_advice =
            self.timing
                .advice(self.output_format, self.outputs, self.output_bytes);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advice_only_past_a_tenth_of_the_stepping_and_lz4_only_where_not_used() {
        let t = Timing {
            stepping_seconds: 10.0,
            output_wait_seconds: 2.5,
            writer_encode_seconds: 0.5,
            writer_write_seconds: 1.5,
            ..Timing::default()
        };
        // 21 frames of 100 MB, 2,100 MB in 2 s of encoding and writing.
        assert_eq!(t.writer_mb_per_second(2_100_000_000), Some(1050.0));
        let raw = t.advice(OutputFormat::Vtu, 21, 2_100_000_000).unwrap();
        assert!(
            raw.starts_with("the stepping waited 25 % of its time"),
            "{raw}"
        );
        assert!(
            raw.contains("100.0 MB a frame, written at 1050 MB/s"),
            "{raw}"
        );
        assert!(raw.contains("vtu-lz4"), "{raw}");
        let lz4 = t.advice(OutputFormat::VtuLz4, 21, 2_100_000_000).unwrap();
        assert!(!lz4.contains("vtu-lz4") && lz4.contains("fewer"), "{lz4}");
        let short = Timing {
            output_wait_seconds: 0.9,
            ..t
        };
        assert_eq!(short.advice(OutputFormat::Vtu, 21, 2_100_000_000), None);
        assert_eq!(t.advice(OutputFormat::Vtu, 0, 0), None);
        assert_eq!(Timing::default().writer_mb_per_second(5), None);
    }
}
