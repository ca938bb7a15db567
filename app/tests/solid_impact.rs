//! An isolated elastic square hit by a block of water: the small reproduction of the
//! impinging-2d break-up (docs/reference/paper-scenes.md, "Resolved: the square's break-up"). The
//! square is the impinging scene's (8 x 8 particles at dx = 0.375, density 0.6, c_s = 85,
//! G = 1080), the water (density 1.0) arrives at speed 6 as in the surge; no walls, no
//! gravity. With the paper's eq. (16) across every pair the square comes apart within
//! 0.3 time units (radius of gyration x 1.34 at t = 0.3, x 2.24 when the run stops at
//! t = 0.48, a particle's density out of range); with the fluid and the body meeting through pressure
//! only (`[solid] interface = "pressure"`, the default) it keeps its shape.

use meshfree::analysis::bodies::{body, Body};
use meshfree_core::backend::cpu_solver;
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::Stepper;

/// The square (group 1) at rest, the water block (group 0) to its left moving at +6.
/// `interface` is the `[solid] interface` value (None: the default).
fn scene(interface: Option<&str>) -> Scene {
    // The paper's whole stress across the interface comes with the body's own pressure.
    let interface = interface.map_or(String::new(), |c| {
        format!("interface = \"{c}\"\nfluid_pressure = \"own\"\n")
    });
    let text = format!(
        r#"dimension = 2
name = "solid-impact"
[domain]
min = [-20.0, -20.0]
max = [40.0, 40.0]
[discretisation]
spacing = 0.375
[time]
end = 1.0
output_interval = 0.1
[fluid]
density = 1.0
sound_speed = 85.0
alpha = 0.02
xsph = 0.5
[solid]
density = 0.6
sound_speed = 85.0
shear_modulus = 1080.0
{interface}
[[fluid_blocks]]
min = [0.0, -1.5]
max = [6.0, 6.0]
velocity = [6.0, 0.0]
[[solids]]
shape = "box"
min = [6.75, 0.0]
max = [9.75, 3.0]
"#
    );
    Scene::from_toml(&text, "solid-impact").unwrap()
}

/// The square every 0.1 up to `t_end`, or the time of the blow-up that stopped the run.
fn follow(scene: &Scene, t_end: f64) -> (Body, Vec<(f64, Body)>, Option<f64>) {
    let setup = scene.setup().unwrap();
    let b0 = body(&setup.particles, 1, 2).unwrap();
    let mut s = cpu_solver(setup);
    let mut stepper = Stepper::new(vec![]);
    let mut out = Vec::new();
    for k in 1..=(t_end * 10.0).round() as usize {
        let t = k as f64 * 0.1;
        let r = stepper.advance_to(s.as_mut(), t);
        let b = body(&s.particles(), 1, 2).unwrap();
        println!(
            "t = {:.2}: v = ({:.2}, {:.2}), omega = {:.3}, rg/rg0 = {:.4}, area/area0 = {:.4}",
            s.time(),
            b.velocity[0],
            b.velocity[1],
            b.omega[2],
            b.rg / b0.rg,
            b.size / b0.size
        );
        if r.is_err() {
            return (b0, out, Some(s.time()));
        }
        out.push((t, b));
    }
    (b0, out, None)
}

#[test]
fn a_square_hit_by_water_keeps_its_shape() {
    let (b0, history, fault) = follow(&scene(None), 1.0);
    assert_eq!(fault, None, "the run stopped");
    for (t, b) in &history {
        assert!(
            (b.rg / b0.rg - 1.0).abs() < 0.03,
            "t = {t:.1}: radius of gyration {} against {} at the start",
            b.rg,
            b0.rg
        );
        assert!(
            (b.size / b0.size - 1.0).abs() < 0.03,
            "t = {t:.1}: area {} against {} at the start",
            b.size,
            b0.size
        );
    }
    // It was hit: the water pushed it in +x.
    let (_, end) = history.last().unwrap();
    assert!(end.velocity[0] > 1.0, "square velocity {:?}", end.velocity);
}

#[test]
fn with_the_papers_interface_stress_the_square_comes_apart() {
    // `interface = "stress"` selects the paper's eq. (16) across every pair: the body's
    // deviatoric stress reaches the fluid, and the square is torn apart (or the run stops).
    let (b0, history, fault) = follow(&scene(Some("stress")), 0.6);
    let worst = history
        .iter()
        .map(|(_, b)| b.rg / b0.rg)
        .fold(1.0f32, f32::max);
    assert!(
        fault.is_some() || worst > 1.3,
        "the square held (rg/rg0 at most {worst}): the fluid-solid coupling no longer differs"
    );
}
