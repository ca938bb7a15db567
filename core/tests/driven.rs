//! Driven groups (`motion` on a wall or a solid; `driven*` in the parameter struct): a piston
//! moves at its prescribed speed and pushes the fluid, other walls stay put; a driven solid
//! with motion zero (a clamp) stays fixed under gravity while a free one falls; a clamp
//! holds the cantilever it is bonded to (`same_body`).

use meshfree_core::backend::cpu_solver;
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::Stepper;

const PISTON: &str = r#"
dimension = 2
name = "piston"

[domain]
min = [-0.2, -0.2]
max = [2.2, 0.7]

[discretisation]
spacing = 0.05

[time]
end = 0.2
output_interval = 0.1

[fluid]
density = 1.0
sound_speed = 20.0
alpha = 0.05

[boundary]
strength = 10.0

[[fluid_blocks]]
min = [0.2, 0.0]
max = [1.0, 0.5]
velocity = [1.0, 0.0]

[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [2.0, 0.5]
open_top = false

[[walls]]
shape = "box"
min = [0.05, 0.0]
max = [0.2, 0.5]
motion = [1.0, 0.0]
"#;

fn by_id(v: Vec<Particle>) -> Vec<Particle> {
    let mut v = v;
    v.sort_by_key(|q| q.id);
    v
}

fn run_to(scene: &Scene, t: f64) -> (Vec<Particle>, Vec<Particle>, f64) {
    let setup = scene.setup().unwrap();
    let start = setup.particles.clone();
    let mut s = cpu_solver(setup);
    Stepper::default()
        .advance_to(s.as_mut(), t)
        .expect("healthy run");
    let t = s.time();
    (start, by_id(s.particles()), t)
}

#[test]
fn piston_moves_at_its_speed_and_pushes_the_fluid() {
    let scene = Scene::from_toml(PISTON, "piston").unwrap();
    let p = scene.params();
    assert_eq!(
        (p.driven, p.driven_group, p.driven_velocity),
        (1, 2, [1.0, 0.0, 0.0])
    );
    let (start, end, t) = run_to(&scene, 0.2);
    let (mut piston, mut fixed) = (0, 0);
    for (a, b) in start.iter().zip(&end) {
        if a.kind != Kind::Boundary {
            continue;
        }
        if a.group == 2 {
            piston += 1;
            // x += u dt every step: exactly u t up to f32 rounding.
            let dx = b.position[0] - a.position[0];
            assert!(
                (dx as f64 - t).abs() < 1e-4,
                "piston moved {dx}, expected {t}"
            );
            assert_eq!(b.position[1], a.position[1]);
            assert_eq!(b.velocity, [1.0, 0.0, 0.0]);
        } else {
            fixed += 1;
            assert_eq!(a.position, b.position, "a fixed wall particle moved");
            assert_eq!(b.velocity, [0.0; 3]);
        }
    }
    assert!(piston > 0 && fixed > 0);
    // The fluid (started at the piston's speed: an impulsive start sends a pressure wave that
    // doubles the free end's speed on reflection) is pushed: its mean x-velocity stays near
    // the piston's, and no fluid particle is behind the piston's face.
    let fluid: Vec<&Particle> = end.iter().filter(|q| q.kind == Kind::Fluid).collect();
    let mean_u = fluid.iter().map(|q| q.velocity[0]).sum::<f32>() / fluid.len() as f32;
    let min_x = fluid.iter().map(|q| q.position[0]).fold(f32::MAX, f32::min);
    eprintln!("t = {t:.3}: mean fluid u = {mean_u:.3}, rearmost fluid x = {min_x:.3}");
    assert!(
        (mean_u - 1.0).abs() < 0.15,
        "mean fluid u {mean_u}, piston 1.0"
    );
    assert!(
        min_x > 0.2 + t as f32 - 0.05,
        "fluid behind the piston face: {min_x}"
    );
}

const CLAMP: &str = r#"
dimension = 2
name = "clamp"
gravity = [0.0, -1.0]

[domain]
min = [0.0, -2.0]
max = [2.0, 1.0]

[discretisation]
spacing = 0.05

[time]
end = 0.2
output_interval = 0.1

[fluid]
density = 1.0
sound_speed = 20.0

[solid]
density = 1.0
sound_speed = 20.0
shear_modulus = 50.0

[[solids]]
shape = "box"
min = [0.2, 0.5]
max = [0.6, 0.7]
motion = [0.0, 0.0]

[[solids]]
shape = "box"
min = [1.2, 0.5]
max = [1.6, 0.7]
"#;

#[test]
fn clamped_solid_stays_while_a_free_one_falls() {
    let scene = Scene::from_toml(CLAMP, "clamp").unwrap();
    let (start, end, t) = run_to(&scene, 0.3);
    let fall = 0.5 * t * t; // g = 1
    for (a, b) in start.iter().zip(&end) {
        if a.group == 0 {
            assert_eq!(a.position, b.position, "a clamped particle moved");
            assert_eq!(b.velocity, [0.0; 3]);
        } else {
            let dy = (a.position[1] - b.position[1]) as f64;
            assert!(
                (dy - fall).abs() < 0.1 * fall,
                "free fall {dy}, expected {fall}"
            );
        }
    }
}

/// A horizontal cantilever, 1 x 0.2 (4 particles thick), its left 0.25 held by a clamp,
/// under gravity 1: E = 9 K G / (3 K + G) = 1.29e4 with K = rho c^2 = 1e4, G = 5e3, so the
/// static tip deflection q L^4 / (8 E I) is 2.9e-3 (Euler-Bernoulli), against a free fall
/// of 0.045 in 0.3.
const CANTILEVER: &str = r#"
dimension = 2
name = "cantilever"
gravity = [0.0, -1.0]

[domain]
min = [-0.5, -1.0]
max = [1.5, 1.0]

[discretisation]
spacing = 0.05

[time]
end = 0.3
output_interval = 0.1

[fluid]
density = 1.0
sound_speed = 20.0

[solid]
density = 1.0
sound_speed = 100.0
shear_modulus = 5000.0

[[solids]]
shape = "box"
min = [-0.25, 0.0]
max = [0.0, 0.2]
motion = [0.0, 0.0]

[[solids]]
shape = "box"
min = [0.0, 0.0]
max = [1.0, 0.2]
"#;

#[test]
fn clamp_holds_the_cantilever_it_is_bonded_to() {
    let scene = Scene::from_toml(CANTILEVER, "cantilever").unwrap();
    let (start, end, t) = run_to(&scene, 0.3);
    let fall = 0.5 * t * t;
    // The tip: the free body's particles in the last column.
    let x_tip = start
        .iter()
        .filter(|q| q.group == 1)
        .map(|q| q.position[0])
        .fold(f32::MIN, f32::max);
    let tip: Vec<f64> = start
        .iter()
        .zip(&end)
        .filter(|(a, _)| a.group == 1 && a.position[0] > x_tip - 1e-4)
        .map(|(a, b)| (a.position[1] - b.position[1]) as f64)
        .collect();
    let sag = tip.iter().sum::<f64>() / tip.len() as f64;
    // A suddenly loaded undamped beam swings to twice its static deflection; the coarse
    // plate (4 particles thick) is softer than Euler-Bernoulli: at most 3 static deflections.
    // Unbonded (the stress crossing the joint only through the pressure) it sagged 0.0137.
    let w_static = 2.9e-3;
    eprintln!("t = {t:.3}: tip sag {sag:.5} (static {w_static}, free fall {fall:.4})");
    assert!(
        sag > 0.0 && sag < 3.0 * w_static,
        "tip sag {sag}, static deflection {w_static}"
    );
    // The clamp takes up the bending: shear stress in its particles at the joint.
    let s_xy = end
        .iter()
        .filter(|q| q.group == 0 && q.position[0] > -0.05)
        .map(|q| q.stress[3].abs())
        .fold(0.0f32, f32::max);
    assert!(s_xy > 0.0, "no stress in the clamp at the joint");
    for (a, b) in start.iter().zip(&end).filter(|(a, _)| a.group == 0) {
        assert_eq!(a.position, b.position, "a clamped particle moved");
    }
}
