//! `meshfree bench`: time the step of dam-break-like blocks (a fluid block in a walled box,
//! open at the top) in 2D and 3D at several sizes on the chosen backend. Cubic spline,
//! support 2h, h = 1.3 dx, f32, continuity density, dynamic walls; the leapfrog at Courant
//! 0.4, or the symplectic or the paper's forward Euler at 0.2 (`BenchOptions::integrator`).
//! Or any scene (`bench_scenes`, `meshfree bench --scene`) with its own scheme, from its
//! start (gates opened as a run opens them). Every row names the scheme it ran (integrator,
//! kernel, density form, density diffusion, viscosity) and gives the simulated time per wall
//! second. Nothing is read back inside the timed steps; each repeat ends with one read-back
//! of the simulated time (a synchronisation). Results: `docs/reference/performance.md`.

use std::path::Path;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use meshfree_core::backend::cpu::{CpuSolver, Grid};
use meshfree_core::backend::{BackendChoice, BackendError};
use meshfree_core::named::Named;
use meshfree_core::physics::dim::{Dim, D2, D3};
use meshfree_core::physics::params::{
    self, SphParams, MF_DENSITY_CONTINUITY, MF_INTEGRATOR_LEAPFROG, MF_KIND_BOUNDARY,
};
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::physics::state::State;
use meshfree_core::scene::scheme::declare::ToParam;
use meshfree_core::scene::scheme::{DensityForm, DiffusionForm, IntegratorChoice, KernelChoice};
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::Stepper;
use meshfree_core::solver::{Setup, Solver};

/// What to run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BenchOptions {
    pub backend: BackendChoice,
    /// 2 and/or 3.
    pub dims: Vec<u32>,
    /// Target fluid particle counts.
    pub sizes: Vec<usize>,
    /// Timed steps per repeat.
    pub steps: usize,
    /// Untimed steps first.
    pub warmup: usize,
    /// Repeats; the median is reported.
    pub repeats: usize,
    /// Count neighbours (a CPU pass over a read-back; slow for many millions).
    pub count_neighbours: bool,
    /// The time integrator of every run (default the leapfrog).
    #[serde(default)]
    pub integrator: IntegratorChoice,
    /// Step in this many subdomains (`backend::Layout::Threads`); None: one domain.
    #[serde(default)]
    pub decompose: Option<usize>,
    /// Step on this many GPUs, a subdomain each (`backend::Layout::Gpus`).
    #[serde(default)]
    pub gpus: Option<usize>,
}

impl Default for BenchOptions {
    fn default() -> Self {
        BenchOptions {
            backend: BackendChoice::Auto,
            dims: vec![2, 3],
            sizes: vec![3_000, 30_000, 300_000, 4_000_000],
            steps: 50,
            warmup: 10,
            repeats: 3,
            count_neighbours: true,
            integrator: IntegratorChoice::default(),
            decompose: None,
            gpus: None,
        }
    }
}

/// One measured configuration.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BenchRow {
    pub backend: String,
    pub device: String,
    pub dim: u32,
    /// All particles (fluid + wall).
    pub particles: usize,
    pub fluid: usize,
    pub steps: usize,
    /// Median over repeats.
    pub ms_per_step: f64,
    /// particles x steps / s, all particles counted.
    pub particle_steps_per_s: f64,
    /// Mean neighbours (within the support, self excluded) per fluid particle; 0 if not counted.
    pub neighbours: f64,
    /// Device bytes per particle (all arrays / all particles); 0 on the CPU.
    pub bytes_per_particle: f64,
    /// Device bytes per fluid particle.
    pub bytes_per_fluid_particle: f64,
    /// The scheme: "leapfrog", "symplectic-euler" or "euler".
    #[serde(default)]
    pub integrator: String,
    /// "continuity" or "summation".
    #[serde(default)]
    pub density: String,
    /// The scene's name; empty for the dam-break blocks.
    #[serde(default)]
    pub scene: String,
    /// The smoothing kernel ("cubic-spline", "wendland-c2").
    #[serde(default)]
    pub kernel: String,
    /// The density diffusion: "none", or delta and its form, e.g. "0.1 fourtakas".
    #[serde(default)]
    pub diffusion: String,
    /// The viscosity: artificial alpha and laminar nu, e.g. "alpha 0.02, nu 0".
    #[serde(default)]
    pub viscosity: String,
    /// [T/s] simulated time per wall second of the timed steps (median repeat).
    #[serde(default)]
    pub simulated_per_second: f64,
    /// The day of the run, `YYYY-MM-DD` (UTC).
    #[serde(default)]
    pub date: String,
    /// The build's commit (`meshfree_core::build_info::COMMIT`).
    #[serde(default)]
    pub commit: String,
    /// Subdomains (`--decompose`, or one per GPU with `--gpus`); 1 for one domain.
    #[serde(default = "one")]
    pub subdomains: usize,
    /// GPUs the subdomains ran on (`--gpus`); 1 otherwise (0 on the CPU).
    #[serde(default = "one")]
    pub gpus: usize,
    /// \[us\] the halo exchange and step-size agreement per timed step (the slowest rank);
    /// 0 for one domain.
    #[serde(default)]
    pub exchange_us_per_step: f64,
    /// Halo bytes received per timed step, over all subdomains; 0 for one domain.
    #[serde(default)]
    pub halo_bytes_per_step: f64,
    /// \[us\] of `exchange_us_per_step`, the transport's send and receive (NCCL between
    /// GPUs), the wait for the slower rank included.
    #[serde(default)]
    pub transfer_us_per_step: f64,
}

fn one() -> usize {
    1
}

/// The scene files' name of the choice `T` whose parameter value is `v`.
fn choice_name<T: Named + ToParam<i32>>(v: i32) -> &'static str {
    T::ALL
        .iter()
        .find(|(c, _, _)| c.to_param() == v)
        .map_or("?", |(_, name, _)| *name)
}

/// The scheme of `p`, in the scene files' words: (integrator, kernel, density form,
/// density diffusion, viscosity).
fn scheme(p: &SphParams) -> [String; 5] {
    let diffusion = if p.density_diffusion > 0.0 {
        format!(
            "{} {}",
            p.density_diffusion,
            choice_name::<DiffusionForm>(p.density_diffusion_form)
        )
    } else {
        "none".into()
    };
    [
        choice_name::<IntegratorChoice>(p.integrator).into(),
        choice_name::<KernelChoice>(p.kernel).into(),
        choice_name::<DensityForm>(p.density_form).into(),
        diffusion,
        format!("alpha {}, nu {}", p.alpha, p.viscosity),
    ]
}

/// The dam-break-like block: about `n_fluid` fluid particles, a 2:1 (height:width) column
/// in the left half of a walled box (3 wall layers, open top).
pub fn dam_break(dim: u32, n_fluid: usize) -> Setup {
    let d3 = dim == 3;
    let nx = if d3 {
        ((n_fluid as f64 / 2.0).cbrt().round() as i32).max(2)
    } else {
        ((n_fluid as f64 / 2.0).sqrt().round() as i32).max(2)
    };
    let (ny, nz) = (2 * nx, if d3 { nx } else { 1 });
    let dx = 1.0 / nx as f32;
    let (bx, by) = (2 * nx, ny + 4);
    let l = 3;
    let g = 9.81f32;
    let height = ny as f32 * dx;
    let mut p = SphParams {
        dim: dim as i32,
        periodic: [0, 0, 0],
        domain_min: [
            -(l as f32) * dx,
            -(l as f32) * dx,
            if d3 { -(l as f32) * dx } else { 0.0 },
        ],
        domain_max: [
            (bx + l) as f32 * dx,
            by as f32 * dx,
            if d3 { (nz + l) as f32 * dx } else { 0.0 },
        ],
        kernel: 0,
        dx,
        h: 1.3 * dx,
        density_form: MF_DENSITY_CONTINUITY as i32,
        rho0: 1000.0,
        c0: 10.0 * (2.0 * g * height).sqrt(),
        tait_gamma: 7.0,
        alpha: 0.02,
        beta: 0.0,
        xsph: 0.5,
        solid_rho0: 1000.0,
        lj_c0: 5.0 * g * height / dx, // Monaghan's D = 5 g H, per unit r0 (an acceleration)
        lj_r0: dx,
        lj_p1: 12,
        lj_p2: 6,
        wall_contact: 1,
        wall_coupling: 1,
        gravity: [0.0, -g, 0.0],
        integrator: MF_INTEGRATOR_LEAPFROG as i32,
        courant: IntegratorChoice::Leapfrog.default_courant() as f32,
        ..Default::default()
    };
    params::derive(&mut p);
    let mass = p.rho0 * dx.powi(dim as i32);
    let mut out = Vec::with_capacity((nx * ny * nz) as usize * 6 / 5);
    let (z0, z1) = if d3 { (-l, nz + l) } else { (0, 1) };
    for k in z0..z1 {
        for j in -l..by {
            for i in -l..bx + l {
                let wall = j < 0 || i < 0 || i >= bx || (d3 && (k < 0 || k >= nz));
                let fluid = !wall && i < nx && j < ny;
                if !wall && !fluid {
                    continue;
                }
                let z = if d3 { (k as f32 + 0.5) * dx } else { 0.0 };
                let y = (j as f32 + 0.5) * dx;
                // The column starts hydrostatic, eq. (9): p = rho0 g (H - y).
                let pressure = if fluid {
                    p.rho0 * g * (height - y)
                } else {
                    0.0
                };
                let density = p.rho0 * (1.0 + pressure / p.tait_b).powf(1.0 / p.tait_gamma);
                out.push(Particle {
                    id: out.len() as u32,
                    kind: if wall { Kind::Boundary } else { Kind::Fluid },
                    group: if wall { 0 } else { 1 },
                    position: [(i as f32 + 0.5) * dx, y, z],
                    density,
                    pressure,
                    mass,
                    ..Default::default()
                });
            }
        }
    }
    Setup {
        params: p,
        particles: out,
        wall_surface: Vec::new(),
        bodies: Vec::new(),
        motion_series: Vec::new(),
    }
}

/// Mean number of neighbours (self excluded) per non-boundary particle.
pub fn mean_neighbours<D: Dim>(p: &SphParams, particles: &[Particle]) -> f64 {
    use rayon::prelude::*;
    let mut s = State::<D>::from_particles(particles, false, false, p.solid_rho0);
    let mut grid = Grid::default();
    grid.build(p, &mut s);
    let (sum, cnt) = (0..s.len())
        .into_par_iter()
        .filter(|&i| s.kind[i] as u32 != MF_KIND_BOUNDARY)
        .map(|i| {
            let mut k = 0u64;
            grid.for_each_neighbor::<D>(p, &s.pos, s.pos[i], |j, _, _| k += (j != i) as u64);
            (k, 1u64)
        })
        .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1));
    sum as f64 / cnt.max(1) as f64
}

/// (solver, device bytes) on `choice`, in `decompose` subdomains or on `gpus` GPUs where
/// given (device bytes then 0 here: `Solver::exchange_cost` counts them after stepping).
fn make<D: Dim>(
    choice: BackendChoice,
    setup: Setup,
    decompose: Option<usize>,
    gpus: Option<usize>,
) -> Result<(Box<dyn Solver>, usize), BackendError> {
    if let Some(g) = gpus {
        return Ok((
            meshfree_core::backend::create(
                BackendChoice::Cuda,
                meshfree_core::backend::Layout::Gpus(g),
                setup,
            )?,
            0,
        ));
    }
    if let Some(n) = decompose {
        return Ok((
            meshfree_core::backend::create(
                choice,
                meshfree_core::backend::Layout::Threads(n),
                setup,
            )?,
            0,
        ));
    }
    #[cfg(feature = "cuda")]
    if choice != BackendChoice::Cpu {
        match meshfree_core::backend::cuda::CudaSolver::<D>::new(setup.clone()) {
            Ok(s) => {
                let b = s.device_bytes();
                return Ok((Box::new(s), b));
            }
            Err(e) if choice == BackendChoice::Cuda => return Err(e),
            Err(_) => {}
        }
    }
    #[cfg(not(feature = "cuda"))]
    if choice == BackendChoice::Cuda {
        return Err(BackendError::CudaUnavailable(
            "this build has the `cuda` feature off".into(),
        ));
    }
    Ok((Box::new(CpuSolver::<D>::new(setup)), 0))
}

fn run_one<D: Dim>(o: &BenchOptions, dim: u32, n: usize) -> Result<BenchRow, BackendError> {
    let mut setup = dam_break(dim, n);
    setup.params.integrator = o.integrator.to_param();
    // Each integrator at its own Courant number (eq. (19)), as a scene without `courant`.
    setup.params.courant = o.integrator.default_courant() as f32;
    timed::<D>(o, setup, Vec::new(), "")
}

/// Time `setup` (its gates `gates`, as `Scene::gates`) as `o` asks; `scene` names it.
fn timed<D: Dim>(
    o: &BenchOptions,
    setup: Setup,
    gates: Vec<(u32, f64)>,
    scene: &str,
) -> Result<BenchRow, BackendError> {
    let dim = setup.params.dim as u32;
    let p = setup.params;
    let fluid = setup
        .particles
        .iter()
        .filter(|q| q.kind == Kind::Fluid)
        .count();
    let resident0 = resident_bytes();
    let (mut s, bytes) = make::<D>(o.backend, setup, o.decompose, o.gpus)?;
    // The one stepping path, as a run takes it: batches of CUDA graphs, the clock read
    // once per batch, the health checked every `step::CHECK_EVERY` steps; the gates due at
    // t = 0 open in the first batch, so the particles are counted after the warm-up.
    let mut stepper = Stepper::new(gates);
    let mut fault = stepper.advance_steps(s.as_mut(), o.warmup as u64).err();
    let total = s.len();
    // (ms per step, simulated time per wall second) of each repeat.
    let mut repeats = Vec::new();
    let cost0 = s.exchange_cost().unwrap_or_default();
    // On the CPU the solver's memory is the host's: what the process's resident set grew
    // by over the set-up and the warm-up (its arrays, grid and scratch; the set-up's
    // particle list was allocated before and is not counted).
    let bytes = match (bytes, resident0, resident_bytes()) {
        (0, Some(before), Some(after)) => after.saturating_sub(before) as usize,
        _ => bytes,
    };
    for _ in 0..o.repeats.max(1) {
        let sim0 = s.time();
        let t0 = Instant::now();
        fault = fault.or(stepper.advance_steps(s.as_mut(), o.steps as u64).err());
        let sim = s.time() - sim0; // waits for the last batch
        let wall = t0.elapsed().as_secs_f64();
        repeats.push((wall * 1e3 / o.steps.max(1) as f64, sim / wall));
    }
    let cost = s.exchange_cost().unwrap_or_default();
    // A decomposed solver's memory after stepping: its halos and spare capacity included.
    let bytes = bytes.max(cost.device_bytes as usize);
    let timed_steps = (o.steps * o.repeats.max(1)).max(1) as f64;
    let exchange_us_per_step = (cost.seconds - cost0.seconds) * 1e6 / timed_steps;
    let halo_bytes_per_step = (cost.bytes - cost0.bytes) as f64 / timed_steps;
    let transfer_us_per_step = (cost.transfer_seconds - cost0.transfer_seconds) * 1e6 / timed_steps;
    repeats.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (med, simulated_per_second) = repeats[repeats.len() / 2];
    let neighbours = if o.count_neighbours {
        mean_neighbours::<D>(&p, &s.particles())
    } else {
        0.0
    };
    if let Some(f) = fault.or(s.check().err()) {
        crate::errln!("bench {scene} {dim}D {total}: {f}");
    }
    let info = s.info();
    let gpus = match (o.gpus, info.backend.as_str()) {
        (Some(g), _) => g,
        (None, "cpu") => 0,
        (None, _) => 1,
    };
    let [integrator, kernel, density, diffusion, viscosity] = scheme(&p);
    Ok(BenchRow {
        backend: info.backend,
        device: info.device,
        dim,
        particles: total,
        fluid,
        steps: o.steps,
        ms_per_step: med,
        particle_steps_per_s: total as f64 / (med * 1e-3),
        neighbours,
        bytes_per_particle: bytes as f64 / total as f64,
        bytes_per_fluid_particle: bytes as f64 / fluid.max(1) as f64,
        integrator,
        density,
        scene: scene.into(),
        kernel,
        diffusion,
        viscosity,
        simulated_per_second,
        date: meshfree_core::build_info::today(),
        commit: meshfree_core::build_info::COMMIT.into(),
        subdomains: o.gpus.or(o.decompose).unwrap_or(1),
        gpus,
        exchange_us_per_step,
        halo_bytes_per_step,
        transfer_us_per_step,
    })
}

/// Run every (dim, size) of `o`; print one line per row; write `bench.csv` and
/// `bench.json` into `out_dir` when given.
pub fn bench(o: &BenchOptions, out_dir: Option<&Path>) -> Result<Vec<BenchRow>, BackendError> {
    let mut rows = Vec::new();
    for &dim in &o.dims {
        for &n in &o.sizes {
            let r = if dim == 2 {
                run_one::<D2>(o, dim, n)?
            } else {
                run_one::<D3>(o, dim, n)?
            };
            let _ = print_row(&r); // the table is also in bench.csv: a closed stdout stops no bench
            rows.push(r);
        }
    }
    write_rows(&rows, out_dir);
    Ok(rows)
}

/// One row of `scaling.json`: a size on `gpus` GPUs against the same work on one.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ScalingRow {
    /// "strong" (the same particles on every count) or "weak" (the particles times the
    /// count).
    pub kind: String,
    pub dim: u32,
    pub gpus: usize,
    pub particles: usize,
    pub ms_per_step: f64,
    /// Strong: t1 / (g tg); weak: t1 / tg, with t1 the one-GPU time of the same size
    /// (strong) or of the size per GPU (weak).
    pub efficiency: f64,
    pub exchange_us_per_step: f64,
    pub transfer_us_per_step: f64,
    pub halo_bytes_per_step: f64,
    /// Device bytes per particle (all GPUs' arrays, halo capacity included, over all
    /// particles).
    pub bytes_per_particle: f64,
}

/// Strong and weak scaling over 1, 2, 4, ... up to `o.gpus` GPUs for every (dim, size) of
/// `o` (`meshfree bench --gpus N --scaling`): the dam-break blocks, one subdomain per GPU
/// (one GPU runs one domain, no exchange); every timed row in `bench.csv`/`bench.json`
/// and the efficiencies in `scaling.json` under `out_dir`.
pub fn scaling(o: &BenchOptions, out_dir: &Path) -> anyhow::Result<Vec<ScalingRow>> {
    let max = o.gpus.unwrap_or(1).max(1);
    let counts: Vec<usize> = std::iter::successors(Some(1usize), |g| Some(g * 2))
        .take_while(|&g| g <= max)
        .collect();
    let mut rows = Vec::new();
    let mut timed_rows = Vec::new();
    let mut one = |dim: u32, n: usize, g: usize| -> anyhow::Result<BenchRow> {
        let mut oo = o.clone();
        oo.gpus = (g > 1).then_some(g);
        oo.backend = BackendChoice::Cuda;
        let r = if dim == 2 {
            run_one::<D2>(&oo, dim, n)?
        } else {
            run_one::<D3>(&oo, dim, n)?
        };
        let _ = print_row(&r); // the table is also in bench.csv: a closed stdout stops no bench
        timed_rows.push(r.clone());
        Ok(r)
    };
    for &dim in &o.dims {
        for &n in &o.sizes {
            let base = one(dim, n, 1)?;
            for (kind, scale) in [("strong", false), ("weak", true)] {
                for &g in &counts {
                    let r = if g == 1 {
                        base.clone()
                    } else {
                        one(dim, if scale { n * g } else { n }, g)?
                    };
                    let efficiency = if scale {
                        base.ms_per_step / r.ms_per_step
                    } else {
                        base.ms_per_step / (g as f64 * r.ms_per_step)
                    };
                    crate::outln!(
                        "{kind} scaling {dim}D: {} particles on {g} GPU(s): {:.3} ms/step, \
                         efficiency {:.1} %",
                        r.particles,
                        r.ms_per_step,
                        100.0 * efficiency
                    )?;
                    rows.push(ScalingRow {
                        kind: kind.into(),
                        dim,
                        gpus: g,
                        particles: r.particles,
                        ms_per_step: r.ms_per_step,
                        efficiency,
                        exchange_us_per_step: r.exchange_us_per_step,
                        transfer_us_per_step: r.transfer_us_per_step,
                        halo_bytes_per_step: r.halo_bytes_per_step,
                        bytes_per_particle: r.bytes_per_particle,
                    });
                }
            }
        }
    }
    write_rows(&timed_rows, Some(out_dir));
    std::fs::write(
        out_dir.join("scaling.json"),
        serde_json::to_string_pretty(&rows)?,
    )?;
    Ok(rows)
}

/// Time each of `scenes` with its own scheme from its start (`o`'s steps, warm-up and
/// repeats; `o.dims`, `sizes` and `integrator` are the blocks' and not used); print and
/// write the rows as `bench` does.
pub fn bench_scenes(
    o: &BenchOptions,
    scenes: &[Scene],
    out_dir: Option<&Path>,
) -> anyhow::Result<Vec<BenchRow>> {
    let mut rows = Vec::new();
    for scene in scenes {
        let setup = scene.setup()?;
        let r = if scene.file.dimension == 2 {
            timed::<D2>(o, setup, scene.gates(), scene.name())?
        } else {
            timed::<D3>(o, setup, scene.gates(), scene.name())?
        };
        let _ = print_row(&r); // the table is also in bench.csv: a closed stdout stops no bench
        rows.push(r);
    }
    write_rows(&rows, out_dir);
    Ok(rows)
}

fn print_row(r: &BenchRow) -> Result<(), crate::term::StdoutError> {
    let mut what = if r.scene.is_empty() {
        String::new()
    } else {
        format!("{}: ", r.scene)
    };
    if r.subdomains > 1 || r.gpus > 1 {
        what += &format!(
            "{} subdomains on {} GPU(s) (exchange {:.1} us/step, of which transfer {:.1}; \
             {:.3e} halo B/step): ",
            r.subdomains,
            r.gpus,
            r.exchange_us_per_step,
            r.transfer_us_per_step,
            r.halo_bytes_per_step
        );
    }
    crate::outln!(
        "{what}{}D {:>9} particles ({:>9} fluid): {:>9.4} ms/step, {:.3e} particle-steps/s, {:.4e} \
         simulated s per s, {:.1} neighbours, {:.0} B/particle ({:.0} B/fluid particle) [{} {}; {}, \
         {}, {} density, diffusion {}, {}]",
        r.dim,
        r.particles,
        r.fluid,
        r.ms_per_step,
        r.particle_steps_per_s,
        r.simulated_per_second,
        r.neighbours,
        r.bytes_per_particle,
        r.bytes_per_fluid_particle,
        r.backend,
        r.device,
        r.integrator,
        r.kernel,
        r.density,
        r.diffusion,
        r.viscosity
    )
}

/// `bench.csv` and `bench.json` of `rows` into `out_dir`, where given.
fn write_rows(rows: &[BenchRow], out_dir: Option<&Path>) {
    if let Some(dir) = out_dir {
        let _ = std::fs::create_dir_all(dir);
        let mut csv = String::from(
            "scene,backend,device,dim,particles,fluid,steps,ms_per_step,particle_steps_per_s,simulated_per_second,neighbours,bytes_per_particle,bytes_per_fluid_particle,integrator,kernel,density,diffusion,viscosity,subdomains,gpus,exchange_us_per_step,transfer_us_per_step,halo_bytes_per_step\n",
        );
        for r in rows {
            csv += &format!(
                "{},{},{},{},{},{},{},{:.6},{:.6e},{:.6e},{:.2},{:.1},{:.1},{},{},{},{},{},{},{},{:.2},{:.2},{:.1}\n",
                r.scene,
                r.backend,
                r.device.replace(',', " "),
                r.dim,
                r.particles,
                r.fluid,
                r.steps,
                r.ms_per_step,
                r.particle_steps_per_s,
                r.simulated_per_second,
                r.neighbours,
                r.bytes_per_particle,
                r.bytes_per_fluid_particle,
                r.integrator,
                r.kernel,
                r.density,
                r.diffusion,
                r.viscosity.replace(',', ";"),
                r.subdomains,
                r.gpus,
                r.exchange_us_per_step,
                r.transfer_us_per_step,
                r.halo_bytes_per_step
            );
        }
        let _ = std::fs::write(dir.join("bench.csv"), csv);
        let _ = std::fs::write(
            dir.join("bench.json"),
            serde_json::to_string_pretty(&rows).unwrap_or_default(),
        );
    }
}

/// The process's resident memory in bytes (Linux: `/proc/self/statm`), where readable.
#[cfg(unix)]
fn resident_bytes() -> Option<u64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    // SAFETY: sysconf(3) reads a system constant; no memory is involved.
    let page = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    Some(pages * u64::try_from(page).ok()?)
}

#[cfg(not(unix))]
fn resident_bytes() -> Option<u64> {
    None
}
