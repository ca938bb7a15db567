//! `meshfree bench`: the dam-break blocks and any scene (`--scene`), each row naming the
//! scheme it ran and the simulated time per wall second.

use meshfree::bench::{self, BenchOptions, BenchRow};
use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::Scene;

fn quick() -> BenchOptions {
    BenchOptions {
        backend: BackendChoice::Cpu,
        dims: vec![2],
        sizes: vec![500],
        steps: 4,
        warmup: 1,
        repeats: 1,
        count_neighbours: false,
        ..Default::default()
    }
}

fn check_timing(r: &BenchRow, steps: usize) {
    assert_eq!(r.steps, steps);
    assert!(r.ms_per_step > 0.0 && r.particle_steps_per_s > 0.0, "{r:?}");
    // Simulated time per wall second = dt per step / wall time per step: positive, finite.
    assert!(
        r.simulated_per_second > 0.0 && r.simulated_per_second.is_finite(),
        "{r:?}"
    );
}

#[test]
fn a_scene_benches_with_its_own_scheme_from_its_start() {
    let dir = tempfile::tempdir().unwrap();
    // The impinging flow opens its gate at t = 0, as a run does.
    let scenes = [Scene::builtin("impinging-2d").unwrap()];
    let rows = bench::bench_scenes(&quick(), &scenes, Some(dir.path())).unwrap();
    let r = &rows[0];
    check_timing(r, 4);
    assert_eq!(r.scene, "impinging-2d");
    assert_eq!(
        (r.integrator.as_str(), r.kernel.as_str(), r.density.as_str()),
        ("leapfrog", "cubic-spline", "continuity")
    );
    assert_eq!(r.diffusion, "none");
    let total = scenes[0].setup().unwrap().particles.len();
    assert!(
        r.particles < total,
        "the gate was not opened: {} of {total} particles",
        r.particles
    );
    let csv = std::fs::read_to_string(dir.path().join("bench.csv")).unwrap();
    assert!(
        csv.starts_with("scene,") && csv.contains("\nimpinging-2d,cpu,"),
        "{csv}"
    );
    let json: Vec<BenchRow> =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("bench.json")).unwrap())
            .unwrap();
    assert_eq!(json[0].scene, "impinging-2d");
}

#[test]
fn a_scenes_diffusion_and_kernel_are_named() {
    // tank-2d's own delta-SPH (0.1, Fourtakas) at another strength, and another kernel.
    let text = Scene::builtin("tank-2d")
        .unwrap()
        .text
        .replace("density_diffusion = 0.1 ", "density_diffusion = 0.05 ");
    assert!(text.contains("density_diffusion = 0.05 "));
    let text = text.replace("kernel = \"cubic-spline\"", "kernel = \"wendland-c2\"");
    let scene = Scene::from_toml(&text, "tank, Wendland, Fourtakas").unwrap();
    let rows = bench::bench_scenes(&quick(), &[scene], None).unwrap();
    assert_eq!(
        (rows[0].kernel.as_str(), rows[0].diffusion.as_str()),
        ("wendland-c2", "0.05 fourtakas")
    );
}

#[test]
fn the_blocks_name_their_scheme() {
    let rows = bench::bench(&quick(), None).unwrap();
    let r = &rows[0];
    check_timing(r, 4);
    assert!(r.scene.is_empty());
    assert_eq!(
        (
            r.integrator.as_str(),
            r.kernel.as_str(),
            r.diffusion.as_str()
        ),
        ("leapfrog", "cubic-spline", "none")
    );
    assert!(r.viscosity.starts_with("alpha "), "{}", r.viscosity);
}

#[test]
fn a_decomposed_bench_row_gives_the_exchange_cost() {
    let o = BenchOptions {
        decompose: Some(2),
        ..quick()
    };
    let rows = bench::bench(&o, None).unwrap();
    let r = &rows[0];
    check_timing(r, 4);
    assert_eq!((r.subdomains, r.gpus), (2, 0), "{r:?}");
    assert!(r.device.contains("2 subdomains"), "{r:?}");
    assert!(r.exchange_us_per_step > 0.0, "{r:?}");
    assert!(r.halo_bytes_per_step > 0.0, "{r:?}");
}
