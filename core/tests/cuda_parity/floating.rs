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
    let mut setup = leapfrog(scene(dim, v));
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
    // The body's particles as its solid, each dx^d at density 0.6: mass and inertia.
    let mut inertia = [0.0f64; 9];
    let m_each = 0.6 * (dx as f64).powi(dim as i32);
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

fn same_path<D: Dim>(label: &str, setup: Setup) {
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
    assert!(dist(bc.force, [0.0; 3]) > 0.0, "no load on the body");
    // The fluid's sums differ in float rounding between the backends (the GPU's lanes), and
    // the body integrates them in double: after 150 steps the poses agree far below a
    // particle's size, the load within a percent.
    assert!(dist(bc.centre, bg.centre) < 1e-5, "centres apart");
    assert!(dist(bc.velocity, bg.velocity) < 1e-3 * (1.0 + dist(bc.velocity, [0.0; 3])));
    assert!(dist(bc.omega, bg.omega) < 1e-3 * dist(bc.omega, [0.0; 3]));
    assert!(dist(bc.force, bg.force) < 1e-2 * dist(bc.force, [0.0; 3]));
    assert!(
        worst < 1e-5,
        "a body particle is {worst} apart on the two backends"
    );
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
