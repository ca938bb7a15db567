//! Floating rigid bodies on the CPU (`floating` walls, `physics::body`,
//! `backend/cpu/bodies.rs`): the built-in floating box at twice its spacing, at two
//! densities, settles by Archimedes and stays rigid; a restart from a checkpoint steps on bit for bit, its
//! body too; bad input is refused with the field and the reason.

use meshfree_core::backend::{self, BackendChoice, Layout};
use meshfree_core::physics::params::MfBody;
use meshfree_core::scene::Scene;
use meshfree_core::solver::{Setup, Solver};

/// The built-in floating box at spacing `dx`, of density `rho` (its file's: 500).
fn box_scene(dx: f64, rho: f64) -> Setup {
    let text = Scene::builtin("floating-box-2d").unwrap().text;
    let text = text
        .replace("spacing = 0.01 ", &format!("spacing = {dx} "))
        .replace("density = 500.0 }", &format!("density = {rho:.1} }}"));
    let scene = Scene::from_toml(&text, "floating box").unwrap();
    scene.setup().unwrap()
}

fn cpu(setup: &Setup) -> Box<dyn Solver> {
    backend::create(BackendChoice::Cpu, Layout::One, setup.clone()).unwrap()
}

/// The box of density `rho` at dx = 0.02 (10 x 5 spacings) run to t = 1.6: the mean height
/// of its centre over [1, 1.6], Archimedes' for it, and the largest change of a distance
/// between two of its particles.
fn settled(rho: f64) -> (f64, f64, f32) {
    let dx = 0.02;
    let setup = box_scene(dx, rho);
    let b0: MfBody = setup.bodies[0];
    assert!((b0.mass - rho * 0.02).abs() < 1e-9, "mass {}", b0.mass);
    assert!((b0.centre[1] - 0.52).abs() < 1e-9);
    // The water's area (fluid particles x dx^2) and the displaced area over the tank's
    // width of 1: the level; the box's bottom a draft under it, its centre 0.05 above that.
    let water = setup
        .particles
        .iter()
        .filter(|q| q.kind == meshfree_core::physics::particle::Kind::Fluid)
        .count() as f64
        * dx
        * dx;
    let draft = rho / 1000.0 * 0.1;
    let want = water + 0.2 * draft - draft + 0.05;
    let body_ids: Vec<u32> = (setup.particles.iter())
        .filter(|q| q.group == b0.group as u32)
        .map(|q| q.id)
        .collect();
    let mut s = cpu(&setup);
    let (mut sum, mut n) = (0.0, 0);
    while s.time() < 1.6 {
        s.advance(10);
        if s.time() >= 1.0 {
            (sum, n) = (sum + s.bodies()[0].centre[1], n + 1);
        }
    }
    let by_id = |v: Vec<meshfree_core::physics::particle::Particle>| {
        let mut v: Vec<_> = v.into_iter().filter(|q| body_ids.contains(&q.id)).collect();
        v.sort_by_key(|q| q.id);
        v
    };
    let (a, b) = (by_id(setup.particles.clone()), by_id(s.particles()));
    let d = |p: [f32; 3], q: [f32; 3]| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
    let mut worst = 0.0f32;
    for i in (0..a.len()).step_by(7) {
        for j in (0..a.len()).step_by(5) {
            worst = worst
                .max((d(a[i].position, a[j].position) - d(b[i].position, b[j].position)).abs());
        }
    }
    (sum / n as f64, want, worst)
}

#[test]
fn floating_boxes_sink_by_archimedes_and_stay_rigid() {
    // Two boxes, of density 500 and 700: each floats a little high (the dynamic walls keep
    // the water about a spacing from the box's particles, so the fluid sees a larger box:
    // +18 % of the draft at this spacing), an offset that the difference of their heights
    // cancels: the heavier sinks 0.02 deeper by Archimedes. A mass off by 10 % would move
    // that difference by 0.005 or more.
    let (light, want_light, rigid_light) = settled(500.0);
    let (heavy, want_heavy, rigid_heavy) = settled(700.0);
    let (got, want) = (light - heavy, want_light - want_heavy);
    eprintln!(
        "floating boxes at dx = 0.02: centres {light:.5} (Archimedes {want_light:.5}) and \
         {heavy:.5} ({want_heavy:.5}); the heavier {got:.5} lower, Archimedes {want:.5} \
         ({:+.1} %)",
        100.0 * (got - want) / want
    );
    assert!(
        (got - want).abs() < 0.15 * want,
        "sank {got} deeper, Archimedes {want}"
    );
    // Both within a quarter of their draft of Archimedes' height.
    assert!(
        (light - want_light).abs() < 0.25 * 0.05,
        "{light} vs {want_light}"
    );
    assert!(
        (heavy - want_heavy).abs() < 0.25 * 0.07,
        "{heavy} vs {want_heavy}"
    );
    // Rigid: every pair of the body's particles as far apart as at the start, to the float
    // rounding of ~6,000 moves (each rounds the turned position once: 1e-5 to 3e-5 here,
    // a thousandth of a spacing), where a move that turned the body by 1e-3 rad too much
    // or too little would stretch a pair across it by 2e-4.
    assert!(
        rigid_light.max(rigid_heavy) < 5e-5,
        "deformed by {rigid_light}, {rigid_heavy}"
    );
}

#[test]
fn a_restart_steps_the_floating_box_on_bit_for_bit() {
    let setup = box_scene(0.03, 500.0);
    let mut a = cpu(&setup);
    a.advance(40);
    let saved = a.save();
    assert_eq!(saved.bodies.len(), 1);
    let mut b = cpu(&setup);
    b.restore(&saved).unwrap();
    a.advance(40);
    b.advance(40);
    let (ba, bb) = (a.bodies()[0], b.bodies()[0]);
    assert!(ba.velocity[1] != 0.0, "the box did not move");
    assert_eq!(ba.centre.map(f64::to_bits), bb.centre.map(f64::to_bits));
    assert_eq!(ba.momentum.map(f64::to_bits), bb.momentum.map(f64::to_bits));
    assert_eq!(
        ba.orientation.map(f64::to_bits),
        bb.orientation.map(f64::to_bits)
    );
    let (pa, pb) = (a.save(), b.save());
    assert!(pa.pos == pb.pos && pa.vel == pb.vel && pa.rho == pb.rho);
    // A checkpoint without the body is refused.
    let mut other = saved.clone();
    other.bodies.clear();
    let e = cpu(&setup).restore(&other).unwrap_err();
    assert!(e.contains("floating bodies"), "{e}");
}

#[test]
fn bad_floating_bodies_are_refused_with_the_field_and_the_reason() {
    let text = Scene::builtin("floating-box-2d").unwrap().text;
    let cases = [
        (
            "floating = { density = 500.0 }",
            "floating = { }",
            "walls[1].floating",
            "density",
        ),
        (
            "floating = { density = 500.0 }",
            "floating = { density = 500.0, mass = 3.0 }",
            "walls[1].floating",
            "not both",
        ),
        (
            "floating = { density = 500.0 }",
            "floating = { density = -1.0 }",
            "walls[1].floating.density",
            "",
        ),
        (
            "floating = { density = 500.0 }",
            "floating = { density = 500.0, turns = [\"x\"] }",
            "walls[1].floating.turns",
            "about z only",
        ),
        (
            "integrator = \"leapfrog\"",
            "integrator = \"euler\"",
            "walls[1].floating",
            "kicks before it drifts",
        ),
    ];
    for (from, to, field, why) in cases {
        let bad = text.replace(from, to);
        assert_ne!(bad, text, "{to}");
        let e = Scene::from_toml(&bad, "bad").unwrap_err().to_string();
        assert!(e.contains(field) && e.contains(why), "{to}: {e}");
    }
    // Several subdomains are refused: a body's load would be one subdomain's.
    let setup = box_scene(0.03, 500.0);
    let e = backend::create(BackendChoice::Cpu, Layout::Threads(2), setup)
        .err()
        .expect("refused");
    assert!(e.to_string().contains("floating"), "{e}");
}

#[test]
fn a_heavy_box_sinks_and_rests_on_the_floor() {
    // Density 3,000 at dx = 0.03: it sinks through the water and stops on the tank's floor,
    // held by the contact (the repulsion of eq. (17) between its particles and the floor's):
    // its centre half its height (0.05) above the floor, within the contact's reach.
    let setup = box_scene(0.03, 3000.0);
    let mut s = cpu(&setup);
    while s.time() < 1.5 {
        s.advance(20);
    }
    let b = s.bodies()[0];
    eprintln!(
        "heavy box at t = {:.3}: centre {:?}, velocity {:?}, contact {:?}",
        s.time(),
        b.centre,
        b.velocity,
        b.contact
    );
    assert!(
        b.centre[1] > 0.035 && b.centre[1] < 0.07,
        "centre {:?}",
        b.centre
    );
    assert!(b.velocity[1].abs() < 0.05, "still moving: {:?}", b.velocity);
    // Resting: the floor carries its weight less its buoyancy, (3000 - 1000) 0.02 g.
    assert!(b.contact[1] > 0.0, "no contact: {:?}", b.contact);
}
