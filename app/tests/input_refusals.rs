//! Bad input through the binary ends in exit status 2 naming what to change (issue #52):
//! a command-line override is blamed on its flag, `compare`'s unreadable files are bad
//! input, an endless scene file is refused without filling memory, and a scene that needs
//! more memory than the address-space limit allows is refused by `check`.

use std::process::{Command, Output};

fn meshfree(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_meshfree"))
        .args(args)
        .output()
        .unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn a_bad_t_end_is_blamed_on_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    for value in ["nan", "-1", "0"] {
        let flag = format!("--t-end={value}");
        let o = meshfree(&["run", "tank-2d", &flag, "--out", out, "--quiet"]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.starts_with("error: command line: --t-end: ")
                && e.contains("time.end of builtin:tank-2d"),
            "{e}"
        );
        assert!(!std::path::Path::new(out).exists());
    }
    // A bad output interval likewise.
    let o = meshfree(&["run", "tank-2d", "--output-interval=-0.1", "--out", out]);
    assert!(
        stderr(&o).starts_with("error: command line: --output-interval: "),
        "{}",
        stderr(&o)
    );
}

#[test]
fn compare_refuses_unreadable_files_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "id,kind,x\n0,fluid,zero\n").unwrap();
    let missing = dir.path().join("missing.csv");
    for (a, what) in [(&missing, "missing.csv"), (&bad, "bad.csv")] {
        let o = meshfree(&["compare", a.to_str().unwrap(), bad.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(stderr(&o).contains(what), "{}", stderr(&o));
    }
}

#[test]
fn an_endless_scene_file_is_refused() {
    if !std::path::Path::new("/dev/zero").exists() {
        return;
    }
    let o = meshfree(&["check", "/dev/zero"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).starts_with("error: /dev/zero: the file is larger than 16 MiB"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn check_holds_the_estimate_against_the_address_space_limit() {
    // tank-2d at a 100th of its spacing: 1.6e7 particles, about 6.5 GB to start, under a
    // 3 GiB address space.
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("fine.toml");
    let text = meshfree_core::scene::Scene::builtin("tank-2d")
        .unwrap()
        .text
        .replace("spacing = 0.025", "spacing = 0.00025");
    std::fs::write(&scene, text).unwrap();
    let script = format!(
        "ulimit -v 3145728 && exec '{}' check '{}'",
        env!("CARGO_BIN_EXE_meshfree"),
        scene.display()
    );
    let o = Command::new("sh").arg("-c").arg(&script).output().unwrap();
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("discretisation.spacing") && e.contains("address-space limit (ulimit -v)"),
        "{e}"
    );
}
