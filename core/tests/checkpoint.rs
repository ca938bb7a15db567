//! Restarts (`Persist::save`, `Persist::restore`, `meshfree_core::solver::checkpoint`): a solver
//! restored from a checkpoint into a fresh solver of the same scene steps on exactly as the
//! saved one did, bit for bit on the same backend (its diagnostics too), with elastic bodies under both solid
//! formulations and a gate opened before the save; a checkpoint of another scene is refused
//! with the reason. On a GPU (ignored without one): the same on the CUDA backend, and a CPU
//! checkpoint continued on the GPU stays within the parity tests' tolerances of the CPU.

use meshfree_core::backend::{self, BackendChoice};
use meshfree_core::scene::Scene;
use meshfree_core::solver::checkpoint::SolverCheckpoint;
use meshfree_core::solver::{Setup, Solver};

/// The built-in impinging flow (water column, gate, an elastic square and disc) at twice
/// the spacing (about 1,400 particles), with the solid `formulation`.
fn impinging(formulation: &str) -> (Setup, u32) {
    let text = Scene::builtin("impinging-2d").unwrap().text;
    let text = text
        .replace("spacing = 0.375", "spacing = 0.75")
        .replace(
            "[solid]\n",
            &format!("[solid]\nformulation = \"{formulation}\"\n"),
        )
        .replace("layers = 3", "layers = 2");
    let scene = Scene::from_toml(&text, "impinging, coarse").unwrap();
    let gates = scene.gates();
    assert_eq!(gates.len(), 1, "the scene has one gate");
    (scene.setup().unwrap(), gates[0].0)
}

/// A solver for `setup` on `backend`, its gate opened.
fn started(choice: BackendChoice, setup: &Setup, gate: u32) -> Box<dyn Solver> {
    let mut s = backend::create(choice, backend::Layout::One, setup.clone()).unwrap_or_else(|e| {
        panic!("this test needs the {choice:?} backend: {e}");
    });
    assert!(s.remove_group(gate) > 0, "the gate removed nothing");
    s
}

/// Whether two checkpoints hold the same bits (f32 `==` would take -0 for 0).
fn same_bits(a: &SolverCheckpoint, b: &SolverCheckpoint) -> Result<(), String> {
    let f = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let f3 = |v: &[[f32; 3]]| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    let f6 = |v: &[[f32; 6]]| v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>();
    let checks = [
        (
            "clock",
            (a.time.to_bits(), a.steps) == (b.time.to_bits(), b.steps),
        ),
        ("dt", a.dt.to_bits() == b.dt.to_bits()),
        (
            "ids",
            a.id == b.id && a.kind == b.kind && a.group == b.group,
        ),
        ("mass", f(&a.mass) == f(&b.mass)),
        ("position", f3(&a.pos) == f3(&b.pos)),
        ("velocity", f3(&a.vel) == f3(&b.vel)),
        ("density", f(&a.rho) == f(&b.rho)),
        ("pressure", f(&a.p) == f(&b.p)),
        ("stress", f6(&a.stress) == f6(&b.stress)),
        ("rho_dev", f(&a.rho_dev) == f(&b.rho_dev)),
        ("displacement", f3(&a.tl_disp) == f3(&b.tl_disp)),
    ];
    match checks.iter().find(|c| !c.1) {
        Some((what, _)) => Err(format!("{what} differs")),
        None => Ok(()),
    }
}

/// Save after `before` steps and run on `after` more; restore the save into a fresh solver
/// and run it `after` steps: the two end states hold the same bits.
fn resumes_bit_for_bit(choice: BackendChoice, formulation: &str, before: u64, after: u64) {
    let (setup, gate) = impinging(formulation);
    let mut a = started(choice, &setup, gate);
    a.advance(before);
    let saved = a.save();
    assert_eq!(saved.steps, before);
    assert!(saved.time > 0.0);
    a.advance(after);
    let end = a.save();

    let mut b = started(choice, &setup, gate);
    b.restore(&saved).expect("a checkpoint of the same scene");
    same_bits(&b.save(), &saved).unwrap_or_else(|e| panic!("restored, not yet stepped: {e}"));
    b.advance(after);
    same_bits(&b.save(), &end).unwrap_or_else(|e| {
        panic!("{choice:?} {formulation}: after {after} steps from the checkpoint, {e}")
    });
    assert!(a.check().is_ok() && b.check().is_ok());
    // The diagnostics' sums come in a fixed order on both backends: the same bits too.
    let (da, db) = (a.diagnostics(), b.diagnostics());
    assert!(
        da.kinetic_energy.to_bits() == db.kinetic_energy.to_bits()
            && da.momentum.map(f64::to_bits) == db.momentum.map(f64::to_bits),
        "diagnostics differ: {da:?}\n{db:?}"
    );
    if formulation == "total-lagrangian" {
        assert!(
            end.tl_disp.iter().flatten().any(|&u| u != 0.0),
            "the bodies never moved: the displacements were not exercised"
        );
    } else {
        assert!(end.tl_disp.is_empty());
    }
}

#[test]
fn a_restored_cpu_solver_steps_on_bit_for_bit_jaumann() {
    resumes_bit_for_bit(BackendChoice::Cpu, "jaumann", 30, 30);
}

#[test]
fn a_restored_cpu_solver_steps_on_bit_for_bit_total_lagrangian() {
    resumes_bit_for_bit(BackendChoice::Cpu, "total-lagrangian", 30, 30);
}

#[test]
fn a_checkpoint_of_another_scene_is_refused_with_the_reason() {
    let (setup, gate) = impinging("jaumann");
    let mut a = started(BackendChoice::Cpu, &setup, gate);
    a.advance(3);
    let saved = a.save();

    // The gate still standing: more particles in the scene than in the checkpoint.
    let mut b = backend::create(BackendChoice::Cpu, backend::Layout::One, setup.clone()).unwrap();
    let e = b.restore(&saved).unwrap_err();
    assert!(e.contains("particles"), "{e}");
    assert_eq!(b.steps(), 0, "a refused restore changed the solver");

    // One mass changed (a scene edited since).
    let mut edited = saved.clone();
    edited.mass[7] *= 1.5;
    let mut c = started(BackendChoice::Cpu, &setup, gate);
    let e = c.restore(&edited).unwrap_err();
    assert!(
        e.contains("mass") && e.contains(&edited.id[7].to_string()),
        "{e}"
    );

    // Another formulation: displacements where the scene keeps none.
    let (tl_setup, _) = impinging("total-lagrangian");
    let mut d = started(BackendChoice::Cpu, &tl_setup, gate);
    let e = d.restore(&saved).unwrap_err();
    assert!(e.contains("total-Lagrangian"), "{e}");

    // A 2D checkpoint into a 3D scene.
    let mut flat = saved.clone();
    flat.dim = 3;
    let e = started(BackendChoice::Cpu, &setup, gate)
        .restore(&flat)
        .unwrap_err();
    assert!(e.contains("3D"), "{e}");
}

#[cfg(feature = "cuda")]
mod gpu {
    use super::*;

    #[test]
    #[cfg_attr(
        not(meshfree_require_cuda),
        ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
    )]
    fn a_restored_gpu_solver_steps_on_bit_for_bit_jaumann() {
        resumes_bit_for_bit(BackendChoice::Cuda, "jaumann", 61, 67);
    }

    #[test]
    #[cfg_attr(
        not(meshfree_require_cuda),
        ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
    )]
    fn a_restored_gpu_solver_steps_on_bit_for_bit_total_lagrangian() {
        resumes_bit_for_bit(BackendChoice::Cuda, "total-lagrangian", 61, 67);
    }

    /// A CPU checkpoint continued on the GPU: the other backend's sums round differently,
    /// so the runs agree as the parity tests' long runs do, not bit for bit.
    #[test]
    #[cfg_attr(
        not(meshfree_require_cuda),
        ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
    )]
    fn a_cpu_checkpoint_continues_on_the_gpu() {
        for formulation in ["jaumann", "total-lagrangian"] {
            let (setup, gate) = impinging(formulation);
            let mut c = started(BackendChoice::Cpu, &setup, gate);
            c.advance(40);
            let saved = c.save();
            let mut g = started(BackendChoice::Cuda, &setup, gate);
            g.restore(&saved).expect("a CPU checkpoint on the GPU");
            c.advance(100);
            g.advance(100);
            let (dc, dg) = (c.diagnostics(), g.diagnostics());
            eprintln!("{formulation}: cpu {dc:?}\n  gpu {dg:?}");
            assert_eq!(dc.step, dg.step);
            let rel = |a: f64, b: f64| (a - b).abs() / a.abs().max(1e-30);
            assert!(rel(dc.time, dg.time) < 1e-3, "time");
            assert!(
                rel(dc.kinetic_energy, dg.kinetic_energy) < 2e-2,
                "kinetic energy: cpu {} gpu {}",
                dc.kinetic_energy,
                dg.kinetic_energy
            );
        }
    }
}
