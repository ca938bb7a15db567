//! `meshfree bench paper`: the paper's Table 1 with our times beside it.
//!
//! A run (`run_scenes`) takes each of the paper's five scenes (the built-ins named in
//! `PAPER_TABLE1`; a missing one is skipped with its reason) to its end time, or a fraction
//! of it, on one backend, and writes `paper-bench.json` (`PaperBench`). The GPU run happens
//! on another machine; `merge` then joins a CPU and a GPU file into the full table
//! (`Table1Row`), which `markdown` writes to `docs/reference/paper-table1.md`. A run that stopped short
//! of the scene's end time is extrapolated per step to the whole run, and the table says so.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::output::RunStatus;
use crate::run::{self, Progress, RunError, RunOptions};
use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::{Counts, Scene, SceneError};

/// One row of the paper's Table 1 (GTX 760 GPU and a serial i5 run, seconds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperRow {
    /// Our built-in scene for it.
    pub scene: &'static str,
    pub label: &'static str,
    pub dimension: u32,
    pub particles: usize,
    pub gpu_s: f64,
    pub serial_s: f64,
}

/// Table 1 of Liu, Wang, Ma & Zhang (section 3.4); no step counts or end times are given.
pub const PAPER_TABLE1: &[PaperRow] = &[
    PaperRow {
        scene: "nozzle",
        label: "unsteady nozzle flow",
        dimension: 2,
        particles: 3_000,
        gpu_s: 40.0,
        serial_s: 255.0,
    },
    PaperRow {
        scene: "vortex-street-re140",
        label: "vortex shedding, Re 140",
        dimension: 2,
        particles: 16_000,
        gpu_s: 622.0,
        serial_s: 2_605.0,
    },
    PaperRow {
        scene: "vortex-street-re105",
        label: "vortex shedding, Re 105",
        dimension: 2,
        particles: 34_000,
        gpu_s: 2_100.0,
        serial_s: 8_176.0,
    },
    PaperRow {
        scene: "impinging-2d",
        label: "impinging flow, elastic square and disc",
        dimension: 2,
        particles: 5_500,
        gpu_s: 180.0,
        serial_s: 840.0,
    },
    PaperRow {
        scene: "impinging-3d",
        label: "impinging flow, elastic sphere",
        dimension: 3,
        particles: 28_000,
        gpu_s: 1_731.0,
        serial_s: 6_840.0,
    },
];

/// The paper's hardware.
pub const PAPER_HARDWARE: &str = "one NVIDIA GTX 760 (2 GB); serial: one Intel i5 core";

/// The paper's row for a scene name (ours, with or without `-paper-exact`).
pub fn paper_row(scene: &str) -> Option<&'static PaperRow> {
    let base = scene.strip_suffix("-paper-exact").unwrap_or(scene);
    PAPER_TABLE1.iter().find(|r| r.scene == base)
}

/// How far to run each scene.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Span {
    /// The scene's own end time.
    #[default]
    Full,
    /// This fraction (0, 1] of the scene's end time.
    Fraction(f64),
    /// This end time \[T\] for every scene.
    Time(f64),
}

/// What `run_scenes` runs.
#[derive(Clone, Debug, Default)]
pub struct PaperBenchOptions {
    pub backend: BackendChoice,
    pub span: Span,
    /// Built-in names; empty = every scene of `PAPER_TABLE1`.
    pub scenes: Vec<String>,
    pub paper_exact: bool,
    pub progress: Progress,
}

/// One scene's measurement.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperBenchRow {
    /// The built-in name (without `-paper-exact`).
    pub scene: String,
    pub dimension: u32,
    pub particles: Counts,
    pub backend: String,
    pub device: String,
    pub steps: u64,
    /// \[T\] reached.
    pub simulated_time: f64,
    /// \[T\] the scene's own end time (what the whole run would reach).
    pub scene_end_time: f64,
    /// Whole run: set-up, steps and output \[s\].
    pub wall_s: f64,
    /// Stepping alone, per step \[ms\].
    pub ms_per_step: f64,
    /// `wall_s`, or for a run short of `scene_end_time`, set-up plus `ms_per_step` times
    /// the steps of the whole run estimated as steps x end time / time reached \[s\].
    pub full_run_s: f64,
    /// True where `full_run_s` is such an estimate (also for a run that failed short of
    /// the end: the table then says where it failed).
    pub extrapolated: bool,
    pub completed: bool,
    /// The blow-up that stopped a failed run.
    pub fault: Option<String>,
}

/// `paper-bench.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PaperBench {
    pub backend: String,
    pub device: String,
    pub paper_exact: bool,
    /// "full", "fraction 0.1 of each end time", "t_end = 0.5".
    pub span: String,
    pub meshfree_version: String,
    pub rows: Vec<PaperBenchRow>,
    /// Scenes not run, with the reason.
    pub skipped: Vec<(String, String)>,
}

/// Errors of `bench paper` that are not a scene's blow-up (those are rows).
#[derive(Debug, thiserror::Error)]
pub enum PaperBenchError {
    #[error("`{0}` is not a scene of the paper's Table 1 (known: {1})")]
    UnknownScene(String, String),
    #[error("t-end fraction {0} must be in (0, 1]")]
    BadFraction(f64),
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Run(#[from] RunError),
    #[error("{path}: {reason}")]
    File { path: String, reason: String },
}

/// Run the scenes on one backend; each writes its output under `out_dir/<scene>` and the
/// result goes to `out_dir/paper-bench.json`.
pub fn run_scenes(o: &PaperBenchOptions, out_dir: &Path) -> Result<PaperBench, PaperBenchError> {
    let names: Vec<String> = if o.scenes.is_empty() {
        PAPER_TABLE1.iter().map(|r| r.scene.to_string()).collect()
    } else {
        o.scenes.clone()
    };
    if let Span::Fraction(f) = o.span {
        if !(f > 0.0 && f <= 1.0) {
            return Err(PaperBenchError::BadFraction(f));
        }
    }
    let known = || {
        PAPER_TABLE1
            .iter()
            .map(|r| r.scene)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut out = PaperBench {
        backend: String::new(),
        device: String::new(),
        paper_exact: o.paper_exact,
        span: match o.span {
            Span::Full => "full".into(),
            Span::Fraction(f) => format!("fraction {f} of each end time"),
            Span::Time(t) => format!("t_end = {t}"),
        },
        meshfree_version: env!("CARGO_PKG_VERSION").into(),
        rows: Vec::new(),
        skipped: Vec::new(),
    };
    for name in names {
        if paper_row(&name).is_none() {
            return Err(PaperBenchError::UnknownScene(name, known()));
        }
        let scene = match Scene::builtin(&name) {
            Ok(s) => s,
            Err(SceneError::UnknownBuiltin { .. }) => {
                let reason = format!("no built-in scene `{name}` in this build");
                crate::errln!("bench paper: skipping {name}: {reason}");
                out.skipped.push((name, reason));
                continue;
            }
            Err(e) => return Err(e.into()),
        };
        let scene = if o.paper_exact {
            scene.with_paper_exact()?
        } else {
            scene
        };
        let end = scene.file.time.end;
        let t_end = match o.span {
            Span::Full => end,
            Span::Fraction(f) => f * end,
            Span::Time(t) => t,
        };
        let options = RunOptions {
            backend: o.backend,
            out_dir: Some(out_dir.join(&name)),
            t_end: Some(t_end),
            max_steps: None,
            // Four outputs: the output's cost stays small beside the steps'.
            output_interval: Some(t_end / 4.0),
            progress: o.progress,
            format: None,
            // A bench's directory is its own: a rerun replaces it.
            overwrite: true,
            ..Default::default()
        };
        let (summary, fault) = match run::run(&scene, &options) {
            Ok(s) => (s, None),
            Err(RunError::BlowUp { fault, summary, .. }) => (*summary, Some(fault.to_string())),
            Err(e) => return Err(e.into()),
        };
        let row = measured_row(&name, end, &summary, fault);
        let _ = print_row(&row); // also in paper-bench.json: a closed stdout stops no bench
        out.backend = row.backend.clone();
        out.device = row.device.clone();
        out.rows.push(row);
    }
    std::fs::create_dir_all(out_dir).map_err(|e| file_err(out_dir, e))?;
    let path = out_dir.join("paper-bench.json");
    let text = serde_json::to_string_pretty(&out).expect("plain data") + "\n";
    std::fs::write(&path, text).map_err(|e| file_err(&path, e))?;
    Ok(out)
}

fn file_err(path: &Path, e: impl std::fmt::Display) -> PaperBenchError {
    PaperBenchError::File {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// A row from a run's summary; `scene_end_time` is the scene's own end time \[T\].
pub fn measured_row(
    scene: &str,
    scene_end_time: f64,
    s: &crate::output::RunSummary,
    fault: Option<String>,
) -> PaperBenchRow {
    let step_s = if s.particle_steps_per_second > 0.0 {
        s.particles.total as f64 * s.steps as f64 / s.particle_steps_per_second
    } else {
        0.0
    };
    let ms_per_step = 1e3 * step_s / s.steps.max(1) as f64;
    let short = s.simulated_time < scene_end_time * (1.0 - 1e-6);
    let full_run_s = if short && s.simulated_time > 0.0 {
        let steps = s.steps as f64 * scene_end_time / s.simulated_time;
        (s.wall_seconds - step_s) + 1e-3 * ms_per_step * steps
    } else {
        s.wall_seconds
    };
    PaperBenchRow {
        scene: scene.to_string(),
        dimension: s.dimension,
        particles: s.particles,
        backend: s.backend.clone(),
        device: s.device.clone(),
        steps: s.steps,
        simulated_time: s.simulated_time,
        scene_end_time,
        wall_s: s.wall_seconds,
        ms_per_step,
        full_run_s,
        extrapolated: short,
        completed: s.status == RunStatus::Completed,
        fault,
    }
}

fn print_row(r: &PaperBenchRow) -> Result<(), crate::term::StdoutError> {
    let p = paper_row(&r.scene).expect("a Table 1 scene");
    crate::outln!(
        "{:<22} {:>7} particles (paper {:>6}): {:>7} steps to t = {:<8.4} {:>9.2} s ({:.3} ms/step{}); \
         paper GPU {:>5.0} s, serial {:>5.0} s [{} {}]{}",
        r.scene,
        r.particles.total,
        p.particles,
        r.steps,
        r.simulated_time,
        r.wall_s,
        r.ms_per_step,
        if r.extrapolated {
            format!(", whole run est. {:.1} s", r.full_run_s)
        } else {
            String::new()
        },
        p.gpu_s,
        p.serial_s,
        r.backend,
        r.device,
        match &r.fault {
            Some(f) => format!(" FAILED: {f}"),
            None => String::new(),
        }
    )
}

/// One row of the merged table.
#[derive(Clone, Debug, PartialEq)]
pub struct Table1Row {
    pub paper: PaperRow,
    /// Ours (from the GPU run where there is one, else the CPU run).
    pub particles: Option<usize>,
    pub steps: Option<u64>,
    pub simulated_time: Option<f64>,
    pub gpu: Option<PaperBenchRow>,
    pub cpu: Option<PaperBenchRow>,
    /// Paper GPU s / our GPU s (whole runs).
    pub speedup_over_paper_gpu: Option<f64>,
    /// Our CPU s / our GPU s (whole runs; a short CPU run extrapolated per step).
    pub speedup_over_our_cpu: Option<f64>,
}

/// Read a `paper-bench.json`.
pub fn read(path: &Path) -> Result<PaperBench, PaperBenchError> {
    let text = std::fs::read_to_string(path).map_err(|e| file_err(path, e))?;
    serde_json::from_str(&text).map_err(|e| file_err(path, format!("not a paper-bench.json: {e}")))
}

/// Join a CPU and a GPU result (either may be absent) into Table 1, in the paper's order.
pub fn merge(cpu: Option<&PaperBench>, gpu: Option<&PaperBench>) -> Vec<Table1Row> {
    let find = |b: Option<&PaperBench>, name: &str| {
        b.and_then(|b| b.rows.iter().find(|r| r.scene == name).cloned())
    };
    PAPER_TABLE1
        .iter()
        .map(|p| {
            let gpu = find(gpu, p.scene);
            let mut cpu = find(cpu, p.scene);
            // The CPU run extrapolated to the GPU run's steps where the GPU run is whole and
            // the CPU run is short: per step, the same scene and time step.
            if let (Some(c), Some(g)) = (cpu.as_mut(), gpu.as_ref()) {
                if c.extrapolated && !g.extrapolated && g.completed {
                    let setup_s = c.wall_s - 1e-3 * c.ms_per_step * c.steps as f64;
                    c.full_run_s = setup_s + 1e-3 * c.ms_per_step * g.steps as f64;
                }
            }
            let whole = |r: &Option<PaperBenchRow>| {
                r.as_ref()
                    .filter(|r| r.completed || r.extrapolated)
                    .map(|r| r.full_run_s)
            };
            let (g_s, c_s) = (whole(&gpu), whole(&cpu));
            let ours = gpu.as_ref().or(cpu.as_ref());
            let (particles, steps, simulated_time) = (
                ours.map(|r| r.particles.total),
                ours.map(|r| r.steps),
                ours.map(|r| r.simulated_time),
            );
            Table1Row {
                paper: *p,
                particles,
                steps,
                simulated_time,
                speedup_over_paper_gpu: g_s.map(|g| p.gpu_s / g),
                speedup_over_our_cpu: g_s.zip(c_s).map(|(g, c)| c / g),
                gpu,
                cpu,
            }
        })
        .collect()
}

fn opt<T>(v: Option<T>, f: impl Fn(T) -> String) -> String {
    v.map(f).unwrap_or_else(|| "-".into())
}

fn seconds(r: &Option<PaperBenchRow>) -> String {
    match r {
        None => "-".into(),
        Some(r) if !r.completed && !r.extrapolated => {
            format!("failed at t = {:.2}", r.simulated_time)
        }
        Some(r) if !r.completed => format!(
            "{:.1}* (failed at t = {:.2})",
            r.full_run_s, r.simulated_time
        ),
        Some(r) if r.extrapolated => format!("{:.1}*", r.full_run_s),
        Some(r) => format!("{:.1}", r.full_run_s),
    }
}

/// A row's cells from "particles (paper)" to "speed-up over our CPU", as both tables show them.
fn cells(r: &Table1Row) -> [String; 10] {
    [
        r.paper.particles.to_string(),
        opt(r.particles, |n| n.to_string()),
        opt(r.steps, |n| n.to_string()),
        opt(r.simulated_time, |t| format!("{t:.3}")),
        format!("{:.0}", r.paper.gpu_s),
        format!("{:.0}", r.paper.serial_s),
        seconds(&r.gpu),
        seconds(&r.cpu),
        opt(r.speedup_over_paper_gpu, |x| format!("{x:.1}")),
        opt(r.speedup_over_our_cpu, |x| format!("{x:.1}")),
    ]
}

/// The merged table as text columns (what the terminal shows).
pub fn text_table(rows: &[Table1Row]) -> String {
    let mut s = format!(
        "{:<22} {:>9} {:>9} {:>8} {:>9} {:>9} {:>9} {:>10} {:>10} {:>9} {:>9}\n",
        "scene",
        "paper N",
        "our N",
        "steps",
        "sim. t",
        "paper GPU",
        "paper ser",
        "our GPU s",
        "our CPU s",
        "x paperGPU",
        "x our CPU"
    );
    for r in rows {
        let c = cells(r);
        s += &format!(
            "{:<22} {:>9} {:>9} {:>8} {:>9} {:>9} {:>9} {:>10} {:>10} {:>9} {:>9}\n",
            r.paper.scene, c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[8], c[9],
        );
    }
    if rows.iter().any(|r| {
        r.gpu.as_ref().is_some_and(|g| g.extrapolated)
            || r.cpu.as_ref().is_some_and(|c| c.extrapolated)
    }) {
        s += "* extrapolated per step from a run to part of the scene's end time\n";
    }
    s
}

/// The merged table as `docs/reference/paper-table1.md`.
pub fn markdown(rows: &[Table1Row], cpu: Option<&PaperBench>, gpu: Option<&PaperBench>) -> String {
    let mut s = String::from(
        "# The paper's Table 1 beside ours\n\n\
         Written by `meshfree bench paper --table CPU.json GPU.json --markdown docs/reference/paper-table1.md`\n\
         from the runs' `paper-bench.json` (kept in `docs/data/`). Times are whole runs in\n\
         seconds (set-up, steps and four outputs). The paper gives neither step counts nor end\n\
         times, so its times compare with ours only as whole-scene figures; our scenes and\n\
         end times are those of `docs/reference/paper-scenes.md`. To fill or renew it: `meshfree bench\n\
         paper --backend cuda --out DIR` on the GPU machine, `--backend cpu` here (with\n\
         `--t-end-fraction F` where the whole run is too long), then this command.\n\n",
    );
    s += &format!("- paper: {PAPER_HARDWARE}\n");
    for (what, b) in [("our GPU", gpu), ("our CPU", cpu)] {
        match b {
            Some(b) => {
                s += &format!(
                    "- {what}: {} ({}), meshfree {}, {}{}\n",
                    b.device,
                    b.backend,
                    b.meshfree_version,
                    b.span,
                    if b.paper_exact { ", --paper-exact" } else { "" }
                );
                for (n, why) in &b.skipped {
                    s += &format!("  - not run: {n}: {why}\n");
                }
            }
            None => s += &format!("- {what}: no run given\n"),
        }
    }
    s += "\n| scene | dim | particles (paper) | particles (ours) | steps | simulated time | paper GPU s | paper serial s | our GPU s | our CPU s | speed-up over paper GPU | speed-up over our CPU |\n";
    s += "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        s += &format!(
            "| {} ({}) | {}D | {} |\n",
            r.paper.label,
            r.paper.scene,
            r.paper.dimension,
            cells(r).join(" | ")
        );
    }
    s += "\nSteps and simulated time are the GPU run's where there is one. \
          `*`: extrapolated per step from a run to part of the scene's end time (set-up \
          plus ms/step times the whole run's steps: the GPU run's where it is whole, else \
          steps x end time / time reached). `-`: not run.\n";
    s
}
