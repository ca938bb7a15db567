//! CPU vs CUDA, stage by stage (`src/backend/cpu/*.rs` <-> `cuda/*.cu`), in 2D and 3D with
//! fluid, an elastic body, wall particles and a periodic axis, in four variants (dynamic
//! walls / Lennard-Jones-only walls, summation / continuity density, forward / symplectic
//! Euler, with / without artificial stress, with / without density diffusion; two also
//! with an inflow band, two more and a long run with the band's ramped start); the stages
//! run in the order of `Solver::step` for the variant's integrator (forward Euler: the
//! GPU's fused `forces_and_rates` pass against the CPU's two stages). Then diagnostics after 200 steps; the fused pass against the GPU's two separate
//! passes, bit for bit; and the `SphParams` layout as nvcc sees it. Morris's no-slip walls
//! (`no_slip`) run in five stage scenes, a long run and the fused-pass check. Probes
//! (`Solver::sample_points`, `cuda/probes.cu`) sample the same values as the CPU's at points
//! over the domain, and sampling leaves the GPU's stepping unchanged, bit for bit. The force
//! monitors' device sums (`Solver::wall_forces`, `cuda/monitor.cu`) against the read-back
//! path (`monitor::wall_force`) on wall objects in flow, with and without bodies.
//! Total-Lagrangian bodies (`cuda/tlsph.cu`): the stage scenes with `solid_stress`,
//! `solid_forces` and the displacements compared too (2D and 3D, both integrators), and runs
//! of 100-200 steps through captured graphs, one with a body removed halfway.
//!
//! The tests that need a GPU are `#[ignore]`d unless the build had `MESHFREE_REQUIRE_CUDA=1`
//! (`build.rs` turns it into the cfg `meshfree_require_cuda`); `-- --include-ignored` runs
//! them too. A test that runs fails without a usable GPU: it never passes by skipping.
//!
//! Each stage starts from identical inputs: after comparing a stage, the CPU state is
//! uploaded to the GPU (`CudaSolver::upload_state`), so differences do not carry over.
#![cfg(feature = "cuda")]

mod common;

use meshfree_core::backend::cpu::{self, CpuSolver};
use meshfree_core::backend::cuda::CudaSolver;
use meshfree_core::dim::{Dim, D2, D3};
use meshfree_core::monitor;
use meshfree_core::params::{
    self, SphParams, MF_DENSITY_CONTINUITY, MF_DENSITY_SUMMATION, MF_DIFFUSION_ANTUONO,
    MF_DIFFUSION_FOURTAKAS, MF_DIFFUSION_MOLTENI, MF_INTEGRATOR_EULER, MF_SOLID_TOTAL_LAGRANGIAN,
};
use meshfree_core::params::{
    MF_INTEGRATOR_LEAPFROG, MF_INTEGRATOR_SYMPLECTIC_EULER, MF_KIND_BOUNDARY,
};
use meshfree_core::particle::{Kind, Particle};
use meshfree_core::solver::{PointSample, Setup, Solver};
use meshfree_core::state::State;

/// The GPU solver for `setup`; without a usable GPU the test fails (it was asked to run).
fn gpu<D: Dim>(setup: &Setup) -> CudaSolver<D> {
    CudaSolver::<D>::new(setup.clone()).unwrap_or_else(|e| {
        panic!(
            "this GPU test needs a usable CUDA device: {e} (it ran because the build had \
             MESHFREE_REQUIRE_CUDA=1, or because of --ignored / --include-ignored)"
        )
    })
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    fn sym(&mut self, a: f32) -> f32 {
        a * (2.0 * self.next() - 1.0)
    }
}

/// What a parity scene switches on.
#[derive(Clone, Copy, Debug)]
struct Variant {
    /// Dynamic walls (`wall_coupling`): boundary particles carry density and pressure.
    dynamic_walls: bool,
    continuity: bool,
    symplectic: bool,
    art_stress: bool,
    laminar: bool,
    /// Density diffusion (delta-SPH, `density_diffusion` = 0.1) with a perturbed initial fluid
    /// density, so that the diffusive term is not zero from the first step.
    density_diffusion: bool,
    /// The fluid diffusion's form (`density_diffusion_form`, `MF_DIFFUSION_*`): Fourtakas et al. 2019's
    /// hydrostatic one, or Antuono et al. 2010's with renormalised gradients.
    density_diffusion_form: u32,
    /// Density diffusion within the solid body (`solid_density_diffusion` = 0.1) with a perturbed
    /// initial solid density.
    solid_delta: bool,
}
/// 2D: summation, dynamic walls, forward Euler, artificial stress, laminar viscosity.
const V_2D_A: Variant = Variant {
    dynamic_walls: true,
    continuity: false,
    symplectic: false,
    art_stress: true,
    laminar: true,
    density_diffusion: false,
    density_diffusion_form: MF_DIFFUSION_MOLTENI,
    solid_delta: false,
};
/// 2D: continuity, Lennard-Jones-only walls, symplectic Euler, artificial stress.
const V_2D_B: Variant = Variant {
    dynamic_walls: false,
    continuity: true,
    symplectic: true,
    art_stress: true,
    laminar: false,
    density_diffusion: false,
    density_diffusion_form: MF_DIFFUSION_MOLTENI,
    solid_delta: false,
};
/// 3D: continuity, Lennard-Jones-only walls, symplectic Euler, no artificial stress.
const V_3D_A: Variant = Variant {
    dynamic_walls: false,
    continuity: true,
    symplectic: true,
    art_stress: false,
    laminar: false,
    density_diffusion: false,
    density_diffusion_form: MF_DIFFUSION_MOLTENI,
    solid_delta: false,
};
/// 3D: continuity with dynamic walls (wall d rho/dt), forward Euler, artificial stress,
/// laminar viscosity.
const V_3D_B: Variant = Variant {
    dynamic_walls: true,
    continuity: true,
    symplectic: false,
    art_stress: true,
    laminar: true,
    density_diffusion: false,
    density_diffusion_form: MF_DIFFUSION_MOLTENI,
    solid_delta: false,
};
/// 2D and 3D: `V_2D_B` / `V_3D_B` with density diffusion.
const V_2D_DELTA: Variant = Variant {
    density_diffusion: true,
    ..V_2D_B
};
const V_3D_DELTA: Variant = Variant {
    density_diffusion: true,
    ..V_3D_B
};
/// `V_2D_DELTA` / `V_3D_DELTA` with the diffusion's hydrostatic form.
const V_2D_FOURTAKAS: Variant = Variant {
    density_diffusion_form: MF_DIFFUSION_FOURTAKAS,
    ..V_2D_DELTA
};
const V_3D_FOURTAKAS: Variant = Variant {
    density_diffusion_form: MF_DIFFUSION_FOURTAKAS,
    ..V_3D_DELTA
};
/// `V_2D_DELTA` / `V_3D_DELTA` with the diffusion in Antuono et al.'s form (the fluid's
/// density gradients: `sph_grad_rho`).
const V_2D_ANTUONO: Variant = Variant {
    density_diffusion_form: MF_DIFFUSION_ANTUONO,
    ..V_2D_DELTA
};
const V_3D_ANTUONO: Variant = Variant {
    density_diffusion_form: MF_DIFFUSION_ANTUONO,
    ..V_3D_DELTA
};
/// `V_2D_B` / `V_3D_B` (artificial stress) with density diffusion within the solid body.
const V_2D_SOLID_DELTA: Variant = Variant {
    solid_delta: true,
    ..V_2D_B
};
const V_3D_SOLID_DELTA: Variant = Variant {
    solid_delta: true,
    ..V_3D_B
};
/// 2D and 3D: dynamic walls, continuity, forward Euler and nothing beyond the paper's fluid
/// scheme: as fluid-only scenes, the lean kernels' cases (`params::lean_scheme`), the
/// scheme `meshfree bench` times.
const V_2D_LEAN: Variant = Variant {
    dynamic_walls: true,
    symplectic: false,
    ..V_2D_B
};
const V_3D_LEAN: Variant = Variant {
    laminar: false,
    ..V_3D_B
};

/// A fluid lattice over a wall (3 layers, bottom; in 3D also the two z faces), periodic in
/// x, with an elastic disc / sphere inside; jittered positions, random velocities and
/// initial solid stress so that every term is exercised.
fn scene(dim: usize, v: Variant) -> Setup {
    scene_with(dim, v, 0.3)
}

/// `scene` with random initial velocities of amplitude `vel_amp` [L/T].
fn scene_with(dim: usize, v: Variant, vel_amp: f32) -> Setup {
    let dx = 0.1f32;
    let d3 = dim == 3;
    let nx = if d3 { 12 } else { 40 };
    let lx = nx as f32 * dx;
    let (fy, fz) = if d3 { (8, 12) } else { (15, 1) };
    let lz = fz as f32 * dx;
    let mut p = SphParams {
        dim: dim as i32,
        periodic: [1, 0, 0],
        domain_min: [0.0, -3.0 * dx, if d3 { -3.0 * dx } else { 0.0 }],
        domain_max: [lx, 3.0, if d3 { lz + 3.0 * dx } else { 0.0 }],
        kernel: 0,
        dx,
        h: 1.3 * dx,
        density_form: if v.continuity {
            MF_DENSITY_CONTINUITY
        } else {
            MF_DENSITY_SUMMATION
        } as i32,
        rho0: 1.0,
        c0: 15.0,
        tait_gamma: 7.0,
        alpha: 0.1,
        beta: 0.1,
        viscosity: if v.laminar { 0.005 } else { 0.0 },
        xsph: 0.3,
        density_diffusion: if v.density_diffusion { 0.1 } else { 0.0 },
        density_diffusion_form: v.density_diffusion_form as i32,
        solid_density_diffusion: if v.solid_delta { 0.1 } else { 0.0 },
        solid_rho0: 0.8,
        solid_c0: 15.0,
        shear_modulus: 50.0,
        artificial_stress: if v.art_stress { 0.3 } else { 0.0 },
        artificial_stress_exponent: 4.0,
        lj_c0: 2.0,
        lj_r0: dx,
        lj_p1: 12,
        lj_p2: 6,
        attractive: 0,
        wall_contact: 1,
        wall_coupling: v.dynamic_walls as i32,
        gravity: [0.0, -1.0, 0.0],
        integrator: if v.symplectic {
            MF_INTEGRATOR_SYMPLECTIC_EULER
        } else {
            MF_INTEGRATOR_EULER
        } as i32,
        courant: 0.25,
        dt: 0.0,
        ..Default::default()
    };
    params::derive(&mut p);
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let mut out: Vec<Particle> = Vec::new();
    let centre = [0.5 * lx, 0.5 * fy as f32 * dx, 0.5 * lz];
    let radius = if d3 { 0.25 } else { 0.35 };
    let push = |out: &mut Vec<Particle>, x: [f32; 3], kind: Kind, group: u32, rng: &mut Rng| {
        let rho = if kind == Kind::Solid {
            p.solid_rho0
        } else {
            p.rho0
        };
        let mut q = Particle {
            id: out.len() as u32,
            kind,
            group,
            position: x,
            density: rho,
            mass: rho * dx.powi(dim as i32),
            ..Default::default()
        };
        if kind != Kind::Boundary {
            for a in 0..dim {
                q.position[a] += rng.sym(0.1 * dx);
                q.velocity[a] = rng.sym(vel_amp);
            }
        }
        if (v.density_diffusion && kind == Kind::Fluid) || (v.solid_delta && kind == Kind::Solid) {
            q.density *= 1.0 + rng.sym(0.01);
        }
        if kind == Kind::Solid {
            for c in 0..6 {
                q.stress[c] = rng.sym(0.5);
            }
        }
        out.push(q);
    };
    let zs: Vec<i32> = if d3 { (-3..fz + 3).collect() } else { vec![0] };
    for &k in &zs {
        for j in -3..fy.max(12) {
            for i in 0..nx {
                let x = [
                    (i as f32 + 0.5) * dx,
                    (j as f32 + 0.5) * dx,
                    if d3 { (k as f32 + 0.5) * dx } else { 0.0 },
                ];
                let wall = j < 0 || (d3 && (k < 0 || k >= fz));
                if wall {
                    push(&mut out, x, Kind::Boundary, 0, &mut rng);
                } else if j < fy {
                    let r2: f32 = (0..dim).map(|a| (x[a] - centre[a]).powi(2)).sum();
                    if r2 < radius * radius {
                        push(&mut out, x, Kind::Solid, 2, &mut rng);
                    } else {
                        push(&mut out, x, Kind::Fluid, 1, &mut rng);
                    }
                }
            }
        }
    }
    Setup {
        params: p,
        particles: out,
        wall_surface: Vec::new(),
    }
}

/// |gpu - cpu| <= atol + rtol |cpu| for every entry; the message names the worst slot.
fn close(what: &str, ids: &[u32], width: usize, cpu: &[f32], gpu: &[f32], rtol: f32, atol: f32) {
    assert_eq!(cpu.len(), gpu.len(), "{what}: lengths differ");
    let mut worst: Option<(f32, usize)> = None;
    let mut bad = 0usize;
    for (k, (a, b)) in cpu.iter().zip(gpu).enumerate() {
        let tol = atol + rtol * a.abs();
        let err = (a - b).abs();
        if err.is_nan() || err > tol {
            bad += 1;
            let excess = if err.is_nan() {
                f32::INFINITY
            } else {
                err / tol.max(f32::MIN_POSITIVE)
            };
            if worst.is_none_or(|w| excess > w.0) {
                worst = Some((excess, k));
            }
        }
    }
    let mut ratio = 0.0f32;
    for (a, b) in cpu.iter().zip(gpu) {
        ratio = ratio.max((a - b).abs() / (atol + rtol * a.abs()).max(f32::MIN_POSITIVE));
    }
    if let Some((_, k)) = worst {
        let slot = k / width;
        panic!(
            "{what}: {bad} entries out of tolerance; worst at slot {slot} (particle id {}), component {}: cpu {} gpu {} \
             (|diff| {:e} > tol {:e} = {atol:e} + {rtol:e} |cpu|)",
            ids[slot],
            k % width,
            cpu[k],
            gpu[k],
            (cpu[k] - gpu[k]).abs(),
            atol + rtol * cpu[k].abs()
        );
    }
    eprintln!(
        "  {what}: ok ({} values, rtol {rtol:e}, atol {atol:e}; worst |diff|/tol {ratio:.3})",
        cpu.len()
    );
}

fn flat_v<D: Dim>(v: &[D::V]) -> Vec<f32> {
    v.iter().flat_map(|x| D::to3(*x)[..D::D].to_vec()).collect()
}
fn flat_m<D: Dim>(v: &[D::M]) -> Vec<f32> {
    v.iter().flat_map(|m| D::sym_to6(*m)).collect()
}
fn max_abs(v: &[f32]) -> f32 {
    v.iter().fold(0.0f32, |m, x| m.max(x.abs()))
}
/// Vectors: absolute tolerance `scale` x the largest entry of the CPU array.
fn close_v<D: Dim>(what: &str, ids: &[u32], cpu: &[D::V], gpu: &[D::V], scale: f32, atol: f32) {
    let (a, b) = (flat_v::<D>(cpu), flat_v::<D>(gpu));
    let m = max_abs(&a);
    close(what, ids, D::D, &a, &b, scale, atol + scale * m);
}
fn close_m<D: Dim>(what: &str, ids: &[u32], cpu: &[D::M], gpu: &[D::M], scale: f32) {
    let (a, b) = (flat_m::<D>(cpu), flat_m::<D>(gpu));
    let m = max_abs(&a);
    close(what, ids, 6, &a, &b, scale, scale * m);
}

fn cmp_density<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32], p: &SphParams) {
    let gs = g.download_state();
    close("density rho", ids, 1, &c.state().rho, &gs.rho, 2e-5, 0.0);
    close(
        "density pressure",
        ids,
        1,
        &c.state().p,
        &gs.p,
        1e-4,
        2e-5 * p.tait_b * p.tait_gamma,
    );
    if let (Some(a), Some(b)) = (&c.state().solid, &gs.solid) {
        // The solids' departure rho - rho0_s: the summed density's, or as it was.
        close(
            "density rho_dev",
            ids,
            1,
            &a.rho_dev,
            &b.rho_dev,
            1e-5,
            2e-5 * p.solid_rho0,
        );
        if let (Some(a), Some(b)) = (&a.art_stress, &b.art_stress) {
            close_m::<D>("density artificial stress R", ids, a, b, 1e-4);
        }
    }
    g.upload_state(c.state());
}

fn check_rates<D: Dim>(cs: &State<D>, gs: &State<D>, ids: &[u32]) {
    close_v::<D>("rates xsph", ids, &cs.xsph, &gs.xsph, 1e-4, 0.0);
    if let (Some(a), Some(b)) = (&cs.drho, &gs.drho) {
        close("rates drho/dt", ids, 1, a, b, 1e-4, 1e-4 * max_abs(a));
    }
    if let (Some(a), Some(b)) = (&cs.solid, &gs.solid) {
        close_m::<D>("rates dS/dt", ids, &a.stress_rate, &b.stress_rate, 2e-4);
    }
}

fn check_forces<D: Dim>(cs: &State<D>, gs: &State<D>, ids: &[u32]) {
    close_v::<D>("forces acc", ids, &cs.acc, &gs.acc, 1e-4, 0.0);
}

fn cmp_rates<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    check_rates(c.state(), &g.download_state(), ids);
    g.upload_state(c.state());
}

fn cmp_forces<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    check_forces(c.state(), &g.download_state(), ids);
    g.upload_state(c.state());
}

/// After `forces_and_rates` (one download: the upload would overwrite both outputs).
fn cmp_forces_and_rates<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let gs = g.download_state();
    check_rates(c.state(), &gs, ids);
    check_forces(c.state(), &gs, ids);
    g.upload_state(c.state());
}

fn cmp_time_step<D: Dim>(c: &mut CpuSolver<D>, g: &mut CudaSolver<D>) {
    c.time_step();
    g.time_step();
    let (dc, dg) = (c.dt(), g.dt());
    assert!(
        (dc - dg).abs() <= 1e-5 * dc,
        "time_step: dt cpu {dc} gpu {dg} (rtol 1e-5)"
    );
    eprintln!("  time_step: dt cpu {dc} gpu {dg}");
}

fn cmp_kick<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let gs = g.download_state();
    close_v::<D>("kick vel", ids, &c.state().vel, &gs.vel, 1e-5, 0.0);
    g.upload_state(c.state());
}

fn check_drift<D: Dim>(c: &mut CpuSolver<D>, g: &mut CudaSolver<D>, gs: &State<D>, ids: &[u32]) {
    let cs = c.state();
    close_v::<D>("drift pos", ids, &cs.pos, &gs.pos, 0.0, 2e-6);
    close("drift rho", ids, 1, &cs.rho, &gs.rho, 1e-6, 0.0);
    if let (Some(a), Some(b)) = (&cs.solid, &gs.solid) {
        close_m::<D>("drift stress", ids, &a.stress, &b.stress, 1e-5);
        // rho_dev += dt d rho/dt from the same state (nvcc may fuse the multiply-add), with
        // the two step sizes, which agree to 1e-5 (`cmp_time_step`): that difference moves
        // rho_dev by |dt_cpu - dt_gpu| |d rho/dt|, more than rho_dev's own rounding where
        // rho_dev passes through zero.
        let m = max_abs(&a.rho_dev);
        let ddt = (c.dt() - g.dt()).abs();
        let rate = cs.drho.as_deref().map_or(0.0, max_abs);
        close(
            "drift rho_dev",
            ids,
            1,
            &a.rho_dev,
            &b.rho_dev,
            1e-6,
            1e-6 * m + ddt * rate,
        );
    }
    let (tc, tg) = (c.time(), g.time());
    assert!((tc - tg).abs() <= 1e-5 * tc, "time: cpu {tc} gpu {tg}");
}

fn cmp_drift<D: Dim>(c: &mut CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let gs = g.download_state();
    check_drift(c, g, &gs, ids);
    g.upload_state(c.state());
}

/// After `drift_kick` (one kernel on the GPU; the CPU's drift then kick).
fn cmp_drift_kick<D: Dim>(c: &mut CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let gs = g.download_state();
    check_drift(c, g, &gs, ids);
    close_v::<D>("kick vel", ids, &c.state().vel, &gs.vel, 1e-5, 0.0);
    g.upload_state(c.state());
}

/// After `solid_stress` (total-Lagrangian bodies, `cuda/tlsph.cu`): the pressure, density
/// and deviatoric stress it writes into the solids' slots (the others are untouched).
fn cmp_solid_stress<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let (cs, gs) = (c.state(), g.download_state());
    close("solid_stress rho", ids, 1, &cs.rho, &gs.rho, 2e-5, 0.0);
    close(
        "solid_stress pressure",
        ids,
        1,
        &cs.p,
        &gs.p,
        1e-4,
        1e-4 * max_abs(&cs.p),
    );
    if let (Some(a), Some(b)) = (&cs.solid, &gs.solid) {
        close_m::<D>("solid_stress deviator", ids, &a.stress, &b.stress, 1e-4);
    }
    eprintln!("  solid_stress: as the CPU's");
    g.upload_state(cs);
}

/// After `solid_forces`: the accelerations with the internal force and hourglass added.
fn cmp_solid_forces<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let (cs, gs) = (c.state(), g.download_state());
    close_v::<D>("solid_forces acc", ids, &cs.acc, &gs.acc, 1e-4, 0.0);
    g.upload_state(cs);
}

/// The total-Lagrangian displacements u (solid space, by id rank) against the CPU's:
/// absolute tolerance `scale` x the largest.
fn cmp_displacement<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, scale: f32) {
    let uc = &c.tl_bodies().expect("a total-Lagrangian scene").disp;
    let ug = g.tl_displacement().expect("the GPU holds the bodies too");
    let ids: Vec<u32> = c.tl_bodies().expect("checked").reference.id.clone();
    close_v::<D>("displacement u", &ids, uc, &ug, scale, 1e-9);
}

fn total_lagrangian(p: &SphParams) -> bool {
    p.solid_formulation as u32 == MF_SOLID_TOTAL_LAGRANGIAN
}

fn stages<D: Dim>(dim: usize, v: Variant) {
    stages_on::<D>(&format!("{v:?}"), scene(dim, v));
}

/// `scene(dim, v)` with an inflow band across the periodic x axis: fluid in
/// 0.4 <= x < 0.8 moves at (1.5, -0.5, 0.25) (src/backend/cpu/integrate.rs::kick).
fn with_inflow_band(dim: usize, v: Variant) -> Setup {
    let mut setup = scene(dim, v);
    let p = &mut setup.params;
    p.inflow = 1;
    p.inflow_axis = 0;
    p.inflow_lo = 0.4;
    p.inflow_hi = 0.8;
    p.inflow_velocity = [1.5, -0.5, 0.25];
    setup
}

/// `setup` (with an inflow band) under a ramped start (`inflow_ramp`) of 8 of its first
/// steps, so that the stage tests' four rounds all kick inside the ramp: the band at its
/// share r(t) of the inflow velocity and the rest accelerated by its increase
/// (src/backend/cpu/integrate.rs::kick, `ramp_share`, `kick_end`).
fn ramped<D: Dim>(mut setup: Setup) -> Setup {
    let mut c = CpuSolver::<D>::new(setup.clone());
    c.step();
    setup.params.inflow_ramp = 8.0 * c.dt();
    setup
}

/// `scene(dim, v)` with the solid body turned into fluid (rest density, no stress): the only
/// scenes that take the fluid-only entries of forces and rates (`sph_forces_fluid_*`,
/// `sph_rates_fluid_*`: batches of 8 candidates at one lane, and the neighbour's kind read
/// from the sign of its vel.w, `vel_load` in cuda/device/packing.cuh).
fn fluid_only(dim: usize, v: Variant) -> Setup {
    fluid_only_of(scene(dim, v))
}

/// `setup` with its solid body turned into fluid.
fn fluid_only_of(mut setup: Setup) -> Setup {
    let dim = setup.params.dim;
    let (rho0, dx) = (setup.params.rho0, setup.params.dx);
    for q in setup.particles.iter_mut().filter(|q| q.kind == Kind::Solid) {
        q.kind = Kind::Fluid;
        q.group = 1;
        q.density = rho0;
        q.mass = rho0 * dx.powi(dim);
        q.stress = Default::default();
    }
    setup
}

/// The stage comparison on any parity scene (`what` names it in the log).
fn stages_on<D: Dim>(what: &str, setup: Setup) {
    let dim = setup.params.dim;
    let mut g = gpu::<D>(&setup);
    let mut c = CpuSolver::<D>::new(setup.clone());
    let p = setup.params;
    eprintln!(
        "{dim}D parity {what}: {} particles ({} solid), on {}",
        c.len(),
        setup
            .particles
            .iter()
            .filter(|q| q.kind == Kind::Solid)
            .count(),
        g.info().device
    );
    let euler = p.integrator as u32 == MF_INTEGRATOR_EULER;
    let tl = total_lagrangian(&p);
    assert_eq!(tl, c.tl_bodies().is_some());
    for lanes in [8, 4, 2, 1] {
        // Each entry of the neighbour kernels: loops split over 8, 4 or 2 lanes per particle
        // (small systems use 4 in 2D and 8 in 3D; large ones fewer), and one thread per
        // particle, the CPU's exact order.
        g.set_lanes(Some(lanes));
        eprintln!(" round with {lanes} lanes per particle");
        // Grid: the (cell, id) order must be identical.
        c.build_grid();
        g.build_grid();
        let gs = g.download_state();
        let cs = c.state().clone();
        assert_eq!(cs.id, gs.id, "build_grid: storage order (ids) differs");
        assert_eq!(
            flat_v::<D>(&cs.pos),
            flat_v::<D>(&gs.pos),
            "build_grid: positions differ after the reorder"
        );
        if let (Some(a), Some(b)) = (&cs.solid, &gs.solid) {
            assert_eq!(
                a.rho_dev, b.rho_dev,
                "build_grid: rho_dev differs after the reorder"
            );
        }
        eprintln!("  build_grid: identical order of {} ids", cs.id.len());
        let ids = cs.id.clone();
        // With the continuity density (no artificial stress) the reorder applied the
        // equation of state: its pressures must be the CPU density stage's.
        let grid_pressure = g.grid_applied_eos().then(|| gs.p.clone());
        g.upload_state(&cs);

        c.density();
        g.density();
        if let Some(pg) = grid_pressure {
            let pc = &c.state().p;
            close(
                "build_grid pressure (eq. 9)",
                &ids,
                1,
                pc,
                &pg,
                1e-4,
                2e-5 * p.tait_b * p.tait_gamma,
            );
            eprintln!(
                "  build_grid: equation of state as the CPU's on {} particles",
                pc.len()
            );
        }
        cmp_density(&c, &mut g, &ids, &p);
        if tl {
            c.solid_stress();
            g.solid_stress();
            cmp_solid_stress(&c, &mut g, &ids);
        }
        // The order of `Solver::step`.
        if euler {
            // The CPU runs rates then forces (the trait's default); the GPU one fused pass
            // (cuda/forces_rates.cu).
            c.forces_and_rates();
            g.forces_and_rates();
            cmp_forces_and_rates(&c, &mut g, &ids);
            if tl {
                c.solid_forces();
                g.solid_forces();
                cmp_solid_forces(&c, &mut g, &ids);
            }
            cmp_time_step(&mut c, &mut g);
            c.drift_kick();
            g.drift_kick();
            cmp_drift_kick(&mut c, &mut g, &ids);
        } else {
            c.forces();
            g.forces();
            cmp_forces(&c, &mut g, &ids);
            if tl {
                c.solid_forces();
                g.solid_forces();
                cmp_solid_forces(&c, &mut g, &ids);
            }
            cmp_time_step(&mut c, &mut g);
            c.kick();
            g.kick();
            cmp_kick(&c, &mut g, &ids);
            c.rates();
            g.rates();
            cmp_rates(&c, &mut g, &ids);
            c.drift();
            g.drift();
            cmp_drift(&mut c, &mut g, &ids);
        }
        if tl {
            cmp_displacement(&c, &mut g, 1e-4);
            // The next round starts from the CPU's displacements too (`upload_state` carries
            // the particles only), so that each round compares the stages from one input;
            // the runs below compare what accumulates.
            g.restore(&c.save())
                .expect("the GPU takes the CPU's checkpoint");
        }
    }
    // Health check and read-back by id.
    assert!(
        g.check().is_ok(),
        "GPU health check reports a fault on a healthy state"
    );
    let (pc, pg) = (c.particles(), g.particles());
    assert_eq!(
        pc.iter().map(|q| q.id).collect::<Vec<_>>(),
        pg.iter().map(|q| q.id).collect::<Vec<_>>()
    );
}

/// Diagnostics after `steps` steps of the whole `Solver::step` from one start. A calmer
/// start than the stage tests (velocity amplitude 0.05 instead of 0.3): the stage tests'
/// violent start splashes and the runs diverge chaotically from f32 rounding alone.
fn long_run<D: Dim>(dim: usize, v: Variant, steps: usize) {
    long_run_on::<D>(&format!("{v:?}"), scene_with(dim, v, 0.05), steps);
}

/// `long_run` on any scene (`what` names it in the log).
fn long_run_on<D: Dim>(what: &str, setup: Setup, steps: usize) {
    let dim = setup.params.dim;
    let mut g = gpu::<D>(&setup);
    let mut c = CpuSolver::<D>::new(setup);
    let t0 = std::time::Instant::now();
    for _ in 0..steps {
        c.step();
    }
    let tc = t0.elapsed();
    let t0 = std::time::Instant::now();
    for _ in 0..steps {
        g.step();
    }
    let tt = g.time();
    let tg = t0.elapsed();
    let (dc, dg) = (c.diagnostics(), g.diagnostics());
    eprintln!("{dim}D {what} after {steps} steps (cpu {tc:?}, gpu {tg:?}, t = {tt:.5}):\n  cpu {dc:?}\n  gpu {dg:?}");
    assert!(
        c.check().is_ok() && g.check().is_ok(),
        "a blow-up in the {steps}-step run"
    );
    common::assert_long_run_close(&dc, &dg);
}

/// `scene(dim, v)` with a driven group (`group` 0: the wall, moving as a piston; 2: the
/// elastic body, a moving clamp) and fluid cohesion (Akinci et al. 2013) switched on.
fn driven_cohesive(dim: usize, v: Variant, group: i32, u: [f32; 3]) -> Setup {
    let mut setup = scene(dim, v);
    let p = &mut setup.params;
    p.driven = 1;
    p.driven_group = group;
    p.driven_velocity = u;
    p.cohesion = 2.0;
    setup
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_driven_wall_cohesion_continuity_symplectic() {
    let setup = driven_cohesive(2, V_2D_B, 0, [0.5, 0.0, 0.0]);
    stages_on::<D2>("V_2D_B + driven wall + cohesion", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_driven_solid_cohesion_summation_euler() {
    let setup = driven_cohesive(2, V_2D_A, 2, [0.0, 0.0, 0.0]);
    stages_on::<D2>("V_2D_A + clamped disc + cohesion", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_driven_solid_cohesion_continuity_euler() {
    let setup = driven_cohesive(3, V_3D_B, 2, [0.2, -0.3, 0.1]);
    stages_on::<D3>("V_3D_B + driven sphere + cohesion", setup);
}

/// `scene(dim, v)` where elastic bodies touch each other and the wall: the disc / sphere
/// split in two bodies at its centre plane (group 3 the +x half), and a layer of solid
/// (group 4, with stress) on the wall under the left part of the fluid. Pairs across two
/// objects take the pressure part of the stress only, or with `whole` the whole stress
/// (`interface`, `whole_stress_pair` in forces.rs / forces.cu).
fn bodies_in_contact(dim: usize, v: Variant, whole: bool) -> Setup {
    let mut setup = scene(dim, v);
    setup.params.interface = whole as i32;
    let p = setup.params;
    let xc = 0.5 * p.domain_max[0];
    let vol = p.dx.powi(dim as i32);
    for (k, q) in setup.particles.iter_mut().enumerate() {
        if q.kind == Kind::Solid && q.position[0] > xc {
            q.group = 3;
        } else if q.kind == Kind::Fluid && q.position[1] < 1.5 * p.dx && q.position[0] < xc {
            q.kind = Kind::Solid;
            q.group = 4;
            q.density = p.solid_rho0;
            q.mass = p.solid_rho0 * vol;
            for c in 0..6 {
                q.stress[c] = 0.1 * ((k * 7 + c * 3) % 11) as f32 - 0.5;
            }
        }
    }
    setup
}

/// `scene(dim, v)` with its elastic body cut in two across x at its centre: the half with
/// x below the mean a clamp (group 2, driven, held fixed), the rest a free body (group 3)
/// bonded to it (`same_body`): XSPH, the velocity gradient and the artificial stress cross
/// the cut.
fn clamped_body(dim: usize, v: Variant) -> Setup {
    clamped_of(scene(dim, v))
}

/// `setup`'s elastic body cut in two across x at its centre, as `clamped_body`.
fn clamped_of(mut setup: Setup) -> Setup {
    let solid: Vec<f32> = (setup.particles.iter())
        .filter(|q| q.kind == Kind::Solid)
        .map(|q| q.position[0])
        .collect();
    let mid = solid.iter().sum::<f32>() / solid.len() as f32;
    for q in setup.particles.iter_mut() {
        if q.kind == Kind::Solid && q.position[0] >= mid {
            q.group = 3;
        }
    }
    let p = &mut setup.params;
    p.driven = 1;
    p.driven_group = 2;
    p.driven_velocity = [0.0; 3];
    setup
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_bodies_in_contact_dynamic_walls() {
    stages_on::<D2>(
        "V_2D_A + bodies in contact",
        bodies_in_contact(2, V_2D_A, false),
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_bodies_in_contact_dynamic_walls() {
    stages_on::<D3>(
        "V_3D_B + bodies in contact",
        bodies_in_contact(3, V_3D_B, false),
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_bodies_in_contact_lj_walls_whole_stress() {
    let setup = bodies_in_contact(2, V_2D_B, true);
    stages_on::<D2>("V_2D_B + bodies in contact, whole stress", setup);
}
/// `bodies_in_contact` where bodies and walls skip each other (`[solid] wall_contact =
/// false`, `wall_contact`; `meets` in backend/pair.rs / pairs.cuh): the solid layer on
/// the wall feels no Lennard-Jones force or wall pressure, and neither enters the other's
/// density (summation in V_2D_A, the walls' continuity in V_3D_B).
fn bodies_skipping_walls(dim: usize, v: Variant) -> Setup {
    let mut setup = bodies_in_contact(dim, v, false);
    setup.params.wall_contact = 0;
    setup
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_bodies_skipping_walls_summation() {
    let setup = bodies_skipping_walls(2, V_2D_A);
    stages_on::<D2>("V_2D_A + bodies in contact, skipping the walls", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_bodies_skipping_walls_continuity() {
    let setup = bodies_skipping_walls(3, V_3D_B);
    stages_on::<D3>("V_3D_B + bodies in contact, skipping the walls", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_clamp_bonded_to_its_body() {
    stages_on::<D2>(
        "V_2D_A + clamp holding half the disc",
        clamped_body(2, V_2D_A),
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_clamp_bonded_to_its_body() {
    stages_on::<D3>(
        "V_3D_B + clamp holding half the sphere",
        clamped_body(3, V_3D_B),
    );
}
/// `clamped_body` with the artificial stress taken from the deviatoric stress alone
/// (`[solid] artificial_stress_from = "deviatoric"`, `artificial_stress_from`; `art_pressure`
/// in stress.rs, `artificial_stress` in density.cu).
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_clamp_deviatoric_artificial_stress() {
    let mut setup = clamped_body(2, V_2D_B);
    setup.params.artificial_stress_from = 1;
    stages_on::<D2>("V_2D_B + clamp, deviatoric artificial stress", setup);
}

/// `clamped_body` made stiff: a solid sound speed of 1e6 (and shear modulus to match), so
/// that a step's change of a solid's density, dt d rho/dt, lies below f32's resolution of
/// rho and only the departure `rho_dev` (`SolidState::rho_dev`) carries it; the pressure
/// c_s^2 rho_dev must agree between the density pass, the continuity scheme's reorder
/// (no artificial stress) and the CPU.
fn stiff_clamp(dim: usize, v: Variant) -> Setup {
    let mut setup = clamped_body(dim, v);
    let p = &mut setup.params;
    p.solid_c0 = 1e6;
    p.shear_modulus = 0.3 * p.solid_rho0 * p.solid_c0 * p.solid_c0;
    params::derive(p);
    setup
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_stiff_clamp_continuity_eos_in_the_reorder() {
    let v = Variant {
        art_stress: false,
        ..V_2D_B
    };
    stages_on::<D2>("V_2D_B without R + stiff clamp", stiff_clamp(2, v));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_stiff_clamp_continuity_euler() {
    stages_on::<D3>("V_3D_B + stiff clamp", stiff_clamp(3, V_3D_B));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_dynamic_walls_summation_euler() {
    stages::<D2>(2, V_2D_A);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_lj_walls_continuity_symplectic() {
    stages::<D2>(2, V_2D_B);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_lj_walls_continuity_symplectic() {
    stages::<D3>(3, V_3D_A);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_dynamic_walls_continuity_euler() {
    stages::<D3>(3, V_3D_B);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_inflow_band_symplectic() {
    stages_on::<D2>("V_2D_B + inflow band", with_inflow_band(2, V_2D_B));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_inflow_band_euler() {
    stages_on::<D3>("V_3D_B + inflow band", with_inflow_band(3, V_3D_B));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_inflow_ramp_symplectic() {
    let setup = ramped::<D2>(with_inflow_band(2, V_2D_B));
    stages_on::<D2>("V_2D_B + inflow band, ramped", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_inflow_ramp_leapfrog() {
    let setup = ramped::<D3>(leapfrog(with_inflow_band(3, V_3D_A)));
    stages_on::<D3>("V_3D_A leapfrog + inflow band, ramped", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_inflow_ramp() {
    // The ramp ends inside the run (at 100 of its first steps): graphs, the clock and the
    // ramp's end together.
    let mut setup = scene_with(2, V_2D_B, 0.05);
    let p = &mut setup.params;
    (p.inflow, p.inflow_axis, p.inflow_lo, p.inflow_hi) = (1, 0, 0.4, 0.8);
    p.inflow_velocity = [0.5, -0.2, 0.0];
    let mut c = CpuSolver::<D2>::new(setup.clone());
    c.step();
    setup.params.inflow_ramp = 100.0 * c.dt();
    long_run_on::<D2>("V_2D_B + inflow band, ramped", setup, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_fluid_only_dynamic_walls_summation_euler() {
    stages_on::<D2>("V_2D_A fluid only", fluid_only(2, V_2D_A));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_lj_walls_continuity_symplectic() {
    stages_on::<D3>("V_3D_A fluid only", fluid_only(3, V_3D_A));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_dynamic_walls_continuity_euler() {
    stages_on::<D3>("V_3D_B fluid only", fluid_only(3, V_3D_B));
}
/// `setup` with no periodic axis: the neighbour loops' other specialisation (the minimum
/// image compiled out, `neighbour_loop` in cuda/device/neighbours.cuh). Particles at the
/// open x ends just have fewer neighbours.
fn not_periodic(mut setup: Setup) -> Setup {
    setup.params.periodic = [0; 3];
    params::derive(&mut setup.params);
    setup
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_no_periodic_axis_with_a_body_symplectic() {
    stages_on::<D2>("V_2D_B, no periodic axis", not_periodic(scene(2, V_2D_B)));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_no_periodic_axis_euler() {
    stages_on::<D3>(
        "V_3D_B fluid only, no periodic axis",
        not_periodic(fluid_only(3, V_3D_B)),
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_fluid_only_no_periodic_axis_symplectic() {
    stages_on::<D2>(
        "V_2D_B fluid only, no periodic axis",
        not_periodic(fluid_only(2, V_2D_B)),
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_no_periodic_axis_symplectic() {
    stages_on::<D3>(
        "V_3D_A fluid only, no periodic axis",
        not_periodic(fluid_only(3, V_3D_A)),
    );
}
/// Which parity scenes take the lean kernels: pinned, so that the lean and the full
/// fluid-only kernels both stay covered.
#[test]
fn lean_kernels_are_covered() {
    for (dim, v) in [(2, V_2D_LEAN), (3, V_3D_LEAN), (3, V_3D_A), (2, V_2D_B)] {
        assert!(
            params::lean_scheme(&fluid_only(dim, v).params),
            "{dim}D {v:?}"
        );
    }
    for (dim, v) in [(2, V_2D_A), (3, V_3D_B), (2, V_2D_DELTA), (3, V_3D_DELTA)] {
        assert!(
            !params::lean_scheme(&fluid_only(dim, v).params),
            "{dim}D {v:?}"
        );
    }
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_lean_dynamic_walls_euler() {
    stages_on::<D2>("V_2D_LEAN fluid only", fluid_only(2, V_2D_LEAN));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_lean_dynamic_walls_euler() {
    stages_on::<D3>("V_3D_LEAN fluid only", fluid_only(3, V_3D_LEAN));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_lean_no_periodic_axis_euler() {
    stages_on::<D3>(
        "V_3D_LEAN fluid only, no periodic axis",
        not_periodic(fluid_only(3, V_3D_LEAN)),
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_lean_euler() {
    let setup = fluid_only_of(scene_with(2, V_2D_LEAN, 0.05));
    long_run_on::<D2>("V_2D_LEAN fluid only", setup, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_lean_euler() {
    let setup = fluid_only_of(scene_with(3, V_3D_LEAN, 0.05));
    long_run_on::<D3>("V_3D_LEAN fluid only", setup, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_density_diffusion() {
    stages::<D2>(2, V_2D_DELTA);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_density_diffusion() {
    stages::<D3>(3, V_3D_DELTA);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_density_diffusion() {
    long_run::<D2>(2, V_2D_DELTA, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_density_diffusion_fourtakas() {
    stages::<D2>(2, V_2D_FOURTAKAS);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_density_diffusion_fourtakas() {
    stages::<D3>(3, V_3D_FOURTAKAS);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_density_diffusion_fourtakas() {
    long_run::<D3>(3, V_3D_FOURTAKAS, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_density_diffusion_antuono() {
    stages::<D2>(2, V_2D_ANTUONO);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_density_diffusion_antuono() {
    stages::<D3>(3, V_3D_ANTUONO);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_density_diffusion_antuono() {
    stages_on::<D3>("V_3D_ANTUONO fluid only", fluid_only(3, V_3D_ANTUONO));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_density_diffusion_antuono() {
    long_run::<D2>(2, V_2D_ANTUONO, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_solid_density_diffusion() {
    stages::<D2>(2, V_2D_SOLID_DELTA);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_solid_density_diffusion() {
    stages::<D3>(3, V_3D_SOLID_DELTA);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_solid_density_diffusion() {
    long_run::<D2>(2, V_2D_SOLID_DELTA, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_dynamic_walls_euler() {
    long_run::<D2>(2, V_2D_A, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_lj_walls_symplectic() {
    long_run::<D2>(2, V_2D_B, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_lj_walls_symplectic() {
    long_run::<D3>(3, V_3D_A, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_dynamic_walls_euler() {
    long_run::<D3>(3, V_3D_B, 200);
}

/// `setup` under the leapfrog: the symplectic Euler's stages with the kick spanning
/// (dt_prev + dt) / 2 and the rates at the drift's midpoint.
fn leapfrog(mut setup: Setup) -> Setup {
    setup.params.integrator = MF_INTEGRATOR_LEAPFROG as i32;
    setup
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_leapfrog_with_a_body() {
    stages_on::<D2>("V_2D_B leapfrog", leapfrog(scene(2, V_2D_B)));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_leapfrog_density_diffusion() {
    stages_on::<D3>(
        "V_3D_DELTA fluid-only leapfrog",
        leapfrog(fluid_only(3, V_3D_DELTA)),
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_leapfrog_with_a_body() {
    long_run_on::<D2>(
        "V_2D_B leapfrog",
        leapfrog(scene_with(2, V_2D_B, 0.05)),
        200,
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_fluid_only_leapfrog() {
    long_run_on::<D3>(
        "V_3D_DELTA fluid-only leapfrog",
        leapfrog(fluid_only_of(scene_with(3, V_3D_DELTA, 0.05))),
        200,
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_fluid_only_euler() {
    // Forward Euler without solids: every step through the fused fluid-only kernel.
    let setup = fluid_only_of(scene_with(2, V_2D_A, 0.05));
    long_run_on::<D2>("V_2D_A fluid only", setup, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_fluid_only_euler() {
    let setup = fluid_only_of(scene_with(3, V_3D_B, 0.05));
    long_run_on::<D3>("V_3D_B fluid only", setup, 200);
}

/// `setup` with the no-slip walls of Morris, Fox & Zhu 1997 (`no_slip`, cap `beta_max`):
/// the wall surface of the parity scenes is the fluid's box, y >= 0 (and 0 <= z <= lz in
/// 3D), so each wall particle faces the nearest point of it (diagonally at the 3D edges).
/// The parity scenes number walls among the fluid, so `wall_surface` spans the smallest to
/// the largest wall id with unused entries between.
fn with_no_slip(mut setup: Setup, beta_max: f32) -> Setup {
    let p = &mut setup.params;
    p.no_slip = params::MF_NO_SLIP_MORRIS as i32;
    p.no_slip_beta_max = beta_max;
    let d3 = p.dim == 3;
    let lz = p.domain_max[2] - 3.0 * p.dx; // `scene_with`: the domain's z runs to lz + 3 dx
    let lo = [f32::NEG_INFINITY, 0.0, 0.0];
    let hi = [f32::INFINITY, f32::INFINITY, if d3 { lz } else { 0.0 }];
    let walls = || setup.particles.iter().filter(|q| q.kind == Kind::Boundary);
    let first = walls().map(|q| q.id).min().expect("walls");
    let last = walls().map(|q| q.id).max().expect("walls");
    let mut surface = vec![[0.0f32; 4]; (last - first) as usize + 1];
    for q in walls() {
        let x = q.position;
        let v: [f32; 3] = std::array::from_fn(|a| x[a].clamp(lo[a], hi[a]) - x[a]);
        let d = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        surface[(q.id - first) as usize] = [v[0] / d, v[1] / d, v[2] / d, d];
    }
    setup.params.wall_first_id = first;
    setup.wall_surface = surface;
    setup
}

/// Symplectic Euler (the separate forces kernel) with dynamic walls and laminar viscosity.
const V_2D_SYMPLECTIC_LAMINAR: Variant = Variant {
    dynamic_walls: true,
    laminar: true,
    ..V_2D_B
};

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_no_slip_walls_summation_euler() {
    let setup = with_no_slip(scene(2, V_2D_A), 2.0);
    stages_on::<D2>("V_2D_A + Morris no-slip walls", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_no_slip_driven_wall_symplectic() {
    // A moving wall (v_w != 0) under the separate forces kernel.
    let setup = driven_cohesive(2, V_2D_SYMPLECTIC_LAMINAR, 0, [0.5, 0.0, 0.0]);
    let setup = with_no_slip(setup, 2.0);
    stages_on::<D2>("2D symplectic + driven Morris no-slip wall", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_no_slip_walls_continuity_euler() {
    let setup = with_no_slip(scene(3, V_3D_B), 2.0);
    stages_on::<D3>("V_3D_B + Morris no-slip walls", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_no_slip_walls_continuity_euler() {
    let setup = with_no_slip(fluid_only(3, V_3D_B), 2.0);
    stages_on::<D3>("V_3D_B fluid only + Morris no-slip walls", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_fluid_only_no_slip_walls_symplectic() {
    let setup = with_no_slip(fluid_only(2, V_2D_SYMPLECTIC_LAMINAR), 2.0);
    stages_on::<D2>("2D symplectic fluid only + Morris no-slip walls", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_no_slip_walls_euler() {
    let setup = with_no_slip(scene_with(2, V_2D_A, 0.05), 2.0);
    long_run_on::<D2>("V_2D_A + Morris no-slip walls", setup, 200);
}

/// The fused `forces_and_rates` pass against `rates` then `forces` on the GPU, from one
/// state, at every lane count: each sum runs over the same neighbours in the same order, so
/// accelerations, rates and the step size agree bit for bit.
fn fused_equals_two_passes<D: Dim>(what: &str, setup: Setup) {
    let mut g = gpu::<D>(&setup);
    g.build_grid();
    g.density();
    let start = g.download_state();
    for lanes in [8, 4, 2, 1] {
        g.set_lanes(Some(lanes));
        g.upload_state(&start);
        g.rates();
        g.forces();
        g.time_step();
        let (two, dt2) = (g.download_state(), g.dt());
        g.upload_state(&start);
        g.forces_and_rates();
        g.time_step();
        let (one, dt1) = (g.download_state(), g.dt());
        assert_eq!(
            flat_v::<D>(&two.acc),
            flat_v::<D>(&one.acc),
            "{what}, {lanes} lanes: acc"
        );
        assert_eq!(
            flat_v::<D>(&two.xsph),
            flat_v::<D>(&one.xsph),
            "{what}, {lanes} lanes: xsph"
        );
        assert_eq!(two.drho, one.drho, "{what}, {lanes} lanes: drho");
        if let (Some(a), Some(b)) = (&two.solid, &one.solid) {
            assert_eq!(
                flat_m::<D>(&a.stress_rate),
                flat_m::<D>(&b.stress_rate),
                "{what}, {lanes} lanes: stress rate"
            );
        }
        assert_eq!(dt2, dt1, "{what}, {lanes} lanes: dt");
    }
    eprintln!("{what}: fused pass = rates + forces, bit for bit, at 8, 4, 2 and 1 lanes");
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn fused_pass_equals_two_passes_2d() {
    fused_equals_two_passes::<D2>("2D V_2D_A", scene(2, V_2D_A));
    fused_equals_two_passes::<D2>("2D V_2D_DELTA fluid only", fluid_only(2, V_2D_DELTA));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn fused_pass_equals_two_passes_3d() {
    fused_equals_two_passes::<D3>("3D V_3D_B", scene(3, V_3D_B));
    fused_equals_two_passes::<D3>("3D V_3D_B fluid only", fluid_only(3, V_3D_B));
    fused_equals_two_passes::<D3>("3D V_3D_A fluid only", fluid_only(3, V_3D_A));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn fused_pass_equals_two_passes_no_slip_walls() {
    let (s2, s3) = (scene(2, V_2D_A), fluid_only(3, V_3D_B));
    fused_equals_two_passes::<D2>("2D V_2D_A + no-slip walls", with_no_slip(s2, 2.0));
    fused_equals_two_passes::<D3>("3D V_3D_B fluid only + no-slip", with_no_slip(s3, 2.0));
}

/// The rates pass of one lane per particle from the forces pass's record of accepted
/// candidates (`PairBits` in cuda/device/neighbours.cuh) against the rates pass that tests
/// every candidate, from one state: the same neighbours in the same order, so d rho/dt, XSPH
/// and the stress rate agree bit for bit. The record holds 256 candidates a particle in 3D
/// and 192 in 2D: at h = 1.3 dx every particle's fit (about 180 and 40); at h = 2 dx in 3D
/// and 4 dx in 2D most particles' overflow it, and the rates pass tests the candidates past
/// it. The rates are taken as a step takes them, after the step size and the kick (under
/// the leapfrog each pair at the drift's midpoint, r + dt/2 (v_i - v_j), from the record of
/// x^n's candidates).
fn replayed_rates_equal_tested<D: Dim>(what: &str, mut setup: Setup, h_over_dx: f32) {
    setup.params.h = h_over_dx * setup.params.dx;
    params::derive(&mut setup.params);
    let mut g = gpu::<D>(&setup);
    g.set_lanes(Some(1));
    g.build_grid();
    g.density();
    let start = g.download_state();
    g.forces();
    assert!(
        g.rates_replay_pairs(),
        "{what}: a forces pass of one lane records its candidates"
    );
    g.time_step();
    g.kick();
    assert!(
        g.rates_replay_pairs(),
        "{what}: the record holds across the step size and the kick"
    );
    let kicked = g.download_state();
    // An upload moves the particles: the record goes, and the rates pass tests.
    g.upload_state(&kicked);
    assert!(
        !g.rates_replay_pairs(),
        "{what}: the record outlived an upload"
    );
    g.rates();
    let tested = g.download_state();
    g.upload_state(&start);
    g.forces();
    g.time_step();
    g.kick();
    g.rates();
    let replayed = g.download_state();
    assert_eq!(
        flat_v::<D>(&tested.xsph),
        flat_v::<D>(&replayed.xsph),
        "{what}: xsph"
    );
    assert_eq!(tested.drho, replayed.drho, "{what}: drho");
    if let (Some(a), Some(b)) = (&tested.solid, &replayed.solid) {
        assert_eq!(
            flat_m::<D>(&a.stress_rate),
            flat_m::<D>(&b.stress_rate),
            "{what}: stress rate"
        );
    }
    g.drift();
    assert!(
        !g.rates_replay_pairs(),
        "{what}: the record outlived a drift"
    );
    eprintln!("{what}, h = {h_over_dx} dx: replayed rates = tested rates, bit for bit");
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn replayed_rates_equal_tested_2d() {
    for h in [1.3, 4.0] {
        replayed_rates_equal_tested::<D2>("2D V_2D_A", scene(2, V_2D_A), h);
        replayed_rates_equal_tested::<D2>("2D V_2D_B", scene(2, V_2D_B), h);
        let lean = fluid_only(2, V_2D_LEAN);
        replayed_rates_equal_tested::<D2>("2D V_2D_LEAN fluid only", lean, h);
        let delta = fluid_only(2, V_2D_DELTA);
        replayed_rates_equal_tested::<D2>("2D V_2D_DELTA fluid only", delta, h);
        let b = leapfrog(scene(2, V_2D_B));
        replayed_rates_equal_tested::<D2>("2D V_2D_B leapfrog", b, h);
    }
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn replayed_rates_equal_tested_3d() {
    for h in [1.3, 2.0] {
        replayed_rates_equal_tested::<D3>("3D V_3D_B", scene(3, V_3D_B), h);
        replayed_rates_equal_tested::<D3>("3D V_3D_A fluid only", fluid_only(3, V_3D_A), h);
        let lean = fluid_only(3, V_3D_LEAN);
        replayed_rates_equal_tested::<D3>("3D V_3D_LEAN fluid only", lean, h);
        let delta = leapfrog(fluid_only(3, V_3D_DELTA));
        replayed_rates_equal_tested::<D3>("3D V_3D_DELTA fluid only leapfrog", delta, h);
    }
}

/// In 3D the neighbour passes walk, for a dynamic wall, only the candidate rows that hold a
/// moving particle, and none where all its candidates are walls at rest (`walked_rows` in
/// cuda/device/grid.cuh: a pair of walls at rest adds 0 to eq. (8)'s d rho/dt). From one
/// state, a step's forces, kick and rates after a grid build at one lane (the rows near
/// moving particles stamped, the skip on) and after an upload (no stamps: every wall walks
/// all its candidates) give the same rates. Part of the side walls above the water are given
/// a velocity across themselves (not driven: it stays, a wall that moves nothing), so that
/// they and their wall neighbours have rates that are not zero: a moving wall must walk the
/// rows of walls at rest around it, its neighbours the rows that hold it.
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn walls_at_rest_are_skipped_exactly_3d() {
    let mut setup = scene(3, V_3D_B);
    let dx = setup.params.dx;
    // Fluid below y = 0.8 (+ 0.1 dx of jitter), support 2.6 dx: the side walls' rows at
    // y = 1.15 are out of its reach, those at 1.05 too (0.3 - 0.01 > 0.26).
    let top = |q: &Particle| q.kind == Kind::Boundary && q.position[1] > 1.1;
    let near_side = |q: &Particle| q.position[2] < 0.0;
    for q in setup.particles.iter_mut() {
        if top(q) && near_side(q) {
            q.velocity = [0.0, 0.2, 0.0];
        }
    }
    let mut g = gpu::<D3>(&setup);
    g.set_lanes(Some(1));
    g.build_grid();
    assert!(
        g.skips_walls_at_rest(),
        "a grid build at one lane in 3D stamps"
    );
    g.density();
    let start = g.download_state();
    let step = |g: &mut CudaSolver<D3>| {
        g.forces();
        g.time_step();
        g.kick();
        g.rates();
        g.download_state()
    };
    let skipped = step(&mut g);
    g.upload_state(&start);
    assert!(!g.skips_walls_at_rest(), "an upload drops the stamps");
    let walked = step(&mut g);
    assert_eq!(
        skipped.drho, walked.drho,
        "d rho/dt with and without the skip"
    );
    assert_eq!(
        flat_v::<D3>(&skipped.xsph),
        flat_v::<D3>(&walked.xsph),
        "xsph with and without the skip"
    );
    // What the test covers: walls of both sorts above the water.
    let drho = walked.drho.as_ref().expect("continuity density");
    let (mut at_rest, mut beside_moving, mut moving) = (0, 0, 0);
    for (((&k, x), v), &d) in walked
        .kind
        .iter()
        .zip(&walked.pos)
        .zip(&walked.vel)
        .zip(drho)
    {
        let wall = k as u32 == MF_KIND_BOUNDARY;
        let (y, z) = (x[1], x[2]);
        if wall && y > 1.0 && z > 2.0 * dx {
            at_rest += (d == 0.0) as usize;
        }
        if wall && y > 1.0 && y < 1.1 && z < 0.0 && d != 0.0 {
            beside_moving += 1;
        }
        if wall && v[1] != 0.0 && d != 0.0 {
            moving += 1;
        }
    }
    assert!(
        at_rest > 0,
        "no wall at rest among walls at rest above the water"
    );
    assert!(
        beside_moving > 0,
        "no wall at rest with a non-zero rate beside the moving walls"
    );
    assert!(moving > 0, "no moving wall with a non-zero rate");
    eprintln!(
        "walls at rest skipped: {at_rest} with rate 0 far from motion, {beside_moving} beside moving walls and {moving} moving walls with a rate, as when walking every row"
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn params_layout_matches_nvcc() {
    let setup = scene(3, V_3D_A);
    let mut g = gpu::<D3>(&setup);
    let l = g.params_layout();
    let rust = [
        std::mem::size_of::<SphParams>() as u32,
        std::mem::offset_of!(SphParams, dt) as u32,
        std::mem::offset_of!(SphParams, gravity) as u32,
        3,
    ];
    assert_eq!(
        l, rust,
        "nvcc (sizeof, offsetof dt, offsetof gravity, dim) vs Rust"
    );
    eprintln!("SphParams layout: nvcc {l:?} == rust {rust:?}");
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn state_round_trip_through_device() {
    let setup = scene(2, V_2D_A);
    let mut g = gpu::<D2>(&setup);
    let s: State<D2> = g.download_state();
    let host = State::<D2>::from_particles(&setup.particles, false, true, setup.params.solid_rho0);
    assert_eq!(s.id, host.id);
    assert_eq!(flat_v::<D2>(&s.pos), flat_v::<D2>(&host.pos));
    let back = g.particles();
    assert_eq!(back.len(), setup.particles.len());
    assert!(back
        .iter()
        .zip(&setup.particles)
        .all(|(a, b)| a.id == b.id && a.position == b.position && a.mass == b.mass));
}

/// `advance` (two steps captured as a CUDA graph, replayed) against the same number of
/// single `step` calls on the GPU: the same kernels on the same inputs, so the same state bit
/// for bit (odd counts end with single steps).
fn graph_replay<D: Dim>(dim: usize, v: Variant) {
    let setup = scene_with(dim, v, 0.05);
    let (mut a, mut b) = (gpu::<D>(&setup), gpu::<D>(&setup));
    for n in [7u64, 10, 1] {
        a.advance(n);
        for _ in 0..n {
            b.step();
        }
    }
    assert_eq!(a.steps(), b.steps());
    assert_eq!(a.time(), b.time(), "simulated time after advance vs step");
    let (pa, pb) = (a.particles(), b.particles());
    for (x, y) in pa.iter().zip(&pb) {
        assert_eq!(x.id, y.id);
        assert_eq!(
            (x.position, x.velocity, x.density),
            (y.position, y.velocity, y.density),
            "particle {} differs between graph replay and single steps",
            x.id
        );
    }
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn graph_replay_matches_single_steps_2d() {
    graph_replay::<D2>(2, V_2D_B);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn graph_replay_matches_single_steps_3d() {
    graph_replay::<D3>(3, V_3D_B);
}

/// `setup` with particle shifting (`shifting` = 0.2): the shift velocity joins the XSPH
/// velocity in rates and moves the particles in the drift.
fn shifted(mut setup: Setup) -> Setup {
    setup.params.shifting = 0.2;
    setup
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_shifting_with_a_body() {
    stages_on::<D2>("V_2D_B shifting", shifted(scene(2, V_2D_B)));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_shifting_dynamic_walls() {
    stages_on::<D3>("V_3D_B fluid only shifting", shifted(fluid_only(3, V_3D_B)));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_background_pressure_dynamic_walls() {
    let mut setup = scene(2, V_2D_A);
    setup.params.background_pressure = 2.0;
    stages_on::<D2>("V_2D_A background pressure", setup);
}

/// `setup` with the dynamic walls' continuity density held at >= rho0 (`wall_density_floor`,
/// DualSPHysics' DBC; `wall_density_floor` in src/backend/cpu/integrate.rs): the random
/// velocities dilate some wall particles, so the drift's clamp binds.
fn with_wall_density_floor(mut setup: Setup) -> Setup {
    setup.params.wall_density_floor = 1;
    setup
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_wall_density_floor_continuity_symplectic() {
    let setup = with_wall_density_floor(scene(2, V_2D_SYMPLECTIC_LAMINAR));
    stages_on::<D2>("V_2D_SYMPLECTIC_LAMINAR wall density floor", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_wall_density_floor_continuity_euler() {
    let setup = with_wall_density_floor(scene(3, V_3D_B));
    stages_on::<D3>("V_3D_B wall density floor", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_wall_density_floor() {
    let setup = with_wall_density_floor(scene_with(2, V_2D_SYMPLECTIC_LAMINAR, 0.05));
    long_run_on::<D2>("V_2D_SYMPLECTIC_LAMINAR wall density floor", setup, 200);
}

/// `scene(dim, v)` in a domain reaching `y_max` [L] up, so that its grid has `cells` cells
/// (asserted): more than 3 x 4096, several blocks of the GPU's cell scan (4096 cells each;
/// the other scenes have one), for the scan of the block totals (`sph_scan_top`) and cell
/// ranges that cross blocks; 4097 to 8192, the one block of twice the cells that
/// `sph_scan_one` scans alone.
fn with_tall_domain(mut setup: Setup, y_max: f32, cells: std::ops::RangeInclusive<usize>) -> Setup {
    setup.params.domain_max[1] = y_max;
    params::derive(&mut setup.params);
    assert!(
        cells.contains(&(setup.params.n_cells as usize)),
        "{} cells, not in {cells:?}",
        setup.params.n_cells
    );
    setup
}
const MANY_SCAN_BLOCKS: std::ops::RangeInclusive<usize> = 3 * 4096 + 1..=usize::MAX;
const TWO_SCAN_BLOCKS: std::ops::RangeInclusive<usize> = 4097..=8192;
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_lean_many_scan_blocks() {
    stages_on::<D2>(
        "V_2D_LEAN, tall domain",
        with_tall_domain(scene(2, V_2D_LEAN), 60.0, MANY_SCAN_BLOCKS),
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_lean_many_scan_blocks() {
    stages_on::<D3>(
        "V_3D_LEAN, tall domain",
        with_tall_domain(scene(3, V_3D_LEAN), 30.0, MANY_SCAN_BLOCKS),
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_many_scan_blocks() {
    let setup = with_tall_domain(scene_with(3, V_3D_LEAN, 0.05), 30.0, MANY_SCAN_BLOCKS);
    long_run_on::<D3>("V_3D_LEAN, tall domain", setup, 200);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_lean_two_scan_blocks() {
    stages_on::<D2>(
        "V_2D_LEAN, two scan blocks",
        with_tall_domain(scene(2, V_2D_LEAN), 30.0, TWO_SCAN_BLOCKS),
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_two_scan_blocks() {
    let setup = with_tall_domain(scene_with(3, V_3D_LEAN, 0.05), 6.0, TWO_SCAN_BLOCKS);
    long_run_on::<D3>("V_3D_LEAN, two scan blocks", setup, 200);
}

/// Every field of a frame (sorted by id) as `particles()` read it back (mass aside: frames
/// carry none).
fn same_particles(what: &str, frame: &[Particle], read: &[Particle]) {
    assert_eq!(frame.len(), read.len(), "{what}: particle count");
    for (f, r) in frame.iter().zip(read) {
        let r = Particle { mass: 0.0, ..*r };
        assert_eq!(*f, r, "{what}: particle {}", r.id);
    }
}

/// Output frames (`Solver::capture`): the device-side copy taken at a step is what
/// `particles()` reads back at that step, although the solver stepped on before the frame
/// was downloaded; two frames in flight at once; a frame dropped unread gives its staging
/// set back; and the CPU backend's capture likewise.
fn capture_is_a_snapshot<D: Dim>(dim: usize, v: Variant) {
    use meshfree_core::frame::{Field, Fields};
    let all = Fields::all();
    let setup = scene(dim, v);
    let mut g = gpu::<D>(&setup);
    g.advance(3);
    let at_a = g.particles();
    let a = g.capture(all);
    g.advance(5);
    let at_b = g.particles();
    let b = g.capture(all);
    g.advance(2);
    let a = a.wait().unwrap();
    assert_eq!(a.step, 3);
    assert!(
        !a.stress.is_empty(),
        "the scene has a solid: stress is captured"
    );
    same_particles("GPU frame A", &a.particles(), &at_a);
    same_particles("GPU frame B", &b.wait().unwrap().particles(), &at_b);
    // Both staging sets are free again; a frame dropped unread frees its set too.
    for _ in 0..3 {
        drop(g.capture(all));
    }
    let few = Fields::of(&[Field::Position, Field::Pressure]);
    let at_c = g.particles();
    let c = g.capture(few).wait().unwrap();
    assert!(c.velocity.is_empty() && c.id.is_empty());
    let mut pos_c: Vec<[f32; 3]> = c.position.clone();
    let mut pos_r: Vec<[f32; 3]> = at_c.iter().map(|q| q.position).collect();
    pos_c.sort_by(|x, y| x.partial_cmp(y).unwrap());
    pos_r.sort_by(|x, y| x.partial_cmp(y).unwrap());
    assert_eq!(pos_c, pos_r, "the positions of a frame without ids");

    let mut c = CpuSolver::<D>::new(setup);
    c.advance(2);
    let at = c.particles();
    let frame = c.capture(all).wait().unwrap();
    same_particles("CPU frame", &frame.particles(), &at);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn capture_is_a_snapshot_2d() {
    capture_is_a_snapshot::<D2>(2, V_2D_A);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn capture_is_a_snapshot_3d() {
    capture_is_a_snapshot::<D3>(3, V_3D_A);
}

/// A lattice of points over the parity scene's domain, offset from the cells' corners: in
/// the fluid, in the body, among the walls and above the fluid out of every particle's reach.
fn probe_points(p: &SphParams) -> Vec<[f32; 3]> {
    let dim = p.dim as usize;
    let n = [9, 13, if dim == 3 { 5 } else { 1 }];
    let mut out = Vec::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let c = [i, j, k];
                let mut x = [0.0f32; 3];
                for a in 0..dim {
                    let (lo, hi) = (p.domain_min[a], p.domain_max[a]);
                    x[a] = lo + (hi - lo) * (c[a] as f32 + 0.37) / n[a] as f32;
                }
                out.push(x);
            }
        }
    }
    out
}

/// The CPU's and the GPU's samples at the same points: NaN at the same points, the same
/// neighbours (to one at the support's edge, where |r|^2 may round either way), values
/// within the density stage's tolerances times `scale` (1 from one state; more where the
/// two stepped apart).
fn cmp_samples(what: &str, p: &SphParams, c: &[PointSample], g: &[PointSample], scale: f32) {
    assert_eq!(c.len(), g.len(), "{what}: sample counts differ");
    let dim = p.dim as usize;
    for (k, (a, b)) in c.iter().zip(g).enumerate() {
        assert!(
            a.neighbours.abs_diff(b.neighbours) <= 1,
            "{what}: point {k}: cpu {} gpu {} neighbours",
            a.neighbours,
            b.neighbours
        );
        assert_eq!(
            (
                a.pressure.is_nan(),
                a.density.is_nan(),
                a.velocity[0].is_nan()
            ),
            (
                b.pressure.is_nan(),
                b.density.is_nan(),
                b.velocity[0].is_nan()
            ),
            "{what}: point {k}: NaN on one side only (cpu {a:?}, gpu {b:?})"
        );
    }
    let ids: Vec<u32> = (0..c.len() as u32).collect();
    let num = |v: f32| if v.is_nan() { 0.0 } else { v };
    let col = |s: &[PointSample], f: &dyn Fn(&PointSample) -> Vec<f32>| -> Vec<f32> {
        s.iter().flat_map(f).map(num).collect()
    };
    let (pc, pg) = (col(c, &|q| vec![q.pressure]), col(g, &|q| vec![q.pressure]));
    let tol_p = 2e-5 * scale * p.tait_b * p.tait_gamma;
    close(
        &format!("{what} pressure"),
        &ids,
        1,
        &pc,
        &pg,
        1e-4 * scale,
        tol_p,
    );
    let (rc, rg) = (col(c, &|q| vec![q.density]), col(g, &|q| vec![q.density]));
    close(
        &format!("{what} density"),
        &ids,
        1,
        &rc,
        &rg,
        2e-5 * scale,
        0.0,
    );
    let vel = |q: &PointSample| q.velocity[..dim].to_vec();
    let (vc, vg) = (col(c, &vel), col(g, &vel));
    let tol_v = 1e-4 * scale * max_abs(&vc);
    close(
        &format!("{what} velocity"),
        &ids,
        dim,
        &vc,
        &vg,
        1e-4 * scale,
        tol_v,
    );
    let (cc, cg) = (col(c, &|q| vec![q.colour]), col(g, &|q| vec![q.colour]));
    close(
        &format!("{what} colour"),
        &ids,
        1,
        &cc,
        &cg,
        2e-5 * scale,
        1e-6 * scale,
    );
    let dry = c.iter().filter(|q| q.neighbours == 0).count();
    eprintln!("  {what}: {} points, {dry} with no particle near", c.len());
}

/// Probes (`Solver::sample_points`: `cuda/probes.cu` against `cpu/probes.rs`) on a parity
/// scene, with and without the walls: at the start (no grid built yet on either), after
/// the CPU's state moved by steps is uploaded (the GPU's grid then stale, as the CPU's after
/// its drift), and after both stepped on (the GPU by graphs) from that one state.
fn probes_on<D: Dim>(what: &str, setup: Setup) {
    let p = setup.params;
    let mut g = gpu::<D>(&setup);
    let mut c = CpuSolver::<D>::new(setup);
    let pts = probe_points(&p);
    eprintln!(
        "{}D probes {what}: {} points, {} particles, on {}",
        p.dim,
        pts.len(),
        c.len(),
        g.info().device
    );
    let (mut sc, mut sg) = (Vec::new(), Vec::new());
    let mut both = |c: &mut CpuSolver<D>, g: &mut CudaSolver<D>, when: &str, scale: f32| {
        for walls in [false, true] {
            c.sample_points(&pts, walls, &mut sc);
            g.sample_points(&pts, walls, &mut sg);
            cmp_samples(&format!("{when}, walls {walls}"), &p, &sc, &sg, scale);
        }
    };
    both(&mut c, &mut g, "at the start", 1.0);
    c.advance(3);
    g.upload_state(c.state());
    both(&mut c, &mut g, "after 3 CPU steps, uploaded", 1.0);
    c.advance(6);
    g.advance(6);
    both(&mut c, &mut g, "after 6 more steps each", 50.0);
}

/// Sampling between batches changes nothing of the GPU's stepping (the grid it rebuilds is
/// the one the next step builds; a replayed graph takes a single step first): bit for bit
/// the states of a solver sampled every other batch and one never sampled.
fn sampling_leaves_gpu_stepping_unchanged<D: Dim>(setup: Setup) {
    let pts = probe_points(&setup.params);
    let mut a = gpu::<D>(&setup);
    let mut b = gpu::<D>(&setup);
    let mut out = Vec::new();
    for k in 0..6 {
        a.advance(5);
        b.advance(5);
        if k % 2 == 0 {
            b.sample_points(&pts, k % 4 == 0, &mut out);
        }
    }
    let (sa, sb) = (a.download_state(), b.download_state());
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<u32>>();
    assert_eq!(sa.id, sb.id, "storage orders differ");
    assert_eq!(
        bits(&flat_v::<D>(&sa.pos)),
        bits(&flat_v::<D>(&sb.pos)),
        "positions"
    );
    assert_eq!(
        bits(&flat_v::<D>(&sa.vel)),
        bits(&flat_v::<D>(&sb.vel)),
        "velocities"
    );
    assert_eq!(bits(&sa.rho), bits(&sb.rho), "densities");
    assert_eq!(bits(&sa.p), bits(&sb.p), "pressures");
    assert_eq!(a.time(), b.time());
    eprintln!(
        "  {}D: 30 steps with and without samples between batches: identical states",
        setup.params.dim
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn probes_2d() {
    probes_on::<D2>("V_2D_A (summation, dynamic walls)", scene(2, V_2D_A));
    probes_on::<D2>("V_2D_B (continuity, Lennard-Jones walls)", scene(2, V_2D_B));
    sampling_leaves_gpu_stepping_unchanged::<D2>(scene_with(2, V_2D_B, 0.05));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn probes_3d() {
    probes_on::<D3>("V_3D_A (continuity, Lennard-Jones walls)", scene(3, V_3D_A));
    probes_on::<D3>("V_3D_B (continuity, dynamic walls)", scene(3, V_3D_B));
    sampling_leaves_gpu_stepping_unchanged::<D3>(scene_with(3, V_3D_B, 0.05));
}

// ---- force monitors (`Solver::wall_forces`, cuda/monitor.cu) ----

/// `setup` in a mean flow: `u` [L/T] added to every fluid particle's velocity (periodic x).
fn in_flow(mut setup: Setup, u: [f32; 3]) -> Setup {
    let dim = setup.params.dim as usize;
    for q in setup.particles.iter_mut().filter(|q| q.kind == Kind::Fluid) {
        for (v, u) in q.velocity.iter_mut().zip(u).take(dim) {
            *v += u;
        }
    }
    setup
}

/// The wall object of `obstacle_in_flow`.
const OBSTACLE: u32 = 3;

/// `scene_with(dim, v, 0.05)` in a mean flow along x with its elastic disc / sphere turned
/// into a fixed obstacle: wall particles of group `OBSTACLE` (at rest, rest density), with
/// fluid on every side; the floor (group 0) is a second wall object. No solids are left:
/// the fluid-only entries (`sph_wall_force_fluid_*`).
fn obstacle_in_flow(dim: usize, v: Variant) -> Setup {
    let mut setup = in_flow(scene_with(dim, v, 0.05), [1.0, 0.0, 0.0]);
    let (rho0, dx) = (setup.params.rho0, setup.params.dx);
    for q in setup.particles.iter_mut().filter(|q| q.kind == Kind::Solid) {
        q.kind = Kind::Boundary;
        q.group = OBSTACLE;
        q.velocity = [0.0; 3];
        q.density = rho0;
        q.mass = rho0 * dx.powi(dim as i32);
        q.stress = Default::default();
    }
    setup
}

/// `with_no_slip` for `obstacle_in_flow`: the obstacle's particles face its own surface, the
/// circle / sphere of the body's radius about its centre (`scene_with`), the normal pointing
/// out into the fluid and d_B = radius - |x - centre|.
fn obstacle_no_slip(setup: Setup, beta_max: f32) -> Setup {
    let mut setup = with_no_slip(setup, beta_max);
    let p = setup.params;
    let d3 = p.dim == 3;
    let (lx, lz) = (p.domain_max[0], p.domain_max[2] - 3.0 * p.dx);
    let fy = if d3 { 8.0 } else { 15.0 };
    let centre = [0.5 * lx, 0.5 * fy * p.dx, 0.5 * lz];
    let radius = if d3 { 0.25 } else { 0.35 };
    for q in setup.particles.iter().filter(|q| q.group == OBSTACLE) {
        let r: [f32; 3] = std::array::from_fn(|a| {
            if a < p.dim as usize {
                q.position[a] - centre[a]
            } else {
                0.0
            }
        });
        let d = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        let n = if d > 0.0 {
            [r[0] / d, r[1] / d, r[2] / d]
        } else {
            [0.0, 1.0, 0.0]
        };
        // (The lattice's jitter puts a few rim particles just outside the radius.)
        setup.wall_surface[(q.id - p.wall_first_id) as usize] =
            [n[0], n[1], n[2], (radius - d).max(0.0)];
    }
    setup
}

/// `scene_with(dim, v, 0.05)` in a mean flow along x with a second elastic body (group 4):
/// the fluid of the two lowest rows over the first half of x turned into a solid slab resting
/// on the floor, so that the floor's force has solid-wall pairs too. With solids: the entries
/// with the stress terms (`sph_wall_force_*`).
fn slab_on_floor(dim: usize, v: Variant) -> Setup {
    let mut setup = in_flow(scene_with(dim, v, 0.05), [1.0, 0.0, 0.0]);
    let p = setup.params;
    let half = 0.5 * (p.domain_min[0] + p.domain_max[0]);
    for q in setup.particles.iter_mut() {
        if q.kind == Kind::Fluid && q.position[1] < 2.0 * p.dx && q.position[0] < half {
            q.kind = Kind::Solid;
            q.group = 4;
            q.velocity = [0.0; 3];
            q.density = p.solid_rho0;
            q.mass = p.solid_rho0 * p.dx.powi(p.dim);
        }
    }
    setup
}

/// sum over the pairs (wall particle j of `group`, fluid or solid neighbour i) of
/// m_i |a_i(from j)| [M L T^-2]: the size of the terms that `monitor::wall_force` sums, on
/// which its rounding differences act whatever their signs. The read-back path's loop
/// (src/backend/cpu/monitor.rs) with absolute values.
fn gross_wall_force<D: Dim>(
    p: &SphParams,
    parts: &[Particle],
    surface: &[[f32; 4]],
    group: u32,
) -> f64 {
    let mut s = State::<D>::from_particles(parts, false, false, p.solid_rho0);
    for i in 0..s.len() {
        s.p[i] = cpu::pressure(p, s.kind[i], s.rho[i], s.rho_dev(i));
    }
    let mut grid = cpu::Grid::default();
    grid.build(p, &mut s);
    let mut sum = 0.0f64;
    for j in 0..s.len() {
        if s.kind[j] != Kind::Boundary.code() || s.group[j] != group {
            continue;
        }
        grid.for_each_neighbor::<D>(p, &s.pos, s.pos[j], |i, r_ji, r2| {
            if s.kind[i] != Kind::Boundary.code() {
                let mut f = cpu::ForceSum::new(p, &s, surface, i, D::V::default());
                f.add(p, j, -r_ji, r2);
                sum += s.mass[i] as f64 * D::length2(f.acc).sqrt() as f64;
            }
        });
    }
    sum
}

/// The relative tolerance of the GPU's wall force: |F_gpu - F_cpu| <= WALL_FORCE_RTOL x
/// sum_pairs m_i |a_i(from j)| on each axis. The pair terms are the force kernel's
/// (`ForceSum::add`), which agree with the CPU's to the force stage's parity (1e-4 of the
/// largest acceleration, `check_forces`: fast division and root, powf and the equation of
/// state's cancellation near rho0); summed over pairs of either sign, the sum's error is
/// bounded by that fraction of the sum of the terms' sizes, not of the net force (a wall in
/// a near-uniform pressure field nets a small difference of large terms).
const WALL_FORCE_RTOL: f64 = 1e-4;

/// The GPU's `wall_forces` (cuda/monitor.cu: the grid rebuilt, the equation of state
/// refreshed, the pair sums and their reduction on the device) against the read-back path
/// (`monitor::wall_force` on `particles()`: the CPU force stage's pair terms) from the same
/// GPU state: at t = 0 (unsorted storage, no grid yet), after 7 single steps and after 20
/// more in graph batches. Then 9 more steps: the sampled run and a twin that was never
/// sampled agree bit for bit (the sample's grid build and pressures are those the next step
/// makes anyway).
fn wall_force_parity<D: Dim>(what: &str, setup: Setup, groups: &[u32]) {
    let p = setup.params;
    let surface = setup.wall_surface.clone();
    let (mut g, mut twin) = (gpu::<D>(&setup), gpu::<D>(&setup));
    eprintln!(
        "{}D wall forces {what}: {} particles, groups {groups:?}, on {}",
        p.dim,
        setup.particles.len(),
        g.info().device
    );
    let mut worst = 0.0f64;
    for (k, steps) in [0u64, 7, 20].into_iter().enumerate() {
        if k == 1 {
            for _ in 0..steps {
                g.step();
                twin.step();
            }
        } else {
            g.advance(steps);
            twin.advance(steps);
        }
        let parts = g.particles();
        let got = g.wall_forces(groups);
        assert_eq!(got.len(), groups.len());
        for (&group, f) in groups.iter().zip(&got) {
            let want = monitor::wall_force(&p, &parts, &surface, group);
            let gross = gross_wall_force::<D>(&p, &parts, &surface, group);
            assert!(gross > 0.0, "{what}: group {group} has no pairs");
            for a in 0..3 {
                let err = (f[a] - want[a]).abs();
                assert!(
                    err <= WALL_FORCE_RTOL * gross,
                    "{what}, t = {:.5}, group {group}, axis {a}: gpu {} cpu {} (|diff| {err:e} > \
                     {WALL_FORCE_RTOL:e} x {gross:e}, the sum of the pair terms' sizes)",
                    g.time(),
                    f[a],
                    want[a]
                );
                worst = worst.max(err / gross);
            }
            eprintln!(
                "  t = {:.5}, group {group}: gpu {f:?}\n  {:>13} cpu {want:?} (pair terms' sizes {gross:.4e})",
                g.time(),
                ""
            );
        }
    }
    eprintln!("  worst |gpu - cpu| / sum of the pair terms' sizes: {worst:.2e} (tolerance {WALL_FORCE_RTOL:e})");
    g.advance(9);
    twin.advance(9);
    let (a, b) = (g.particles(), twin.particles());
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(
            (x.id, x.position, x.velocity, x.density),
            (y.id, y.position, y.velocity, y.density),
            "{what}: sampling the wall forces changed the run (particle {})",
            x.id
        );
    }
    eprintln!("  9 steps on: the sampled run = the unsampled twin, bit for bit");
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn wall_forces_2d_obstacle_dynamic_walls_summation() {
    let setup = obstacle_in_flow(2, V_2D_A);
    wall_force_parity::<D2>("obstacle, V_2D_A", setup, &[OBSTACLE, 0]);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn wall_forces_2d_obstacle_no_slip_walls() {
    let setup = obstacle_no_slip(obstacle_in_flow(2, V_2D_A), 2.0);
    wall_force_parity::<D2>("obstacle, V_2D_A + Morris no-slip", setup, &[OBSTACLE, 0]);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn wall_forces_2d_bodies_lj_walls_continuity() {
    wall_force_parity::<D2>("slab on the floor, V_2D_B", slab_on_floor(2, V_2D_B), &[0]);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn wall_forces_3d_obstacle_lj_walls_continuity() {
    let setup = obstacle_in_flow(3, V_3D_A);
    wall_force_parity::<D3>("obstacle, V_3D_A", setup, &[OBSTACLE, 0]);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn wall_forces_3d_bodies_dynamic_no_slip_walls() {
    let setup = with_no_slip(slab_on_floor(3, V_3D_B), 2.0);
    wall_force_parity::<D3>("slab on the floor, V_3D_B + Morris no-slip", setup, &[0]);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn wall_forces_3d_obstacle_dynamic_no_slip_walls() {
    let setup = obstacle_no_slip(obstacle_in_flow(3, V_3D_B), 2.0);
    wall_force_parity::<D3>("obstacle, V_3D_B + Morris no-slip", setup, &[OBSTACLE, 0]);
}

/// `setup` with total-Lagrangian bodies (`[solid] formulation = "total-lagrangian"`,
/// `cuda/tlsph.cu`, twin `src/backend/cpu/tlsph.rs`) and the hourglass control at `alpha`;
/// its variant has no artificial stress (the formulation refuses it).
fn total_lagrangian_of(mut setup: Setup, alpha: f32) -> Setup {
    assert_eq!(setup.params.artificial_stress, 0.0);
    setup.params.solid_formulation = MF_SOLID_TOTAL_LAGRANGIAN as i32;
    setup.params.hourglass = alpha;
    setup
}

const V_2D_A_TL: Variant = Variant {
    art_stress: false,
    ..V_2D_A
};
const V_2D_B_TL: Variant = Variant {
    art_stress: false,
    ..V_2D_B
};
const V_3D_B_TL: Variant = Variant {
    art_stress: false,
    ..V_3D_B
};

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_total_lagrangian_clamped_plate_summation_euler() {
    let setup = total_lagrangian_of(clamped_body(2, V_2D_A_TL), 0.1);
    stages_on::<D2>(
        "V_2D_A, total Lagrangian, clamp holding half the disc",
        setup,
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_total_lagrangian_bodies_in_contact_continuity_symplectic() {
    let setup = total_lagrangian_of(bodies_in_contact(2, V_2D_B_TL, false), 0.1);
    stages_on::<D2>("V_2D_B, total Lagrangian, bodies in contact", setup);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_total_lagrangian_clamped_block_continuity_euler() {
    let setup = total_lagrangian_of(clamped_body(3, V_3D_B_TL), 0.1);
    stages_on::<D3>(
        "V_3D_B, total Lagrangian, clamp holding half the sphere",
        setup,
    );
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_total_lagrangian_clamped_block_continuity_symplectic() {
    let setup = total_lagrangian_of(clamped_body(3, V_3D_A), 0.1);
    stages_on::<D3>(
        "V_3D_A, total Lagrangian, clamp holding half the sphere",
        setup,
    );
}

/// A total-Lagrangian run of `steps` steps from a calm start, the GPU's through
/// `Solver::advance` (captured graphs), `remove` (a group) taken away from both halfway:
/// diagnostics as `long_run_on`, and the displacements within `scale` of the largest.
fn tl_long_run<D: Dim>(what: &str, setup: Setup, steps: u64, remove: Option<u32>) {
    let mut g = gpu::<D>(&setup);
    let mut c = CpuSolver::<D>::new(setup);
    let half = steps / 2;
    c.advance(half);
    g.advance(half);
    if let Some(grp) = remove {
        let (rc, rg) = (c.remove_group(grp), g.remove_group(grp));
        assert_eq!(rc, rg, "remove_group({grp}): removed cpu {rc} gpu {rg}");
        assert!(rc > 0, "remove_group({grp}) removed nothing");
    }
    c.advance(steps - half);
    g.advance(steps - half);
    let (dc, dg) = (c.diagnostics(), g.diagnostics());
    let dim = D::D;
    eprintln!("{dim}D {what} after {steps} steps:\n  cpu {dc:?}\n  gpu {dg:?}");
    assert!(c.check().is_ok() && g.check().is_ok(), "a blow-up");
    assert_eq!(
        (dc.fluid, dc.solid, dc.boundary),
        (dg.fluid, dg.solid, dg.boundary)
    );
    let rel = |a: f64, b: f64| (a - b).abs() / a.abs().max(1e-30);
    assert!(
        rel(dc.time, dg.time) < 1e-3,
        "time: cpu {} gpu {}",
        dc.time,
        dg.time
    );
    assert!(
        rel(dc.kinetic_energy, dg.kinetic_energy) < 2e-2,
        "kinetic energy: cpu {} gpu {} (rtol 2e-2)",
        dc.kinetic_energy,
        dg.kinetic_energy
    );
    assert!(
        (dc.density_error - dg.density_error).abs() < 5e-3,
        "density error: cpu {} gpu {} (atol 5e-3)",
        dc.density_error,
        dg.density_error
    );
    cmp_displacement(&c, &mut g, 2e-2);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn long_run_2d_total_lagrangian_clamped_plate_symplectic() {
    let setup = total_lagrangian_of(clamped_of(scene_with(2, V_2D_B_TL, 0.05)), 0.1);
    tl_long_run::<D2>("total Lagrangian clamped plate (V_2D_B)", setup, 200, None);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn long_run_3d_total_lagrangian_clamped_block_symplectic() {
    // The symplectic Euler: under the forward Euler this body's elastic modes grow (as an
    // oscillator's do) and blew the run up on both backends alike by step 200.
    let setup = total_lagrangian_of(clamped_of(scene_with(3, V_3D_A, 0.05)), 0.1);
    tl_long_run::<D3>("total Lagrangian clamped block (V_3D_A)", setup, 200, None);
}
/// The slot map after `remove_group` (`sph_tl_slots`; twin `TlBodies::map_slots`): one of
/// the bodies (the solid layer on the wall, group 4) removed halfway.
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn long_run_2d_total_lagrangian_remove_a_body() {
    let mut setup = bodies_in_contact(2, V_2D_B_TL, false);
    for q in setup.particles.iter_mut() {
        for a in 0..2 {
            q.velocity[a] *= 0.05 / 0.3;
        }
    }
    let setup = total_lagrangian_of(setup, 0.1);
    tl_long_run::<D2>("total Lagrangian bodies, one removed", setup, 100, Some(4));
}

/// A health check queued on the GPU (`Solver::queue_check`, read by `queued_fault` with
/// the clock) reports the fault that the immediate check (`Solver::check`) and the CPU's
/// check report, with the step and time of the queued check; and a later check's fault
/// does not replace the first one's.
fn queued_check_on<D: Dim>(setup: Setup) {
    let mut g = gpu::<D>(&setup);
    let mut c = CpuSolver::<D>::new(setup.clone());
    for _ in 0..3 {
        c.step();
    }
    let mut st = c.state().clone();
    g.upload_state(&st);
    assert!(
        g.queue_check().is_ok() && g.queued_fault().is_ok(),
        "a fault on a healthy state"
    );
    let fluid: Vec<usize> = (0..st.len())
        .filter(|&i| st.kind[i] == Kind::Fluid.code())
        .collect();
    let (a, b) = (fluid[fluid.len() / 2], fluid[fluid.len() / 4]);
    st.rho[a] *= 5.0;
    g.upload_state(&st);
    g.queue_check().expect("queued: nothing read back yet");
    let (step, time) = (g.steps(), g.time());
    // The CPU's check of the same particles.
    let mut faulty = setup;
    faulty.particles = st.to_particles();
    let cpu = CpuSolver::<D>::new(faulty)
        .check()
        .expect_err("the CPU's fault");
    // A second fault, at a lower slot, found by a later check.
    let rho_b = st.rho[b];
    st.rho[b] = f32::NAN;
    g.upload_state(&st);
    g.queue_check().expect("queued");
    let queued = g.queued_fault().expect_err("the queued check's fault");
    st.rho[b] = rho_b;
    g.upload_state(&st);
    let now = g.check().expect_err("the immediate check's fault");
    eprintln!("queued: {queued}\nnow:    {now}\ncpu:    {cpu}");
    assert_eq!((queued.step, queued.time), (step, time));
    for f in [&queued, &now] {
        assert_eq!(f.particle, st.id[a]);
        assert_eq!(
            (&f.kind, &f.quantity, f.value, &f.reason),
            (&cpu.kind, &cpu.quantity, cpu.value, &cpu.reason)
        );
    }
    assert_eq!(cpu.particle, st.id[a]);
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn queued_check_reports_the_first_fault_2d() {
    queued_check_on::<D2>(scene_with(2, V_2D_B, 0.05));
}
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn queued_check_reports_the_first_fault_3d() {
    queued_check_on::<D3>(scene_with(3, V_3D_B, 0.05));
}
