//! Modified dynamic walls (`[boundary] wall_coupling = "mdbc"`, English et al. 2022;
//! `physics::mdbc`, `backend/cpu/density.rs`) on the CPU, beside dynamic walls: still water
//! rests on its floor and the floor's wall particles read the water's pressure; a dam-break
//! surge runs on the floor instead of on a cushion; a floating box floats closer to its draft
//! (its normals turning with it); several subdomains are refused.

use meshfree_core::backend::{self, BackendChoice, Layout};
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::Scene;
use meshfree_core::solver::Solver;

/// Built-in `name` with `edits` (exact text replacements) applied, and its CPU solver with
/// its gates removed.
fn solver(name: &str, edits: &[(&str, &str)]) -> Box<dyn Solver> {
    let mut text = Scene::builtin(name).unwrap().text;
    for (from, to) in edits {
        assert!(text.contains(from), "{name} has no {from:?}");
        text = text.replacen(from, to, 1);
    }
    let scene = Scene::from_toml(&text, name).unwrap();
    let mut s = backend::create(BackendChoice::Cpu, Layout::One, scene.setup().unwrap()).unwrap();
    // Gates open at t = 0 in these scenes (the run loop's removal, `Scene::gates`).
    for (group, at) in scene.gates() {
        assert_eq!(at, 0.0);
        s.remove_group(group);
    }
    s
}

fn of(v: &[Particle], k: Kind) -> impl Iterator<Item = &Particle> {
    v.iter().filter(move |q| q.kind == k)
}

/// `tank-2d` at dx = 0.05 (20 x 20 water particles, 1 deep) with `coupling` walls, run to
/// t = 1: the mean over t in [0.5, 1] of (the floor's first wall row's pressure against
/// rho0 g (H + dx/2), relative; the water's lowest particle's height in spacings), and the
/// rms over those times of the left wall's first row's pressure against rho0 g (H - y),
/// relative to rho0 g H.
fn still_tank(coupling: &str) -> (f64, f64, f64) {
    let dx = 0.05;
    let mut s = solver(
        "tank-2d",
        &[
            ("spacing = 0.025 ", "spacing = 0.05 "),
            ("min = [-0.1, -0.1]", "min = [-0.2, -0.2]"),
            ("max = [1.1, 1.3]", "max = [1.2, 1.3]"),
            (
                "wall_coupling = \"dynamic\"",
                &format!("wall_coupling = \"{coupling}\""),
            ),
        ],
    );
    let (mut err, mut low, mut side_rms, mut n) = (0.0, 0.0, 0.0, 0);
    while s.time() < 1.0 {
        s.advance(20);
        if s.time() < 0.5 {
            continue;
        }
        let v = s.particles();
        let water: Vec<_> = of(&v, Kind::Fluid).collect();
        // The level: the water's area over the tank's width (the particles keep their mass).
        let level = water.len() as f64 * dx * dx;
        let floor: Vec<f64> = of(&v, Kind::Boundary)
            .filter(|q| (q.position[1] as f64 + 0.5 * dx).abs() < 0.1 * dx)
            .filter(|q| q.position[0] > 0.1 && q.position[0] < 0.9)
            .map(|q| q.pressure as f64)
            .collect();
        assert!(floor.len() >= 15, "{} floor particles", floor.len());
        let want = 1000.0 * 9.81 * (level + 0.5 * dx);
        err += (floor.iter().sum::<f64>() / floor.len() as f64 - want) / want;
        low += water
            .iter()
            .map(|q| q.position[1] as f64)
            .fold(f64::MAX, f64::min)
            / dx;
        // The left wall's first row, from 0.2 under the surface to 0.2 over the floor.
        let side: Vec<f64> = of(&v, Kind::Boundary)
            .filter(|q| (q.position[0] as f64 + 0.5 * dx).abs() < 0.1 * dx)
            .filter(|q| q.position[1] as f64 > 0.2 && (q.position[1] as f64) < level - 0.2)
            .map(|q| {
                let want = 1000.0 * 9.81 * (level - q.position[1] as f64);
                (q.pressure as f64 - want) / (1000.0 * 9.81 * level)
            })
            .collect();
        assert!(side.len() >= 10, "{} side particles", side.len());
        side_rms += side.iter().map(|e| e * e).sum::<f64>() / side.len() as f64;
        n += 1;
    }
    (err / n as f64, low / n as f64, (side_rms / n as f64).sqrt())
}

#[test]
fn still_water_rests_on_an_mdbc_floor_which_reads_its_pressure() {
    let (err, low, side) = still_tank("mdbc");
    let (err_dyn, low_dyn, side_dyn) = still_tank("dynamic");
    eprintln!("mdbc: floor pressure {err:+.4}, lowest water {low:.3} dx, side wall rms {side:.4}");
    eprintln!(
        "dynamic: floor pressure {err_dyn:+.4}, lowest water {low_dyn:.3} dx, side wall rms \
         {side_dyn:.4}"
    );
    // The first wall row lies dx/2 under the floor: the ghost node's first-order
    // extrapolation gives it the column's pressure at its own depth.
    assert!(err.abs() < 0.01, "mdbc floor pressure off by {err:+.4}");
    // The water's lowest row stays where the lattice put it, half a spacing over the floor.
    assert!((low - 0.5).abs() < 0.1, "lowest water at {low:.3} dx");
    // The side wall reads the column's pressure at each depth too.
    assert!(side < 0.02, "mdbc side wall rms {side:.4}");
}

/// `dam-break-2d` (dx = 0.02, 2,500 water particles) with `coupling` walls at t = 0.4 and 0.5: the mean over the
/// surge's 0.2-wide bins from x = 1.2 to 0.4 short of its front (its thin tip) of the lowest water particle's
/// height [dx], and the lowest of all.
fn surge_cushion(coupling: &str) -> (f64, f64) {
    let dx = 0.02;
    let mut s = solver(
        "dam-break-2d",
        &[(
            "wall_coupling = \"dynamic\"",
            &format!("wall_coupling = \"{coupling}\""),
        )],
    );
    let (mut sum, mut n, mut lowest) = (0.0, 0, f64::MAX);
    for t in [0.4, 0.5] {
        while s.time() < t {
            s.advance(10);
        }
        let v = s.particles();
        let water: Vec<_> = of(&v, Kind::Fluid).collect();
        let front = water.iter().map(|q| q.position[0]).fold(0.0f32, f32::max) as f64;
        let mut x = 1.2;
        while x + 0.2 <= front - 0.4 {
            let low = (water.iter())
                .filter(|q| (q.position[0] as f64) >= x && (q.position[0] as f64) < x + 0.2)
                .map(|q| q.position[1] as f64)
                .fold(f64::MAX, f64::min);
            sum += low / dx;
            n += 1;
            lowest = lowest.min(low / dx);
            x += 0.2;
        }
    }
    assert!(n >= 4, "{n} bins under the surge");
    (sum / n as f64, lowest)
}

#[test]
fn a_dam_break_surge_runs_on_an_mdbc_floor_not_on_a_cushion() {
    let (mean, lowest) = surge_cushion("mdbc");
    let (mean_dyn, lowest_dyn) = surge_cushion("dynamic");
    eprintln!("mdbc: surge's lowest water {mean:.3} dx (lowest {lowest:.3})");
    eprintln!("dynamic: surge's lowest water {mean_dyn:.3} dx (lowest {lowest_dyn:.3})");
    // Dynamic walls hold the surge about h off the floor (issue #56: 1.1-1.6 spacings);
    // mDBC's walls read the water's own pressure, so it runs half a spacing over the floor.
    assert!(
        mean < 0.6,
        "mdbc: the surge runs {mean:.3} dx over the floor"
    );
    assert!(lowest > 0.25, "mdbc: water {lowest:.3} dx over the floor");
    assert!(
        mean_dyn > mean + 0.3,
        "dynamic {mean_dyn:.3} against mdbc {mean:.3}"
    );
}

/// The built-in floating box of density `rho` at dx = 0.02 on `coupling` walls, run to
/// t = 1.6: the mean height of its centre over [1, 1.6] and Archimedes' for it.
fn floating_box(coupling: &str, rho: f64) -> (f64, f64) {
    let dx = 0.02;
    let density = format!("density = {rho:.1} }}");
    let walls = format!("wall_coupling = \"{coupling}\"");
    let mut s = solver(
        "floating-box-2d",
        &[
            ("spacing = 0.01 ", "spacing = 0.02 "),
            ("density = 500.0 }", &density),
            ("wall_coupling = \"dynamic\"", &walls),
        ],
    );
    let water = of(&s.particles(), Kind::Fluid).count() as f64 * dx * dx;
    // The level: the water's area plus the displaced area over the tank's width of 1; the
    // box's bottom a draft under it, its centre 0.05 over its bottom.
    let draft = rho / 1000.0 * 0.1;
    let want = water + 0.2 * draft - draft + 0.05;
    let (mut sum, mut n) = (0.0, 0);
    while s.time() < 1.6 {
        s.advance(10);
        if s.time() >= 1.0 {
            (sum, n) = (sum + s.bodies()[0].centre[1], n + 1);
        }
    }
    (sum / n as f64, want)
}

#[test]
fn a_box_floating_on_mdbc_walls_floats_closer_to_archimedes_draft() {
    // Dynamic walls hold the water about a spacing off the box, which floats 9 mm high
    // (18 % of its draft of 0.05: tests/floating.rs); the box's walls under mDBC read the
    // water's pressure at their surface, and its normals turn with it: it floats 5 mm high
    // (10 % of its draft, a quarter of a spacing; measured 2026-12-07), not yet at
    // Archimedes' draft (issue #56).
    let (h, want) = floating_box("mdbc", 500.0);
    let (h_dyn, _) = floating_box("dynamic", 500.0);
    eprintln!("mdbc: centre {h:.5} against Archimedes' {want:.5}; dynamic {h_dyn:.5}");
    assert!(
        (h - want).abs() < 0.13 * 0.05,
        "mdbc: {h:.5} against {want:.5}"
    );
    assert!(
        (h - want).abs() < 0.75 * (h_dyn - want),
        "mdbc {h:.5}, dynamic {h_dyn:.5} against {want:.5}"
    );
}

#[test]
fn mdbc_walls_in_several_subdomains_are_refused() {
    let dam = Scene::builtin("dam-break-2d").unwrap().text.replacen(
        "wall_coupling = \"dynamic\"",
        "wall_coupling = \"mdbc\"",
        1,
    );
    let setup = Scene::from_toml(&dam, "d").unwrap().setup().unwrap();
    assert!(!setup.wall_surface.is_empty());
    let e = backend::create(BackendChoice::Cpu, Layout::Threads(2), setup)
        .err()
        .expect("mdbc with --decompose is refused")
        .to_string();
    assert!(e.contains("mDBC"), "{e}");
}
