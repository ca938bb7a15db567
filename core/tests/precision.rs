//! The density of a stiff solid as a departure from rest (`SolidState::rho_dev`): a step's
//! change dt d rho/dt of an aluminium-like solid is far below f32's resolution of rho
//! itself (the ulp of 2700 is 2.4e-4), so rho += dt d rho/dt rounds it away and the
//! volumetric stiffness is lost; the departure rho - rho0_s keeps it.
mod common;

use meshfree_core::backend::cpu::{pressure, CpuSolver};
use meshfree_core::physics::dim::D2;
use meshfree_core::physics::params::{self, MF_KIND_SOLID};
use meshfree_core::physics::particle::Kind;
use meshfree_core::solver::{Setup, Solver};

/// A periodic block of aluminium-like solid (rho0_s = 2700, c_s = 5000 m/s) in uniform slow
/// compression v = -k x (k = 1e-3 / s): d rho/dt = rho div v... = 2 k rho = 5.4 [M L^-2 T^-1]
/// in 2D, and dt ~ 5e-7 s, so each step adds ~3e-6 to a density of 2700.
fn compressed_block() -> Setup {
    let (dx, n) = (0.01f32, 16);
    let hi = [n as f32 * dx, n as f32 * dx, 0.0];
    let mut p = common::params(2, dx, [0.0; 3], hi, [0, 0, 0]);
    p.solid_rho0 = 2700.0;
    p.solid_c0 = 5000.0;
    p.shear_modulus = 2.6e10;
    p.gravity = [0.0; 3];
    params::derive(&mut p);
    let mut particles = Vec::new();
    let pts = common::lattice(2, dx, [0.0; 3], hi);
    common::add(&mut particles, &pts, Kind::Solid, 1, p.solid_rho0, &p);
    let (k, c) = (1e-3f32, 0.5 * hi[0]);
    for q in particles.iter_mut() {
        q.velocity = [-k * (q.position[0] - c), -k * (q.position[1] - c), 0.0];
    }
    Setup {
        params: p,
        particles,
        wall_surface: Vec::new(),
        bodies: Vec::new(),
        motion_series: Vec::new(),
    }
}

/// Over many tiny steps the departure rho_dev equals the exact (f64) sum of dt d rho/dt
/// within f32's relative precision of the departure, and the pressure is c_s^2 rho_dev;
/// rho itself (what the drift integrated before) stays at rho0_s.
#[test]
fn a_stiff_solids_density_departure_sums_steps_below_rhos_resolution() {
    let setup = compressed_block();
    let p = setup.params;
    let mut c = CpuSolver::<D2>::new(setup);
    c.build_grid();
    let n = c.len();
    let mut exact = vec![0.0f64; n];
    let steps = 2000;
    for _ in 0..steps {
        c.density_gradient();
        c.rates();
        c.time_step();
        let s = c.state();
        let dt = c.dt();
        let drho = s.drho.as_ref().expect("continuity density");
        for i in 0..n {
            exact[i] += (dt * drho[i]) as f64;
        }
        c.drift();
    }
    let s = c.state();
    let dev = &s.solid.as_ref().expect("solid arrays").rho_dev;
    let (mut worst, mut max_dev) = (0.0f64, 0.0f64);
    for i in 0..n {
        let e = exact[i];
        assert!(e > 0.0, "slot {i}: the block is compressed, d rho/dt > 0");
        worst = worst.max((dev[i] as f64 - e).abs() / e);
        max_dev = max_dev.max(e);
        // rho is rho0_s + rho_dev, rounded to f32's resolution of rho.
        assert_eq!(s.rho[i], p.solid_rho0 + dev[i]);
    }
    eprintln!(
        "{steps} steps: rho_dev up to {max_dev:e} (ulp of rho0_s {:e}); worst relative \
         error against the exact sum {worst:e}",
        f32::EPSILON * p.solid_rho0
    );
    // Each step's change is below half an ulp of rho: rho += dt d rho/dt kept nothing.
    assert!(
        max_dev / (steps as f64) < 0.5 * (f32::EPSILON * p.solid_rho0) as f64,
        "the test must take steps that round away in rho"
    );
    // f32 accumulation of `steps` terms: a few ulp of the departure per hundred steps.
    assert!(worst < 1e-4, "rho_dev off the exact sum by {worst:e}");
    // The pressure the next density pass takes: P = c_s^2 (rho - rho0_s) from rho_dev.
    c.density();
    let s = c.state();
    let dev = &s.solid.as_ref().unwrap().rho_dev;
    for (i, (&pr, (&rho, &d))) in s.p.iter().zip(s.rho.iter().zip(dev)).enumerate() {
        assert_eq!(pr, pressure(&p, MF_KIND_SOLID as u8, rho, d), "slot {i}");
        let want = p.solid_c0 * p.solid_c0 * d;
        assert!(pr > 0.0 && (pr - want).abs() <= 1e-6 * want);
    }
}
