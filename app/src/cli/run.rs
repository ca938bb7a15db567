//! `meshfree run`: a scene, or a run continued from its checkpoint (`crate::run`).

use std::path::PathBuf;

use anyhow::Context;

use super::named;
use crate::run::{self, Progress, RunOptions};
use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::Scene;

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
    /// Output directory (default: `out/<scene file's stem>`, `out/<name>` for a built-in).
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
    /// End time, in the scene's time unit (seconds for SI scenes), replacing the scene's
    /// `time.end`.
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
    /// Time between outputs, in the scene's time unit (seconds for SI scenes), replacing
    /// the scene's `time.output_interval`.
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
    /// Write a checkpoint every this many minutes of wall time besides those every
    /// `[output] checkpoint_interval` of simulated time and at every stop, so a run killed
    /// outright (kill -9, a power cut) loses at most that much work; 0: none by wall time.
    #[arg(long, value_name = "MINUTES", default_value_t = 10.0)]
    pub checkpoint_every: f64,
    /// No progress output; only errors (and the final line on stdout).
    #[arg(long, short)]
    pub quiet: bool,
}

pub(super) fn run(a: RunArgs) -> anyhow::Result<()> {
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
    anyhow::ensure!(
        a.checkpoint_every.is_finite() && a.checkpoint_every >= 0.0,
        "--checkpoint-every {}: give the minutes of wall time between checkpoints (0: none)",
        a.checkpoint_every
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
        checkpoint_wall: (a.checkpoint_every > 0.0).then_some(a.checkpoint_every * 60.0),
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
    crate::outln!(
        "{}: {} steps to t = {:.4} on {} ({}), {:.3e} particle-steps/s; output in {}",
        summary.scene,
        summary.steps,
        summary.simulated_time,
        summary.backend,
        summary.device,
        summary.particle_steps_per_second,
        summary.output_dir
    )?;
    Ok(())
}
