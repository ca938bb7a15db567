//! The `meshfree` binary end to end.

use std::process::Command;

fn meshfree(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_meshfree"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn help_teaches() {
    let o = meshfree(&["--help"]);
    assert!(o.status.success());
    let s = String::from_utf8_lossy(&o.stdout);
    for want in [
        "run",
        "scenes",
        "check",
        "Examples:",
        "meshfree run dam-break-2d",
    ] {
        assert!(s.contains(want), "`{want}` missing from --help:\n{s}");
    }
    let o = meshfree(&["run", "--help"]);
    let s = String::from_utf8_lossy(&o.stdout);
    for want in [
        "--backend",
        "--out",
        "--t-end",
        "--steps",
        "--output-interval",
        "--quiet",
        "cuda",
    ] {
        assert!(s.contains(want), "`{want}` missing from run --help:\n{s}");
    }
}

#[test]
fn scenes_json_parses() {
    let o = meshfree(&["scenes", "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let rows = v.as_array().unwrap();
    assert_eq!(rows.len(), meshfree_core::scene::BUILTIN.len());
    for r in rows {
        let n = |k: &str| r[k].as_u64().unwrap();
        assert_eq!(n("fluid") + n("solid") + n("boundary"), n("total"));
        assert!(r["dimension"] == 2 || r["dimension"] == 3);
    }
    assert!(rows
        .iter()
        .any(|r| r["name"] == "dam-break-2d" && r["fluid"] == 2500));
    let o = meshfree(&["scenes"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("tank-2d"));
}

#[test]
fn scenes_reference_is_the_committed_one() {
    let o = meshfree(&["scenes", "--reference"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let committed = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/reference/scene.md"),
    )
    .unwrap();
    assert!(
        String::from_utf8_lossy(&o.stdout) == committed,
        "docs/reference/scene.md is stale: meshfree scenes --reference > docs/reference/scene.md"
    );
}

#[test]
fn check_writes_nothing() {
    let o = meshfree(&["check", "tank-2d"]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout).contains("2026 particles"));
}

/// `check` reports an open line as one: its length and that its sides come from its order.
#[test]
fn check_reports_an_open_line() {
    let o = meshfree(&["check", "beach-2d"]);
    assert!(o.status.success());
    let out = String::from_utf8_lossy(&o.stdout);
    let line = out
        .lines()
        .find(|l| l.contains("walls[1].polygon"))
        .unwrap_or_else(|| panic!("{out}"));
    // The beach: from (2.5, 0) to (5, 0.5), 2.5495 long.
    assert!(
        line.contains("1 edges")
            && line.contains("length 2.549510")
            && line.contains("open: its sides from its faces' order"),
        "{line}"
    );
}

#[test]
fn unknown_scene_fails() {
    let o = meshfree(&["run", "no-such-scene", "--quiet"]);
    assert!(!o.status.success());
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.starts_with("error: builtin:no-such-scene: no built-in scene"),
        "{e}"
    );
}

/// Needs a working backend (the CPU one).
#[test]
fn tiny_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/tank-2d.toml");
    let o = Command::new(env!("CARGO_BIN_EXE_meshfree"))
        .args([
            "run",
            scene.to_str().unwrap(),
            "--backend",
            "cpu",
            "--steps",
            "5",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    // Not a terminal: plain progress lines naming the backend.
    assert!(stderr.contains("on cpu ("), "{stderr}");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("5 steps"), "{stdout}");
    for f in [
        "particles.pvd",
        "particles_00000.vtu",
        "particles_00001.vtu",
        "diagnostics.csv",
        "summary.json",
        "scene.toml",
    ] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["steps"], 5);
    assert_eq!(json["backend"], "cpu");
    assert_eq!(json["scene_source"], scene.display().to_string());
}

#[test]
fn quiet_run_prints_nothing_on_stderr() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("q");
    let o = Command::new(env!("CARGO_BIN_EXE_meshfree"))
        .args([
            "run",
            "tank-2d",
            "--backend",
            "cpu",
            "--steps",
            "2",
            "--quiet",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// `run --decompose 3` writes the one-domain run's particle files, byte for byte (the
/// particles are the same bits and each file is sorted by id), and the same clock in
/// diagnostics.csv; a scene that cannot be decomposed is bad input (exit 2) with the reason.
#[test]
fn a_decomposed_run_writes_the_one_domain_files() {
    let dir = std::env::temp_dir().join(format!("meshfree-decompose-{}", std::process::id()));
    let run = |out: &str, extra: &[&str]| {
        let out = dir.join(out);
        let mut args = vec![
            "run",
            "dam-break-2d",
            "--backend",
            "cpu",
            "--t-end",
            "0.03",
            "--format",
            "csv",
            "--quiet",
            "--overwrite",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = meshfree(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        out
    };
    let (one, three) = (run("one", &[]), run("three", &["--decompose", "3"]));
    let frames: Vec<_> = std::fs::read_dir(&one)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|f| f.starts_with("particles_") && f.ends_with(".csv"))
        .collect();
    assert!(frames.len() >= 2, "{frames:?}");
    for f in &frames {
        let (a, b) = (
            std::fs::read(one.join(f)).unwrap(),
            std::fs::read(three.join(f)).unwrap(),
        );
        assert!(a == b, "{f} differs between one domain and 3 subdomains");
    }
    let clock = |d: &std::path::Path| {
        std::fs::read_to_string(d.join("diagnostics.csv"))
            .unwrap()
            .lines()
            .map(|l| l.split(',').take(3).collect::<Vec<_>>().join(","))
            .collect::<Vec<_>>()
    };
    assert_eq!(clock(&one), clock(&three));
    let summary = std::fs::read_to_string(three.join("summary.json")).unwrap();
    assert!(summary.contains("3 subdomains along x"), "{summary}");

    let tl = dir.join("tl.toml");
    let text = meshfree_core::scene::Scene::builtin("impinging-2d")
        .unwrap()
        .text
        .replace("[solid]\n", "[solid]\nformulation = \"total-lagrangian\"\n");
    std::fs::write(&tl, text).unwrap();
    let o = meshfree(&[
        "run",
        tl.to_str().unwrap(),
        "--backend",
        "cpu",
        "--decompose",
        "2",
        "--out",
        dir.join("tl").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("total-Lagrangian"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `run --gpus N` where NCCL or the GPUs are missing (as here, without a GPU) stops before
/// writing anything, saying what is missing; it takes no `--backend` (always CUDA).
#[test]
fn gpus_without_nccl_or_gpus_say_what_is_missing_and_write_nothing() {
    let out = std::env::temp_dir().join(format!("meshfree-gpus-{}", std::process::id()));
    let o = meshfree(&[
        "run",
        "dam-break-2d",
        "--gpus",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    if o.status.success() {
        // A machine with two GPUs and NCCL: the run is the multi-GPU tests' business.
        let _ = std::fs::remove_dir_all(&out);
        return;
    }
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("NCCL") || err.contains("CUDA"), "{err}");
    assert!(!out.exists(), "a refused run left {}", out.display());
    let o = meshfree(&["run", "dam-break-2d", "--gpus", "2", "--backend", "cpu"]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A run writes checkpoints by wall time without being asked (`--checkpoint-every`, 10
/// minutes by default; here a few milliseconds), so one killed outright resumes (#51).
#[test]
fn a_killed_run_resumes_from_its_wall_clock_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("k");
    let mut child = Command::new(env!("CARGO_BIN_EXE_meshfree"))
        .args(["run", "tank-2d", "--backend", "cpu", "--quiet"])
        .args(["--checkpoint-every", "0.0002", "--out"])
        .arg(&out)
        .spawn()
        .unwrap();
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while !out.join("checkpoint.bin").exists() {
        assert!(
            std::time::Instant::now() < deadline,
            "no checkpoint by wall time"
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    std::thread::sleep(std::time::Duration::from_millis(100));
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let o = meshfree(&[
        "run",
        "--resume",
        out.to_str().unwrap(),
        "--steps",
        "5",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let from = s["resumed_from"][0].as_f64().unwrap();
    assert!(from > 0.0, "resumed from t = {from}");
}

/// `view` without a display points to `render`, not into winit's sources (#51).
#[cfg(feature = "viewer")]
#[test]
fn view_without_a_display_points_to_render() {
    let dir = tempfile::tempdir().unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_meshfree"))
        .args(["view", "tank-2d", "--backend", "cpu"])
        .current_dir(dir.path())
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("meshfree render"), "{err}");
    assert!(!err.contains(".cargo"), "{err}");
}
