//! `meshfree bench peers`: whole runs of GPUSPH's own dam breaks, re-expressed in our scene
//! format (`scenes/peers/*.toml`), beside GPUSPH's whole-run times on one H100
//! (`GPUSPH_H100`: GPUSPH branch spheric2022, commit dcb9d216, sm_90, release, float,
//! driver 580.159.04, measured 2026-11-25).
//!
//! Each scene runs as a user would run it (`run::run`: 21 frames of binary VTU, the
//! scene's own `[output]`), from a fresh solver, and the row gives the whole wall time and
//! its split (set-up, stepping, output waits) from the run's summary, and the ratio to
//! GPUSPH's whole process. `peers-bench.json` holds the rows.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::run::{self, Progress, RunOptions};
use meshfree_core::backend::BackendChoice;
use meshfree_core::named::Named as _;
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::Scene;

/// GPUSPH's figures for one scene on one H100 (seconds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeerRow {
    /// The scene file's stem in `scenes/peers/`.
    pub scene: &'static str,
    pub particles: usize,
    pub setup_s: f64,
    pub main_loop_s: f64,
    pub whole_s: f64,
}

/// GPUSPH on one H100, from its own logs (../shared/peers/gpusph.md).
pub const GPUSPH_H100: &[PeerRow] = &[
    PeerRow {
        scene: "db3d-ppH70",
        particles: 1_060_000,
        setup_s: 1.1,
        main_loop_s: 9.6,
        whole_s: 10.7,
    },
    PeerRow {
        scene: "db2d-ppH670",
        particles: 1_010_000,
        setup_s: 0.9,
        main_loop_s: 14.1,
        whole_s: 15.0,
    },
    PeerRow {
        scene: "db3d-ppH180",
        particles: 12_960_000,
        setup_s: 10.8,
        main_loop_s: 25.0,
        whole_s: 35.8,
    },
];

/// One of our whole runs beside GPUSPH's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PeersRow {
    pub scene: String,
    pub particles: usize,
    pub steps: u64,
    pub outputs: usize,
    pub output_bytes: u64,
    /// The frames' format (`[output] format` or `bench peers --format`).
    #[serde(default)]
    pub format: String,
    /// \[MB/s\] the writer's rate on the frames (`RunSummary::writer_mb_per_second`).
    #[serde(default)]
    pub writer_mb_per_s: Option<f64>,
    pub setup_s: f64,
    pub stepping_s: f64,
    pub output_wait_s: f64,
    pub whole_s: f64,
    pub gpusph_whole_s: f64,
    /// whole_s / gpusph_whole_s.
    pub ratio: f64,
    pub backend: String,
    pub device: String,
}

/// The report: when, where, which build.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PeersBench {
    pub date: String,
    pub commit: String,
    pub rows: Vec<PeersRow>,
}

/// Run every scene of `dir` that `GPUSPH_H100` lists (or only `only`), writing each run
/// under `out` and `out/peers-bench.json`; prints a table.
pub fn run_peers(
    dir: &Path,
    only: &[String],
    backend: BackendChoice,
    format: Option<OutputFormat>,
    out: &Path,
    progress: Progress,
) -> anyhow::Result<PeersBench> {
    let mut rows = Vec::new();
    crate::outln!(
        "{:<14} {:>11} {:>6} {:>7} {:>8} {:>9} {:>8} {:>8} {:>8} {:>6}",
        "scene",
        "particles",
        "steps",
        "frames",
        "set-up",
        "stepping",
        "out wait",
        "whole",
        "GPUSPH",
        "ratio"
    )?;
    for peer in GPUSPH_H100 {
        if !only.is_empty() && !only.iter().any(|s| s == peer.scene) {
            continue;
        }
        let path = dir.join(format!("{}.toml", peer.scene));
        let scene = Scene::from_file(&path)?;
        let options = RunOptions {
            backend,
            out_dir: Some(out.join(peer.scene)),
            progress,
            format,
            // A bench's directory is its own: a rerun replaces it.
            overwrite: true,
            ..Default::default()
        };
        let s = run::run(&scene, &options)?;
        let row = PeersRow {
            scene: peer.scene.to_string(),
            particles: s.particles.total,
            steps: s.steps,
            outputs: s.outputs,
            output_bytes: s.output_bytes,
            format: s.output_format.name().to_string(),
            writer_mb_per_s: s.writer_mb_per_second,
            setup_s: s.timing.setup_seconds,
            stepping_s: s.timing.stepping_seconds,
            output_wait_s: s.timing.output_wait_seconds,
            whole_s: s.timing.total_seconds,
            gpusph_whole_s: peer.whole_s,
            ratio: s.timing.total_seconds / peer.whole_s,
            backend: s.backend.clone(),
            device: s.device.clone(),
        };
        crate::outln!(
            "{:<14} {:>11} {:>6} {:>7} {:>7.2}s {:>8.2}s {:>7.2}s {:>7.2}s {:>7.1}s {:>6.2}",
            row.scene,
            row.particles,
            row.steps,
            row.outputs,
            row.setup_s,
            row.stepping_s,
            row.output_wait_s,
            row.whole_s,
            row.gpusph_whole_s,
            row.ratio
        )?;
        rows.push(row);
    }
    let report = PeersBench {
        date: meshfree_core::build_info::today(),
        commit: meshfree_core::build_info::COMMIT.to_string(),
        rows,
    };
    std::fs::create_dir_all(out)?;
    let path: PathBuf = out.join("peers-bench.json");
    std::fs::write(&path, serde_json::to_string_pretty(&report)? + "\n")?;
    crate::outln!("wrote {}", path.display())?;
    Ok(report)
}
