//! Known failures stay known: the paper's forward Euler past its CFL limit blows up, and the
//! run stops with a message naming the step, time, particle and quantity (no NaN output);
//! the symplectic Euler at the same step size survives.

use meshfree::run::{run, Progress, RunError, RunOptions};
use meshfree::scene::format::IntegratorChoice;
use meshfree::scene::Scene;

fn tank(integrator: IntegratorChoice, courant: f64) -> Scene {
    let mut s = Scene::builtin("tank-2d")
        .unwrap()
        .with_spacing(0.05)
        .unwrap();
    s.file.time.courant = courant;
    s.file.time.end = 0.5;
    s.file.time.integrator = integrator;
    s.revalidate().unwrap();
    s
}

fn options(dir: &std::path::Path) -> RunOptions {
    RunOptions {
        backend: meshfree::backend::BackendChoice::Cpu,
        out_dir: Some(dir.to_path_buf()),
        t_end: None,
        max_steps: None,
        output_interval: Some(0.05),
        progress: Progress::Quiet,
        particle_csv: false,
    }
}

#[test]
fn forward_euler_past_its_cfl_limit_blows_up_with_a_clear_report() {
    let dir = tempfile::tempdir().unwrap();
    let err = run(&tank(IntegratorChoice::Euler, 1.5), &options(dir.path()))
        .expect_err("forward Euler at Courant 1.5 must fail");
    let RunError::BlowUp { fault, summary, .. } = err else {
        panic!("expected a blow-up, got {err}")
    };
    let text = fault.to_string();
    assert!(
        text.contains("step") && text.contains("particle") && text.contains(&fault.quantity),
        "{text}"
    );
    assert!(fault.step > 0 && fault.time > 0.0, "{fault:?}");
    assert_eq!(summary.fault.as_ref(), Some(fault.as_ref()));
    // The output written before the blow-up holds no NaN.
    for e in std::fs::read_dir(dir.path()).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "vtu" || x == "csv") {
            let t = std::fs::read_to_string(&p).unwrap();
            assert!(
                !t.contains("NaN") && !t.contains("nan"),
                "{} holds NaN",
                p.display()
            );
        }
    }
    let summary_json = std::fs::read_to_string(dir.path().join("summary.json")).unwrap();
    assert!(summary_json.contains("\"failed\""), "{summary_json}");
}

#[test]
fn symplectic_euler_survives_where_forward_euler_fails() {
    let dir = tempfile::tempdir().unwrap();
    // The same tank at Courant 0.4 with each integrator.
    let euler = run(
        &tank(IntegratorChoice::Euler, 0.4),
        &options(&dir.path().join("e")),
    );
    assert!(
        matches!(euler, Err(RunError::BlowUp { .. })),
        "forward Euler at Courant 0.4 should blow up in 0.5 T"
    );
    let symplectic = run(
        &tank(IntegratorChoice::SymplecticEuler, 0.4),
        &options(&dir.path().join("s")),
    );
    assert!(
        symplectic.is_ok(),
        "symplectic Euler at Courant 0.4 failed: {:?}",
        symplectic.err().map(|e| e.to_string())
    );
}
