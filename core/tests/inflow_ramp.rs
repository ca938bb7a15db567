//! The inflow band's ramped start (`[inflow] ramp`, `inflow_ramp`; CPU; the GPU's twin in
//! `cuda_parity/`): the generator starts the fluid at rest, the band's velocity and a
//! uniform acceleration of everything else bring the whole channel to the inflow velocity
//! along r(t) = (1 - cos(pi t / T_r)) / 2 without a pressure gradient, and the scene check
//! rejects the ramp where the kick does not come first.

use meshfree_core::backend::cpu_solver;
use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::Scene;

/// [T] the ramp; [T] the fixed step; [L/T] the inflow velocity.
const T_R: f64 = 0.05;
const DT: f64 = 5e-4;
const U: [f64; 2] = [1.0, 0.25];

/// A periodic 1 x 0.5 channel of fluid at rest in a lattice (so no pressure and no force:
/// whatever the fluid's velocity is, the ramp gave it), the band x in [0, 0.2).
fn channel(integrator: &str, ramp: f64) -> String {
    format!(
        r#"
dimension = 2
name = "ramp"
[domain]
min = [0.0, 0.0]
max = [1.0, 0.5]
periodic = [true, true]
[discretisation]
spacing = 0.05
[time]
end = 1.0
output_interval = 1.0
dt = {DT}
integrator = "{integrator}"
[fluid]
density = 1.0
sound_speed = 20.0
density_form = "summation"
viscosity = 0.01
[[fluid_blocks]]
min = [0.0, 0.0]
max = [1.0, 0.5]
velocity = [{u}, {v}]
[inflow]
axis = "x"
min = 0.0
max = 0.2
velocity = [{u}, {v}]
ramp = {ramp}
"#,
        u = U[0],
        v = U[1]
    )
}

fn share(t: f64) -> f64 {
    if t >= T_R {
        1.0
    } else {
        0.5 * (1.0 - (std::f64::consts::PI * t / T_R).cos())
    }
}

/// The largest |v - expected(t) U| over the fluid after `steps` steps, relative to |U|.
fn deviation(integrator: &str, steps: u32, expected: impl Fn(f64) -> f64) -> f64 {
    let scene = Scene::from_toml(&channel(integrator, T_R), "ramp").expect("scene");
    let setup = scene.setup().expect("set-up");
    assert!(
        setup
            .particles
            .iter()
            .all(|q| q.kind != Kind::Fluid || q.velocity == [0.0; 3]),
        "a ramped start begins at rest"
    );
    let mut s = cpu_solver(setup);
    for _ in 0..steps {
        s.step();
    }
    let r = expected(s.time());
    let norm = U[0].hypot(U[1]);
    s.particles()
        .iter()
        .filter(|q| q.kind == Kind::Fluid)
        .map(|q| {
            let dv = [
                q.velocity[0] as f64 - r * U[0],
                q.velocity[1] as f64 - r * U[1],
            ];
            dv[0].hypot(dv[1]) / norm
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_ramped_start_brings_the_whole_channel_up_together() {
    // Mid-ramp (t = 0.4 T_r and 0.8 T_r) and after it: every fluid particle, in the band and
    // out of it, at r(t) U (the symplectic Euler's velocity lives at the step's end).
    for steps in [40, 80, 140] {
        let e = deviation("symplectic-euler", steps, share);
        assert!(e < 1e-4, "{steps} steps: |v - r U| / |U| = {e:.2e}");
    }
    // The leapfrog's velocities live half a step back: r(t - dt / 2).
    for steps in [40, 140] {
        let e = deviation("leapfrog", steps, |t| share(t - 0.5 * DT));
        assert!(
            e < 1e-4,
            "leapfrog, {steps} steps: |v - r U| / |U| = {e:.2e}"
        );
    }
    // And the measure tells: mid-ramp the velocity is not the full U.
    let e = deviation("symplectic-euler", 40, |_| 1.0);
    assert!(e > 0.3, "mid-ramp at U already: {e:.2e}");
}

#[test]
fn the_ramp_needs_a_kick_first_and_a_time_not_below_zero() {
    let err = Scene::from_toml(&channel("euler", T_R), "ramp")
        .expect_err("the forward Euler with a ramp")
        .to_string();
    assert!(err.contains("inflow.ramp"), "{err}");
    let err = Scene::from_toml(&channel("symplectic-euler", -1.0), "ramp")
        .expect_err("a negative ramp")
        .to_string();
    assert!(err.contains("inflow.ramp"), "{err}");
    // Without a ramp the fluid starts at the block's velocity, as before.
    let scene = Scene::from_toml(&channel("euler", 0.0), "ramp").expect("no ramp");
    let setup = scene.setup().expect("set-up");
    assert!(setup
        .particles
        .iter()
        .filter(|q| q.kind == Kind::Fluid)
        .all(|q| q.velocity == [U[0] as f32, U[1] as f32, 0.0]));
}
