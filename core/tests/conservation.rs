//! Physics invariants of the CPU backend on small particle sets: momentum conservation,
//! an elastic body in free fall keeping its shape.
#![allow(clippy::needless_range_loop)]
mod common;

use meshfree_core::backend::cpu_solver;
use meshfree_core::physics::particle::Kind;
use meshfree_core::solver::{Setup, Solver};

fn momentum(s: &mut dyn Solver) -> [f64; 3] {
    s.diagnostics().momentum
}

#[test]
fn momentum_is_conserved_without_walls_or_gravity() {
    for dim in [2usize, 3] {
        let lo = [0.0; 3];
        let hi = if dim == 2 {
            [1.0, 1.0, 0.0]
        } else {
            [0.5, 0.5, 0.5]
        };
        let mut p = common::params(dim as i32, 0.05, lo, hi, [1, 1, 1]);
        p.viscosity = 1e-3;
        p.xsph = 0.3;
        p.artificial_stress = 0.3;
        meshfree_core::physics::params::derive(&mut p);
        let pts = common::lattice(dim, p.dx, lo, hi);
        let mut ps = Vec::new();
        let centre = [0.25; 3];
        let (fluid, solid): (Vec<_>, Vec<_>) = pts.into_iter().partition(|x| {
            (0..dim)
                .map(|a| (x[a] - centre[a]).powi(2))
                .sum::<f32>()
                .sqrt()
                > 0.15
        });
        common::add(&mut ps, &fluid, Kind::Fluid, 0, p.rho0, &p);
        common::add(&mut ps, &solid, Kind::Solid, 1, p.solid_rho0, &p);
        let mut seed = 11u64;
        for q in &mut ps {
            for a in 0..dim {
                q.velocity[a] = common::rand01(&mut seed) - 0.5;
            }
        }
        let mut s = cpu_solver(Setup {
            params: p,
            particles: ps.clone(),
            wall_surface: Vec::new(),
            bodies: Vec::new(),
            motion_series: Vec::new(),
        });
        assert!(s.has_solids());
        let before = momentum(s.as_mut());
        let scale: f64 = ps.iter().map(|q| q.mass as f64 * q.speed() as f64).sum();
        for _ in 0..60 {
            s.step();
        }
        s.check().expect("healthy run");
        let after = momentum(s.as_mut());
        for a in 0..dim {
            let err = (after[a] - before[a]).abs() / scale;
            assert!(
                err < 1e-5,
                "{dim}D axis {a}: momentum {} -> {} (relative change {err:e}, tolerance 1e-5)",
                before[a],
                after[a]
            );
        }
        // The flow did something: forces are not all zero.
        assert!(s.diagnostics().kinetic_energy > 0.0);
    }
}

/// Radius of gyration and centroid of the particles of `group`.
fn gyration(ps: &[meshfree_core::physics::particle::Particle]) -> ([f64; 3], f64) {
    let n = ps.len() as f64;
    let mut c = [0.0f64; 3];
    for q in ps {
        for a in 0..3 {
            c[a] += q.position[a] as f64 / n;
        }
    }
    let rg = (ps
        .iter()
        .map(|q| {
            (0..3)
                .map(|a| (q.position[a] as f64 - c[a]).powi(2))
                .sum::<f64>()
        })
        .sum::<f64>()
        / n)
        .sqrt();
    (c, rg)
}

#[test]
fn spinning_elastic_disc_in_free_fall_keeps_its_shape() {
    let lo = [0.0; 3];
    let hi = [2.0, 2.0, 0.0];
    let mut p = common::params(2, 0.02, lo, hi, [0; 3]);
    p.gravity = [0.0, -9.81, 0.0];
    p.solid_rho0 = 1000.0;
    p.solid_c0 = 30.0;
    p.shear_modulus = 2.0e5;
    p.alpha = 0.1;
    meshfree_core::physics::params::derive(&mut p);
    let centre = [1.0, 1.6];
    let radius = 0.2;
    let omega = 5.0; // rad/T
    let disc: Vec<[f32; 3]> = common::lattice(2, p.dx, [0.8, 1.4, 0.0], [1.2, 1.8, 0.0])
        .into_iter()
        .filter(|x| ((x[0] - centre[0]).powi(2) + (x[1] - centre[1]).powi(2)).sqrt() < radius)
        .collect();
    let mut ps = Vec::new();
    common::add(&mut ps, &disc, Kind::Solid, 0, p.solid_rho0, &p);
    for q in &mut ps {
        q.velocity = [
            -omega * (q.position[1] - centre[1]),
            omega * (q.position[0] - centre[0]),
            0.0,
        ];
    }
    let (c0, rg0) = gyration(&ps);
    let mut s = cpu_solver(Setup {
        params: p,
        particles: ps,
        wall_surface: Vec::new(),
        bodies: Vec::new(),
        motion_series: Vec::new(),
    });
    while s.time() < 0.3 {
        s.step();
        if s.steps().is_multiple_of(200) {
            let d = s.diagnostics();
            eprintln!(
                "step {} t {} dt {} vmax {}",
                d.step, d.time, d.dt, d.max_speed
            );
        }
        assert!(s.steps() < 20_000, "too many steps");
    }
    s.check().expect("healthy run");
    let t = s.time();
    let out = s.particles();
    let (c1, rg1) = gyration(&out);
    let fall = c0[1] - c1[1];
    let expect = 0.5 * 9.81 * t * t;
    assert!(
        (fall - expect).abs() < 0.01 * expect,
        "centroid fell {fall}, free fall gives {expect}"
    );
    assert!(
        (c1[0] - c0[0]).abs() < 1e-3,
        "centroid drifted sideways by {}",
        c1[0] - c0[0]
    );
    assert!(
        (rg1 / rg0 - 1.0).abs() < 0.02,
        "radius of gyration {rg0} -> {rg1}: more than 2% change"
    );
    // Still spinning: angular momentum about the centroid kept within 5%.
    let l: f64 = out
        .iter()
        .map(|q| {
            let (x, y) = (q.position[0] as f64 - c1[0], q.position[1] as f64 - c1[1]);
            q.mass as f64 * (x * q.velocity[1] as f64 - y * (q.velocity[0] as f64))
        })
        .sum();
    let l0 = omega as f64 * rg0 * rg0 * out.iter().map(|q| q.mass as f64).sum::<f64>();
    assert!((l / l0 - 1.0).abs() < 0.05, "angular momentum {l0} -> {l}");
}
