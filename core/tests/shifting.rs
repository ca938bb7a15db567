//! Particle shifting (`[fluid] shifting`, Lind et al. 2012 with Sun et al. 2017's
//! anti-clumping term; `shift_velocity` in cpu/rates.rs): a particle pushed off its lattice
//! site is moved back towards it, and not without shifting; in a resting tank the free
//! surface does not rise and the water away from the walls stays at rest; a free-surface
//! particle gets no shift.

use meshfree_core::backend::cpu::shift_velocity;
use meshfree_core::backend::cpu_solver;
use meshfree_core::physics::dim::D2;
use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::Stepper;

/// A periodic 1 x 1 box of resting fluid at spacing 0.05.
fn periodic_box(shifting: f64) -> Scene {
    let text = format!(
        r#"dimension = 2
name = "shift-box"

[domain]
min = [0.0, 0.0]
max = [1.0, 1.0]
periodic = [true, true]

[discretisation]
spacing = 0.05

[time]
end = 0.01
output_interval = 0.01

[fluid]
density = 1.0
sound_speed = 10.0
shifting = {shifting}

[[fluid_blocks]]
min = [0.0, 0.0]
max = [1.0, 1.0]
"#
    );
    Scene::from_toml(&text, "tests/shifting.rs").unwrap()
}

/// The distance [L] of particle `id` from its lattice site after `steps` steps, started
/// 0.2 dx off it along x.
fn offset_after(shifting: f64, steps: u64) -> f32 {
    let scene = periodic_box(shifting);
    let mut setup = scene.setup().unwrap();
    let dx = setup.params.dx;
    let id = setup.particles.len() / 2 + 7;
    let site = setup.particles[id].position;
    setup.particles[id].position[0] += 0.2 * dx;
    let mut s = cpu_solver(setup);
    for _ in 0..steps {
        s.step();
    }
    let q = s
        .particles()
        .into_iter()
        .find(|q| q.id as usize == id)
        .unwrap();
    ((q.position[0] - site[0]).powi(2) + (q.position[1] - site[1]).powi(2)).sqrt()
}

#[test]
fn a_displaced_particle_is_shifted_back_towards_its_site() {
    let dx = 0.05f32;
    let steps = 20;
    let off = offset_after(0.0, steps);
    let on = offset_after(0.2, steps);
    eprintln!(
        "offset after {steps} steps: without shifting {off:.3e}, with 0.2: {on:.3e} (start {:.3e})",
        0.2 * dx
    );
    // Without shifting the pressure alone moves it back by little in 20 steps.
    assert!(off > 0.15 * dx, "without shifting: {off:e}");
    assert!(
        on < 0.5 * off,
        "with shifting {on:e} not below half of {off:e}"
    );
}

#[test]
fn a_resting_tank_with_shifting_stays_at_rest() {
    let mut scene = Scene::builtin("tank-2d")
        .unwrap()
        .with_spacing(0.05)
        .unwrap();
    scene.file.fluid.shifting = 0.2;
    scene.revalidate().unwrap();
    let setup = scene.setup().unwrap();
    let dx = setup.params.dx;
    let start = setup.particles.clone();
    let mut s = cpu_solver(setup);
    let mut stepper = Stepper::new(scene.gates());
    stepper.advance_to(s.as_mut(), 0.5).expect("healthy run");
    let end = s.particles();
    let top = |ps: &[meshfree_core::physics::particle::Particle]| {
        ps.iter()
            .filter(|q| q.kind == Kind::Fluid)
            .map(|q| q.position[1])
            .fold(f32::MIN, f32::max)
    };
    let rise = top(&end) - top(&start);
    // Away from the walls (the contact lines, where the walls above the water fill part of
    // the support, rearrange by up to 0.8 dx: docs/reference/accuracy.md) no particle moves.
    let support = 2.6 * dx;
    let drift = start
        .iter()
        .zip(&end)
        .filter(|(a, _)| {
            a.kind == Kind::Fluid && a.position[0] > support && a.position[0] < 1.0 - support
        })
        .map(|(a, b)| {
            ((a.position[0] - b.position[0]).powi(2) + (a.position[1] - b.position[1]).powi(2))
                .sqrt()
        })
        .fold(0.0f32, f32::max);
    eprintln!(
        "free surface rise {:.3} dx, largest drift {:.3} dx",
        rise / dx,
        drift / dx
    );
    assert!(rise < 0.25 * dx, "the free surface rose {rise:e} (dx {dx})");
    assert!(drift < 0.5 * dx, "a particle drifted {drift:e} (dx {dx})");
}

#[test]
fn a_free_surface_particle_is_not_shifted() {
    let scene = periodic_box(0.2);
    let p = scene.setup().unwrap().params;
    let grad_c = glam::Vec2::new(0.0, -3.0);
    // Inside the fluid the position divergence is d = 2; at a free surface about half.
    let inside = shift_velocity::<D2>(&p, grad_c, 2.0);
    let surface = shift_velocity::<D2>(&p, grad_c, 1.2);
    assert!(
        inside.y > 0.0,
        "down the concentration gradient: {inside:?}"
    );
    assert_eq!(surface, glam::Vec2::ZERO);
}

/// `[fluid] background_pressure` adds to eq. (9) for fluid and dynamic wall particles, not
/// for Lennard-Jones-only walls or solids.
#[test]
fn a_background_pressure_adds_to_the_equation_of_state() {
    use meshfree_core::backend::cpu::pressure;
    use meshfree_core::physics::params::{MF_KIND_BOUNDARY, MF_KIND_FLUID, MF_KIND_SOLID};
    let mut scene = periodic_box(0.0);
    scene.file.fluid.background_pressure = 3.0;
    scene.revalidate().unwrap();
    let mut p = scene.setup().unwrap().params;
    let (fluid, wall) = (MF_KIND_FLUID as u8, MF_KIND_BOUNDARY as u8);
    assert_eq!(pressure(&p, fluid, p.rho0, 0.0), 3.0);
    let rho = 1.01 * p.rho0;
    let tait = p.tait_b * (1.01f32.powf(p.tait_gamma) - 1.0);
    assert!((pressure(&p, fluid, rho, 0.0) - (tait + 3.0)).abs() < 1e-5);
    p.wall_coupling = 1;
    assert_eq!(pressure(&p, wall, p.rho0, 0.0), 3.0);
    p.wall_coupling = 0;
    assert_eq!(pressure(&p, wall, p.rho0, 0.0), 0.0);
    p.solid_rho0 = 2.0;
    p.solid_c0 = 1.0;
    // Solids: P = c_s^2 (rho - rho0_s) from the departure rho - rho0_s, not from rho.
    assert_eq!(pressure(&p, MF_KIND_SOLID as u8, 2.0, 0.0), 0.0);
    assert_eq!(pressure(&p, MF_KIND_SOLID as u8, 2.0, 1e-6), 1e-6);
}
