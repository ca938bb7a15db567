//! `[solid] wall_contact`: a body and the walls meet (default), or skip each other, both
//! ways (`wall_contact`, `meets` in src/physics/pairs.rs).

use meshfree_core::backend::{self, BackendChoice};
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::Stepper;

/// A 10 x 4 elastic block standing on the floor of a dynamic-wall tank (no fluid, no
/// gravity) and moving into it at 0.5 m/s; the state after 0.01 s (half a spacing).
fn block_into_floor(contact: bool) -> Vec<Particle> {
    let text = format!(
        r#"dimension = 2
name = "block-on-floor"

[domain]
min = [-0.05, -0.05]
max = [0.55, 0.35]

[discretisation]
spacing = 0.01

[time]
end = 0.01
output_interval = 0.01

[fluid]
density = 1000.0
sound_speed = 20.0

[solid]
density = 1100.0
sound_speed = 60.0
shear_modulus = 1e6
wall_contact = {contact}

[boundary]
strength = 10.0

[[solids]]
shape = "box"
min = [0.2, 0.0]
max = [0.3, 0.04]
velocity = [0.0, -0.5]

[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [0.5, 0.3]
"#
    );
    let scene = Scene::from_toml(&text, "test:block-on-floor").unwrap();
    let mut s = backend::create(
        BackendChoice::Cpu,
        backend::Layout::One,
        scene.setup().unwrap(),
    )
    .unwrap();
    (Stepper::new(scene.gates()))
        .advance_to(s.as_mut(), 0.01)
        .unwrap();
    s.particles()
}

#[test]
fn a_body_without_wall_contact_passes_the_floor_untouched() {
    let ps = block_into_floor(false);
    let (solid, wall): (Vec<&Particle>, Vec<&Particle>) = (ps.iter())
        .filter(|q| q.kind != Kind::Fluid)
        .partition(|q| q.kind == Kind::Solid);
    assert_eq!(solid.len(), 40);
    // No force from the floor: the block keeps its uniform velocity, so no strain, no
    // density change, no stress.
    for q in &solid {
        assert!(
            q.velocity[0].abs() < 1e-6 && (q.velocity[1] + 0.5).abs() < 1e-6,
            "{q:?}"
        );
        assert!((q.density - 1100.0).abs() < 1e-3, "{q:?}");
        assert!(q.stress.iter().all(|s| s.abs() < 1e-3), "{q:?}");
    }
    // And the floor feels nothing of the block: its density stays at rest.
    assert!(wall
        .iter()
        .all(|q| q.density == 1000.0 && q.pressure == 0.0));
    // It moved half a spacing into the floor's first row.
    let y_min = solid.iter().map(|q| q.position[1]).fold(f32::MAX, f32::min);
    assert!((y_min - 0.0).abs() < 2e-4, "{y_min}");
}

#[test]
fn a_body_with_wall_contact_is_stopped_by_the_floor() {
    let ps = block_into_floor(true);
    let solid: Vec<&Particle> = ps.iter().filter(|q| q.kind == Kind::Solid).collect();
    let wall_change = (ps.iter())
        .filter(|q| q.kind == Kind::Boundary)
        .map(|q| (q.density - 1000.0).abs())
        .fold(0.0f32, f32::max);
    // The floor's particles under the block see it (their continuity sums over the block:
    // compressed, then stretched as it bounces off), and their pressure and the
    // Lennard-Jones force stop the bottom row and throw it back.
    assert!(wall_change > 1.0, "{wall_change}");
    let bottom_vy = (solid.iter())
        .filter(|q| q.position[1] < 0.01)
        .map(|q| q.velocity[1])
        .fold(f32::MAX, f32::min);
    assert!(bottom_vy > -0.4, "bottom row down to vy {bottom_vy}");
    let y_min = solid.iter().map(|q| q.position[1]).fold(f32::MAX, f32::min);
    assert!(y_min > 0.002, "{y_min}");
}
