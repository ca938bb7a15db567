//! A time step that collapses to 0 stops a loop that steps to a time, with or without the
//! run's end time (`Stepper::with_end`): the stability maps stepped a blown-up forward Euler
//! dam break towards its next sample for ever (2026-11-28).

use meshfree_core::backend::{self, BackendChoice};
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::Stepper;

/// The quick stability map's dam break (dx = 0.1) with the paper's forward Euler, the
/// summation density and alpha 0.05 at Courant 0.4: its step falls to 0 at t ~ 0.17.
const SCENE: &str = r#"dimension = 2
name = "collapse"
gravity = [0.0, -9.81]
[domain]
min = [-0.34, -0.34]
max = [4.34, 2.34]
[discretisation]
spacing = 0.1
h_factor = 1.3
kernel = "cubic-spline"
[time]
end = 2.0
output_interval = 0.02
courant = 0.4
integrator = "euler"
[fluid]
density = 1000.0
sound_speed = 44.29446918522963
density_form = "summation"
alpha = 0.05
xsph = 0.5
[boundary]
strength = 490.5
wall_coupling = "dynamic"
wall_density_floor = true
[[fluid_blocks]]
min = [0.0, 0.0]
max = [1.0, 1.0]
hydrostatic = true
[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [4.0, 2.0]
layers = 3
open_top = false
[[walls]]
shape = "box"
min = [1.0, 0.0]
max = [1.3, 1.5]
remove_at = 0.0
"#;

#[test]
fn a_collapsed_step_is_a_fault_without_an_end_time() {
    let scene = Scene::from_toml(SCENE, "collapse").unwrap();
    let mut solver = backend::create(
        BackendChoice::Cpu,
        backend::Layout::One,
        scene.setup().unwrap(),
    )
    .unwrap();
    let mut stepper = Stepper::new(scene.gates());
    let fault = stepper
        .advance_to(solver.as_mut(), 1.0)
        .expect_err("the forward Euler's step collapses before t = 1");
    assert!(solver.time() < 1.0, "t = {}", solver.time());
    assert!(fault.quantity == "time step", "{fault:?}");
}
