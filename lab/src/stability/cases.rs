//! The base scenes of the stability maps and how one run is measured.
//!
//! * Dam break: `validate::dam_break`'s square column (a = 1 in a 4 x 2 tank); error = the
//!   worst relative error of the surge front against Martin & Moyce (1952) at their times.
//! * Elastic strip: a free 1 x 0.2 strip given the stretching velocity
//!   v_x = v0 (x - x_c) / (L / 2); without artificial stress (Gray, Monaghan & Swift 2001)
//!   the tensile instability clumps its particles in pairs within 0.3 T. Error = the
//!   largest deviation of the nearest-neighbour distance from dx, as a fraction of dx
//!   (clumping: a pair closer than dx; fracture: a particle farther than dx from all).

use std::time::Instant;

use super::sweep::Base;
use crate::validate::dam_break;
use meshfree_core::backend::{self, BackendChoice};
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::Stepper;
use meshfree_core::solver::{BackendInfo, Fault};

/// A measured run: the error, or the blow-up that stopped it.
pub struct Measured {
    pub result: Result<f64, Fault>,
    pub particles: usize,
    pub wall_seconds: f64,
    /// The backend and device it ran on.
    pub info: BackendInfo,
}

/// The stretched strip: spacing `dx`, solid density 1000, bulk sound speed 20, shear
/// modulus 2e5 (shear wave speed about 14), artificial stress `art_stress`; no gravity,
/// no walls.
pub fn strip_scene_text(dx: f64, art_stress: f64) -> String {
    format!(
        r#"dimension = 2
name = "elastic-strip"
[domain]
min = [-1.0, -1.0]
max = [2.0, 1.2]
[discretisation]
spacing = {dx}
[time]
end = {STRIP_END}
output_interval = 0.05
[fluid]
density = 1000.0
sound_speed = 20.0
[solid]
density = 1000.0
sound_speed = 20.0
shear_modulus = 2e5
artificial_stress = {art_stress}
[[solids]]
shape = "box"
min = [0.0, 0.0]
max = [{STRIP_LEN}, 0.2]
"#
    )
}

/// \[L\] the strip's length and \[T\] how long it is followed.
pub const STRIP_LEN: f64 = 1.0;
pub const STRIP_END: f64 = 0.3;
/// [L/T] the end speed of the initial stretch (5 % of the bulk sound speed).
pub const STRIP_V0: f32 = 1.0;

/// Give the strip its initial stretching velocity v_x = v0 (x - L/2) / (L/2).
pub fn stretch(particles: &mut [Particle]) {
    let half = 0.5 * STRIP_LEN as f32;
    for q in particles.iter_mut().filter(|q| q.kind == Kind::Solid) {
        q.velocity[0] = STRIP_V0 * (q.position[0] - half) / half;
    }
}

/// (smallest, largest) nearest-neighbour distance \[L\] among the solid particles.
pub fn nearest_neighbour_range(ps: &[Particle]) -> (f32, f32) {
    let s: Vec<[f32; 3]> = ps
        .iter()
        .filter(|q| q.kind == Kind::Solid)
        .map(|q| q.position)
        .collect();
    let (mut lo, mut hi) = (f32::INFINITY, 0.0f32);
    for (i, a) in s.iter().enumerate() {
        let nearest = s
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .map(|(_, b)| (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f32>())
            .fold(f32::INFINITY, f32::min)
            .sqrt();
        lo = lo.min(nearest);
        hi = hi.max(nearest);
    }
    (lo, hi)
}

/// The clumping / fracture error of the strip [-]: max over the samples of
/// max(1 - nn_min / dx, nn_max / dx - 1).
pub fn strip_error(ps: &[Particle], dx: f32) -> f64 {
    let (lo, hi) = nearest_neighbour_range(ps);
    ((1.0 - lo / dx).max(hi / dx - 1.0)) as f64
}

/// The spacing of a base scene per tier.
pub fn spacing(base: Base, quick: bool) -> f64 {
    match (base, quick) {
        (Base::DamBreak, true) => 0.1,
        (Base::DamBreak, false) => 0.04,
        (Base::ElasticStrip, true) => 0.05,
        (Base::ElasticStrip, false) => 0.02,
    }
}

/// The base scene at spacing `dx`.
pub fn base_scene(base: Base, dx: f64) -> Scene {
    let text = match base {
        Base::DamBreak => dam_break::scene_text(dx, 1.0, 1.0, 4.0, 2.0),
        Base::ElasticStrip => strip_scene_text(dx, 0.0),
    };
    Scene::from_toml(&text, "stability").expect("the stability base scenes are valid")
}

/// Run `scene` (a `base` scene with the swept values applied) and measure its error.
/// `t_end`: the normalised end time of the dam break, T = t sqrt(g / a).
pub fn measure(
    base: Base,
    scene: &Scene,
    backend: BackendChoice,
    t_end: f64,
) -> anyhow::Result<Measured> {
    let mut setup = scene.setup()?;
    if base == Base::ElasticStrip {
        stretch(&mut setup.particles);
    }
    let particles = setup.particles.len();
    let dx = setup.params.dx;
    let params = setup.params;
    let mut solver = backend::create(backend, backend::Layout::One, setup)?;
    // The clock starts after the solver is built, as for the validate cases (`Sim`): the
    // first CUDA solver of a process waits for the driver to compile the PTX (28 s on a fresh
    // H100 machine, whose compute cache is empty), which is no cost of the run's scheme.
    let started = Instant::now();
    let info = solver.info();
    let mut stepper = Stepper::new(scene.gates());
    let mut error = 0.0f64;
    let mut go = || -> Result<f64, Fault> {
        match base {
            Base::DamBreak => {
                // a = 1, g = 9.81: t = T / sqrt(g).
                for (t_norm, x_ref) in dam_break::martin_moyce_front(t_end) {
                    stepper.advance_to(solver.as_mut(), t_norm / 9.81f64.sqrt())?;
                    let front = dam_break::surge_front(
                        &params,
                        &solver.particles(),
                        dam_break::FRONT_DEPTH,
                    );
                    error = error.max((front - x_ref).abs() / x_ref);
                }
            }
            Base::ElasticStrip => {
                let samples = 6;
                for k in 1..=samples {
                    let t = STRIP_END * k as f64 / samples as f64;
                    stepper.advance_to(solver.as_mut(), t)?;
                    error = error.max(strip_error(&solver.particles(), dx));
                }
            }
        }
        Ok(error)
    };
    let result = go();
    Ok(Measured {
        result,
        particles,
        wall_seconds: started.elapsed().as_secs_f64(),
        info,
    })
}
