//! Density diffusion (delta-SPH, Molteni & Colagrossi 2009, `[fluid] density_diffusion`):
//! in a tank that starts at uniform density (no hydrostatic initialisation, so the start
//! rings), the particle-scale density noise after the transient is lower with delta = 0.1
//! than without; started hydrostatic, the pressure stays hydrostatic with it; the mass is
//! unchanged either way. Its hydrostatic form (Fourtakas et al. 2019,
//! `density_diffusion_form = "fourtakas"`) diffuses nothing in water at rest, where the plain
//! form's one-sided sums at the free surface and the walls do.

use meshfree_core::backend::cpu::CpuSolver;
use meshfree_core::backend::cpu_solver;
use meshfree_core::physics::dim::D2;
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::scheme::DiffusionForm;
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::Stepper;
use meshfree_core::solver::Solver;

const DX: f64 = 0.05;

fn tank(delta: f64, hydrostatic: bool) -> Scene {
    let mut s = Scene::builtin("tank-2d").unwrap().with_spacing(DX).unwrap();
    s.file.fluid.density_diffusion = delta;
    s.file.fluid_blocks[0].hydrostatic = hydrostatic;
    s.revalidate().unwrap();
    s
}

/// Interior fluid particles: one support radius from the walls and the free surface.
fn interior(ps: &[Particle], support: f32) -> Vec<&Particle> {
    let top = ps
        .iter()
        .filter(|q| q.kind == Kind::Fluid)
        .map(|q| q.position[1])
        .fold(f32::MIN, f32::max);
    ps.iter()
        .filter(|q| {
            q.kind == Kind::Fluid
                && q.position[0] > support
                && q.position[0] < 1.0 - support
                && q.position[1] > support
                && q.position[1] < top - support
        })
        .collect()
}

/// Density noise [-]: the rms over interior particles of rho / rho0 - 1 less its mean in
/// the particle's layer (one spacing thick), so that the hydrostatic gradient and the
/// column's slow acoustic mode do not count.
fn layer_noise(ps: &[Particle], rho0: f32, support: f32, dx: f32) -> f64 {
    let inner = interior(ps, support);
    let mut layers: std::collections::BTreeMap<i32, (f64, usize)> = Default::default();
    for q in &inner {
        let e = layers.entry((q.position[1] / dx) as i32).or_default();
        e.0 += (q.density / rho0 - 1.0) as f64;
        e.1 += 1;
    }
    let mut sum2 = 0.0;
    for q in &inner {
        let (s, n) = layers[&((q.position[1] / dx) as i32)];
        sum2 += ((q.density / rho0 - 1.0) as f64 - s / n as f64).powi(2);
    }
    (sum2 / inner.len() as f64).sqrt()
}

/// Mean layer noise over `samples` snapshots in (t0, t1], and the solver at t1.
fn noise_after_transient(scene: &Scene, t0: f64, t1: f64, samples: usize) -> (f64, f64, f64) {
    let setup = scene.setup().unwrap();
    let p = setup.params;
    let mass0: f64 = setup.particles.iter().map(|q| q.mass as f64).sum();
    let mut s = cpu_solver(setup);
    let mut stepper = Stepper::new(scene.gates());
    stepper.advance_to(s.as_mut(), t0).expect("healthy run");
    let mut noise = 0.0;
    for k in 1..=samples {
        let t = t0 + (t1 - t0) * k as f64 / samples as f64;
        stepper.advance_to(s.as_mut(), t).expect("healthy run");
        noise += layer_noise(&s.particles(), p.rho0, p.support, p.dx) / samples as f64;
    }
    let mass1: f64 = s.particles().iter().map(|q| q.mass as f64).sum();
    (noise, mass0, mass1)
}

#[test]
fn density_diffusion_lowers_the_density_noise_of_a_ringing_tank() {
    let (off, m0, m1) = noise_after_transient(&tank(0.0, false), 0.3, 0.5, 10);
    let (on, n0, n1) = noise_after_transient(&tank(0.1, false), 0.3, 0.5, 10);
    eprintln!("layer density noise: delta 0: {off:.3e}, delta 0.1: {on:.3e}");
    assert!(
        on < 0.5 * off,
        "density noise with delta = 0.1 ({on:.3e}) not below half of that without ({off:.3e})"
    );
    assert_eq!(m0, m1, "mass changed without diffusion");
    assert_eq!(n0, n1, "mass changed with diffusion");
}

#[test]
fn with_density_diffusion_a_resting_tank_keeps_hydrostatic_pressure() {
    let scene = tank(0.1, true);
    let setup = scene.setup().unwrap();
    let p = setup.params;
    let mut s = cpu_solver(setup);
    let mut stepper = Stepper::new(scene.gates());
    stepper.advance_to(s.as_mut(), 0.4).expect("healthy run");
    // Mean pressure over 0.2 T (several acoustic periods 2 H / c0).
    let samples = 10;
    let mut mean_p = vec![0.0f32; s.len()];
    for k in 1..=samples {
        stepper
            .advance_to(s.as_mut(), 0.4 + 0.2 * k as f64 / samples as f64)
            .unwrap();
        for (m, q) in mean_p.iter_mut().zip(s.particles()) {
            *m += q.pressure / samples as f32;
        }
    }
    let mut end = s.particles();
    for (q, m) in end.iter_mut().zip(&mean_p) {
        q.pressure = *m;
    }
    let (g, rho0, h_col) = (-p.gravity[1], p.rho0, 1.0f32);
    let top = end
        .iter()
        .filter(|q| q.kind == Kind::Fluid)
        .map(|q| q.position[1])
        .fold(f32::MIN, f32::max)
        + 0.5 * p.dx;
    let inner = interior(&end, p.support);
    assert!(inner.len() > 100, "{} interior particles", inner.len());
    let mut worst = 0.0f32;
    for q in &inner {
        let want = rho0 * g * (top - q.position[1]);
        worst = worst.max((q.pressure - want).abs() / (rho0 * g * h_col));
    }
    // The tolerance of the hydrostatic test without diffusion (tests/physics.rs).
    assert!(
        worst < 0.10,
        "worst interior pressure error {worst:.3} of rho g H (tolerance 0.10)"
    );
}

/// The largest |d rho/dt| [M L^-d T^-1] over the fluid particles of the resting tank, started
/// hydrostatic (walls too), at t = 0 with density diffusion 0.1 of the given form: all of it
/// is diffusion, since nothing moves.
fn resting_diffusion(form: DiffusionForm) -> f32 {
    let mut s = tank(0.1, true);
    s.file.fluid.density_diffusion_form = form;
    s.file.boundary.as_mut().unwrap().hydrostatic_walls = true;
    s.revalidate().unwrap();
    let mut c = CpuSolver::<D2>::new(s.setup().unwrap());
    c.build_grid();
    c.density_gradient();
    c.rates();
    let st = c.state();
    let drho = st.drho.as_ref().expect("continuity density");
    (0..st.len())
        .filter(|&i| st.kind[i] == Kind::Fluid as u8)
        .map(|i| drho[i].abs())
        .fold(0.0, f32::max)
}

#[test]
fn the_hydrostatic_form_diffuses_nothing_in_water_at_rest() {
    let plain = resting_diffusion(DiffusionForm::MolteniColagrossi);
    let fourtakas = resting_diffusion(DiffusionForm::Fourtakas);
    eprintln!(
        "max |d rho/dt| at rest: Molteni & Colagrossi {plain:.3e}, Fourtakas {fourtakas:.3e}"
    );
    // The plain form diffuses the hydrostatic gradient where the support is cut (the rows
    // at the floor and the free surface): rho0 g dx / c0^2 ~ 0.25 kg/m^3 a row, times about
    // delta h c0 / dx^2 ~ 100 /s.
    assert!(plain > 1.0, "the plain form diffused nothing ({plain:.3e})");
    // The hydrostatic form leaves the Tait law's curvature (p / B ~ 3 % at the floor).
    assert!(
        fourtakas < 0.05 * plain,
        "the hydrostatic form diffuses {fourtakas:.3e}, the plain form {plain:.3e}"
    );
}

#[test]
fn the_renormalised_form_diffuses_nothing_in_water_at_rest() {
    let plain = resting_diffusion(DiffusionForm::MolteniColagrossi);
    let antuono = resting_diffusion(DiffusionForm::Antuono);
    eprintln!("max |d rho/dt| at rest: Molteni & Colagrossi {plain:.3e}, Antuono {antuono:.3e}");
    assert!(plain > 1.0, "the plain form diffused nothing ({plain:.3e})");
    // Antuono et al. 2010's correction removes any linear density, the hydrostatic one
    // included, where the support is cut too (renormalised gradients): what is left is the
    // Tait law's curvature, as with Fourtakas et al.'s form.
    assert!(
        antuono < 0.05 * plain,
        "the renormalised form diffuses {antuono:.3e}, the plain form {plain:.3e}"
    );
}
