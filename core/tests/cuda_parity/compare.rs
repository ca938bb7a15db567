//! How the parity tests compare: the GPU solver (`gpu`), the tolerances (`close` and its
//! vector and matrix forms), each stage of `Solver::step` on both backends from identical
//! inputs (`cmp_*`, `stages_on`), and long runs through captured graphs (`long_run_on`).

use super::*;
use meshfree_core::solver::Persist;
use meshfree_core::solver::Readback;

/// The GPU solver for `setup`; without a usable GPU the test fails (it was asked to run).
pub(crate) fn gpu<D: Dim>(setup: &Setup) -> CudaSolver<D> {
    CudaSolver::<D>::new(setup.clone()).unwrap_or_else(|e| {
        panic!(
            "this GPU test needs a usable CUDA device: {e} (it ran because the build had \
             MESHFREE_REQUIRE_CUDA=1, or because of --ignored / --include-ignored)"
        )
    })
}

/// |gpu - cpu| <= atol + rtol |cpu| for every entry; the message names the worst slot.
pub(crate) fn close(
    what: &str,
    ids: &[u32],
    width: usize,
    cpu: &[f32],
    gpu: &[f32],
    rtol: f32,
    atol: f32,
) {
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

pub(crate) fn flat_v<D: Dim>(v: &[D::V]) -> Vec<f32> {
    v.iter().flat_map(|x| D::to3(*x)[..D::D].to_vec()).collect()
}

pub(crate) fn flat_m<D: Dim>(v: &[D::M]) -> Vec<f32> {
    v.iter().flat_map(|m| D::sym_to6(*m)).collect()
}

pub(crate) fn max_abs(v: &[f32]) -> f32 {
    v.iter().fold(0.0f32, |m, x| m.max(x.abs()))
}

/// Vectors: absolute tolerance `scale` x the largest entry of the CPU array.
pub(crate) fn close_v<D: Dim>(
    what: &str,
    ids: &[u32],
    cpu: &[D::V],
    gpu: &[D::V],
    scale: f32,
    atol: f32,
) {
    let (a, b) = (flat_v::<D>(cpu), flat_v::<D>(gpu));
    let m = max_abs(&a);
    close(what, ids, D::D, &a, &b, scale, atol + scale * m);
}

pub(crate) fn close_m<D: Dim>(what: &str, ids: &[u32], cpu: &[D::M], gpu: &[D::M], scale: f32) {
    let (a, b) = (flat_m::<D>(cpu), flat_m::<D>(gpu));
    let m = max_abs(&a);
    close(what, ids, 6, &a, &b, scale, scale * m);
}

pub(crate) fn cmp_density<D: Dim>(
    c: &CpuSolver<D>,
    g: &mut CudaSolver<D>,
    ids: &[u32],
    p: &SphParams,
) {
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

pub(crate) fn check_rates<D: Dim>(cs: &State<D>, gs: &State<D>, ids: &[u32]) {
    close_v::<D>("rates xsph", ids, &cs.xsph, &gs.xsph, 1e-4, 0.0);
    if let (Some(a), Some(b)) = (&cs.drho, &gs.drho) {
        close("rates drho/dt", ids, 1, a, b, 1e-4, 1e-4 * max_abs(a));
    }
    if let (Some(a), Some(b)) = (&cs.solid, &gs.solid) {
        close_m::<D>("rates dS/dt", ids, &a.stress_rate, &b.stress_rate, 2e-4);
    }
}

pub(crate) fn check_forces<D: Dim>(cs: &State<D>, gs: &State<D>, ids: &[u32]) {
    close_v::<D>("forces acc", ids, &cs.acc, &gs.acc, 1e-4, 0.0);
}

pub(crate) fn cmp_rates<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    check_rates(c.state(), &g.download_state(), ids);
    g.upload_state(c.state());
}

pub(crate) fn cmp_forces<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    check_forces(c.state(), &g.download_state(), ids);
    g.upload_state(c.state());
}

/// After `forces_and_rates` (one download: the upload would overwrite both outputs).
pub(crate) fn cmp_forces_and_rates<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let gs = g.download_state();
    check_rates(c.state(), &gs, ids);
    check_forces(c.state(), &gs, ids);
    g.upload_state(c.state());
}

pub(crate) fn cmp_time_step<D: Dim>(c: &mut CpuSolver<D>, g: &mut CudaSolver<D>) {
    c.time_step();
    g.time_step();
    let (dc, dg) = (c.dt(), g.dt());
    assert!(
        (dc - dg).abs() <= 1e-5 * dc,
        "time_step: dt cpu {dc} gpu {dg} (rtol 1e-5)"
    );
    eprintln!("  time_step: dt cpu {dc} gpu {dg}");
}

pub(crate) fn cmp_kick<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let gs = g.download_state();
    close_v::<D>("kick vel", ids, &c.state().vel, &gs.vel, 1e-5, 0.0);
    g.upload_state(c.state());
}

pub(crate) fn check_drift<D: Dim>(
    c: &mut CpuSolver<D>,
    g: &mut CudaSolver<D>,
    gs: &State<D>,
    ids: &[u32],
) {
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

pub(crate) fn cmp_drift<D: Dim>(c: &mut CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let gs = g.download_state();
    check_drift(c, g, &gs, ids);
    g.upload_state(c.state());
}

/// After `drift_kick` (one kernel on the GPU; the CPU's drift then kick).
pub(crate) fn cmp_drift_kick<D: Dim>(c: &mut CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let gs = g.download_state();
    check_drift(c, g, &gs, ids);
    close_v::<D>("kick vel", ids, &c.state().vel, &gs.vel, 1e-5, 0.0);
    g.upload_state(c.state());
}

/// After `solid_stress` (total-Lagrangian bodies, `cuda/tlsph.cu`): the pressure, density
/// and deviatoric stress it writes into the solids' slots (the others are untouched).
pub(crate) fn cmp_solid_stress<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
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
pub(crate) fn cmp_solid_forces<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, ids: &[u32]) {
    let (cs, gs) = (c.state(), g.download_state());
    close_v::<D>("solid_forces acc", ids, &cs.acc, &gs.acc, 1e-4, 0.0);
    g.upload_state(cs);
}

/// The total-Lagrangian displacements u (solid space, by id rank) against the CPU's:
/// absolute tolerance `scale` x the largest.
pub(crate) fn cmp_displacement<D: Dim>(c: &CpuSolver<D>, g: &mut CudaSolver<D>, scale: f32) {
    let uc = &c.tl_bodies().expect("a total-Lagrangian scene").disp;
    let ug = g.tl_displacement().expect("the GPU holds the bodies too");
    let ids: Vec<u32> = c.tl_bodies().expect("checked").reference.id.clone();
    close_v::<D>("displacement u", &ids, uc, &ug, scale, 1e-9);
}

pub(crate) fn total_lagrangian(p: &SphParams) -> bool {
    p.solid_formulation as u32 == MF_SOLID_TOTAL_LAGRANGIAN
}

pub(crate) fn stages<D: Dim>(dim: usize, v: Variant) {
    stages_on::<D>(&format!("{v:?}"), scene(dim, v));
}

/// The stage comparison on any parity scene (`what` names it in the log).
pub(crate) fn stages_on<D: Dim>(what: &str, setup: Setup) {
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
        // The fluid's pressure at the bodies (where they meet the fluid at it), which the
        // force stage reads: compared through the forces.
        c.solid_interface();
        g.solid_interface();
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
            c.density_gradient();
            g.density_gradient();
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
            c.density_gradient();
            g.density_gradient();
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
pub(crate) fn long_run<D: Dim>(dim: usize, v: Variant, steps: usize) {
    long_run_on::<D>(&format!("{v:?}"), scene_with(dim, v, 0.05), steps);
}

/// `long_run` on any scene (`what` names it in the log).
pub(crate) fn long_run_on<D: Dim>(what: &str, setup: Setup, steps: usize) {
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
