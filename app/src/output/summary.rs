//! `summary.json`: what ran, on what, how fast, and how it ended.

use serde::{Deserialize, Serialize};

use crate::analysis::bodies::BodySummary;
use meshfree_core::monitor::MonitorSummary;
use meshfree_core::scene::Counts;
use meshfree_core::solver::{Diagnostics, Fault};

/// How the run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RunStatus {
    Completed,
    Failed,
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
    /// [T]
    pub simulated_time: f64,
    pub wall_seconds: f64,
    /// Particles x steps / wall seconds (particles counted at the start).
    pub particle_steps_per_second: f64,
    /// Number of VTK files written.
    pub outputs: usize,
    pub output_dir: String,
    pub final_diagnostics: Option<Diagnostics>,
    /// Connected clusters of fluid particles (links under 1.5 dx,
    /// `analysis::clusters`) at the last output: droplets.
    #[serde(default)]
    pub fluid_clusters: Option<usize>,
    pub status: RunStatus,
    /// The blow-up that stopped a failed run.
    pub fault: Option<Fault>,
    /// The scene's force monitors: Strouhal number, mean Cd, rms Cl, blockage ratio.
    #[serde(default)]
    pub monitors: Vec<MonitorSummary>,
    /// The elastic bodies (solid groups): largest |omega|, worst change of size (area or
    /// volume) and of radius of gyration over the outputs (`analysis::bodies`).
    #[serde(default)]
    pub bodies: Vec<BodySummary>,
}

impl RunSummary {
    pub fn write(&self, path: &std::path::Path) -> std::io::Result<()> {
        let mut text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        text.push('\n');
        super::write_atomic(path, text.as_bytes())
    }
}
