//! Open boundaries (`[[open_boundaries]]`, `physics::open`, `backend/cpu/open.rs`) on the
//! CPU: a plane channel between an inlet and an outlet (Poiseuille flow at Re = U H / nu =
//! 5) takes in and lets out the particles it should, keeps its particles' count, builds the
//! pressure drop the flow needs, and resumes from a checkpoint bit for bit across creations
//! and removals; bad input is refused with its field, and several subdomains say they
//! cannot run it.

mod common;

use meshfree_core::backend::{self, BackendChoice, Layout};
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::Scene;
use meshfree_core::solver::Solver;

/// `common::open_channel` in 2D with `edits` (exact replacements) applied.
fn channel(edits: &[(&str, &str)]) -> String {
    let mut text = common::open_channel(2);
    for (from, to) in edits {
        assert!(text.contains(from), "the channel has no {from:?}");
        text = text.replacen(from, to, 1);
    }
    text
}

fn cpu(text: &str) -> Box<dyn Solver> {
    let scene = Scene::from_toml(text, "channel-open").unwrap();
    backend::create(BackendChoice::Cpu, Layout::One, scene.setup().unwrap()).unwrap()
}

fn run_to(s: &mut dyn Solver, t: f64) {
    while s.time() < t {
        s.advance(10);
    }
}

fn fluid(v: &[Particle]) -> Vec<&Particle> {
    v.iter().filter(|q| q.kind == Kind::Fluid).collect()
}

/// Mean pressure of the fluid with |x - x0| < 0.02 (the channel's particles only).
fn pressure_at(v: &[Particle], x0: f32) -> f64 {
    let near: Vec<f64> = fluid(v)
        .into_iter()
        .filter(|q| (q.position[0] - x0).abs() < 0.02)
        .map(|q| q.pressure as f64)
        .collect();
    near.iter().sum::<f64>() / near.len() as f64
}

#[test]
fn a_channel_flows_through() {
    let mut s = cpu(&channel(&[]));
    let start = s.particles();
    let n0 = fluid(&start).len();
    let first_new = start.iter().map(|q| q.id).max().unwrap() + 1;
    run_to(&mut *s, 1.5);
    let v = s.particles();
    let tally = s.open_tally();
    assert_eq!(tally.len(), 2);
    let (inlet, outlet) = (tally[0], tally[1]);
    // The inlet's rows cross at U: U t / dx = 75 rows of 10 particles by t = 1.5.
    let expected = 750.0;
    assert!(
        (inlet.count_in as f64 - expected).abs() <= 10.0,
        "{} particles came in, {expected} expected",
        inlet.count_in
    );
    assert_eq!((inlet.count_out, outlet.count_in), (0, 0), "{tally:?}");
    // The outlet let out about what came in (the channel's count settles within a row of
    // each end's particles).
    assert!(
        (outlet.count_out as f64 - inlet.count_in as f64).abs() <= 30.0,
        "{tally:?}"
    );
    assert!((inlet.mass_in - inlet.count_in as f64 * 0.1f32 as f64).abs() < 1e-9);
    // Particles are neither lost nor doubled: the fluid's count changed by in - out.
    let n1 = fluid(&v).len();
    assert_eq!(
        n1 as i64 - n0 as i64,
        inlet.count_in as i64 - outlet.count_out as i64
    );
    // Every id once; the new ones after the scene's.
    let mut ids: Vec<u32> = v.iter().map(|q| q.id).collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), v.len(), "an id twice");
    assert!(v.iter().filter(|q| q.id >= first_new).count() > 400);
    // The fluid in the channel: its particles about the channel's 500 (the dynamic walls'
    // gap takes some), at about U.
    let inside: Vec<&Particle> = fluid(&v)
        .into_iter()
        .filter(|q| (0.0..0.5).contains(&q.position[0]))
        .collect();
    assert!(
        (470..=510).contains(&inside.len()),
        "{} particles in the channel",
        inside.len()
    );
    let mean_u = inside.iter().map(|q| q.velocity[0] as f64).sum::<f64>() / inside.len() as f64;
    assert!((mean_u - 0.5).abs() < 0.05, "mean u {mean_u}");
    // The pressure drop of Poiseuille flow, dp/dx = -12 rho nu U / H^2 = -6000 Pa/m
    // (measured -5170 at 10 across, -5740 at 20: converging).
    let slope = (pressure_at(&v, 0.35) - pressure_at(&v, 0.15)) / 0.2;
    assert!(
        (slope / -6000.0 - 1.0).abs() < 0.2,
        "dp/dx = {slope} Pa/m against -6000"
    );
}

#[test]
fn a_parabolic_inlet_brings_the_flux_of_its_mean_in_its_profile() {
    // `profile = "parabolic"`: the buffer moves at 6 U eta (1 - eta), eta = y / H, U = 0.5.
    let mut s = cpu(&channel(&[(
        "velocity = [0.5, 0.0]\n[[open",
        "velocity = [0.5, 0.0]\nprofile = \"parabolic\"\n[[open",
    )]));
    let first_new = s.particles().iter().map(|q| q.id).max().unwrap() + 1;
    run_to(&mut *s, 0.5);
    let v = s.particles();
    // Group 3: the inlet's buffer (one fluid block, two walls before it); group 4 the fluid
    // that came in through it.
    let buffer: Vec<&Particle> = v.iter().filter(|q| q.group == 3).collect();
    assert!(buffer.len() >= 20, "{} buffer particles", buffer.len());
    for q in &buffer {
        let eta = q.position[1] as f64 / 0.1;
        let u = 0.5 * 6.0 * eta * (1.0 - eta);
        assert!(
            (q.velocity[0] as f64 - u).abs() < 1e-5 && q.velocity[1] == 0.0,
            "a buffer particle at y = {} moves at {:?}, the profile's {u}",
            q.position[1],
            q.velocity
        );
    }
    // The flux is the mean's: the rows at y_j = (j + 1/2) dx cross at u_j, so that
    // sum_j u_j t / dx = 502.5 t particles came in (uniform: 500 t), each row's count
    // rounded down.
    let inlet = s.open_tally()[0];
    let expected = 502.5 * s.time();
    assert!(
        (inlet.count_in as f64 - expected).abs() <= 10.0,
        "{} particles came in, {expected:.1} expected",
        inlet.count_in
    );
    // And in its profile: the four middle rows (u_j 1.37-1.49 U) brought in more than twice
    // as many a row as the two rows at the floor (0.29 U and 0.77 U); uniform: as many.
    let came: Vec<&Particle> = v.iter().filter(|q| q.id >= first_new).collect();
    let rows = |lo: f32, hi: f32| {
        came.iter()
            .filter(|q| (lo..hi).contains(&q.position[1]))
            .count()
    };
    let (middle, floor) = (rows(0.03, 0.07) as f64 / 4.0, rows(0.0, 0.02) as f64 / 2.0);
    eprintln!(
        "parabolic inlet to t = {:.3}: {} in ({expected:.1} expected), {middle} a middle row, \
         {floor} a floor row",
        s.time(),
        inlet.count_in
    );
    assert!(
        middle > 2.0 * floor,
        "{middle} new particles a middle row, {floor} a floor row"
    );
}

#[test]
fn a_parabolic_profile_spans_the_closed_sides_only() {
    let axes = |text: &str| {
        Scene::from_toml(text, "channel-open")
            .unwrap()
            .setup()
            .unwrap()
            .params
            .open[0]
            .profile_axes
    };
    let parabolic = |dim| {
        common::open_channel(dim).replacen(
            "kind = \"inlet\"",
            "kind = \"inlet\"\nprofile = \"parabolic\"",
            1,
        )
    };
    // 2D: across y. The 3D duct (periodic across z): across y alone. Uniform: none.
    assert_eq!(axes(&parabolic(2)), 1 << 1);
    assert_eq!(axes(&parabolic(3)), 1 << 1);
    assert_eq!(axes(&common::open_channel(3)), 0);
    // The duct closed across z too (walls or not: the box's sides bound the profile): both.
    let closed = parabolic(3).replace(
        "periodic = [false, false, true]",
        "periodic = [false, false, false]",
    );
    assert_eq!(axes(&closed), (1 << 1) | (1 << 2));
    // Every side periodic: nothing for a parabola to span.
    let open = parabolic(3).replace(
        "periodic = [false, false, true]",
        "periodic = [false, true, true]",
    );
    let e = Scene::from_toml(&open, "channel-open")
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("open_boundaries[0].profile"), "{e}");
}

#[test]
fn a_restart_steps_on_bit_for_bit() {
    let text = channel(&[]);
    let mut a = cpu(&text);
    run_to(&mut *a, 0.1);
    let saved = a.save();
    assert!(saved.open.as_ref().unwrap().tally[0].count_in > 0);
    let mut b = cpu(&text);
    b.restore(&saved).unwrap();
    for s in [&mut a, &mut b] {
        s.advance(100);
    }
    let key = |v: Vec<Particle>| {
        let mut v: Vec<_> = v
            .into_iter()
            .map(|q| {
                (
                    q.id,
                    q.group,
                    q.position.map(f32::to_bits),
                    q.velocity.map(f32::to_bits),
                    q.density.to_bits(),
                )
            })
            .collect();
        v.sort_unstable();
        v
    };
    assert_eq!(a.open_tally(), b.open_tally());
    assert_eq!(key(a.particles()), key(b.particles()));
    // A checkpoint of another scene's open boundaries is refused.
    let mut c = cpu(&text);
    let mut other = saved.clone();
    other.open.as_mut().unwrap().tally.pop();
    assert!(c.restore(&other).unwrap_err().contains("open boundaries"));
}

#[test]
fn bad_input_is_refused_with_its_field() {
    let refused = |edits: &[(&str, &str)], field: &str| {
        let e = Scene::from_toml(&channel(edits), "channel-open")
            .err()
            .unwrap_or_else(|| panic!("{edits:?} accepted"))
            .to_string();
        assert!(e.contains(field), "{edits:?}: {e}");
    };
    refused(
        &[("normal = [1.0, 0.0]", "normal = [0.6, 0.8]")],
        "open_boundaries[0].normal",
    );
    refused(
        &[(
            "velocity = [0.5, 0.0]\n[[open",
            "velocity = [-0.5, 0.0]\n[[open",
        )],
        "open_boundaries[0].velocity",
    );
    refused(
        &[("min = [-0.03, 0.0]", "min = [-0.01, 0.0]")],
        "open_boundaries[0].max",
    );
    refused(
        &[("max = [0.53, 0.1]", "max = [0.59, 0.1]")],
        "open_boundaries[1].max",
    );
    refused(
        &[(
            "normal = [-1.0, 0.0]",
            "normal = [-1.0, 0.0]\nvelocity = [1.0, 0.0]",
        )],
        "open_boundaries[1].velocity",
    );
    refused(
        &[(
            "kind = \"outlet\"\nmin = [0.5, 0.0]",
            "kind = \"outlet\"\nmin = [-0.02, 0.0]",
        )],
        "overlaps",
    );
    refused(
        &[(
            "normal = [-1.0, 0.0]",
            "normal = [-1.0, 0.0]\nprofile = \"parabolic\"",
        )],
        "open_boundaries[1].profile",
    );
    refused(
        &[(
            "velocity = [0.5, 0.0]\n[[open",
            "velocity = [0.5, 0.0]\nprofile = \"round\"\n[[open",
        )],
        "profile",
    );
    refused(
        &[("wall_density_floor = true", "wall_density_floor = false")],
        "boundary.wall_density_floor",
    );
    // Several subdomains say they cannot run it.
    let setup = || {
        Scene::from_toml(&channel(&[]), "channel-open")
            .unwrap()
            .setup()
            .unwrap()
    };
    let e = backend::create(BackendChoice::Cpu, Layout::Threads(2), setup())
        .err()
        .unwrap();
    assert!(e.to_string().contains("open boundaries"), "{e}");
}
