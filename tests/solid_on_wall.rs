//! An elastic block standing on a dynamic wall and lifted off it at a uniform speed (a rigid
//! translation): its density must not change. A solid's continuity density once summed over
//! its wall neighbours too, so a row leaving the floor read as a dilatation of the body:
//! the elastic gate's row on the floor (issue #6, docs/accuracy.md) lost 1.4 % of its
//! density rising 0.1 dx, -2.7e5 Pa, and the run blew up at 4 particles across. With that
//! sum this block's bottom row was held down by its own spurious tension: it ended at
//! y = 4.54 mm, below its start at 5 mm, while the block rose 1 mm.

use meshfree::backend::cpu_solver;
use meshfree::particle::Kind;
use meshfree::run::{self, Gates};
use meshfree::scene::Scene;

/// A 10 x 4 block at dx = 0.01 on the floor of a tank, moving up at `lift` [m/s], no gravity.
fn scene(lift: f64) -> Scene {
    let text = format!(
        r#"dimension = 2
name = "solid-on-wall"
[domain]
min = [-0.05, -0.05]
max = [0.35, 0.3]
[discretisation]
spacing = 0.01
[time]
end = 0.02
output_interval = 0.02
[fluid]
density = 1000.0
sound_speed = 20.0
[solid]
density = 1000.0
sound_speed = 50.0
shear_modulus = 1e5
[boundary]
strength = 10.0
wall_coupling = "dynamic"
[[solids]]
shape = "box"
min = [0.1, 0.0]
max = [0.2, 0.04]
velocity = [0.0, {lift}]
[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [0.3, 0.2]
"#
    );
    Scene::from_toml(&text, "solid-on-wall").unwrap()
}

#[test]
fn a_block_lifted_off_the_floor_keeps_its_density() {
    // 0.05 m/s for 0.02 s: the block rises 1 mm = 0.1 dx, as the gate's row did.
    let setup = scene(0.05).setup().unwrap();
    let mut s = cpu_solver(setup);
    run::advance_to(s.as_mut(), &mut Gates::new(vec![]), 0.02).unwrap();
    let ps = s.particles();
    let solid: Vec<_> = ps.iter().filter(|q| q.kind == Kind::Solid).collect();
    assert_eq!(solid.len(), 40);
    let lowest = solid.iter().map(|q| q.position[1]).fold(f32::MAX, f32::min);
    assert!(
        lowest > 0.0055,
        "the block did not rise: lowest row at {lowest}"
    );
    let worst = solid
        .iter()
        .map(|q| (q.density / 1000.0 - 1.0).abs())
        .fold(0.0f32, f32::max);
    assert!(
        worst < 1e-4,
        "a solid particle's density changed by {worst}"
    );
}
