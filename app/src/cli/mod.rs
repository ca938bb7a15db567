//! The command line (clap derive). `main.rs` parses `Cli` and calls `cli::main`; each
//! command's arguments and handler are in the file named for it (`run.rs`, `scenes.rs` for
//! `scenes` and `check`, `bench.rs`, `view.rs` for `view` and `render`, `compare.rs`,
//! `validate.rs`, `stability.rs`, `chart.rs`, `docs.rs`, `waves.rs`).

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Parser, Subcommand};

use crate::run::RunError;
use meshfree_core::backend::BackendError;
use meshfree_core::named::Named;
use meshfree_core::scene::SceneError;

mod bench;
mod chart;
mod compare;
mod docs;
mod run;
mod scenes;
mod stability;
mod validate;
mod view;
mod waves;

pub use bench::{BenchArgs, BenchMode, PaperBenchArgs, PeersBenchArgs};
pub use chart::ChartArgs;
pub use compare::CompareArgs;
pub use docs::DocsArgs;
pub use run::RunArgs;
pub use scenes::{scene_rows, CheckArgs, SceneRow, ScenesArgs};
pub use stability::StabilityArgs;
pub use validate::ValidateArgs;
pub use view::{RenderArgs, ViewArgs};
pub use waves::{WavesArgs, WavesReport};

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
blow-up), every [output] checkpoint_interval of simulated time, and every 10 minutes of
wall time (--checkpoint-every), so a run killed outright loses at most that. `run --resume DIR`
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
    Scenes(ScenesArgs),
    /// Validate a scene (file or built-in name) and print its particle counts (above two
    /// million, the estimate: up to how many and the memory to start); writes nothing.
    Check(CheckArgs),
    /// Measure speed: 2D and 3D dam-break blocks at several sizes; prints a table and writes
    /// bench.csv and bench.json.
    Bench(BenchArgs),
    /// Watch a scene live in an OpenGL window, or step through a finished run's frames (needs
    /// the `viewer` feature and a display).
    #[command(after_help = VIEW_HELP)]
    View(ViewArgs),
    /// Render a scene, or a finished run's frames, to PNG without a display (EGL), at a time
    /// or as a sequence of frames.
    #[command(after_help = RENDER_HELP)]
    Render(RenderArgs),
    /// Compare two particle CSV files (`run --format csv`, or another code's export in the same
    /// columns): per-field error norms and the worst particles.
    Compare(CompareArgs),
    /// Regular waves at a run's gauges (gauges.csv): each gauge's mean level and wave height
    /// over whole periods, and the incident and reflected heights and the reflection
    /// coefficient from two or more gauges (Mansard & Funke 1980).
    Waves(WavesArgs),
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

const VIEW_HELP: &str = "\
Examples:
  meshfree view dam-break-2d               simulate a built-in scene live
  meshfree view out/dam-break-2d           step through the frames of a finished run";

const RENDER_HELP: &str = "\
Examples:
  meshfree render dam-break-2d --at 0.4 --out db.png
                                   simulate a built-in scene to t = 0.4 and draw it
  meshfree render out/dam-break-2d --out last.png
                                   draw the last frame of a finished run (no simulation)
  meshfree render out/dam-break-2d --frames 50 --out movie/f.png
                                   50 of the run's frames, evenly spaced: movie/f_0000.png ...
  meshfree render out/dam-break-2d --at 1.5 --field pressure --out p.png
                                   the run's frame nearest t = 1.5, coloured by pressure
  meshfree render out/dam-break-2d --movie db.mp4 --fps 30
                                   every frame of the run as a video (needs ffmpeg)

A directory is read as a run's output (particles.pvd and its .vtu files, or
particles_NNNNN.csv, and scene.toml); anything else as a scene file or a built-in name.
A field the run did not write (its scene's [output] fields) is refused, naming the fields
the frames have.";

/// Exit statuses (listed in `meshfree run --help`).
pub mod exit {
    pub const OTHER: u8 = 1;
    pub const BAD_INPUT: u8 = 2;
    pub const BLOW_UP: u8 = 3;
    pub const IO: u8 = 4;
    pub const INTERRUPTED: u8 = crate::interrupt::EXIT_INTERRUPTED;
}

/// The exit status for an error `main` returned: the first run, scene or standard-output
/// error in its chain decides. 0 where the reader of standard output went away
/// (`term::StdoutError::closed`): the output ended there, and nothing is printed.
pub fn exit_code(e: &anyhow::Error) -> u8 {
    for cause in e.chain() {
        if let Some(out) = cause.downcast_ref::<crate::term::StdoutError>() {
            return if out.closed() { 0 } else { exit::IO };
        }
        if let Some(r) = cause.downcast_ref::<RunError>() {
            return match r {
                RunError::Scene(_)
                | RunError::Backend(BackendError::Decomposition(_))
                | RunError::OutputInUse { .. }
                | RunError::Checkpoint { .. } => exit::BAD_INPUT,
                RunError::BlowUp { .. } => exit::BLOW_UP,
                RunError::Io { .. } => exit::IO,
                RunError::Interrupted { .. } => exit::INTERRUPTED,
                RunError::Backend(_) => exit::OTHER,
            };
        }
        if cause.downcast_ref::<SceneError>().is_some()
            || cause.downcast_ref::<crate::bad_input::BadInput>().is_some()
        {
            return exit::BAD_INPUT;
        }
    }
    exit::OTHER
}

/// Carry out a parsed command line. `View` and `Render` are carried out by the binary's
/// viewer glue (`src/view.rs`), which keeps GL out of this library.
pub fn main(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Run(a) => run::run(a),
        Command::Scenes(a) => scenes::scenes(a),
        Command::Check(a) => scenes::check(a),
        Command::Bench(a) => bench::bench(a),
        Command::Compare(a) => compare::compare(a),
        Command::Waves(a) => waves::waves(a),
        Command::Validate(a) => validate::validate(a),
        Command::Stability(a) => stability::stability(a),
        Command::Chart(a) => chart::chart(a),
        Command::Docs(a) => docs::docs(a),
        Command::View(_) | Command::Render(_) => anyhow::bail!(
            "this build has no viewer: rebuild with the `viewer` feature (on by default)"
        ),
    }
}
