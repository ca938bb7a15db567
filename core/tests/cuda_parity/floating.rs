//! Floating rigid bodies (`cuda/bodies.cu`, the loads in `cuda/monitor.cu`) against the CPU's
//! (`backend/cpu/bodies.rs`) over whole steps, through the step's captured graphs: the
//! scenes' elastic disc / sphere made a rigid body of boundary particles, lighter than the
//! fluid, released spinning (about a tilted axis in 3D).

use super::*;
use meshfree_core::physics::body::{free_bits, matrix};
use meshfree_core::physics::params::MfBody;
use meshfree_core::solver::Readback;

/// `scene(dim, v)` under the leapfrog with its body (group 2) rigid and floating: its
/// particles boundary ones at the fluid's density, the body of density 0.6 spinning.
pub(crate) fn floating(dim: usize, v: Variant) -> Setup {
    floating_with(dim, v, 0.6, false)
}

/// `floating` with the body of `density` (relative to the fluid's rest density), and where
/// `on_floor`, lowered onto the wall: its lowest particle 0.9 r0 over the wall's top row (the
/// contact's repulsion acting from the first step), the fluid particles it then overlaps
/// (within 0.8 dx of one of its particles) left out.
pub(crate) fn floating_with(dim: usize, v: Variant, density: f64, on_floor: bool) -> Setup {
    let mut setup = leapfrog(scene(dim, v));
    if on_floor {
        let body = |q: &Particle| q.group == 2;
        let r0 = setup.params.lj_r0;
        let low = (setup.particles.iter().filter(|q| body(q)))
            .map(|q| q.position[1])
            .fold(f32::MAX, f32::min);
        // The floor under the body: the highest wall particle below it within its extent
        // across (x, and z in 3D), not the top of a side wall.
        let span = |a: usize| {
            (setup.particles.iter().filter(|q| body(q)))
                .map(|q| q.position[a])
                .fold((f32::MAX, f32::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)))
        };
        let across: Vec<(usize, (f32, f32))> = [0, 2]
            .into_iter()
            .filter(|&a| a < dim)
            .map(|a| (a, span(a)))
            .collect();
        let top = (setup.particles.iter())
            .filter(|q| q.kind == Kind::Boundary && !body(q) && q.position[1] < low)
            .filter(|q| {
                across
                    .iter()
                    .all(|&(a, (lo, hi))| q.position[a] >= lo && q.position[a] <= hi)
            })
            .map(|q| q.position[1])
            .fold(f32::MIN, f32::max);
        assert!(top > f32::MIN, "no floor under the body");
        let shift = top + 0.9 * r0 - low;
        for q in setup.particles.iter_mut().filter(|q| body(q)) {
            q.position[1] += shift;
        }
        let dx = setup.params.dx;
        let placed: Vec<[f32; 3]> = (setup.particles.iter().filter(|q| body(q)))
            .map(|q| q.position)
            .collect();
        setup.particles.retain(|q| {
            q.kind != Kind::Fluid
                || placed.iter().all(|x| {
                    (0..3).map(|a| (x[a] - q.position[a]).powi(2)).sum::<f32>()
                        >= (0.8 * dx).powi(2)
                })
        });
    }
    let p = &mut setup.params;
    let dx = p.dx;
    let mut centre = [0.0f64; 3];
    let mut n = 0;
    for q in setup.particles.iter_mut().filter(|q| q.group == 2) {
        q.kind = Kind::Boundary;
        q.density = p.rho0;
        q.mass = p.rho0 * dx.powi(dim as i32);
        q.velocity = [0.0; 3];
        q.stress = Default::default();
        for (c, x) in centre.iter_mut().zip(q.position) {
            *c += x as f64;
        }
        n += 1;
    }
    let centre = centre.map(|c| c / n as f64);
    // The body's particles as its solid, each dx^d at `density`: mass and inertia.
    let mut inertia = [0.0f64; 9];
    let m_each = density * (dx as f64).powi(dim as i32);
    for q in setup.particles.iter().filter(|q| q.group == 2) {
        let r = [0, 1, 2].map(|a| q.position[a] as f64 - centre[a]);
        let r2: f64 = r.iter().map(|x| x * x).sum();
        for i in 0..3 {
            for j in 0..3 {
                inertia[3 * i + j] += m_each * ((i == j) as i32 as f64 * r2 - r[i] * r[j]);
            }
        }
    }
    let mut b = MfBody {
        group: 2,
        free: free_bits(dim, [true; 3], [true; 3]),
        mass: m_each * n as f64,
        inertia,
        centre,
        orientation: [1.0, 0.0, 0.0, 0.0],
        turn: matrix(&[1.0, 0.0, 0.0, 0.0]),
        velocity: [0.1, 0.05, 0.0],
        ..Default::default()
    };
    let spin = if dim == 3 {
        [0.6, 0.3, 1.5]
    } else {
        [0.0, 0.0, 1.5]
    };
    b.momentum = [0, 1, 2].map(|a| (0..3).map(|k| inertia[3 * a + k] * spin[k]).sum());
    b.omega = b.omega_of(b.momentum);
    let p = &mut setup.params;
    p.driven = 1;
    p.driven_motion[0] = params::MfMotion {
        group: 2,
        floating: 1,
        ..Default::default()
    };
    setup.bodies = vec![b];
    setup
}

/// The CPU's and the GPU's body after 150 steps, having checked that they agree.
fn same_path<D: Dim>(label: &str, setup: Setup) -> (MfBody, MfBody) {
    let start = setup.bodies[0];
    let mut g = gpu::<D>(&setup);
    let mut c = CpuSolver::<D>::new(setup);
    // Through the graphs: 2 single steps, then pairs.
    c.advance(150);
    g.advance(150);
    let (bc, bg) = (c.bodies()[0], g.bodies()[0]);
    let by_id = |mut v: Vec<Particle>| {
        v.sort_by_key(|q| q.id);
        v
    };
    let (pc, pg) = (by_id(c.particles()), by_id(g.particles()));
    let mut worst = 0.0f32;
    for (a, b) in pc.iter().zip(&pg).filter(|(a, _)| a.group == 2) {
        for d in 0..D::D {
            worst = worst.max((a.position[d] - b.position[d]).abs());
        }
    }
    let dist = |a: [f64; 3], b: [f64; 3]| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt();
    let moved = dist(bc.centre, start.centre);
    let turned = 2.0 * (bc.orientation[0].clamp(-1.0, 1.0)).acos();
    eprintln!(
        "{label}: after 150 steps (t = {:.4}) the body moved {moved:.3e} and turned {turned:.3} rad; \
         CPU - GPU: centre {:.3e}, velocity {:.3e}, omega {:.3e}, load {:.3e} (of {:.3e}), \
         particles up to {worst:.3e}",
        c.time(),
        dist(bc.centre, bg.centre),
        dist(bc.velocity, bg.velocity),
        dist(bc.omega, bg.omega),
        dist(bc.force, bg.force),
        dist(bc.force, [0.0; 3]),
    );
    assert!(
        moved > 1e-3 && turned > 0.05,
        "the body did not move ({moved}, {turned})"
    );
    // A load of some kind: the fluid's, or a contact's (the heavy sphere lowered onto the
    // floor meets no fluid within these 150 steps: its fluid load is 0 on both backends).
    assert!(
        dist(bc.force, [0.0; 3]) > 0.0 || dist(bc.contact, [0.0; 3]) > 0.0,
        "no load on the body"
    );
    // The contacts' force (zero where the body meets no other object) on both alike.
    assert!(
        dist(bc.contact, bg.contact) <= 1e-2 * dist(bc.contact, [0.0; 3]),
        "contact CPU {:?} GPU {:?}",
        bc.contact,
        bg.contact
    );
    // The fluid's sums differ in float rounding between the backends (the GPU's lanes), and
    // the body integrates them in double: after 150 steps the poses agree far below a
    // particle's size, the load within a percent.
    assert!(dist(bc.centre, bg.centre) < 1e-5, "centres apart");
    assert!(dist(bc.velocity, bg.velocity) < 1e-3 * (1.0 + dist(bc.velocity, [0.0; 3])));
    assert!(dist(bc.omega, bg.omega) < 1e-3 * dist(bc.omega, [0.0; 3]));
    assert!(dist(bc.force, bg.force) <= 1e-2 * dist(bc.force, [0.0; 3]));
    assert!(
        worst < 1e-5,
        "a body particle is {worst} apart on the two backends"
    );
    eprintln!(
        "{label}: contact CPU {:?}, GPU {:?}",
        bc.contact, bg.contact
    );
    (bc, bg)
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_floating_disc_follows_the_same_path_on_both_backends() {
    same_path::<D2>("2D floating disc", floating(2, V_2D_B));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_floating_sphere_follows_the_same_path_on_both_backends() {
    same_path::<D3>("3D floating sphere", floating(3, V_3D_B));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_heavy_disc_on_the_floor_meets_the_same_contact_on_both_backends() {
    let setup = floating_with(2, V_2D_B, 3.0, true);
    let (c, _) = same_path::<D2>("2D heavy disc on the floor", setup);
    assert!(
        c.contact[1] > 0.0,
        "the floor does not push the disc up: {:?}",
        c.contact
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_heavy_sphere_on_the_floor_meets_the_same_contact_on_both_backends() {
    let setup = floating_with(3, V_3D_B, 3.0, true);
    let (c, _) = same_path::<D3>("3D heavy sphere on the floor", setup);
    assert!(
        c.contact[1] > 0.0,
        "the floor does not push the sphere up: {:?}",
        c.contact
    );
}

/// `floating(dim, v)` on mDBC walls (`with_mdbc`), the body's particles facing out of its
/// centre (a disc's, a sphere's normals; d_B from its outermost particle plus dx / 2): the
/// ghost nodes of a body that turns, whose normals turn with its orientation.
fn floating_on_mdbc(dim: usize, v: Variant) -> Setup {
    let mut setup = with_mdbc(floating(dim, v));
    let c = setup.bodies[0].centre.map(|x| x as f32);
    let (first, dx) = (setup.params.wall_first_id, setup.params.dx);
    let arm = |q: &Particle| -> ([f32; 3], f32) {
        let r: [f32; 3] = std::array::from_fn(|a| q.position[a] - c[a]);
        (r, (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt())
    };
    let body = |q: &&Particle| q.group == 2;
    let reach = (setup.particles.iter().filter(body))
        .map(|q| arm(q).1)
        .fold(0.0f32, f32::max);
    for q in setup.particles.iter().filter(body) {
        let (r, len) = arm(q);
        let n = if len > 0.0 {
            r.map(|x| x / len)
        } else {
            [0.0; 3]
        };
        setup.wall_surface[(q.id - first) as usize] = [n[0], n[1], n[2], reach + 0.5 * dx - len];
    }
    setup
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_floating_disc_on_mdbc_walls_follows_the_same_path_on_both_backends() {
    same_path::<D2>("2D floating disc, mDBC", floating_on_mdbc(2, V_2D_B));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_floating_sphere_on_mdbc_walls_follows_the_same_path_on_both_backends() {
    same_path::<D3>("3D floating sphere, mDBC", floating_on_mdbc(3, V_3D_B));
}
