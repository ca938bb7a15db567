//! `[fluid] gradient_correction` (`backend/cpu/forces.rs`, `gradient_correction`): the
//! renormalised pressure pair keeps momentum conserved where the matrices differ most
//! (two drops colliding in free space, their supports cut at every surface), changes the
//! motion, and several subdomains say they cannot run it. Its accuracy is `validate`'s
//! `standing-wave` case (the linear period within 1 %, where the plain gradient is 4-5 %
//! fast).

use meshfree_core::backend::{self, BackendChoice, Layout};
use meshfree_core::scene::Scene;

/// Two square drops of water meeting head on at 1 m/s in free space (no gravity, no walls).
fn drops(corrected: bool) -> String {
    format!(
        r#"dimension = 2
name = "drops"

[domain]
min = [0.0, 0.0]
max = [2.0, 2.0]

[discretisation]
spacing = 0.02
h_factor = 1.3
kernel = "wendland-c2"

[time]
end = 1.0
output_interval = 1.0
courant = 0.4
integrator = "leapfrog"

[fluid]
density = 1000.0
sound_speed = 20.0
gamma = 7.0
alpha = 0.01
gradient_correction = {corrected}

[boundary]
strength = 0.0

[[fluid_blocks]]
min = [0.6, 0.7]
max = [1.0, 1.3]
velocity = [0.5, 0.1]

[[fluid_blocks]]
min = [1.0, 0.8]
max = [1.4, 1.2]
velocity = [-0.75, -0.15]
"#
    )
}

/// The total momentum and the sum of |m v| after `steps` steps, and the particles' positions.
fn run(corrected: bool, steps: u64) -> ([f64; 3], f64, Vec<[f32; 3]>) {
    let scene = Scene::from_toml(&drops(corrected), "drops").unwrap();
    let mut s = backend::create(BackendChoice::Cpu, Layout::One, scene.setup().unwrap()).unwrap();
    s.advance(steps);
    let p = s.particles();
    let scale: f64 = p
        .iter()
        .map(|q| q.mass as f64 * (q.velocity[0] as f64).hypot(q.velocity[1] as f64))
        .sum();
    (
        s.diagnostics().momentum,
        scale,
        p.iter().map(|q| q.position).collect(),
    )
}

#[test]
fn the_corrected_pressure_pair_conserves_momentum_and_changes_the_motion() {
    let (plain, _, x_plain) = run(false, 150);
    let (corrected, scale, x_corrected) = run(true, 150);
    // The drops start with zero momentum (0.4 x 0.6 at +0.5 against 0.4 x 0.4 at -0.75).
    for m in [plain, corrected] {
        let off = m[0].hypot(m[1]) / scale;
        assert!(off < 1e-5, "momentum {m:?} against sum |m v| {scale}");
    }
    let moved = x_plain
        .iter()
        .zip(&x_corrected)
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
        .fold(0.0f32, f32::max);
    assert!(moved > 1e-4, "the correction changed nothing ({moved})");
}

#[test]
fn the_correction_in_several_subdomains_is_refused() {
    let setup = Scene::from_toml(&drops(true), "drops")
        .unwrap()
        .setup()
        .unwrap();
    let e = backend::create(BackendChoice::Cpu, Layout::Threads(2), setup)
        .err()
        .expect("the correction with --decompose is refused")
        .to_string();
    assert!(e.contains("gradient_correction"), "{e}");
}
