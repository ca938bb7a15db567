//! `mpirun -np N meshfree run SCENE --mpi` (the `mpi` feature; `crate::mpi`): N processes,
//! one subdomain each, CPU halos over MPI, write what `--decompose N` writes in one process,
//! byte for byte: the particle files (each rank's particles in its storage order, in rank
//! order), the diagnostics, the force monitor's CSV and the checkpoint's pieces. A run
//! stopped mid-way resumes under MPI to the same files; a bad scene ends every process
//! with rank 0's error.
//!
//! The scene: the impinging flow at twice the spacing (a gate opened at t = 0, two elastic
//! bodies), a force monitor (wall forces across the cuts) and a checkpoint every 0.3.
//! Needs `mpirun` (OpenMPI) on the PATH; CI installs it (`.ci/run`).
#![cfg(feature = "mpi")]

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_meshfree");

mod support;

fn scene(dir: &Path) -> PathBuf {
    support::coarse_impinging(dir, "0.8", "0.2")
}

/// Run `cmd` to its end, killed after two minutes (a rank that waits for a message that
/// never comes must fail the test, not hang it).
fn finish(mut cmd: Command) -> Output {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("mpirun starts (OpenMPI's openmpi-bin)");
    let deadline = Instant::now() + Duration::from_secs(120);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            child.kill().unwrap();
            panic!("the run did not end within two minutes: {cmd:?}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

/// `mpirun -np n meshfree ARGS --mpi`.
fn mpirun(n: usize, args: &[&str]) -> Output {
    let mut cmd = Command::new("mpirun");
    cmd.args(["--oversubscribe", "-np", &n.to_string(), BIN])
        .args(args)
        .arg("--mpi")
        // OpenMPI refuses root without these (CI's containers run as root).
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    finish(cmd)
}

fn meshfree(args: &[&str]) -> Output {
    let mut cmd = Command::new(BIN);
    cmd.args(args);
    finish(cmd)
}

/// `run SCENE --backend cpu -q --out OUT` and `extra`.
fn cpu_run<'a>(scene: &'a str, out: &'a Path, extra: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec!["run", scene, "--backend", "cpu", "-q", "--out"];
    a.push(out.to_str().unwrap());
    a.extend_from_slice(extra);
    a
}

fn ok(o: &Output, what: &str) {
    assert!(
        o.status.success(),
        "{what} failed: {}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Every file of `a` but the summary (wall times) and the checkpoint's index (its run
/// state records the timing) is in `b`, byte for byte, and `b` has no other.
fn same_files(a: &Path, b: &Path) -> usize {
    let names = |d: &Path| {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n != "summary.json" && n != "checkpoint.bin")
            .collect();
        v.sort();
        v
    };
    let (na, nb) = (names(a), names(b));
    assert_eq!(na, nb, "the two runs wrote other files");
    for n in &na {
        let (x, y) = (
            std::fs::read(a.join(n)).unwrap(),
            std::fs::read(b.join(n)).unwrap(),
        );
        assert!(
            x == y,
            "{n} differs between {} and {}",
            a.display(),
            b.display()
        );
    }
    na.len()
}

#[test]
fn mpi_processes_write_what_one_process_of_as_many_subdomains_writes() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = scene(tmp.path());
    let s = scene.to_str().unwrap();
    for n in [2usize, 3] {
        let (one, many) = (
            tmp.path().join(format!("decompose{n}")),
            tmp.path().join(format!("mpi{n}")),
        );
        let count = n.to_string();
        let d = meshfree(&cpu_run(s, &one, &["--decompose", &count]));
        ok(&d, "the in-process run");
        let m = mpirun(n, &cpu_run(s, &many, &[]));
        ok(&m, "the MPI run");
        let stdout = String::from_utf8_lossy(&m.stdout);
        assert!(
            stdout.contains(&format!("{n} MPI processes")),
            "rank 0 alone reports, naming the processes: {stdout}"
        );
        assert_eq!(
            stdout.matches("steps to t =").count(),
            1,
            "one final line: {stdout}"
        );
        let files = same_files(&one, &many);
        assert!(files >= 8, "frames, pieces, CSVs compared: {files}");
        let monitor = std::fs::read_dir(&many)
            .unwrap()
            .filter_map(|e| e.ok())
            .any(|e| e.file_name().to_string_lossy().starts_with("forces"));
        assert!(monitor, "the force monitor wrote its CSV");
    }
}

#[test]
fn an_mpi_run_stopped_mid_way_resumes_under_mpi_to_the_same_files() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = scene(tmp.path());
    let s = scene.to_str().unwrap();
    let (whole, parts) = (tmp.path().join("whole"), tmp.path().join("parts"));
    let w = mpirun(2, &cpu_run(s, &whole, &[]));
    ok(&w, "the uninterrupted run");
    let first = mpirun(2, &cpu_run(s, &parts, &["--steps", "150"]));
    ok(&first, "the first half");
    let rest = mpirun(
        2,
        &[
            "run",
            "--resume",
            parts.to_str().unwrap(),
            "--backend",
            "cpu",
            "-q",
        ],
    );
    ok(&rest, "the resumed half");
    same_files(&whole, &parts);
}

#[test]
fn a_bad_scene_ends_every_process_with_rank_0s_error() {
    let tmp = tempfile::tempdir().unwrap();
    let missing = tmp.path().join("no-such-scene.toml");
    let o = mpirun(
        2,
        &["run", missing.to_str().unwrap(), "--backend", "cpu", "-q"],
    );
    assert!(!o.status.success(), "a missing scene fails the run");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("no-such-scene.toml"),
        "rank 0's error names the file: {err}"
    );
}
