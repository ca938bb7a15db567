//! Checkpoints and `meshfree run --resume` (`meshfree::resume`, `output::checkpoint`): a
//! run killed with SIGKILL mid-way and resumed ends with the uninterrupted run's files, bit
//! for bit (every frame, CSV and the series; the final checkpoint's solver state); an
//! interrupted run resumes, and a finished one extends with `--t-end`; a missing, damaged or
//! foreign checkpoint and an edited scene are refused with the file and the reason.
//!
//! The scene exercises every kind of state a run carries: the impinging flow at twice the
//! spacing (a gate opened at t = 0, two elastic bodies in `bodies.csv`), with fluid
//! clusters, a force monitor, probes and a gauge, and a checkpoint every 0.4 time units.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use meshfree::output::{checkpoint, RunStatus};
use meshfree::run::{self, Progress, RunError, RunOptions};
use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::Scene;
use meshfree_core::solver::checkpoint::SolverCheckpoint;

fn scene_text() -> String {
    let text = Scene::builtin("impinging-2d").unwrap().text;
    let text = text
        .replace("spacing = 0.375", "spacing = 0.75")
        .replace("layers = 3", "layers = 2")
        .replace("end = 12.0", "end = 3.0")
        .replace("output_interval = 0.1 ", "output_interval = 0.25 ");
    assert!(text.contains("end = 3.0") && text.contains("output_interval = 0.25"));
    text + r#"
[output]
clusters = true
checkpoint_interval = 0.4

[[monitors]]
wall = 0
interval = 0.1
reference_velocity = 1.0
reference_length = 1.0

[[probes]]
name = "floor"
points = [[5.0, 1.0], [20.0, 1.0]]
interval = 0.15

[[gauges]]
name = "mid"
start = [20.0, 0.0]
end = [20.0, 30.0]
interval = 0.15
"#
}

/// The scene file in `dir`.
fn scene_file(dir: &Path) -> PathBuf {
    let path = dir.join("impinging-coarse.toml");
    std::fs::write(&path, scene_text()).unwrap();
    path
}

/// The binary under test: this build's, or `MESHFREE_BIN` (the test binary carried to a
/// GPU machine with a release build beside it).
fn meshfree() -> Command {
    Command::new(std::env::var_os("MESHFREE_BIN").unwrap_or(env!("CARGO_BIN_EXE_meshfree").into()))
}

/// Run `cmd`, which must succeed (else its stderr in the failure).
fn succeeded(cmd: &mut Command) {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn summary_json(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn solver_state(dir: &Path) -> SolverCheckpoint {
    let (s, _): (SolverCheckpoint, serde_json::Value) =
        checkpoint::read(&dir.join(checkpoint::FILE)).unwrap();
    s
}

/// Every file of `a` but the summary and the checkpoint (whose headers hold timings) has
/// the same bytes in `b`, and `b` has no other; the checkpoints' solver states agree.
fn same_output(a: &Path, b: &Path) {
    let names = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    assert_eq!(names(a), names(b), "the two runs wrote other files");
    let mut compared = 0;
    for name in names(a) {
        if name == "summary.json" || name == checkpoint::FILE {
            continue;
        }
        let (x, y) = (
            std::fs::read(a.join(&name)).unwrap(),
            std::fs::read(b.join(&name)).unwrap(),
        );
        assert!(
            x == y,
            "{name} differs between the run in one go and the resumed one"
        );
        compared += 1;
    }
    assert!(compared > 15, "only {compared} files compared");
    let (x, y) = (solver_state(a), solver_state(b));
    assert_eq!(x.steps, y.steps);
    assert!(
        x.time.to_bits() == y.time.to_bits()
            && x.pos.iter().flatten().map(|v| v.to_bits()).eq(y
                .pos
                .iter()
                .flatten()
                .map(|v| v.to_bits()))
            && x.rho
                .iter()
                .map(|v| v.to_bits())
                .eq(y.rho.iter().map(|v| v.to_bits()))
            && x.stress.iter().flatten().map(|v| v.to_bits()).eq(y
                .stress
                .iter()
                .flatten()
                .map(|v| v.to_bits())),
        "the final checkpoints' solver states differ"
    );
}

#[test]
fn a_run_killed_mid_way_and_resumed_equals_the_run_in_one_go() {
    killed_and_resumed("cpu", 3.0, 100);
}

#[test]
#[ignore = "needs a CUDA GPU: run with --include-ignored there (MESHFREE_BIN names the binary)"]
fn a_run_killed_mid_way_and_resumed_equals_the_run_in_one_go_on_the_gpu() {
    // The GPU steps this scene some 30 times faster: a longer run, killed sooner.
    killed_and_resumed("cuda", 12.0, 20);
}

/// One run in one go to `t_end`, one killed `wait_ms` after its first checkpoint and
/// resumed, on `backend`; their output compared.
fn killed_and_resumed(backend: &str, t_end: f64, wait_ms: u64) {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_file(dir.path());
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let t_end = t_end.to_string();
    let args = [
        "run",
        scene.to_str().unwrap(),
        "--backend",
        backend,
        "--t-end",
        &t_end,
        "--quiet",
        "--out",
    ];
    let whole = meshfree().args(args).arg(&a).output().unwrap();
    assert!(
        whole.status.success(),
        "{}",
        String::from_utf8_lossy(&whole.stderr)
    );

    // The same run, killed outright (SIGKILL: no handler runs) after its first checkpoint.
    let mut child = meshfree()
        .args(args)
        .arg(&b)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while !b.join(checkpoint::FILE).exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its first checkpoint"
        );
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no checkpoint after 2 min"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    std::thread::sleep(Duration::from_millis(wait_ms));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the run finished before it was killed: nothing was resumed"
    );
    child.kill().unwrap();
    child.wait().unwrap();
    assert_eq!(
        summary_json(&b)["status"],
        "running",
        "a killed run leaves `running`"
    );
    let killed_at = solver_state(&b).time;
    assert!(
        killed_at > 0.0 && killed_at < 3.0,
        "checkpoint at t = {killed_at}"
    );

    succeeded(
        meshfree()
            .args(["run", "--resume"])
            .arg(&b)
            .args(["--backend", backend, "--quiet"]),
    );
    same_output(&a, &b);
    let (sa, sb) = (summary_json(&a), summary_json(&b));
    assert_eq!(sb["status"], "completed");
    assert_eq!(sa["steps"], sb["steps"], "the summary counts the whole run");
    assert_eq!(sa["outputs"], sb["outputs"]);
    assert_eq!(
        sa["monitors"], sb["monitors"],
        "the monitors' statistics take every sample"
    );
    assert_eq!(
        sa["bodies"], sb["bodies"],
        "the bodies' extremes carry over"
    );
    assert_eq!(sb["resumed_from"].as_array().unwrap().len(), 1);
    assert_eq!(sb["resumed_from"][0], killed_at);
    assert_eq!(
        sa["checkpoint_time"], sa["simulated_time"],
        "one at the end"
    );
}

/// Quiet runs on the CPU.
fn quiet() -> RunOptions {
    RunOptions {
        backend: BackendChoice::Cpu,
        progress: Progress::Quiet,
        ..Default::default()
    }
}

/// `scene` run in one go into `dir/a`, and into `dir/b` stopped through `stop` at its
/// frame `stop_at`: the two directories and the stopped run's error.
fn one_go_and_stopped(
    scene: &Scene,
    dir: &Path,
    stop_at: usize,
    stop: &'static AtomicBool,
    quiet: &RunOptions,
) -> (PathBuf, PathBuf, RunError) {
    let (a, b) = (dir.join("a"), dir.join("b"));
    run::run(
        scene,
        &RunOptions {
            out_dir: Some(a.clone()),
            ..quiet.clone()
        },
    )
    .unwrap();
    let err = run::run_observed(
        scene,
        &RunOptions {
            out_dir: Some(b.clone()),
            interrupt: Some(stop),
            ..quiet.clone()
        },
        &mut |f| {
            if f.index == stop_at {
                stop.store(true, Ordering::SeqCst);
            }
        },
    )
    .unwrap_err();
    (a, b, err)
}

#[test]
fn an_interrupted_run_resumes_and_a_finished_one_extends() {
    static STOP: AtomicBool = AtomicBool::new(false);
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::from_file(scene_file(dir.path())).unwrap();
    let quiet = quiet();
    let (a, b, err) = one_go_and_stopped(&scene, dir.path(), 3, &STOP, &quiet);
    let RunError::Interrupted { summary, .. } = &err else {
        panic!("expected an interruption, got {err}")
    };
    assert!(err.to_string().contains("--resume"), "{err}");
    assert_eq!(
        summary.checkpoint_time,
        Some(summary.simulated_time),
        "the stop writes a checkpoint of the state it reached"
    );
    // The stop's last frame (off the output times) is rolled back with its series entry.
    let done = run::resume(&b, &quiet).unwrap();
    assert_eq!(done.status, RunStatus::Completed);
    same_output(&a, &b);

    // Resumed again without --t-end: finished already, it completes at once, unchanged.
    let again = run::resume(&b, &quiet).unwrap();
    assert_eq!(again.status, RunStatus::Completed);
    assert_eq!((again.steps, again.outputs), (done.steps, done.outputs));
    same_output(&a, &b);

    // Extended past its end: two more outputs, and the resumes listed.
    let more = run::resume(
        &b,
        &RunOptions {
            t_end: Some(3.5),
            ..quiet.clone()
        },
    )
    .unwrap();
    assert!(more.simulated_time >= 3.5 - 1e-9, "{}", more.simulated_time);
    assert_eq!(more.outputs, done.outputs + 2);
    assert_eq!(more.resumed_from.len(), 3);
    assert!(b.join("particles_00014.vtu").exists());

    // An end before the checkpoint is refused.
    let e = run::resume(
        &b,
        &RunOptions {
            t_end: Some(1.0),
            ..quiet
        },
    )
    .unwrap_err();
    assert!(matches!(e, RunError::Checkpoint { .. }), "{e}");
    assert!(e.to_string().contains("before the checkpoint"), "{e}");
}

#[test]
fn a_missing_damaged_or_foreign_checkpoint_is_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let scene = scene_file(dir.path());
    let out = dir.path().join("r");
    let resume = |d: &Path| {
        meshfree()
            .args(["run", "--resume"])
            .arg(d)
            .args(["--backend", "cpu", "--quiet"])
            .output()
            .unwrap()
    };
    let refused = |o: &std::process::Output, words: &[&str]| {
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        for w in words {
            assert!(err.contains(w), "`{w}` not in: {err}");
        }
    };
    refused(&resume(&out), &["checkpoint.bin", "no run's output"]);

    // A run stopped by --steps has one; a damaged copy is refused, and nothing is changed.
    let o = meshfree()
        .args([
            "run",
            scene.to_str().unwrap(),
            "--backend",
            "cpu",
            "--quiet",
            "--steps",
            "30",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let path = out.join(checkpoint::FILE);
    let good = std::fs::read(&path).unwrap();
    let mut bad = good.clone();
    let k = bad.len() - 100;
    bad[k] ^= 1;
    std::fs::write(&path, &bad).unwrap();
    let before = std::fs::read(out.join("diagnostics.csv")).unwrap();
    refused(&resume(&out), &["checkpoint.bin", "damaged", "checksum"]);
    std::fs::write(&path, &good[..good.len() / 2]).unwrap();
    refused(&resume(&out), &["damaged"]);
    std::fs::write(&path, b"not a checkpoint at all").unwrap();
    refused(&resume(&out), &["not a meshfree checkpoint"]);
    assert_eq!(std::fs::read(out.join("diagnostics.csv")).unwrap(), before);

    // The run's scene edited since.
    std::fs::write(&path, &good).unwrap();
    let copy = out.join("scene.toml");
    let text = std::fs::read_to_string(&copy).unwrap();
    std::fs::write(&copy, text.replace("alpha = 0.02", "alpha = 0.03")).unwrap();
    refused(&resume(&out), &["scene.toml", "edited"]);
    std::fs::write(&copy, text).unwrap();

    // A run directory's shortened CSV: the output was damaged since the checkpoint.
    std::fs::write(out.join("forces.csv"), "t\n").unwrap();
    refused(&resume(&out), &["forces.csv", "damaged"]);
}

/// A wave maker's paddle and a damping zone (issues #54, #57) read the clock: a run
/// stopped mid-way resumes from its checkpoint's time with the paddle where the run in one
/// go has it, bit for bit.
#[test]
fn a_flume_stopped_and_resumed_equals_the_run_in_one_go() {
    static STOP: AtomicBool = AtomicBool::new(false);
    let dir = tempfile::tempdir().unwrap();
    let text = Scene::builtin("flume-2d")
        .unwrap()
        .text
        .replace("spacing = 0.01 ", "spacing = 0.02 ")
        .replace("end = 12.0 ", "end = 0.4 ")
        .replace("output_interval = 0.05", "output_interval = 0.025");
    assert!(text.contains("end = 0.4 ") && text.contains("spacing = 0.02 "));
    let path = dir.path().join("flume.toml");
    std::fs::write(&path, text).unwrap();
    let scene = Scene::from_file(&path).unwrap();
    let quiet = quiet();
    let (a, b, err) = one_go_and_stopped(&scene, dir.path(), 4, &STOP, &quiet);
    assert!(matches!(err, RunError::Interrupted { .. }), "{err}");
    let done = run::resume(&b, &quiet).unwrap();
    assert_eq!(done.status, RunStatus::Completed);
    same_output(&a, &b);
}

/// A run copies its motion series' files into its directory (`motion-N.csv`) and its copy
/// of the scene names them there, so it resumes, bit for bit, after the original file is
/// gone (issue #54).
#[test]
fn a_run_with_a_motion_series_resumes_without_the_original() {
    static STOP: AtomicBool = AtomicBool::new(false);
    let dir = tempfile::tempdir().unwrap();
    // dam-break-2d's gate lifted by a recorded series at twice the spacing.
    std::fs::write(dir.path().join("gate.csv"), "t y\n0 0\n0.1 0.02\n1 1\n").unwrap();
    let text = Scene::builtin("dam-break-2d")
        .unwrap()
        .text
        .replace(
            "remove_at = 0.0 ",
            "motion = { series = { file = \"gate.csv\" } } # lifted ",
        )
        .replace("spacing = 0.02 ", "spacing = 0.04 ")
        .replace("min = [-0.1, -0.1] ", "min = [-0.2, -0.2] ")
        .replace("max = [4.1, 2.1] ", "max = [4.2, 2.2] ")
        .replace("end = 2.0 ", "end = 0.3 ");
    assert!(text.contains("gate.csv") && text.contains("end = 0.3 "));
    let path = dir.path().join("gate.toml");
    std::fs::write(&path, text).unwrap();
    let scene = Scene::from_file(&path).unwrap();
    let quiet = quiet();
    let (a, b, err) = one_go_and_stopped(&scene, dir.path(), 4, &STOP, &quiet);
    assert!(matches!(err, RunError::Interrupted { .. }), "{err}");
    let copy = std::fs::read_to_string(b.join("scene.toml")).unwrap();
    assert!(
        copy.contains("motion = { series = { file = \"motion-0.csv\" } } # lifted"),
        "{copy}"
    );
    assert_eq!(
        std::fs::read(b.join("motion-0.csv")).unwrap(),
        std::fs::read(dir.path().join("gate.csv")).unwrap()
    );
    std::fs::remove_file(dir.path().join("gate.csv")).unwrap();
    let done = run::resume(&b, &quiet).unwrap();
    assert_eq!(done.status, RunStatus::Completed);
    same_output(&a, &b);
    assert!(
        done.files.iter().any(|f| f == "motion-0.csv"),
        "{:?}",
        done.files
    );
}

/// A scene's surface files (issue #53) travel with its run: the run copies them beside its
/// scene (`surface-N.<ext>`), so the run resumes, bit for bit, after the original file is
/// gone; `--overwrite` removes the copies with the rest of the run's files.
#[test]
fn a_run_with_a_surface_file_resumes_without_the_original() {
    static STOP: AtomicBool = AtomicBool::new(false);
    let dir = tempfile::tempdir().unwrap();
    // dam-break-2d's tank as a polygon from a file of points, at twice the spacing.
    std::fs::write(dir.path().join("tank.csv"), "x,y\n0,0\n4,0\n4,2\n0,2\n").unwrap();
    let text = Scene::builtin("dam-break-2d")
        .unwrap()
        .text
        .replace(
            "shape = \"box-container\"\nmin = [0.0, 0.0]\nmax = [4.0, 2.0]",
            "shape = \"polygon\"\npolygon = { file = \"tank.csv\" } # the tank\nsolid = \"outside\"",
        )
        .replacen("open_top = false", "# closed", 1)
        .replace("spacing = 0.02 ", "spacing = 0.04 ")
        .replace("min = [-0.1, -0.1] ", "min = [-0.2, -0.2] ")
        .replace("max = [4.1, 2.1] ", "max = [4.2, 2.2] ")
        .replace("end = 2.0 ", "end = 0.3 ");
    assert!(
        text.contains("tank.csv") && text.contains("end = 0.3 ") && text.contains("[4.2, 2.2]")
    );
    let path = dir.path().join("tank.toml");
    std::fs::write(&path, text).unwrap();
    let scene = Scene::from_file(&path).unwrap();
    let quiet = quiet();
    let (a, b, err) = one_go_and_stopped(&scene, dir.path(), 4, &STOP, &quiet);
    assert!(matches!(err, RunError::Interrupted { .. }), "{err}");
    let copy = std::fs::read_to_string(b.join("scene.toml")).unwrap();
    assert!(
        copy.contains("polygon = { file = \"surface-0.csv\" } # the tank"),
        "{copy}"
    );
    assert_eq!(
        std::fs::read(b.join("surface-0.csv")).unwrap(),
        std::fs::read(dir.path().join("tank.csv")).unwrap()
    );
    std::fs::remove_file(dir.path().join("tank.csv")).unwrap();
    let done = run::resume(&b, &quiet).unwrap();
    assert_eq!(done.status, RunStatus::Completed);
    same_output(&a, &b);
    // A new run over it removes the copy with the rest (the scene has no surface file now:
    // a box container).
    let plain = Scene::builtin("dam-break-2d").unwrap();
    let plain = plain
        .with_overrides(&meshfree_core::scene::Overrides {
            t_end: Some(0.02),
            output_interval: None,
        })
        .unwrap();
    run::run(
        &plain,
        &RunOptions {
            out_dir: Some(b.clone()),
            overwrite: true,
            ..quiet
        },
    )
    .unwrap();
    assert!(!b.join("surface-0.csv").exists());
}

/// A floating body's run resumes (its `floating.csv` is the monitors' file of the
/// checkpoint) and ends with the rows of the run in one go.
#[test]
fn a_floating_run_resumes_with_its_rows() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let go = |dir: &Path, t_end: &str| {
        succeeded(
            meshfree()
                .args([
                    "run",
                    "floating-box-2d",
                    "--backend",
                    "cpu",
                    "--format",
                    "none",
                ])
                .args([
                    "--output-interval",
                    "0.025",
                    "--quiet",
                    "--t-end",
                    t_end,
                    "--out",
                ])
                .arg(dir),
        )
    };
    go(&a, "0.1");
    go(&b, "0.05");
    succeeded(
        meshfree()
            .args(["run", "--resume"])
            .arg(&b)
            .args(["--t-end", "0.1", "--quiet"]),
    );
    let rows = |d: &Path| std::fs::read_to_string(d.join("floating.csv")).unwrap();
    assert_eq!(rows(&a).lines().count(), 1 + 5);
    assert_eq!(rows(&a), rows(&b));
}
