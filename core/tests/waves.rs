//! Wave makers and the damping zone (issue #57): a piston paddle moves with the stroke of
//! Biesel's transfer function; the damping zone relaxes the fluid's velocity at its rate
//! where it is at full strength and leaves the fluid before it alone.

use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::format::Paddle;
use meshfree_core::scene::wave::{height_per_stroke, wave_number};
use meshfree_core::scene::Scene;

mod common;
use common::run_scene_to as run_to;

const CHANNEL: &str = r#"
dimension = 2
name = "sponge"

[domain]
min = [0.0, 0.0]
max = [2.0, 0.5]
periodic = [true, true]

[discretisation]
spacing = 0.05

[time]
end = 0.05
output_interval = 0.05
integrator = "symplectic-euler"

[fluid]
density = 1000.0
sound_speed = 2.0
alpha = 0.0

[[fluid_blocks]]
min = [0.0, 0.0]
max = [2.0, 0.5]
velocity = [0.1, 0.0]

[damping_zone]
axis = "x"
start = 1.0
end = 1.2
strength = 20.0
"#;

#[test]
fn the_damping_zone_relaxes_the_velocity_at_its_rate() {
    let scene = Scene::from_toml(CHANNEL, "sponge").unwrap();
    let (_, end, t) = run_to(&scene, 0.05);
    let mean = |lo: f32, hi: f32| {
        let v: Vec<f32> = (end.iter())
            .filter(|p| p.kind == Kind::Fluid && p.position[0] > lo && p.position[0] < hi)
            .map(|p| p.velocity[0])
            .collect();
        assert!(v.len() > 10);
        v.iter().sum::<f32>() / v.len() as f32
    };
    // Full strength (beyond `end`, away from the zone's edges by more than c t = 0.1):
    // v0 exp(-strength t), the product of each kick's factor (the symplectic Euler's
    // velocities are at the step's end; the leapfrog's half a step earlier).
    let want = 0.1 * (-20.0 * t).exp() as f32;
    let deep = mean(1.35, 1.85);
    assert!(
        (deep - want).abs() < 0.01 * want,
        "in the zone {deep}, want {want} (t {t})"
    );
    // Before the zone, out of the sound's reach: untouched.
    let before = mean(0.3, 0.7);
    assert!((before - 0.1).abs() < 1e-4, "before the zone {before}");
}

#[test]
fn a_piston_paddle_moves_with_biesels_stroke() {
    let scene = Scene::builtin("flume-2d").unwrap();
    let p = scene.params();
    assert_eq!(p.driven, 1);
    let m = p.driven_motion[0];
    // T = 1.2, d = 0.3: kd = 1.0647, H / S = 1.0405 (the module's equations evaluated
    // apart, in Python's double precision).
    let k = wave_number(9.81, 1.2, 0.3);
    let r = height_per_stroke(Paddle::Piston, k * 0.3);
    assert!(
        (k * 0.3 - 1.0647).abs() < 1e-4 && (r - 1.0405).abs() < 1e-4,
        "kd {}, H/S {r}",
        k * 0.3
    );
    assert!(
        (m.amplitude[0] as f64 - 0.5 * 0.05 / r).abs() < 1e-6,
        "{:?}",
        m.amplitude
    );
    assert_eq!((m.period, m.ramp, m.rate, m.angle), (1.2, 2.4, 0.0, 0.0));
    assert_eq!(
        (p.damping, p.damping_axis, p.damping_start, p.damping_end),
        (1, 0, 4.0, 6.0)
    );
}
