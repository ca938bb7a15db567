//! The command line (clap derive). `main.rs` parses `Cli` and calls `cli::main`.

use std::path::PathBuf;

use anyhow::Context;
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Parser, Subcommand};
use serde::Serialize;

use crate::run::{self, Progress, RunOptions};
use meshfree_core::backend::{BackendChoice, BackendError};
use meshfree_core::named::Named;
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::{self, Counts, Scene};
use meshfree_core::scheme::IntegratorChoice;

/// The parser of a `Named` option: its values with their help in `--help`.
fn named<T: Named>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(
        T::ALL
            .iter()
            .map(|(_, n, h)| PossibleValue::new(*n).help(*h)),
    )
    .map(|s| T::from_name(&s).expect("clap accepted a possible value"))
}

const AFTER_HELP: &str = "\
Examples:
  meshfree scenes                          list the built-in scenes
  meshfree run dam-break-2d                run a built-in scene into out/dam-break-2d
  meshfree run my.toml --out runs/a        run a scene file
  meshfree run tank-2d --backend cpu --steps 100 --quiet
  meshfree run --resume out/dam-break-2d   continue a stopped or killed run from its checkpoint
  meshfree check my.toml                   validate a scene and count its particles

Scene files: copy one of scenes/*.toml and edit it; every key is commented there, and
`meshfree scenes --reference` (docs/reference/scene.md) describes them all.
Output: particles.pvd (open it in ParaView), particles_NNNNN.vtu (binary VTK),
diagnostics.csv, summary.json (with the wall time's split) and a copy of the scene, in the
output directory; a scene's [output] table chooses the format, the fields and cluster counts.
A directory holding an earlier run is refused unless --overwrite. Ctrl-C (or SIGTERM,
SIGHUP) stops a run after the current batch of steps, writing the state it reached as a
last frame, a checkpoint and summary.json with status \"interrupted\"; a second Ctrl-C
quits at once.
Checkpoints: checkpoint.bin holds the whole state (binary, versioned, checksummed, replaced
atomically); one is written wherever a run stops (its end, --steps, a signal; not at a
blow-up) and every [output] checkpoint_interval of simulated time. `run --resume DIR`
continues from it, also after kill -9 or a power cut, with the files of later outputs
removed first; on the same backend and build the result is bit for bit the uninterrupted
run's. --t-end extends a finished run; --backend may differ from the run's.

Exit status:
  0    success
  1    any other error (a failed validation check, no GPU where one was asked for, ...)
  2    bad input: a scene file, field or command-line value (the message names it), or an
       output directory in use
  3    a blow-up: summary.json holds the fault (particle, time, reason)
  4    an output file could not be written (the message names the file)
  130  interrupted by a signal";

/// meshfree: weakly compressible SPH with elastic solids on the CPU or an NVIDIA GPU
/// (Liu, Wang, Ma & Zhang).
#[derive(Debug, Parser)]
#[command(name = "meshfree", version, about, long_about = None, after_help = AFTER_HELP)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a scene and write VTK files, a diagnostics CSV and a JSON summary.
    #[command(after_help = AFTER_HELP)]
    Run(RunArgs),
    /// List the built-in scenes with their particle counts by kind, or print the reference
    /// of every scene key.
    Scenes {
        /// Print JSON (an array of objects) instead of a table.
        #[arg(long)]
        json: bool,
        /// Print the scene reference instead (Markdown: every key with its type, default and
        /// the reason for it, its value under --paper-exact, its check and the parameter
        /// field it sets), as committed in docs/reference/scene.md.
        #[arg(long, conflicts_with = "json")]
        reference: bool,
    },
    /// Validate a scene (file or built-in name) and print its particle counts (above two
    /// million, the estimate: up to how many and the memory to start); writes nothing.
    Check {
        /// A scene file path or a built-in scene name.
        scene: String,
    },
    /// Measure speed: 2D and 3D dam-break blocks at several sizes; prints a table and writes
    /// bench.csv and bench.json.
    Bench(BenchArgs),
    /// Watch a scene live in an OpenGL window (needs the `viewer` feature and a display).
    View(ViewArgs),
    /// Render a scene to PNG without a display (EGL), at a time or as a sequence of frames.
    Render(RenderArgs),
    /// Compare two particle CSV files (`run --format csv`, or another code's export in the same
    /// columns): per-field error norms and the worst particles.
    Compare(CompareArgs),
    /// Accuracy cases against published references (hydrostatic tank, dam break, Poiseuille,
    /// Taylor-Green, cylinder, onset of shedding, oscillating plate, elastic gate): plots,
    /// report.md and report.json; exits non-zero when a check fails.
    Validate(ValidateArgs),
    /// Stability maps: sweep the Courant number, alpha, density form, integrator,
    /// Lennard-Jones strength, density diffusion and artificial stress; each run stable,
    /// inaccurate or failed (with its blow-up time); heat-map PNGs, report.md, report.json,
    /// cells.csv.
    Stability(StabilityArgs),
    /// Speed against accuracy: error vs wall time over resolutions, kernels, density forms,
    /// viscosity, integrators and backends, log-log with the Pareto front; one PNG per case,
    /// chart.csv and chart.json.
    Chart(ChartArgs),
    /// Write the measured tables of the reference docs from the tools' own reports
    /// (validate's report.json, bench's bench.json), stamped with date, device and build.
    Docs(DocsArgs),
}

#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// The particle CSV to check (e.g. the GPU run's).
    pub a: PathBuf,
    /// The reference particle CSV (e.g. the CPU run's).
    pub b: PathBuf,
    /// Pair particles by id (same scene) or by nearest position (different codes).
    #[arg(long = "match", value_enum, default_value_t = crate::compare::MatchBy::Id)]
    pub match_by: crate::compare::MatchBy,
    /// How many of the farthest-apart pairs to list.
    #[arg(long, default_value_t = 5)]
    pub worst: usize,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

#[derive(Debug, clap::Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub mode: Option<BenchMode>,
    /// Where to run.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// Time these scenes (files or built-in names; repeatable) instead of the dam-break
    /// blocks, each with its own scheme from its start: ms per step, particle-steps per
    /// second and simulated seconds per wall second.
    #[arg(long, value_name = "SCENE", conflicts_with_all = ["dims", "sizes", "integrator"])]
    pub scene: Vec<String>,
    /// Dimensions to run, e.g. `2,3`.
    #[arg(long, value_delimiter = ',', default_values_t = [2u32, 3])]
    pub dims: Vec<u32>,
    /// Fluid particle counts, e.g. `3000,30000,300000,4000000` [default: up to 4e6 on a GPU,
    /// up to 3e5 on the CPU].
    #[arg(long, value_delimiter = ',')]
    pub sizes: Vec<f64>,
    /// Timed steps per repeat.
    #[arg(long, default_value_t = 50)]
    pub steps: usize,
    /// Repeats; the median is reported.
    #[arg(long, default_value_t = 3)]
    pub repeats: usize,
    /// Skip counting neighbours (a CPU pass over a read-back, slow at many millions).
    #[arg(long)]
    pub no_neighbours: bool,
    /// Time integrator: `leapfrog` (the scenes' default), `symplectic-euler`, or `euler`,
    /// the paper's forward Euler (forces and rates from one state: one neighbour pass on the
    /// GPU), each at its default Courant number (0.4, 0.2, 0.2). Every result line names the
    /// scheme it ran.
    #[arg(long, value_parser = named::<IntegratorChoice>(), default_value = "leapfrog")]
    pub integrator: IntegratorChoice,
    /// Step every configuration in N subdomains (as `run --decompose`); each row then
    /// gives the exchange's microseconds and halo bytes per step.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub decompose: Option<u32>,
    /// Step every configuration on N GPUs (as `run --gpus`). With --scaling, on 1, 2, 4, ...
    /// up to N GPUs instead: strong scaling (each size on every count) and weak scaling (the
    /// size times the count), with the parallel efficiency against one GPU.
    #[arg(long, value_name = "N", conflicts_with = "decompose", value_parser = clap::value_parser!(u32).range(1..=64))]
    pub gpus: Option<u32>,
    /// With --gpus: strong and weak scaling over 1, 2, 4, ... GPUs (scaling.json).
    #[arg(long, requires = "gpus")]
    pub scaling: bool,
    /// Output directory for bench.csv and bench.json.
    #[arg(long, value_name = "DIR", default_value = "out/bench")]
    pub out: PathBuf,
}

#[derive(Debug, Subcommand)]
pub enum BenchMode {
    /// The paper's Table 1 beside ours: run the paper's five scenes on one backend and write
    /// DIR/paper-bench.json, or (with --table) merge a CPU and a GPU result into the table.
    Paper(PaperBenchArgs),
    /// Whole runs of GPUSPH's own dam breaks in our format (scenes/peers/*.toml: 1.1 M
    /// particles in 3D, 1.0 M in 2D, 13.5 M in 3D; 21 binary VTU frames each, as a user
    /// runs them) beside GPUSPH's whole-run times on one H100; writes DIR/peers-bench.json.
    Peers(PeersBenchArgs),
}

#[derive(Debug, clap::Args)]
pub struct PeersBenchArgs {
    /// Where to run.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// The folder of the peer scenes.
    #[arg(long, value_name = "DIR", default_value = "scenes/peers")]
    pub scenes: PathBuf,
    /// Only these, e.g. `db3d-ppH70,db2d-ppH670` [default: all three].
    #[arg(long, value_delimiter = ',', value_name = "A,B")]
    pub only: Vec<String>,
    /// Output directory: peers-bench.json and each scene's run.
    #[arg(long, value_name = "DIR", default_value = "out/peers-bench")]
    pub out: PathBuf,
}

#[derive(Debug, clap::Args)]
pub struct PaperBenchArgs {
    /// Where to run.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// Run each scene to this fraction of its end time (the whole run is then estimated
    /// per step, and the table says so).
    #[arg(long, value_name = "F", conflicts_with = "t_end")]
    pub t_end_fraction: Option<f64>,
    /// Run every scene to this end time instead of its own.
    #[arg(long, value_name = "T")]
    pub t_end: Option<f64>,
    /// Only these built-in scenes, e.g. `impinging-2d,impinging-3d` [default: all five].
    #[arg(long, value_delimiter = ',', value_name = "A,B")]
    pub scenes: Vec<String>,
    /// Run the scenes in the paper's own scheme (see `meshfree run --help`).
    #[arg(long)]
    pub paper_exact: bool,
    /// Output directory: paper-bench.json and each scene's run.
    #[arg(long, value_name = "DIR", default_value = "out/paper-bench")]
    pub out: PathBuf,
    /// Instead of running: merge paper-bench.json files (a CPU and a CUDA run, in either
    /// order; one alone leaves the other's columns empty) into the full table.
    #[arg(long, num_args = 1..=2, value_names = ["A.json", "B.json"],
          conflicts_with_all = ["t_end_fraction", "t_end", "scenes", "paper_exact"])]
    pub table: Vec<PathBuf>,
    /// With --table: also write the table as Markdown here (e.g. docs/reference/paper-table1.md).
    #[arg(long, value_name = "MD", requires = "table")]
    pub markdown: Option<PathBuf>,
    /// No progress output.
    #[arg(long, short)]
    pub quiet: bool,
}

/// What the window or the renderer shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum ShownField {
    #[default]
    Speed,
    Pressure,
    Density,
    Kind,
}

#[derive(Debug, clap::Args)]
pub struct ViewArgs {
    /// A scene file path or a built-in scene name.
    pub scene: String,
    /// Where to run the solver.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// The field that colours the particles (press `f` in the window to change it).
    #[arg(long, value_enum, default_value_t = ShownField::Speed)]
    pub field: ShownField,
    /// Solver steps per drawn frame (`+`/`-` in the window).
    #[arg(long, default_value_t = 10)]
    pub steps_per_frame: u32,
    /// Where the final particles and summary.json go when the window closes
    /// [default: out/<scene name>].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Use only the paper's own equations: summation density, forward Euler at a fixed
    /// step, artificial viscosity only, Lennard-Jones walls (docs/reference/paper-scenes.md).
    #[arg(long)]
    pub paper_exact: bool,
    /// Replace the scene's particle spacing (more or fewer particles; the wall strength
    /// follows).
    #[arg(long, value_name = "DX")]
    pub spacing: Option<f64>,
    /// 3D: start with the fluid drawn as a screen-space surface (`s` in the window).
    #[arg(long)]
    pub surface: bool,
}

#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// A scene file path or a built-in scene name.
    pub scene: String,
    /// Where to run the solver.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// Render at this simulated time [default: the start].
    #[arg(long, value_name = "T", conflicts_with = "frames")]
    pub at: Option<f64>,
    /// Render N frames evenly spaced up to the scene's end time (or --t-end), as
    /// OUT_0000.png, OUT_0001.png, ...
    #[arg(long, value_name = "N")]
    pub frames: Option<u32>,
    /// Render at each of the scene's figure moments (`time.figures`: the moments of the
    /// paper's figures) into the directory --out, as SCENE_tT.png.
    #[arg(long, conflicts_with_all = ["at", "frames"])]
    pub figures: bool,
    /// End time for --frames (and --figures: later moments are skipped), replacing the
    /// scene's.
    #[arg(long, value_name = "T")]
    pub t_end: Option<f64>,
    /// The PNG to write (with --frames, the stem of the sequence; with --figures, a
    /// directory).
    #[arg(long, value_name = "PNG")]
    pub out: PathBuf,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// The field that colours the particles.
    #[arg(long, value_enum, default_value_t = ShownField::Speed)]
    pub field: ShownField,
    /// Draw boundary (wall) particles too (hidden by default in 3D, as in the paper).
    #[arg(long)]
    pub show_boundary: bool,
    /// Replace the scene's particle spacing (more or fewer particles; the wall strength
    /// follows).
    #[arg(long, value_name = "DX")]
    pub spacing: Option<f64>,
    /// Use only the paper's own equations: summation density, forward Euler at a fixed
    /// step, artificial viscosity only, Lennard-Jones walls (docs/reference/paper-scenes.md).
    #[arg(long)]
    pub paper_exact: bool,
    /// With --frames: solver steps between frames instead of even times, and a timing line
    /// (frames per second, drawing and solver ms, solver slow-down from drawing, the
    /// static-buffer drawing ceiling: the same spheres drawn again as sprites from the
    /// vertex buffers, device-to-host bytes per frame) and its JSON (`timing-json: {...}`).
    /// With the CUDA backend the spheres come from the GPU's visibility splat from a view's
    /// second frame on (sprites at most 32 pixels across, in perspective).
    #[arg(long, value_name = "K", requires = "frames")]
    pub steps_per_frame: Option<u32>,
    /// 3D: draw the fluid as a screen-space surface (smoothed depth, Fresnel, absorption)
    /// instead of spheres.
    #[arg(long)]
    pub surface: bool,
    /// Draw the viewer's panel (time, particles, steps/s, frames/s, field and range, what
    /// is shown) as the live window does.
    #[arg(long)]
    pub panel: bool,
    /// Colour range LO,HI instead of the visible particles' (with the CUDA backend nothing
    /// then comes back from the device to draw a frame).
    #[arg(long, value_name = "LO,HI", value_parser = parse_range)]
    pub range: Option<(f32, f32)>,
    /// Draw from a host copy of the particles (read back, then uploaded: the CPU backend's
    /// path) even with the CUDA backend, instead of filling the vertex buffers on the GPU
    /// (CUDA-OpenGL interop); for comparison.
    #[arg(long)]
    pub host_copy: bool,
}

fn parse_range(s: &str) -> Result<(f32, f32), String> {
    let (lo, hi) = s
        .split_once(',')
        .ok_or_else(|| format!("`{s}`: expected LO,HI, e.g. 0,2.5"))?;
    match (lo.trim().parse::<f32>(), hi.trim().parse::<f32>()) {
        (Ok(lo), Ok(hi)) if lo.is_finite() && hi.is_finite() && lo < hi => Ok((lo, hi)),
        _ => Err(format!(
            "`{s}`: LO and HI must be finite numbers with LO < HI"
        )),
    }
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once('x')
        .ok_or_else(|| format!("`{s}`: expected WIDTHxHEIGHT, e.g. 1280x720"))?;
    let parse = |v: &str| v.parse::<u32>().ok().filter(|&n| (16..=16384).contains(&n));
    match (parse(w), parse(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(format!(
            "`{s}`: width and height must be integers from 16 to 16384"
        )),
    }
}

#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// A scene file path (e.g. scenes/tank-2d.toml) or a built-in scene name (see `meshfree scenes`).
    #[arg(required_unless_present = "resume")]
    pub scene: Option<String>,
    /// Continue the run in DIR from its checkpoint (checkpoint.bin), with its own scene,
    /// output interval and format; --backend, --decompose / --gpus, --t-end (to extend it),
    /// --steps and --quiet apply. A decomposed run's checkpoint (one piece per rank)
    /// resumed on as many ranks gives each its own piece; on another count, gathered.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["scene", "out", "overwrite", "format", "output_interval", "paper_exact", "max_particles"])]
    pub resume: Option<PathBuf>,
    /// Where to run: `auto` takes CUDA where a driver and a device answer, else the CPU.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// Output directory [default: out/<scene file's stem>, out/<name> for a built-in].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Refuse the scene if it may hold more particles than this (estimated before anything
    /// is generated; a scene that needs more memory than the machine has available is
    /// refused either way).
    #[arg(long, value_name = "N")]
    pub max_particles: Option<u64>,
    /// Replace an earlier run's output in the output directory (only files a run writes are
    /// removed); without it such a directory is refused.
    #[arg(long)]
    pub overwrite: bool,
    /// End time, replacing the scene's `time.end`.
    #[arg(long, value_name = "T")]
    pub t_end: Option<f64>,
    /// The particle files of each output, replacing the scene's `[output] format`: `csv`
    /// writes plain particle CSV for `meshfree compare` and other codes, `none` only the
    /// diagnostics.
    #[arg(long, value_name = "FORMAT", value_parser = named::<OutputFormat>())]
    pub format: Option<OutputFormat>,
    /// Stop after N time steps (even before the end time).
    #[arg(long, value_name = "N")]
    pub steps: Option<u64>,
    /// Time between outputs, replacing the scene's `time.output_interval`.
    #[arg(long, value_name = "T")]
    pub output_interval: Option<f64>,
    /// Use only the paper's own equations: summation density, forward Euler at a fixed
    /// step, artificial viscosity only, Lennard-Jones walls (docs/reference/paper-scenes.md).
    #[arg(long)]
    pub paper_exact: bool,
    /// Step the scene in N subdomains: slabs of equal particle counts along the domain's
    /// longest axis, one thread each, exchanging halos (copies of the particles within reach
    /// of a slab) every step and agreeing on the step size. The particles come out as in one
    /// domain, bit for bit; the diagnostics' sums to round-off. On the CPU it spreads the
    /// work no further than rayon does already: it is the check of a decomposition, and the
    /// way several subdomains share one GPU. Not with total-Lagrangian bodies.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub decompose: Option<u32>,
    /// Step the scene on N GPUs of this machine, one subdomain each (as --decompose), the
    /// halos sent between GPUs through NCCL. Needs libnccl.so on the loader path (e.g. the
    /// nvidia-nccl Python package's nvidia/nccl/lib in LD_LIBRARY_PATH, with a libnccl.so
    /// link to libnccl.so.2). The particles come out as on one GPU, bit for bit.
    #[arg(long, value_name = "N", conflicts_with_all = ["decompose", "backend"], value_parser = clap::value_parser!(u32).range(1..=64))]
    pub gpus: Option<u32>,
    /// One subdomain per MPI process, on one machine or several: `mpirun -np N meshfree run
    /// SCENE --mpi` (N processes; each takes the GPU of its local rank, and the GPUs talk
    /// through NCCL; with --backend cpu, the halos go over MPI). Rank 0 writes the output;
    /// the particles come out as with --decompose N, bit for bit. Needs a build with the
    /// `mpi` feature (`cargo build --release --features mpi`, with OpenMPI installed).
    #[arg(long, conflicts_with_all = ["decompose", "gpus"])]
    pub mpi: bool,
    /// No progress output; only errors (and the final line on stdout).
    #[arg(long, short)]
    pub quiet: bool,
}

/// One row of `meshfree scenes`.
#[derive(Debug, Serialize)]
pub struct SceneRow {
    pub name: String,
    pub dimension: u32,
    pub description: String,
    #[serde(flatten)]
    pub counts: Counts,
}

/// Every built-in scene, generated.
pub fn scene_rows() -> anyhow::Result<Vec<SceneRow>> {
    scene::builtin_names()
        .into_iter()
        .map(|name| {
            let s = Scene::builtin(name)?;
            let setup = s.setup()?;
            Ok(SceneRow {
                name: name.to_string(),
                dimension: s.file.dimension,
                description: s.file.description.clone(),
                counts: Counts::of(&setup.particles),
            })
        })
        .collect()
}

/// `meshfree check` counts the particles exactly (by generating them) up to this estimate,
/// and prints the estimate above it, so that it answers within a second for any scene.
const CHECK_GENERATES_UP_TO: f64 = 2e6;

/// Exit statuses (listed in `meshfree run --help`).
pub mod exit {
    pub const OTHER: u8 = 1;
    pub const BAD_INPUT: u8 = 2;
    pub const BLOW_UP: u8 = 3;
    pub const IO: u8 = 4;
    pub const INTERRUPTED: u8 = crate::interrupt::EXIT_INTERRUPTED;
}

/// The exit status for an error `main` returned: the first run or scene error in its chain
/// decides.
pub fn exit_code(e: &anyhow::Error) -> u8 {
    for cause in e.chain() {
        if let Some(r) = cause.downcast_ref::<run::RunError>() {
            return match r {
                run::RunError::Scene(_)
                | run::RunError::Backend(BackendError::Decomposition(_))
                | run::RunError::OutputInUse { .. }
                | run::RunError::Checkpoint { .. } => exit::BAD_INPUT,
                run::RunError::BlowUp { .. } => exit::BLOW_UP,
                run::RunError::Io { .. } => exit::IO,
                run::RunError::Interrupted { .. } => exit::INTERRUPTED,
                run::RunError::Backend(_) => exit::OTHER,
            };
        }
        if cause.downcast_ref::<scene::SceneError>().is_some() {
            return exit::BAD_INPUT;
        }
    }
    exit::OTHER
}

/// Carry out a parsed command line. `View` and `Render` are carried out by the binary's
/// viewer glue (`src/view.rs`), which keeps GL out of this library.
pub fn main(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Bench(a) => bench(a),
        Command::Compare(a) => compare(a),
        Command::Validate(a) => validate(a),
        Command::Stability(a) => stability(a),
        Command::Chart(a) => chart(a),
        Command::Docs(a) => docs(a),
        Command::View(_) | Command::Render(_) => anyhow::bail!(
            "this build has no viewer: rebuild with the `viewer` feature (on by default)"
        ),
        Command::Scenes {
            reference: true, ..
        } => {
            print!("{}", meshfree_core::scheme::reference::markdown());
            Ok(())
        }
        Command::Scenes { json, .. } => {
            let rows = scene_rows()?;
            if json {
                println!("{}", serde_json::to_string_pretty(&rows)?);
            } else {
                println!(
                    "{:<16} {:>3} {:>8} {:>8} {:>9} {:>8}  description",
                    "name", "dim", "fluid", "solid", "boundary", "total"
                );
                for r in rows {
                    println!(
                        "{:<16} {:>3} {:>8} {:>8} {:>9} {:>8}  {}",
                        r.name,
                        r.dimension,
                        r.counts.fluid,
                        r.counts.solid,
                        r.counts.boundary,
                        r.counts.total,
                        r.description
                    );
                }
            }
            Ok(())
        }
        Command::Check { scene } => {
            let s = Scene::load(&scene)?;
            let e = s.check_size(None)?;
            let p = s.params();
            if e.particles > CHECK_GENERATES_UP_TO {
                // Generating would take minutes and gigabytes: the estimate says enough.
                println!(
                    "{}: ok: {} ({}D), up to {:.3e} particles (estimated, about {:.1} GB to \
                     start); h = {}, {} neighbour cells",
                    s.origin(),
                    s.name(),
                    s.file.dimension,
                    e.particles,
                    e.host_bytes() / 1e9,
                    p.h,
                    p.n_cells
                );
                return Ok(());
            }
            let setup = s.setup()?;
            let c = Counts::of(&setup.particles);
            println!(
                "{}: ok: {} ({}D), {} particles: {} fluid, {} solid, {} boundary; h = {}, {} neighbour cells",
                s.origin(),
                s.name(),
                s.file.dimension,
                c.total,
                c.fluid,
                c.solid,
                c.boundary,
                setup.params.h,
                setup.params.n_cells
            );
            Ok(())
        }
        Command::Run(a) => {
            // Held to the end of the run: its drop lets the other ranks go where the run
            // stopped before they started (bad input), and finalises MPI.
            #[cfg(feature = "mpi")]
            let _mpi = match a.mpi {
                true => {
                    let m = crate::mpi::Mpi::init()?;
                    if m.rank() != 0 {
                        // The interrupt is rank 0's to act on: it stops the run for all.
                        crate::interrupt::install();
                        return crate::mpi::follow();
                    }
                    Some(m)
                }
                false => None,
            };
            #[cfg(not(feature = "mpi"))]
            anyhow::ensure!(
                !a.mpi,
                "--mpi needs a build with the `mpi` feature: cargo build --release --features mpi \
                 (with an MPI installation, e.g. OpenMPI's libopenmpi-dev)"
            );
            let options = RunOptions {
                format: a.format,
                backend: a.backend,
                out_dir: a.out,
                overwrite: a.overwrite,
                max_particles: a.max_particles,
                interrupt: Some(crate::interrupt::install()),
                t_end: a.t_end,
                max_steps: a.steps,
                output_interval: a.output_interval,
                decompose: a.decompose.map(|n| n as usize),
                gpus: a.gpus.map(|n| n as usize),
                mpi: a.mpi,
                progress: if a.quiet {
                    Progress::Quiet
                } else {
                    Progress::Auto
                },
            };
            let (result, what) = match (&a.resume, &a.scene) {
                (Some(dir), _) => (
                    run::resume(dir, &options),
                    format!("resuming the run in {}", dir.display()),
                ),
                (None, Some(scene)) => {
                    let mut s = Scene::load(scene)?;
                    if a.paper_exact {
                        s = s.with_paper_exact()?;
                    }
                    (
                        run::run(&s, &options),
                        format!("running scene `{}`", s.name()),
                    )
                }
                (None, None) => unreachable!("clap requires a scene without --resume"),
            };
            let summary = match result {
                Ok(summary) => summary,
                // Scene and checkpoint errors already name their file.
                Err(e @ (run::RunError::Scene(_) | run::RunError::Checkpoint { .. })) => {
                    return Err(e.into())
                }
                Err(e) => return Err(e).with_context(|| what),
            };
            println!(
                "{}: {} steps to t = {:.4} on {} ({}), {:.3e} particle-steps/s; output in {}",
                summary.scene,
                summary.steps,
                summary.simulated_time,
                summary.backend,
                summary.device,
                summary.particle_steps_per_second,
                summary.output_dir
            );
            Ok(())
        }
    }
}

fn bench(a: BenchArgs) -> anyhow::Result<()> {
    match a.mode {
        Some(BenchMode::Paper(p)) => return paper_bench(p),
        Some(BenchMode::Peers(p)) => {
            crate::peers_bench::run_peers(&p.scenes, &p.only, p.backend, &p.out, Progress::Lines)?;
            return Ok(());
        }
        None => {}
    }
    let mut o = crate::bench::BenchOptions {
        backend: a.backend,
        dims: a.dims,
        steps: a.steps,
        repeats: a.repeats,
        count_neighbours: !a.no_neighbours,
        integrator: a.integrator,
        decompose: a.decompose.map(|n| n as usize),
        gpus: a.gpus.map(|n| n as usize),
        ..Default::default()
    };
    if !a.sizes.is_empty() {
        o.sizes = a.sizes.iter().map(|&x| x as usize).collect();
    } else if a.backend == BackendChoice::Cpu || meshfree_core::backend::cuda::available().is_err()
    {
        o.sizes = vec![3_000, 30_000, 300_000];
    }
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    if !a.scene.is_empty() {
        let scenes = (a.scene.iter())
            .map(|s| Scene::load(s))
            .collect::<Result<Vec<_>, _>>()?;
        crate::bench::bench_scenes(&o, &scenes, Some(&a.out))?;
        println!("wrote {}/bench.csv and bench.json", a.out.display());
        return Ok(());
    }
    if a.scaling {
        crate::bench::scaling(&o, &a.out)?;
        println!(
            "wrote {}/bench.csv, bench.json and scaling.json",
            a.out.display()
        );
        return Ok(());
    }
    crate::bench::bench(&o, Some(&a.out))?;
    println!("wrote {}/bench.csv and bench.json", a.out.display());
    Ok(())
}

fn paper_bench(a: PaperBenchArgs) -> anyhow::Result<()> {
    use crate::paper_bench as pb;
    if !a.table.is_empty() {
        let (mut cpu, mut gpu) = (None, None);
        for path in &a.table {
            let b = pb::read(path)?;
            let slot = if b.backend == "cuda" {
                &mut gpu
            } else {
                &mut cpu
            };
            anyhow::ensure!(
                slot.is_none(),
                "--table wants one CPU and one CUDA paper-bench.json; {} is a second `{}` run",
                path.display(),
                b.backend
            );
            *slot = Some(b);
        }
        let rows = pb::merge(cpu.as_ref(), gpu.as_ref());
        print!("{}", pb::text_table(&rows));
        if let Some(md) = &a.markdown {
            std::fs::write(md, pb::markdown(&rows, cpu.as_ref(), gpu.as_ref()))
                .with_context(|| format!("writing {}", md.display()))?;
            println!("wrote {}", md.display());
        }
        return Ok(());
    }
    let o = pb::PaperBenchOptions {
        backend: a.backend,
        span: match (a.t_end_fraction, a.t_end) {
            (Some(f), _) => pb::Span::Fraction(f),
            (None, Some(t)) => pb::Span::Time(t),
            (None, None) => pb::Span::Full,
        },
        scenes: a.scenes,
        paper_exact: a.paper_exact,
        progress: if a.quiet {
            Progress::Quiet
        } else {
            Progress::Auto
        },
    };
    let b = pb::run_scenes(&o, &a.out)?;
    let rows = if b.backend == "cuda" {
        pb::merge(None, Some(&b))
    } else {
        pb::merge(Some(&b), None)
    };
    print!("{}", pb::text_table(&rows));
    println!("wrote {}", a.out.join("paper-bench.json").display());
    Ok(())
}

#[derive(Debug, clap::Args)]
pub struct ValidateArgs {
    /// The quick tier: one coarse resolution per case, robust checks (what the tests run).
    /// Without it: the full tier, three resolutions, literature tolerances, convergence order.
    #[arg(long)]
    pub quick: bool,
    /// Where to run: `auto` takes CUDA where a driver and a device answer, else the CPU.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// Output directory for report.md, report.json and the plots.
    #[arg(long, value_name = "DIR", default_value = "out/validate")]
    pub out: PathBuf,
    /// Run only this case (repeatable): hydrostatic-tank, dam-break, poiseuille, taylor-green,
    /// cylinder, cylinder-onset (full tier only: the quick tier skips it), plate, cantilever,
    /// gate.
    #[arg(long, value_name = "NAME")]
    pub case: Vec<String>,
    /// Run every case at this Courant number (eq. (19)) instead of its own (its integrator's
    /// default: 0.4 for the leapfrog): what a larger step costs in accuracy.
    #[arg(long, value_name = "C")]
    pub courant: Option<f64>,
    /// Run every case with this integrator instead of its own (`symplectic-euler`,
    /// `leapfrog`, `euler`), at that integrator's default Courant number (0.2 for the Euler
    /// schemes) unless --courant gives one: what another scheme gives on the same cases.
    #[arg(long, value_parser = named::<IntegratorChoice>())]
    pub integrator: Option<IntegratorChoice>,
}

fn validate(a: ValidateArgs) -> anyhow::Result<()> {
    let report = meshfree_lab::validate::run(&meshfree_lab::validate::Options {
        tier: if a.quick {
            meshfree_lab::validate::Tier::Quick
        } else {
            meshfree_lab::validate::Tier::Full
        },
        backend: a.backend,
        out_dir: a.out.clone(),
        cases: a.case,
        verbose: true,
        courant: a.courant,
        integrator: a.integrator,
    })?;
    let failed = report.checks.iter().filter(|c| !c.pass).count();
    println!(
        "validate ({:?} tier): {} of {} checks pass in {:.1} s; report in {}",
        report.tier,
        report.checks.len() - failed,
        report.checks.len(),
        report.wall_seconds,
        a.out.join("report.md").display()
    );
    anyhow::ensure!(failed == 0, "{failed} validation check(s) failed");
    Ok(())
}

#[derive(Debug, clap::Args)]
pub struct StabilityArgs {
    /// The quick tier: two values per axis on coarse scenes (seconds; what the tests run).
    /// Without it: five values per axis, dx = 0.04 dam break (tens of minutes on a CPU).
    #[arg(long)]
    pub quick: bool,
    /// Where to run: `auto` takes CUDA where a driver and a device answer, else the CPU.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// Output directory for report.md, report.json, cells.csv and the heat maps.
    #[arg(long, value_name = "DIR", default_value = "out/stability")]
    pub out: PathBuf,
    /// Run only the maps whose name contains this (repeatable), e.g. `elastic-strip`.
    #[arg(long, value_name = "NAME")]
    pub map: Vec<String>,
}

fn stability(a: StabilityArgs) -> anyhow::Result<()> {
    use meshfree_lab::stability::{self, Class};
    let report = stability::run(&stability::Options {
        tier: if a.quick {
            stability::Tier::Quick
        } else {
            stability::Tier::Full
        },
        backend: a.backend,
        out_dir: a.out.clone(),
        maps: a.map,
        verbose: true,
    })?;
    for m in &report.maps {
        let n = |k: Class| m.cells.iter().filter(|c| c.class == k).count();
        println!(
            "{}: {} stable, {} inaccurate, {} failed",
            m.def.name,
            n(Class::Stable),
            n(Class::Inaccurate),
            n(Class::Failed)
        );
    }
    println!(
        "stability ({:?} tier) in {:.1} s; report in {}",
        report.tier,
        report.wall_seconds,
        a.out.join("report.md").display()
    );
    Ok(())
}

#[derive(Debug, clap::Args)]
pub struct ChartArgs {
    /// The quick tier: two coarse resolutions and one variant per case (seconds).
    /// Without it: four resolutions and nine variants per case (minutes in a release build),
    /// and the cylinder at Re 100 (three resolutions, nine variants: for the GPU).
    #[arg(long)]
    pub quick: bool,
    /// Where to run (repeatable: `--backend cpu --backend cuda` puts both on the charts).
    #[arg(long, value_parser = named::<BackendChoice>(), default_values = ["auto"])]
    pub backend: Vec<BackendChoice>,
    /// Output directory for chart-<case>.png, chart.csv and chart.json.
    #[arg(long, value_name = "DIR", default_value = "out/chart")]
    pub out: PathBuf,
}

fn chart(a: ChartArgs) -> anyhow::Result<()> {
    use meshfree_lab::chart;
    use meshfree_lab::validate::Tier;
    let points = chart::run(&chart::Options {
        tier: if a.quick { Tier::Quick } else { Tier::Full },
        backends: a.backend,
        out_dir: a.out.clone(),
        verbose: true,
    })?;
    let failed = points.iter().filter(|p| p.error.is_none()).count();
    println!(
        "chart: {} runs ({failed} failed, {} on the Pareto front); charts in {}",
        points.len(),
        points.iter().filter(|p| p.pareto).count(),
        a.out.display()
    );
    Ok(())
}

fn compare(a: CompareArgs) -> anyhow::Result<()> {
    let c = crate::compare::compare_files(&a.a, &a.b, a.match_by, a.worst)
        .map_err(anyhow::Error::msg)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&c)?);
        return Ok(());
    }
    println!(
        "{} pairs matched by {:?}; {} particles only in A, {} only in B",
        c.matched, a.match_by, c.only_in_a, c.only_in_b
    );
    println!(
        "{:<9} {:>12} {:>12} {:>12} {:>9}",
        "field", "max |A-B|", "rms", "rel. L2", "worst id"
    );
    for f in &c.fields {
        println!(
            "{:<9} {:>12.4e} {:>12.4e} {:>12.4e} {:>9}",
            f.field, f.max_abs, f.rms, f.rel_l2, f.worst_id
        );
    }
    println!("farthest pairs (id in A, id in B, distance):");
    for (ia, ib, d) in &c.worst_positions {
        println!("  {ia:>8} {ib:>8} {d:.4e}");
    }
    Ok(())
}

#[derive(Debug, clap::Args)]
#[command(after_help = "\
Examples:
  meshfree validate --quick --backend cuda --out out/validate
  meshfree bench --backend cuda --no-neighbours --out out/bench
  meshfree docs --validate out/validate/report.json --bench out/bench/bench.json

Each table goes between the lines `<!-- generated by `meshfree docs`: NAME -->` and
`<!-- end of generated: NAME -->` of its file: `validate-quick` or `validate-full` (by the
report's tier) in the accuracy page, `bench` in the performance page.")]
pub struct DocsArgs {
    /// A `meshfree validate` report.json.
    #[arg(long, value_name = "JSON")]
    pub validate: Option<PathBuf>,
    /// `meshfree bench` bench.json files (repeatable: their rows are listed in order).
    #[arg(long, value_name = "JSON")]
    pub bench: Vec<PathBuf>,
    /// A `meshfree bench peers` peers-bench.json.
    #[arg(long, value_name = "JSON")]
    pub peers: Option<PathBuf>,
    /// The accuracy page.
    #[arg(long, value_name = "MD", default_value = "docs/reference/accuracy.md")]
    pub accuracy: PathBuf,
    /// The performance page.
    #[arg(
        long,
        value_name = "MD",
        default_value = "docs/reference/performance.md"
    )]
    pub performance: PathBuf,
}

fn read_json<T: serde::de::DeserializeOwned>(path: &std::path::Path) -> anyhow::Result<T> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    serde_json::from_str(&text).with_context(|| format!("parsing {}", path.display()))
}

fn docs(a: DocsArgs) -> anyhow::Result<()> {
    use crate::docs;
    if a.validate.is_none() && a.bench.is_empty() && a.peers.is_none() {
        anyhow::bail!(
            "nothing to write: give --validate REPORT.json, --bench BENCH.json and/or --peers PEERS.json"
        );
    }
    if let Some(path) = &a.peers {
        let b: crate::peers_bench::PeersBench = read_json(path)?;
        docs::splice(&a.performance, "peers", &docs::peers_table(&b))?;
        eprintln!(
            "docs: {} <- {} (peers)",
            a.performance.display(),
            path.display()
        );
    }
    if let Some(path) = &a.validate {
        let report: meshfree_lab::validate::Report = read_json(path)?;
        let name = match report.tier {
            meshfree_lab::validate::Tier::Quick => "validate-quick",
            meshfree_lab::validate::Tier::Full => "validate-full",
        };
        docs::splice(&a.accuracy, name, &docs::accuracy_table(&report))?;
        eprintln!(
            "docs: {} <- {} ({name})",
            a.accuracy.display(),
            path.display()
        );
    }
    if !a.bench.is_empty() {
        let mut rows: Vec<crate::bench::BenchRow> = Vec::new();
        for path in &a.bench {
            rows.extend(read_json::<Vec<crate::bench::BenchRow>>(path)?);
        }
        docs::splice(&a.performance, "bench", &docs::performance_table(&rows))?;
        eprintln!(
            "docs: {} <- {} bench rows",
            a.performance.display(),
            rows.len()
        );
    }
    Ok(())
}
