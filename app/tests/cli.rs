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
