//! How a run ends besides completing: interrupted (a signal, or the caller's flag), refused
//! because its output directory holds another run, and the exit statuses that tell them
//! apart (`meshfree run --help`).

use std::path::Path;
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use meshfree::output::RunStatus;
use meshfree::run::{self, Progress, RunError, RunOptions};
use meshfree_core::scene::Scene;

fn summary_json(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn a_raised_flag_stops_the_run_with_a_last_frame_and_an_interrupted_summary() {
    static STOP: AtomicBool = AtomicBool::new(false);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r");
    let options = RunOptions {
        out_dir: Some(out.clone()),
        max_steps: Some(400),
        output_interval: Some(1e-3),
        progress: Progress::Quiet,
        interrupt: Some(&STOP),
        ..Default::default()
    };
    let (mut frames, mut last_step) = (0, 0);
    let err = run::run_observed(&Scene::builtin("tank-2d").unwrap(), &options, &mut |f| {
        frames += 1;
        last_step = f.data.step;
        // Raised after the second frame: the run stops within a batch of steps.
        if f.index == 1 {
            STOP.store(true, Ordering::SeqCst);
        }
    })
    .unwrap_err();
    let RunError::Interrupted { summary, .. } = &err else {
        panic!("expected an interruption, got {err}")
    };
    assert_eq!(summary.status, RunStatus::Interrupted);
    assert!(
        summary.steps < 400,
        "{} steps: the flag did not stop it",
        summary.steps
    );
    // The state it reached is the last frame, and the summary on disk says so.
    let written = summary_json(&out);
    assert_eq!(written["status"], "interrupted");
    assert_eq!(written["steps"], summary.steps);
    assert_eq!(written["outputs"], frames);
    // (The stop may come right after an output, which then is that state.)
    assert_eq!(
        last_step, summary.steps,
        "{frames} frames: the state at the stop was not written"
    );
    assert!(err.to_string().contains("interrupted by"), "{err}");
}

#[test]
fn an_earlier_runs_directory_is_refused_unless_overwrite_and_foreign_files_are_kept() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let scene = Scene::builtin("tank-2d").unwrap();
    let mut options = RunOptions {
        out_dir: Some(out.clone()),
        max_steps: Some(2),
        progress: Progress::Quiet,
        ..Default::default()
    };
    run::run(&scene, &options).unwrap();
    let err = run::run(&scene, &options).unwrap_err();
    assert!(
        matches!(err, RunError::OutputInUse { .. }) && err.to_string().contains("--overwrite"),
        "{err}"
    );
    options.overwrite = true;
    let s = run::run(&scene, &options).unwrap();
    assert_eq!(s.status, RunStatus::Completed);
    assert_eq!(summary_json(&out)["status"], "completed");

    // The user's own files beside a run, of the extensions a run writes too: --overwrite
    // removes exactly the earlier run's files and keeps these (issue #52).
    let mine = [
        "notes.txt",
        "plot.png",
        "data.csv",
        "extra.json",
        "old.bin",
        "x.vtu",
    ];
    for name in mine {
        std::fs::write(out.join(name), "mine").unwrap();
    }
    run::run(&scene, &options).unwrap();
    for name in mine {
        assert_eq!(
            std::fs::read_to_string(out.join(name)).unwrap(),
            "mine",
            "{name}"
        );
    }

    // A file of a name the run writes that the earlier run's summary does not list (tank-2d
    // counts no clusters): refused, not replaced, and nothing is removed.
    std::fs::write(out.join("clusters.csv"), "mine").unwrap();
    let err = run::run(&scene, &options).unwrap_err();
    assert!(err.to_string().contains("clusters.csv"), "{err}");
    assert_eq!(
        std::fs::read_to_string(out.join("clusters.csv")).unwrap(),
        "mine"
    );
    assert!(
        out.join("summary.json").exists(),
        "nothing is removed when refusing"
    );
}

#[test]
fn a_fresh_directory_with_a_file_or_link_of_a_run_files_name_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Scene::builtin("tank-2d").unwrap();
    let victim = dir.path().join("victim.txt");
    std::fs::write(&victim, "keep").unwrap();
    for (k, name) in ["diagnostics.csv", "scene.toml", "summary.json.tmp"]
        .iter()
        .enumerate()
    {
        let out = dir.path().join(format!("o{k}"));
        std::fs::create_dir_all(&out).unwrap();
        std::os::unix::fs::symlink(&victim, out.join(name)).unwrap();
        let options = RunOptions {
            out_dir: Some(out.clone()),
            max_steps: Some(2),
            progress: Progress::Quiet,
            overwrite: k == 2,
            ..Default::default()
        };
        let err = run::run(&scene, &options).unwrap_err();
        assert!(
            matches!(err, RunError::OutputInUse { .. }) && err.to_string().contains(name),
            "{name}: {err}"
        );
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep", "{name}");
        let left: Vec<_> = std::fs::read_dir(&out).unwrap().collect();
        assert_eq!(left.len(), 1, "{name}: the refused run wrote nothing");
    }
}

#[test]
fn a_scene_files_default_output_is_named_after_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("my-copy.toml");
    std::fs::write(&path, &Scene::builtin("tank-2d").unwrap().text).unwrap();
    let from_file = Scene::from_file(&path).unwrap();
    assert_eq!(run::default_out_dir(&from_file), Path::new("out/my-copy"));
    let paper = from_file.with_paper_exact().unwrap();
    assert_eq!(
        run::default_out_dir(&paper),
        Path::new("out/my-copy-paper-exact")
    );
    let builtin = Scene::builtin("tank-2d").unwrap();
    assert_eq!(run::default_out_dir(&builtin), Path::new("out/tank-2d"));
}

fn meshfree(args: &[&str], out: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_meshfree"))
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

#[test]
fn exit_statuses_tell_bad_input_and_a_directory_in_use_from_success() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("e");
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "dimension = 4\n").unwrap();
    let o = meshfree(&["run", bad.to_str().unwrap(), "--quiet"], &out);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!out.exists(), "a refused scene writes nothing");

    let args = [
        "run",
        "tank-2d",
        "--backend",
        "cpu",
        "--steps",
        "2",
        "--quiet",
    ];
    let o = meshfree(&args, &out);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = meshfree(&args, &out);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("--overwrite"));
    let mut again = args.to_vec();
    again.push("--overwrite");
    let o = meshfree(&again, &out);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[cfg(unix)]
#[test]
fn sigint_and_sigterm_stop_the_binary_with_status_130_and_an_interrupted_summary() {
    for (sig, name) in [(libc::SIGINT, "SIGINT"), (libc::SIGTERM, "SIGTERM")] {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("s");
        let mut child = Command::new(env!("CARGO_BIN_EXE_meshfree"))
            .args([
                "run",
                "tank-2d",
                "--backend",
                "cpu",
                "--quiet",
                "--t-end",
                "1000",
                "--output-interval",
                "1000",
                "--out",
            ])
            .arg(&out)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // The first frame lands once the run is stepping.
        let started = Instant::now();
        while !out.join("particles_00000.vtu").exists() {
            assert!(
                started.elapsed() < Duration::from_secs(60),
                "the run never started"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        assert_eq!(summary_json(&out)["status"], "running");
        // SAFETY: kill with a live child's pid and a valid signal number.
        assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, sig) }, 0);
        let status = child.wait().unwrap();
        let mut stderr = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
        assert_eq!(status.code(), Some(130), "{name}: {stderr}");
        assert!(
            stderr.contains(&format!("interrupted by {name}")),
            "{stderr}"
        );
        let s = summary_json(&out);
        assert_eq!(s["status"], "interrupted");
        assert_eq!(s["interrupted_by"], name);
        assert!(s["steps"].as_u64().unwrap() > 0);
        assert_eq!(s["outputs"], 2, "the first frame and the state at the stop");
    }
}

#[test]
fn a_time_step_that_collapses_stops_the_run_with_a_fault_naming_the_term() {
    let dir = tempfile::tempdir().unwrap();
    let mut scene = Scene::builtin("tank-2d").unwrap();
    // The viscous limit of the step takes dt to ~1e-35 s: it used to step forever.
    scene.file.fluid.viscosity = 1e30;
    scene.revalidate().unwrap();
    let options = RunOptions {
        out_dir: Some(dir.path().join("g")),
        progress: Progress::Quiet,
        ..Default::default()
    };
    let started = Instant::now();
    let err = run::run(&scene, &options).unwrap_err();
    assert!(started.elapsed() < Duration::from_secs(60));
    let RunError::BlowUp { fault, summary, .. } = &err else {
        panic!("expected a fault, got {err}")
    };
    assert_eq!(fault.quantity, "time step");
    assert!(fault.value < 1e-12, "{fault}");
    assert!(fault.reason.contains("viscous term"), "{fault}");
    assert!(
        fault.particle != u32::MAX && fault.kind == "fluid",
        "{fault}"
    );
    assert_eq!(summary.status, RunStatus::Failed);
}

#[test]
fn a_scene_too_large_for_the_limit_is_refused_before_generation() {
    let dir = tempfile::tempdir().unwrap();
    let options = RunOptions {
        out_dir: Some(dir.path().join("big")),
        progress: Progress::Quiet,
        max_particles: Some(1000),
        ..Default::default()
    };
    let err = run::run(&Scene::builtin("tank-2d").unwrap(), &options).unwrap_err();
    let RunError::Scene(e) = &err else {
        panic!("expected a scene error, got {err}")
    };
    assert_eq!(e.field(), Some("discretisation.spacing"), "{err}");
    assert!(err.to_string().contains("--max-particles 1000"), "{err}");
    assert!(!dir.path().join("big").exists(), "nothing written");
}

#[test]
fn check_answers_at_once_for_a_scene_of_a_billion_particles() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.toml");
    let text = Scene::builtin("tank-2d").unwrap().text;
    let spacing = text
        .lines()
        .find(|l| l.trim_start().starts_with("spacing"))
        .unwrap();
    std::fs::write(&path, text.replacen(spacing, "spacing = 2.5e-5", 1)).unwrap();
    let started = Instant::now();
    let o = Command::new(env!("CARGO_BIN_EXE_meshfree"))
        .args(["check", path.to_str().unwrap()])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        started.elapsed() < Duration::from_secs(5),
        "check took {:?}",
        started.elapsed()
    );
    // Either the estimate (this machine holds it) or a refusal naming the spacing.
    assert!(
        (o.status.success() && out.contains("estimated"))
            || (o.status.code() == Some(2) && err.contains("discretisation.spacing")),
        "{out}{err}"
    );
}
