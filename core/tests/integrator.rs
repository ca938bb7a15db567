//! The order in dt of the integrators (CPU): a collapsing water column stepped to one time
//! with fixed steps dt, dt/2, dt/4; the differences between successive runs shrink by 2^k
//! for an integrator of order k. The leapfrog (velocities at half steps, rates at the
//! drift's midpoint) must be second order; the symplectic Euler, which takes the density
//! rate at the drift's start, is first order, and shows that the measure tells them apart.

use meshfree_core::backend::cpu_solver;
use meshfree_core::scene::Scene;

/// [T] the compared time: the column has slumped and the surge runs along the floor.
const T: f64 = 0.1;

/// A 0.8 x 0.8 column in a 2.4 x 1.6 box (no gate: it collapses from t = 0), dx = 0.08,
/// with the scenes' usual scheme: continuity density, dynamic walls, XSPH, artificial
/// viscosity.
fn scene(integrator: &str, steps: u32) -> String {
    format!(
        r#"
dimension = 2
name = "column"
gravity = [0.0, -9.81]
[domain]
min = [-0.4, -0.4]
max = [2.8, 2.0]
[discretisation]
spacing = 0.08
h_factor = 1.3
kernel = "cubic-spline"
[time]
end = {T}
output_interval = {T}
dt = {dt}
integrator = "{integrator}"
[fluid]
density = 1000.0
sound_speed = 40.0
density_form = "continuity"
alpha = 0.02
xsph = 0.5
[boundary]
strength = 981.0
attractive = false
wall_coupling = "dynamic"
wall_density_floor = true
[[fluid_blocks]]
min = [0.0, 0.0]
max = [0.8, 0.8]
hydrostatic = true
[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [2.4, 1.6]
layers = 3
"#,
        dt = T / steps as f64
    )
}

/// Fluid positions by id at t = T after `steps` fixed steps.
fn positions(integrator: &str, steps: u32) -> Vec<[f32; 3]> {
    let scene = Scene::from_toml(&scene(integrator, steps), "column").expect("scene");
    let mut s = cpu_solver(scene.setup().expect("set-up"));
    for _ in 0..steps {
        s.step();
    }
    assert!((s.time() - T).abs() < 1e-6 * T, "t = {}", s.time());
    s.check().expect("a healthy run");
    s.particles()
        .iter()
        .filter(|q| q.kind == meshfree_core::physics::particle::Kind::Fluid)
        .map(|q| q.position)
        .collect()
}

/// The rms distance between two runs' particles [L].
fn rms(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    let s: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| {
            (0..2)
                .map(|k| (x[k] as f64 - y[k] as f64).powi(2))
                .sum::<f64>()
        })
        .sum();
    (s / a.len() as f64).sqrt()
}

/// d(N, 2N) / d(2N, 4N) for N = 50 (Courant ~ 0.5 down to 0.13 over the three runs).
fn convergence_ratio(integrator: &str) -> f64 {
    let x: Vec<_> = [50, 100, 200]
        .iter()
        .map(|&n| positions(integrator, n))
        .collect();
    let (d1, d2) = (rms(&x[0], &x[1]), rms(&x[1], &x[2]));
    eprintln!(
        "{integrator}: d(50, 100) = {d1:.3e}, d(100, 200) = {d2:.3e} [L], ratio {:.2}",
        d1 / d2
    );
    d1 / d2
}

#[test]
fn leapfrog_is_second_order_and_the_symplectic_euler_first() {
    let leapfrog = convergence_ratio("leapfrog");
    let symplectic = convergence_ratio("symplectic-euler");
    assert!(
        leapfrog > 3.0,
        "leapfrog: the step's error falls {leapfrog:.2}x when dt halves (second order: 4)"
    );
    assert!(
        symplectic < 2.8,
        "symplectic Euler: {symplectic:.2}x (first order: 2); the measure does not tell the orders apart"
    );
}
