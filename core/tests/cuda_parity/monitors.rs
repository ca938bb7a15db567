//! The force monitors' device sums (`Readback::wall_forces`, `cuda/monitor.cu`) against the
//! read-back path (`monitor::wall_force`) on wall objects in flow, with and without bodies.

use super::*;
use meshfree_core::solver::Readback;

// ---- force monitors (`Readback::wall_forces`, cuda/monitor.cu) ----

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
                let mut f = cpu::ForceSum::new(p, &s, surface, None, i, D::V::default());
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
