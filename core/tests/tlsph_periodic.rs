//! A total-Lagrangian body across a periodic seam (issue #62): its reference neighbours, clamp
//! faces and deflection are those of the same body anywhere else on the periodic axis.
//!
//! The scene is a ring: on a periodic x axis of period LX, a clamp (driven, motion zero)
//! LC long and a plate that fills the rest of the period, so the plate is clamped at both of
//! its ends by the one clamp, and sags under gravity. Placed two ways that differ only by a
//! shift of the pattern along x:
//! * `mid_seam`: the clamp in the middle of the domain; the seam cuts the plate at midspan.
//! * `clamp_seam`: the clamp at the domain's left edge; the seam runs along the clamp's face
//!   that holds the plate's right end.
//!
//! Each particle must find in the reference configuration as many neighbours and clamp face
//! points as its counterpart in the other placement, and both plates must deflect alike.
//! Before the reference took the minimum image, the seam cut the bonds: `mid_seam` was two
//! cantilevers of half the span, `clamp_seam` one cantilever of the whole span.

use meshfree_core::backend::cpu_solver;
use meshfree_core::physics::dim::D2;
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::physics::tlsph::Reference;
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::Stepper;

/// [L] the period, the clamp's length, the plate's thickness, the spacing: 20 x 4 particles,
/// of which 4 x 4 are the clamp.
const LX: f64 = 1.0;
const LC: f64 = 0.2;
const DX: f64 = 0.05;
/// [L] the shift along x from `clamp_seam` to `mid_seam` (a whole number of spacings).
const SHIFT: f64 = 0.5 * (LX - LC);
/// [T] the bottom of the first swing (about 100 steps): suddenly loaded, the plate sags to
/// about twice its static deflection there, 1e-4; its first mode's period is 0.039 s.
const T_END: f64 = 0.02;

/// The ring with its clamp from x = `clamp_at` to `clamp_at + LC`: the clamp first, so that
/// the plate's box (the whole period) keeps the lattice points the clamp left free. Material
/// as tests/driven.rs's cantilever (E = 1.29e4, rho = 1, g = 1).
fn scene(clamp_at: f64) -> Scene {
    let text = format!(
        r#"dimension = 2
name = "periodic-ring"
gravity = [0.0, -1.0]

[domain]
min = [0.0, -0.5]
max = [{LX}, 0.5]
periodic = [true, false]

[discretisation]
spacing = {DX}

[time]
end = {T_END}
output_interval = {T_END}

[fluid]
density = 1.0
sound_speed = 20.0

[solid]
density = 1.0
sound_speed = 100.0
shear_modulus = 5000.0
formulation = "total-lagrangian"

[[solids]]
shape = "box"
min = [{clamp_at}, -0.1]
max = [{clamp_end}, 0.1]
motion = [0.0, 0.0]

[[solids]]
shape = "box"
min = [0.0, -0.1]
max = [{LX}, 0.1]
"#,
        clamp_end = clamp_at + LC,
    );
    Scene::from_toml(&text, "periodic-ring").expect("scene")
}

/// The lattice cell (column, row) of a particle at `x`, its column shifted by `shift`
/// spacings round the period.
fn cell(x: [f32; 3], shift: i64) -> (i64, i64) {
    let n = (LX / DX).round() as i64;
    let col = (x[0] as f64 / DX - 0.5).round() as i64;
    let row = (x[1] as f64 / DX - 0.5).round() as i64;
    ((col + shift).rem_euclid(n), row)
}

/// For every particle of `from` (sorted by id) the index in `to` of the particle in the same
/// lattice cell after `shift` spacings.
fn counterparts(from: &[Particle], to: &[Particle], shift: i64) -> Vec<usize> {
    let at: std::collections::HashMap<(i64, i64), usize> = to
        .iter()
        .enumerate()
        .map(|(i, q)| (cell(q.position, 0), i))
        .collect();
    from.iter().map(|q| at[&cell(q.position, shift)]).collect()
}

#[test]
fn reference_neighbours_reach_through_the_seam() {
    let (a, b) = (scene(0.0).setup().unwrap(), scene(SHIFT).setup().unwrap());
    let p = scene(0.0).params();
    let (ra, rb) = (
        Reference::<D2>::new(&p, &a.particles),
        Reference::<D2>::new(&p, &b.particles),
    );
    assert_eq!(ra.len(), b.particles.len());
    // Solid index = rank by id = index in the setup's list (all particles are solid).
    let twin = counterparts(&a.particles, &b.particles, (SHIFT / DX).round() as i64);
    let mut wrong = Vec::new();
    for (i, &j) in twin.iter().enumerate() {
        let (na, nb) = (ra.neighbours(i).len(), rb.neighbours(j).len());
        let (fa, fb) = (ra.faces_of(i).len(), rb.faces_of(j).len());
        if na != nb || fa != fb || (ra.quad[i] - rb.quad[j]).abs() > 1e-4 {
            wrong.push((a.particles[i].position, na, nb, fa, fb));
        }
    }
    // The clamp's faces hold the plate in both placements (`tlsph::faces`), across the seam
    // in `clamp_seam`.
    assert!(
        !ra.face_pts.is_empty() && ra.face_pts.len() == rb.face_pts.len(),
        "face pairs: {} at the seam, {} away from it",
        ra.face_pts.len(),
        rb.face_pts.len()
    );
    assert!(
        wrong.is_empty(),
        "{} of {} particles see another reference through the seam than away from it \
         (X0, neighbours, shifted copy's, face points, shifted copy's): {:?}",
        wrong.len(),
        twin.len(),
        &wrong[..wrong.len().min(6)]
    );
}

/// The particles at `T_END`, sorted by id, with their starting positions.
fn run(s: &Scene) -> (Vec<Particle>, Vec<Particle>) {
    let setup = s.setup().unwrap();
    let start = setup.particles.clone();
    let mut solver = cpu_solver(setup);
    Stepper::default()
        .advance_to(solver.as_mut(), T_END)
        .expect("healthy run");
    let mut end = solver.particles();
    end.sort_by_key(|q| q.id);
    (start, end)
}

/// [L] each particle's sag, its y displacement downwards. (Not x: a position near x = 1 is
/// rounded to 6e-8 at every drift, which adds up to 1e-6 over the run, 1 % of the sag,
/// differently on the two sides of the seam; the solver's own displacement u is integrated
/// apart from it, `TlBodies::disp`.)
fn sag(start: &[Particle], end: &[Particle]) -> Vec<f64> {
    start
        .iter()
        .zip(end)
        .map(|(a, b)| (a.position[1] - b.position[1]) as f64)
        .collect()
}

#[test]
fn plate_across_the_seam_deflects_as_it_does_away_from_it() {
    let (s0, e0) = run(&scene(0.0));
    let (s1, e1) = run(&scene(SHIFT));
    let (u0, u1) = (sag(&s0, &e0), sag(&s1, &e1));
    let twin = counterparts(&s0, &s1, (SHIFT / DX).round() as i64);
    // The midspan sag: the plate's two middle columns, where mid_seam has its seam.
    let midspan = |s: &[Particle], u: &[f64], centre: f64| {
        let mid: Vec<f64> = s
            .iter()
            .zip(u)
            .filter(|(q, _)| q.kind == Kind::Solid && q.group == 1)
            .filter(|(q, _)| {
                let d = q.position[0] as f64 - centre;
                (d - LX * (d / LX).round()).abs() < DX
            })
            .map(|(_, &u)| u)
            .collect();
        mid.iter().sum::<f64>() / mid.len() as f64
    };
    let (w0, w1) = (midspan(&s0, &u0, 0.5 * (LX + LC)), midspan(&s1, &u1, 0.0));
    let worst = twin
        .iter()
        .enumerate()
        .map(|(i, &j)| (u0[i] - u1[j]).abs())
        .fold(0.0f64, f64::max);
    let scale = u1.iter().map(|u| u.abs()).fold(0.0f64, f64::max);
    eprintln!(
        "midspan sag at t = {T_END}: clamp at the seam {w0:.4e}, plate across the seam {w1:.4e} \
         (free fall {:.4e}); worst |sag - sag_twin| {worst:.3e} of max sag {scale:.3e}",
        0.5 * T_END * T_END
    );
    assert!(w0 > 0.0 && w1 > 0.0, "the plate did not sag: {w0}, {w1}");
    assert!(
        (w1 / w0 - 1.0).abs() < 0.02,
        "midspan sag {w1} across the seam, {w0} with the clamp at the seam"
    );
    assert!(
        worst < 0.02 * scale,
        "the sags differ by {worst} between the placements (max sag {scale})"
    );
}
