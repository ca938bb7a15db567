//! Set-up's cost grows with the particles and objects, not with their product (issue
//! #52): the tests hold the algorithms' structure, not a time. A quadratic set-up takes
//! minutes on them (80,452 one-particle blocks took 26.9 s to check in a release build,
//! now 0.44 s), a linear one about a second. That the particles are the same as before is
//! held by `scenes.rs` and the built-in scenes' counts.

use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::{Counts, Scene};

/// tank-2d's text up to its objects, at spacing `dx` (the wall strength scaled with it).
fn tank_head(dx: f64) -> String {
    let text = Scene::builtin("tank-2d").unwrap().text;
    let head = text.split("[[fluid_blocks]]").next().unwrap().to_string();
    assert!(head.contains("spacing = 0.025") && head.contains("strength = 1962.0"));
    head.replace("spacing = 0.025", &format!("spacing = {dx}"))
        .replace(
            "strength = 1962.0",
            &format!("strength = {}", 5.0 * 9.81 / dx),
        )
}

const CONTAINER: &str = "[[walls]]\nshape = \"box-container\"\nmin = [0.0, 0.0]\n\
                         max = [1.0, 1.2]\nlayers = 3\nopen_top = true\n";

#[test]
fn a_scene_of_100000_one_particle_blocks_is_set_up_in_linear_time() {
    // 100,000 hydrostatic blocks of one particle each (in a tank whose dynamic walls take
    // the blocks' pressure): each block's particles are tested against those kept before
    // it, and each wall particle against the blocks near it.
    let k = 317;
    let dx = 1.0 / k as f64;
    let mut text = tank_head(dx);
    let mut n = 0;
    'rows: for j in 0..k {
        for i in 0..k {
            if n == 100_000 {
                break 'rows;
            }
            let (x, y) = (i as f64 * dx, j as f64 * dx);
            text += &format!(
                "[[fluid_blocks]]\nmin = [{x}, {y}]\nmax = [{}, {}]\nhydrostatic = true\n",
                x + dx,
                y + dx
            );
            n += 1;
        }
    }
    text += CONTAINER;
    let scene = Scene::from_toml(&text, "blocks.toml").unwrap();
    let setup = scene.setup().unwrap();
    let c = Counts::of(&setup.particles);
    assert_eq!(c.fluid, 100_000);
    // The walls next to the fluid start at its hydrostatic pressure, as in one block.
    let one = Scene::from_toml(
        &format!(
            "{}[[fluid_blocks]]\nmin = [0.0, 0.0]\nmax = [1.0, {}]\nhydrostatic = true\n{CONTAINER}",
            tank_head(dx),
            (100_000 / k) as f64 * dx
        ),
        "one.toml",
    )
    .unwrap();
    let walls = |s: &Scene| -> Vec<f32> {
        let ps = s.setup().unwrap().particles;
        ps.iter()
            .filter(|p| p.kind == Kind::Boundary && p.position[1] < 0.0)
            .map(|p| p.pressure)
            .collect()
    };
    // (Each block's top is its own: the floor's pressures differ, not where they are.)
    let wet = |ps: &[f32]| ps.iter().filter(|&&p| p > 0.0).count();
    let (many, single) = (walls(&scene), walls(&one));
    assert_eq!(many.len(), single.len());
    assert!(
        wet(&many) > 0 && wet(&many) == wet(&single),
        "the floor is under water"
    );
}

#[test]
fn fluid_around_50000_small_solids_is_set_up_in_linear_time() {
    // One fluid block holding 50,000 one-particle solid boxes: each fluid particle is
    // tested against the solids that may hold it, not against all of them.
    let k = 250;
    let dx = 1.0 / k as f64;
    let mut text = tank_head(dx)
        + "[solid]\ndensity = 1100.0\nsound_speed = 45.0\nshear_modulus = 1e5\n\
           [[fluid_blocks]]\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n";
    for j in 0..k {
        for i in (0..k).filter(|i| (i + j) % 5 < 4) {
            let (x, y) = (i as f64 * dx, j as f64 * dx);
            text += &format!(
                "[[solids]]\nshape = \"box\"\nmin = [{x}, {y}]\nmax = [{}, {}]\n",
                x + dx,
                y + dx
            );
        }
    }
    let scene = Scene::from_toml(&text, "solids.toml").unwrap();
    let c = Counts::of(&scene.setup().unwrap().particles);
    assert_eq!(c.solid, 50_000);
    assert_eq!(c.fluid + c.solid, k * k, "the fluid fills the rest, once");
}
