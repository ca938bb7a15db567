//! The command line (clap derive). `main.rs` parses `Cli` and calls `cli::main`.

use std::path::PathBuf;

use anyhow::Context;
use clap::{Parser, Subcommand};
use serde::Serialize;

use crate::backend::BackendChoice;
use crate::run::{self, Progress, RunOptions};
use crate::scene::{self, Counts, Scene};

const AFTER_HELP: &str = "\
Examples:
  meshfree scenes                          list the built-in scenes
  meshfree run dam-break-2d                run a built-in scene into out/dam-break-2d
  meshfree run my.toml --out runs/a        run a scene file
  meshfree run tank-2d --backend cpu --steps 100 --quiet
  meshfree check my.toml                   validate a scene and count its particles

Scene files: copy one of scenes/*.toml and edit it; every key is commented there.
Output: particles.pvd (open it in ParaView), particles_NNNNN.vtu, diagnostics.csv,
summary.json and a copy of the scene, in the output directory.";

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
    /// List the built-in scenes with their particle counts by kind.
    Scenes {
        /// Print JSON (an array of objects) instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Validate a scene (file or built-in name) and print its particle counts; writes nothing.
    Check {
        /// A scene file path or a built-in scene name.
        scene: String,
    },
}

#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// A scene file path (e.g. scenes/tank-2d.toml) or a built-in scene name (see `meshfree scenes`).
    pub scene: String,
    /// Where to run: `auto` takes CUDA where a driver and a device answer, else the CPU.
    #[arg(long, value_enum, default_value_t = BackendChoice::Auto)]
    pub backend: BackendChoice,
    /// Output directory [default: out/<scene name>].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// End time, replacing the scene's `time.end`.
    #[arg(long, value_name = "T")]
    pub t_end: Option<f64>,
    /// Stop after N time steps (even before the end time).
    #[arg(long, value_name = "N")]
    pub steps: Option<u64>,
    /// Time between outputs, replacing the scene's `time.output_interval`.
    #[arg(long, value_name = "T")]
    pub output_interval: Option<f64>,
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

/// Carry out a parsed command line.
pub fn main(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        Command::Scenes { json } => {
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
            let s = Scene::load(&a.scene)?;
            let options = RunOptions {
                backend: a.backend,
                out_dir: a.out,
                t_end: a.t_end,
                max_steps: a.steps,
                output_interval: a.output_interval,
                progress: if a.quiet {
                    Progress::Quiet
                } else {
                    Progress::Auto
                },
            };
            let summary = match run::run(&s, &options) {
                Ok(summary) => summary,
                // Scene errors already read `<file>: <field>: <reason>`.
                Err(run::RunError::Scene(e)) => return Err(e.into()),
                Err(e) => return Err(e).with_context(|| format!("running scene `{}`", s.name())),
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
