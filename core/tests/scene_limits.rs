//! What a scene may ask for. The estimate (`scene::estimate`): an upper bound on the particles that is close to
//! the generated count on every built-in scene, the grid's cell count as `params::derive`
//! makes it, and refusals of sizes the solver cannot index, before anything is allocated;
//! numbers outside single precision and names that cannot name a directory.

use meshfree_core::scene::estimate::estimate;
use meshfree_core::scene::{builtin_names, Scene, SceneError};

#[test]
fn the_estimate_bounds_every_builtin_scene_closely_and_counts_its_cells() {
    for name in builtin_names() {
        let scene = Scene::builtin(name).unwrap();
        let e = estimate(&scene.file);
        let setup = scene.setup().unwrap();
        let n = setup.particles.len() as f64;
        assert!(
            e.particles >= n,
            "{name}: estimate {} < {n} generated",
            e.particles
        );
        assert!(
            e.particles <= 1.6 * n,
            "{name}: estimate {} for {n} generated",
            e.particles
        );
        assert_eq!(e.cells, setup.params.n_cells as f64, "{name}");
    }
}

/// tank-2d changed by `edit`, validated again: the refused field and the reason.
fn refused(edit: impl FnOnce(&mut meshfree_core::scene::scheme::SceneFile)) -> (String, String) {
    let mut scene = Scene::builtin("tank-2d").unwrap();
    edit(&mut scene.file);
    match scene.revalidate() {
        Err(SceneError::Invalid { field, reason, .. }) => (field, reason),
        other => panic!("expected a refusal, got {other:?}"),
    }
}

#[test]
fn sizes_the_solver_cannot_index_or_hold_are_refused_naming_the_field() {
    // A tiny spacing: more particles than u32 ids (it allocated until the allocator aborted).
    let (field, reason) = refused(|f| f.discretisation.spacing = 1e-6);
    assert_eq!(field, "discretisation.spacing", "{reason}");
    assert!(reason.contains("particles"), "{reason}");
    // Below single precision: it rounded to zero (and panicked).
    let (field, reason) = refused(|f| f.discretisation.spacing = 1e-300);
    assert_eq!(field, "discretisation.spacing", "{reason}");
    assert!(reason.contains("single precision"), "{reason}");
    // A tiny smoothing length: more cells than an i32 (it panicked in the grid).
    let (field, reason) = refused(|f| f.discretisation.h_factor = 1e-12);
    assert_eq!(field, "discretisation.h_factor", "{reason}");
    assert!(reason.contains("cells"), "{field}: {reason}");
    // A huge one: every particle in each one's reach, every pair computed (three steps of a
    // 6,400-particle tank took 40 s).
    let (field, reason) = refused(|f| f.discretisation.h_factor = 1e12);
    assert_eq!(field, "discretisation.h_factor", "{reason}");
    assert!(reason.contains("at most 8"), "{reason}");
    // A huge domain at a sane spacing: the grid's count overflowed an i32 and `check` said
    // "-1671184943 cells, ok".
    let (field, reason) = refused(|f| f.domain.max = vec![5000.0, 5000.0]);
    assert_eq!(field, "domain.max", "{reason}");
}

#[test]
fn numbers_outside_single_precision_are_refused() {
    let (field, reason) = refused(|f| f.gravity = Some(vec![0.0, -1e39]));
    assert_eq!(field, "gravity[1]", "{reason}");
    assert!(reason.contains("3.4e38"), "{reason}");
    let (field, reason) = refused(|f| f.time.dt = Some(1e-40));
    assert_eq!(field, "time.dt", "{reason}");
    assert!(reason.contains("round to zero"), "{reason}");
}

#[test]
fn names_that_cannot_name_a_directory_are_refused() {
    for bad in ["a\0b", "two\nlines", &"n".repeat(300), " padded"] {
        let (field, reason) = refused(|f| f.name = bad.to_string());
        assert_eq!(field, "name", "{bad:?}: {reason}");
    }
}
