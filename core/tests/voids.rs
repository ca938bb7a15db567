//! The void metric (`src/measure/voids.rs`): a lattice (one particle per cell) without and with
//! holes of known size, in the middle and across a periodic corner, and the fluid region of
//! a scene with a cylinder.

use meshfree_core::measure::voids::{VoidMeter, VoidSample, VoidSummary};
use meshfree_core::physics::particle::Particle;
use meshfree_core::scene::Scene;

/// A 4 x 4 periodic box of fluid at dx = 0.1: a 40 x 40 lattice at (i + 1/2) dx, one
/// particle per cell.
fn lattice() -> (Scene, Vec<Particle>) {
    let text = r#"dimension = 2
name = "voids"
[domain]
min = [0.0, 0.0]
max = [4.0, 4.0]
periodic = [true, true]
[discretisation]
spacing = 0.1
[time]
end = 1.0
output_interval = 1.0
[fluid]
density = 1.0
sound_speed = 10.0
[[fluid_blocks]]
min = [0.0, 0.0]
max = [4.0, 4.0]
"#;
    let scene = Scene::from_toml(text, "test").expect("scene");
    let particles = scene.particles();
    assert_eq!(particles.len(), 1600);
    (scene, particles)
}

/// `particles` without those within `r` (in dx, plus a rounding margin) of `centre`, the
/// distance taken across the periodic box of side 4; and how many went.
fn with_hole(particles: &[Particle], centre: [f32; 2], r: f32) -> (Vec<Particle>, usize) {
    let dx = 0.1f32;
    let wrap = |d: f32| d - 4.0 * (d / 4.0).round();
    let kept: Vec<Particle> = particles
        .iter()
        .filter(|q| {
            let (a, b) = (
                wrap(q.position[0] - centre[0]),
                wrap(q.position[1] - centre[1]),
            );
            (a * a + b * b).sqrt() > (r + 1e-3) * dx
        })
        .copied()
        .collect();
    let gone = particles.len() - kept.len();
    (kept, gone)
}

#[test]
fn a_full_lattice_has_no_void() {
    let (scene, particles) = lattice();
    let meter = VoidMeter::new(&scene.file, &particles);
    assert_eq!(meter.region_cells(), 1600);
    let s = meter.measure(&particles, 0.0);
    assert_eq!(s.empty_fraction, 0.0);
    // The largest empty circle of a square lattice sits between four particles: sqrt 2 dx.
    assert!(
        (s.largest_void_dx - 2f64.sqrt()).abs() < 1e-3,
        "{}",
        s.largest_void_dx
    );
}

#[test]
fn one_missing_particle_is_a_void_of_two_dx() {
    let (scene, particles) = lattice();
    let meter = VoidMeter::new(&scene.file, &particles);
    let (holed, gone) = with_hole(&particles, [2.05, 2.05], 0.0);
    assert_eq!(gone, 1);
    let s = meter.measure(&holed, 1.0);
    assert_eq!(s.empty_fraction, 1.0 / 1600.0);
    assert!(
        (s.largest_void_dx - 2.0).abs() < 1e-3,
        "{}",
        s.largest_void_dx
    );
}

/// Removing every particle within 3 dx of a lattice point leaves 29 empty cells and the
/// nearest particles at sqrt 10 dx ((3, 1) and its images): a void of 2 sqrt 10 = 6.32 dx.
/// The same across the periodic corner, where the hole is split over four edges.
#[test]
fn a_hole_of_radius_three_dx_reads_as_its_size_also_across_a_periodic_corner() {
    let (scene, particles) = lattice();
    let meter = VoidMeter::new(&scene.file, &particles);
    for centre in [[2.05f32, 2.05], [0.05, 0.05], [3.95, 0.05]] {
        let (holed, gone) = with_hole(&particles, centre, 3.0);
        assert_eq!(gone, 29, "at {centre:?}");
        let s = meter.measure(&holed, 2.0);
        assert_eq!(s.empty_fraction, 29.0 / 1600.0, "at {centre:?}");
        let expected = 2.0 * 10f64.sqrt();
        assert!(
            (s.largest_void_dx - expected).abs() < 1e-2,
            "at {centre:?}: {} against {expected}",
            s.largest_void_dx
        );
    }
}

/// Voids wider than the search radius read as the search radius's diameter, not more.
#[test]
fn an_empty_box_reads_as_the_search_limit() {
    let (scene, particles) = lattice();
    let meter = VoidMeter::new(&scene.file, &particles);
    let s = meter.measure(&particles[..1], 0.0);
    assert_eq!(s.empty_fraction, 1599.0 / 1600.0);
    let cap = 2.0 * meshfree_core::measure::voids::MAX_RADIUS_DX as f64;
    assert!(
        (s.largest_void_dx - cap).abs() < 1e-3,
        "{}",
        s.largest_void_dx
    );
}

/// The fluid region leaves out the cylinder's inside (no fluid there at the start), so the
/// built-in vortex street starts without a void.
#[test]
fn the_fluid_region_leaves_out_the_cylinder() {
    let scene = Scene::builtin("vortex-street-re140").expect("built-in");
    let particles = scene.particles();
    let meter = VoidMeter::new(&scene.file, &particles);
    // 200 x 80 cells; the cylinder (radius 1 = 10 dx, 3 wall layers) holds no fluid.
    assert!(
        meter.region_cells() < 200 * 80 - 300,
        "{}",
        meter.region_cells()
    );
    assert!(
        meter.region_cells() > 200 * 80 - 500,
        "{}",
        meter.region_cells()
    );
    let s = meter.measure(&particles, 0.0);
    assert_eq!(s.empty_fraction, 0.0);
    assert!(s.largest_void_dx <= 2.0, "{}", s.largest_void_dx);
}

#[test]
fn the_summary_keeps_the_worst_output() {
    let mut sum = VoidSummary::default();
    for (t, f, v) in [(0.0, 0.0, 1.4), (1.0, 0.1, 3.0), (2.0, 0.05, 1.8)] {
        sum.add(VoidSample {
            time: t,
            empty_fraction: f,
            largest_void_dx: v,
        });
    }
    assert_eq!(sum.outputs, 3);
    assert_eq!((sum.largest_void_dx, sum.largest_void_time), (3.0, 1.0));
    assert_eq!(sum.max_empty_fraction, 0.1);
    assert!((sum.mean_empty_fraction - 0.05).abs() < 1e-12);
    assert_eq!(sum.last.map(|s| s.time), Some(2.0));
}
