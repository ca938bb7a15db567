//! The binary under faults from outside the scene file (issue #52): closed and full
//! standard streams, a panic in the stepping, signals with a closed terminal, crafted
//! checkpoints with valid checksums, planted links and foreign files in the output
//! directory, a second writer on one directory, a resume that must refuse before it
//! touches a file. Each case drives the real executable and fails where its fix is
//! reverted (a hang is a failure: every wait has a deadline).

use std::collections::BTreeMap;
use std::io::Read as _;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

fn meshfree() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_meshfree"));
    c.env_remove("MESHFREE_TEST_PANIC_IN_STEP");
    c
}

/// Wait for `child` at most `limit`; a hang kills it and fails the test.
fn wait(child: &mut Child, limit: Duration, what: &str) -> ExitStatus {
    let deadline = Instant::now() + limit;
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("{what}: still running after {limit:?} (a hang)");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Wait until `path` exists (a run started), at most 60 s.
fn wait_for(path: &Path) {
    let deadline = Instant::now() + Duration::from_secs(60);
    while !path.exists() {
        assert!(
            Instant::now() < deadline,
            "{} never appeared",
            path.display()
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn summary(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// Every file in `dir` with its bytes: to tell that a refusal touched nothing.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    (std::fs::read_dir(dir).unwrap())
        .map(|e| {
            let e = e.unwrap();
            let name = e.file_name().to_string_lossy().into_owned();
            (name, std::fs::read(e.path()).unwrap_or_default())
        })
        .collect()
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

/// A short tank-2d run on the CPU into `out` (a checkpoint at its stop).
fn short_run(out: &Path) {
    let o = meshfree()
        .args(["run", "tank-2d", "--backend", "cpu", "--steps", "30"])
        .args(["--output-interval", "2e-3", "--quiet", "--out"])
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[cfg(unix)]
fn signal(child: &Child, sig: i32) {
    // SAFETY: kill(2) on our own child's pid; no memory is involved.
    assert_eq!(unsafe { libc::kill(child.id() as i32, sig) }, 0);
}

#[test]
fn a_closed_pipe_on_stderr_lets_the_run_complete() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x");
    let mut child = meshfree()
        .args([
            "run",
            "tank-2d",
            "--backend",
            "cpu",
            "--steps",
            "200",
            "--out",
        ])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // `| head -c 1`: one byte, then the reader goes.
    let mut byte = [0u8; 1];
    child.stderr.take().unwrap().read_exact(&mut byte).unwrap();
    drop(child.stdout.take());
    let status = wait(&mut child, Duration::from_secs(120), "run | head -c 1");
    assert!(status.success(), "{status}");
    assert_eq!(summary(&out)["status"], "completed");
}

#[test]
fn a_panic_in_the_stepping_ends_the_process_and_says_failed() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("p");
    let mut child = meshfree()
        .args([
            "run",
            "tank-2d",
            "--backend",
            "cpu",
            "--steps",
            "50",
            "--quiet",
            "--out",
        ])
        .arg(&out)
        .env("MESHFREE_TEST_PANIC_IN_STEP", "1")
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let status = wait(&mut child, Duration::from_secs(60), "a panicking run");
    assert_eq!(status.code(), Some(101), "{status}");
    let s = summary(&out);
    assert_eq!(s["status"], "failed", "{s}");
    assert!(
        s["error"].as_str().unwrap().contains("internal error"),
        "{s}"
    );
}

#[test]
fn a_closed_or_full_stdout_is_no_panic() {
    // A reader that went before the output came: the end of the output, exit 0.
    for args in [
        &["scenes", "--json"][..],
        &["scenes", "--reference"],
        &["check", "tank-2d"],
    ] {
        let mut child = meshfree()
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let status = wait(&mut child, Duration::from_secs(60), "a closed stdout");
        let mut err = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut err)
            .unwrap();
        assert!(status.success(), "{args:?}: {status} {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    // A full device: an I/O error naming standard output (exit 4).
    let full = std::fs::OpenOptions::new().write(true).open("/dev/full");
    if let Ok(full) = full {
        let o = meshfree()
            .args(["check", "tank-2d"])
            .stdout(full)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(4), "{err}");
        assert!(err.contains("standard output"), "{err}");
    }
}

#[cfg(unix)]
#[test]
fn a_hang_up_with_a_closed_terminal_exits_130() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("h");
    let mut child = meshfree()
        .args(["run", "tank-2d", "--backend", "cpu", "--out"])
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The terminal went (an SSH drop): its stream is closed, then the hang-up comes.
    drop(child.stderr.take());
    wait_for(&out.join("summary.json"));
    signal(&child, libc::SIGHUP);
    let status = wait(&mut child, Duration::from_secs(60), "a hung-up run");
    assert_eq!(status.code(), Some(130), "{status}");
    assert_eq!(summary(&out)["status"], "interrupted");
}

#[cfg(unix)]
#[test]
fn a_second_writer_on_a_live_run_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("live");
    let mut first = meshfree()
        .args(["run", "tank-2d", "--backend", "cpu", "--quiet", "--out"])
        .arg(&out)
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for(&out.join("summary.json"));
    for args in [
        vec!["run", "--resume", out.to_str().unwrap(), "--steps", "5"],
        vec![
            "run",
            "tank-2d",
            "--overwrite",
            "--steps",
            "5",
            "--out",
            out.to_str().unwrap(),
        ],
    ] {
        let o = meshfree().args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains("lock"), "{args:?}: {err}");
    }
    signal(&first, libc::SIGTERM);
    let status = wait(&mut first, Duration::from_secs(60), "the first run");
    assert_eq!(status.code(), Some(130), "{status}");
    assert_eq!(summary(&out)["status"], "interrupted");
}

/// Rewrite `checkpoint.bin`'s JSON header through `edit`, with a valid checksum.
fn craft(path: &Path, edit: &dyn Fn(&mut serde_json::Value)) {
    let bytes = std::fs::read(path).unwrap();
    let len = u64::from_le_bytes(bytes[20..28].try_into().unwrap()) as usize;
    let mut header: serde_json::Value = serde_json::from_slice(&bytes[28..28 + len]).unwrap();
    edit(&mut header);
    let json = serde_json::to_vec(&header).unwrap();
    let mut out = bytes[..20].to_vec();
    out.extend((json.len() as u64).to_le_bytes());
    out.extend(&json);
    out.extend(&bytes[28 + len..bytes.len() - 4]);
    let crc = crc32fast::hash(&out);
    out.extend(crc.to_le_bytes());
    std::fs::write(path, out).unwrap();
}

#[test]
fn a_crafted_checkpoint_is_refused_and_touches_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let base = dir.path().join("base");
    short_run(&base);
    let victim = dir.path().join("victim.csv");
    std::fs::write(&victim, "the user's data\n".repeat(100)).unwrap();
    let abs = victim.to_str().unwrap().to_string();
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let cases: Vec<(&str, Edit)> = vec![
        (
            "nothing (a control: the crafting itself is valid)",
            Box::new(|_| {}),
        ),
        (
            "a writer file outside the directory",
            Box::new(|h| h["run"]["writer"]["files"][0][0] = "../victim.csv".into()),
        ),
        (
            "an absolute writer file",
            Box::new(move |h| h["run"]["writer"]["files"][0][0] = abs.clone().into()),
        ),
        (
            "a monitor file the scene does not have",
            Box::new(|h| h["run"]["monitors"]["files"] = serde_json::json!([["../victim.csv", 0]])),
        ),
        (
            "a series entry outside the directory",
            Box::new(|h| h["run"]["writer"]["series"][0][1] = "../../../../etc/passwd".into()),
        ),
        (
            "steps at 2^64 - 1",
            Box::new(|h| h["steps"] = u64::MAX.into()),
        ),
        ("a negative time", Box::new(|h| h["time"] = (-5.0).into())),
        (
            "a frame count of 10^12",
            Box::new(|h| h["run"]["writer"]["frames"] = 1_000_000_000_000u64.into()),
        ),
    ];
    let victim_before = std::fs::read(&victim).unwrap();
    for (k, (what, edit)) in cases.iter().enumerate() {
        let run = dir.path().join(format!("c{k}"));
        copy_dir(&base, &run);
        craft(&run.join("checkpoint.bin"), edit.as_ref());
        let before = snapshot(&run);
        let o = meshfree()
            .args([
                "run",
                "--resume",
                run.to_str().unwrap(),
                "--steps",
                "3",
                "--quiet",
            ])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        if k == 0 {
            assert!(o.status.success(), "{what}: {err}");
            continue;
        }
        assert_eq!(o.status.code(), Some(2), "{what}: {err}");
        assert!(err.contains("checkpoint.bin"), "{what}: {err}");
        assert_eq!(snapshot(&run), before, "{what}: the directory changed");
        assert_eq!(std::fs::read(&victim).unwrap(), victim_before, "{what}");
    }
}

#[test]
fn a_refused_resume_rolls_nothing_back() {
    if meshfree_core::backend::cuda::available().is_ok() {
        return; // here --backend cuda runs: nothing to refuse
    }
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("r");
    short_run(&run);
    // What a kill -9 after the checkpoint leaves: a later frame and a longer CSV.
    let frames = summary(&run)["outputs"].as_u64().unwrap() as usize;
    std::fs::copy(
        run.join("particles_00000.vtu"),
        run.join(format!("particles_{frames:05}.vtu")),
    )
    .unwrap();
    let mut diag = std::fs::read_to_string(run.join("diagnostics.csv")).unwrap();
    diag.push_str("a row after the checkpoint\n");
    std::fs::write(run.join("diagnostics.csv"), diag).unwrap();
    let before = snapshot(&run);
    let o = meshfree()
        .args([
            "run",
            "--resume",
            run.to_str().unwrap(),
            "--backend",
            "cuda",
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert_eq!(
        snapshot(&run),
        before,
        "a refused resume changed the directory"
    );
}

#[cfg(unix)]
#[test]
fn planted_links_and_foreign_files_are_never_written_through() {
    let dir = tempfile::tempdir().unwrap();
    let victim = dir.path().join("victim.txt");
    std::fs::write(&victim, "keep").unwrap();
    // A fresh directory with a link at a run file's name, and one with the user's own
    // diagnostics.csv and no run: both refused (exit 2), nothing written.
    let linked = dir.path().join("linked");
    std::fs::create_dir_all(&linked).unwrap();
    std::os::unix::fs::symlink(&victim, linked.join("diagnostics.csv")).unwrap();
    let theirs = dir.path().join("theirs");
    std::fs::create_dir_all(&theirs).unwrap();
    std::fs::write(theirs.join("diagnostics.csv"), "mine").unwrap();
    for out in [&linked, &theirs] {
        let before = snapshot(out);
        let o = meshfree()
            .args([
                "run",
                "tank-2d",
                "--backend",
                "cpu",
                "--steps",
                "3",
                "--quiet",
                "--out",
            ])
            .arg(out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains("diagnostics.csv"), "{err}");
        assert_eq!(snapshot(out), before);
    }
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");

    // --overwrite beside the user's files: the earlier run's go, theirs stay.
    let run = dir.path().join("run");
    short_run(&run);
    let mine: Vec<PathBuf> = ["notes.csv", "plot.png", "old.bin", "extra.json", "a.tmp"]
        .iter()
        .map(|n| run.join(n))
        .collect();
    for p in &mine {
        std::fs::write(p, "mine").unwrap();
    }
    let o = meshfree()
        .args([
            "run",
            "tank-2d",
            "--backend",
            "cpu",
            "--steps",
            "3",
            "--quiet",
        ])
        .args(["--overwrite", "--out"])
        .arg(&run)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for p in &mine {
        assert_eq!(
            std::fs::read_to_string(p).unwrap(),
            "mine",
            "{}",
            p.display()
        );
    }
    assert_eq!(summary(&run)["steps"], 3);
}

/// SIGINT, SIGTERM or SIGHUP at a random moment of a run (seeded): it ends 130 with an
/// interrupted summary (or 0, where the run ended first), and `--resume` continues it.
#[cfg(unix)]
#[test]
fn signals_at_random_moments_stop_cleanly_and_resume() {
    let dir = tempfile::tempdir().unwrap();
    let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
    for k in 0..6 {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        let sig = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP][k % 3];
        let delay = Duration::from_millis(seed % 300);
        let out = dir.path().join(format!("s{k}"));
        let mut child = meshfree()
            .args([
                "run",
                "tank-2d",
                "--backend",
                "cpu",
                "--steps",
                "400",
                "--quiet",
            ])
            .args(["--output-interval", "1e-3", "--out"])
            .arg(&out)
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        wait_for(&out.join("summary.json"));
        std::thread::sleep(delay);
        signal(&child, sig);
        let what = format!("signal {sig} after {delay:?}");
        let status = wait(&mut child, Duration::from_secs(60), &what);
        let s = summary(&out);
        match status.code() {
            Some(130) => assert_eq!(s["status"], "interrupted", "{what}: {s}"),
            Some(0) => assert_eq!(s["status"], "completed", "{what}: {s}"),
            _ => panic!("{what}: {status}"),
        }
        let o = meshfree()
            .args([
                "run",
                "--resume",
                out.to_str().unwrap(),
                "--steps",
                "3",
                "--quiet",
            ])
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{what}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

/// A checkpoint that is a directory or a FIFO is named as such (a FIFO is never opened:
/// reading it would block the resume for ever).
#[cfg(unix)]
#[test]
fn a_checkpoint_that_is_no_file_is_named_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let run = dir.path().join("r");
    short_run(&run);
    let path = run.join("checkpoint.bin");
    for (kind, want) in [("directory", "a directory"), ("fifo", "not a regular file")] {
        std::fs::remove_file(&path)
            .or_else(|_| std::fs::remove_dir(&path))
            .unwrap();
        if kind == "directory" {
            std::fs::create_dir(&path).unwrap();
        } else {
            let c = std::ffi::CString::new(path.to_str().unwrap()).unwrap();
            // SAFETY: mkfifo(3) on a NUL-terminated path that lives across the call.
            assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        }
        let mut child = meshfree()
            .args(["run", "--resume", run.to_str().unwrap(), "--quiet"])
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let status = wait(&mut child, Duration::from_secs(30), kind);
        let mut err = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut err)
            .unwrap();
        assert_eq!(status.code(), Some(2), "{kind}: {err}");
        assert!(err.contains(want), "{kind}: {err}");
    }
}
