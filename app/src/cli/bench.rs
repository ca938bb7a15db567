//! `meshfree bench`: the dam-break blocks or given scenes (`crate::bench`), and its modes
//! `bench paper` (`crate::paper_bench`) and `bench peers` (`crate::peers_bench`).

use std::path::PathBuf;

use anyhow::Context;
use clap::Subcommand;

use super::named;
use crate::run::Progress;
use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::scheme::IntegratorChoice;
use meshfree_core::scene::Scene;

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
    /// The frames' format for every scene, e.g. `vtu-lz4` [default: each scene's own].
    #[arg(long, value_parser = named::<OutputFormat>())]
    pub format: Option<OutputFormat>,
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

pub(super) fn bench(a: BenchArgs) -> anyhow::Result<()> {
    match a.mode {
        Some(BenchMode::Paper(p)) => return paper_bench(p),
        Some(BenchMode::Peers(p)) => {
            crate::peers_bench::run_peers(
                &p.scenes,
                &p.only,
                p.backend,
                p.format,
                &p.out,
                Progress::Lines,
            )?;
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
        crate::outln!("wrote {}/bench.csv and bench.json", a.out.display())?;
        return Ok(());
    }
    if a.scaling {
        crate::bench::scaling(&o, &a.out)?;
        crate::outln!(
            "wrote {}/bench.csv, bench.json and scaling.json",
            a.out.display()
        )?;
        return Ok(());
    }
    crate::bench::bench(&o, Some(&a.out))?;
    crate::outln!("wrote {}/bench.csv and bench.json", a.out.display())?;
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
        crate::out!("{}", pb::text_table(&rows))?;
        if let Some(md) = &a.markdown {
            std::fs::write(md, pb::markdown(&rows, cpu.as_ref(), gpu.as_ref()))
                .with_context(|| format!("writing {}", md.display()))?;
            crate::outln!("wrote {}", md.display())?;
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
    crate::out!("{}", pb::text_table(&rows))?;
    crate::outln!("wrote {}", a.out.join("paper-bench.json").display())?;
    Ok(())
}
