//! Probes and gauges on the CPU backend (`Readback::sample_points`, `probe::surface`): the
//! built-in still tanks, whose hydrostatic start has p = rho0 g d at depth d below the
//! block's top (`scene/generate.rs`), and whose free surface is that top.

use meshfree_core::backend::cpu::{pressure, CpuSolver};
use meshfree_core::measure::probe::{line_points, surface};
use meshfree_core::physics::dim::{Dim, D2, D3};
use meshfree_core::physics::kernel;
use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::Scene;
use meshfree_core::solver::Readback;
use meshfree_core::solver::{PointSample, Solver};

/// [L/T^2] the tanks' gravity; [M L^-d] their fluid's rest density.
const G: f64 = 9.81;
const RHO0: f64 = 1000.0;

/// Samples at `points`.
fn sample(s: &mut dyn Solver, points: &[[f32; 3]], walls: bool) -> Vec<PointSample> {
    let mut out = Vec::new();
    s.sample_points(points, walls, &mut out);
    assert_eq!(out.len(), points.len());
    out
}

/// The probe pressure at depths 1/4, 1/2, 3/4 of `h` below the surface `top` on the
/// tank's centre line `centre` (the vertical axis is 1): within 1 % of rho0 g d.
fn hydrostatic_pressure(s: &mut dyn Solver, centre: [f32; 3], top: f64, h: f64, what: &str) {
    let depths = [0.25 * h, 0.5 * h, 0.75 * h];
    let points: Vec<[f32; 3]> = depths
        .iter()
        .map(|d| {
            let mut x = centre;
            x[1] = (top - d) as f32;
            x
        })
        .collect();
    for walls in [false, true] {
        for (d, q) in depths.iter().zip(sample(s, &points, walls)) {
            let want = RHO0 * G * d;
            let err = (q.pressure as f64 - want) / want;
            eprintln!(
                "{what} (walls {walls}): depth {d}: pressure {} vs rho0 g d = {want:.2} \
                 ({:+.3} %), density {}, |v| {:.2e}, colour {}, {} neighbours",
                q.pressure,
                100.0 * err,
                q.density,
                q.velocity.iter().map(|v| v * v).sum::<f32>().sqrt(),
                q.colour,
                q.neighbours
            );
            assert!(err.abs() < 0.01, "{what}: depth {d}: {err:+e} off");
            // Deep inside, the fluid fills the support: Shepard's sum is the colour.
            assert!((q.colour - 1.0).abs() < 0.02, "colour {}", q.colour);
        }
    }
}

/// A vertical gauge on `centre` from the floor to `y_end`: the surface within dx / 2 of `top`.
fn gauge_height(s: &mut dyn Solver, centre: [f32; 3], y_end: f64, top: f64, dx: f64, what: &str) {
    let mut a = centre.map(|c| c as f64);
    let mut b = a;
    a[1] = 0.0;
    b[1] = y_end;
    let line = line_points(&a, &b, 0.5 * dx, 3);
    let pts: Vec<[f32; 3]> = line.iter().map(|x| x.map(|c| c as f32)).collect();
    let colour: Vec<f32> = sample(s, &pts, false).iter().map(|q| q.colour).collect();
    let found = surface(&line, &colour).expect("a wet gauge");
    let err = found.position[1] - top;
    eprintln!(
        "{what}: surface at y = {:.5} (expected {top}, {:+.3} dx), distance {:.5}",
        found.position[1],
        err / dx,
        found.distance
    );
    assert!(err.abs() <= 0.5 * dx, "{what}: the gauge is {err} off");
}

fn tank<D: Dim>(name: &str) -> (CpuSolver<D>, Scene) {
    let scene = Scene::builtin(name).unwrap();
    (CpuSolver::<D>::new(scene.setup().unwrap()), scene)
}

/// The Shepard interpolation of `PointSample` at `x` from every particle (no grid), in f64:
/// the reference for the grid's sums after the particles moved.
fn brute_force(s: &mut dyn Solver, x: [f32; 3], walls: bool) -> (f64, f64) {
    let p = *s.params();
    let (mut w, mut pw) = (0.0f64, 0.0f64);
    for q in s.particles() {
        let wall = q.kind == Kind::Boundary;
        if !(q.kind == Kind::Fluid || (walls && wall)) {
            continue;
        }
        let r = (0..3)
            .map(|a| (x[a] - q.position[a]).powi(2))
            .sum::<f32>()
            .sqrt();
        if r * r >= p.support2 {
            continue;
        }
        let wv = kernel::w(&p, r) as f64 * (q.mass / q.density) as f64;
        w += wv;
        pw += pressure(&p, q.kind.code(), q.density, q.density - p.solid_rho0) as f64 * wv;
    }
    (pw / w, w)
}

/// tank-2d: water 1 deep, dx = 0.025; at its hydrostatic start and after 300 steps
/// (t = 0.043: half the period 4 H / c0 of the column's quarter-wave acoustic mode).
/// Stepped, the column oscillates about a pressure up to 1 % below the start's (the
/// solver's discrete balance, not the probe's: the probes follow the particles); there the
/// probe must equal the interpolation from all particles, and the gauge stay at the top.
#[test]
fn tank_2d_probes_and_gauge() {
    let (mut s, scene) = tank::<D2>("tank-2d");
    let dx = scene.file.discretisation.spacing;
    let c = [0.5, 0.0, 0.0];
    hydrostatic_pressure(&mut s, c, 1.0, 1.0, "tank-2d at t = 0");
    gauge_height(&mut s, c, 1.2, 1.0, dx, "tank-2d at t = 0");
    s.advance(300);
    let what = format!("tank-2d at t = {:.4}", s.time());
    gauge_height(&mut s, c, 1.2, 1.0, dx, &what);
    // Points near the floor and a side wall too, where the walls' pressure enters.
    let pts = [
        [0.5f32, 0.75, 0.0],
        [0.5, 0.5, 0.0],
        [0.5, 0.25, 0.0],
        [0.02, 0.02, 0.0],
    ];
    for walls in [false, true] {
        for (x, q) in pts.iter().zip(sample(&mut s, &pts, walls)) {
            let (want, weight) = brute_force(&mut s, *x, walls);
            let d = 1.0 - x[1] as f64;
            eprintln!(
                "{what} (walls {walls}): at {x:?}: pressure {} (all particles: {want:.3}; \
                 rho0 g d = {:.1}, {:+.3} %)",
                q.pressure,
                RHO0 * G * d,
                100.0 * (q.pressure as f64 / (RHO0 * G * d) - 1.0)
            );
            assert!(((q.pressure as f64 - want) / want).abs() < 1e-5);
            assert!((q.colour as f64 - weight).abs() < 1e-5 || walls);
            assert!((q.pressure as f64 / (RHO0 * G * d) - 1.0).abs() < 0.03);
        }
    }
    // Above the surface, beyond the support: no particle, NaN fields and no colour.
    let dry = sample(&mut s, &[[0.5, 1.15, 0.0]], false)[0];
    assert!(dry.pressure.is_nan() && dry.density.is_nan() && dry.velocity[0].is_nan());
    assert_eq!((dry.colour, dry.neighbours), (0.0, 0));
}

/// tank-3d: water 0.5 deep, dx = 0.025, at its hydrostatic start.
#[test]
fn tank_3d_probes_and_gauge() {
    let (mut s, scene) = tank::<D3>("tank-3d");
    let dx = scene.file.discretisation.spacing;
    let c = [0.25, 0.0, 0.25];
    hydrostatic_pressure(&mut s, c, 0.5, 0.5, "tank-3d at t = 0");
    gauge_height(&mut s, c, 0.6, 0.5, dx, "tank-3d at t = 0");
}

/// Sampling rebuilds the grid where the particles moved, and changes nothing of the
/// stepping: the same states, bit for bit, with and without samples between the steps.
#[test]
fn sampling_leaves_the_stepping_unchanged() {
    let (mut a, _) = tank::<D2>("tank-2d");
    let (mut b, _) = tank::<D2>("tank-2d");
    let pts = [[0.5f32, 0.5, 0.0], [0.2, 0.9, 0.0], [0.01, 0.01, 0.0]];
    for k in 0..20 {
        a.step();
        b.step();
        if k % 3 == 0 {
            sample(&mut b, &pts, k % 2 == 0);
        }
    }
    let (pa, pb) = (a.particles(), b.particles());
    assert_eq!(pa, pb);
    assert_eq!(a.time(), b.time());
}
