//! Checkpoints of a decomposed run, one piece per rank (`output::checkpoint::Saved`,
//! `Solver::save_pieces`): a `--decompose 2` and a `--decompose 3` run stopped mid-way and
//! resumed on as many ranks end with the uninterrupted run's files, byte for byte (each
//! rank took back its own piece, slab and storage order: the VTU files, which hold each
//! rank's particles in its storage order, agree too); resumed on another rank count the
//! pieces are gathered and the particles come out alike; a missing or damaged piece is
//! refused naming its file and the reason; only the last checkpoint's pieces are left.
//!
//! The scene: the impinging flow at twice the spacing (a gate opened at t = 0, two elastic
//! bodies), a force monitor and a checkpoint every 0.3 time units.

use std::path::{Path, PathBuf};

use meshfree::output::checkpoint::{self, Saved};
use meshfree::run::{self, Progress, RunError, RunOptions};
use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::Scene;
use meshfree_core::solver::checkpoint::SolverCheckpoint;

mod support;

fn scene(dir: &Path) -> Scene {
    Scene::from_file(support::coarse_impinging(dir, "1.0", "0.25")).unwrap()
}

fn options(out: &Path, ranks: usize) -> RunOptions {
    RunOptions {
        backend: BackendChoice::Cpu,
        progress: Progress::Quiet,
        out_dir: Some(out.to_path_buf()),
        decompose: Some(ranks),
        ..Default::default()
    }
}

fn names(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The run's last checkpoint, its pieces gathered, sorted by id.
fn final_state(dir: &Path) -> SolverCheckpoint {
    let (saved, _): (Saved, serde_json::Value) =
        checkpoint::load(&dir.join(checkpoint::FILE)).unwrap();
    let c = saved.gathered();
    let mut order: Vec<usize> = (0..c.len()).collect();
    order.sort_unstable_by_key(|&i| c.id[i]);
    SolverCheckpoint {
        id: order.iter().map(|&i| c.id[i]).collect(),
        pos: order.iter().map(|&i| c.pos[i]).collect(),
        vel: order.iter().map(|&i| c.vel[i]).collect(),
        rho: order.iter().map(|&i| c.rho[i]).collect(),
        stress: order.iter().map(|&i| c.stress[i]).collect(),
        ..c.clone()
    }
}

fn same_bits(a: &SolverCheckpoint, b: &SolverCheckpoint) {
    let bits = |c: &SolverCheckpoint| {
        let mut v: Vec<u32> = c.id.clone();
        v.extend(c.pos.iter().flatten().map(|x| x.to_bits()));
        v.extend(c.vel.iter().flatten().map(|x| x.to_bits()));
        v.extend(c.rho.iter().map(|x| x.to_bits()));
        v.extend(c.stress.iter().flatten().map(|x| x.to_bits()));
        v
    };
    assert_eq!((a.steps, a.time.to_bits()), (b.steps, b.time.to_bits()));
    assert!(bits(a) == bits(b), "the final particles differ");
}

/// Every file of `a` but the summary and the checkpoint index (whose headers hold
/// timings) has the same bytes in `b`, and `b` has no other.
fn same_output(a: &Path, b: &Path) {
    assert_eq!(names(a), names(b), "the two runs wrote other files");
    let mut compared = 0;
    for name in names(a) {
        if name == "summary.json" || name == checkpoint::FILE {
            continue;
        }
        let same = std::fs::read(a.join(&name)).unwrap() == std::fs::read(b.join(&name)).unwrap();
        assert!(
            same,
            "{name} differs between the run in one go and the resumed one"
        );
        compared += 1;
    }
    assert!(compared > 8, "only {compared} files compared");
}

/// The index and one piece per rank of the checkpoint at the run's last step, nothing of
/// the earlier checkpoints.
fn pieces_of_last_checkpoint(dir: &Path, ranks: usize) -> Vec<PathBuf> {
    let (saved, _): (Saved, serde_json::Value) =
        checkpoint::load(&dir.join(checkpoint::FILE)).unwrap();
    let Saved::Pieces { clock, pieces } = &saved else {
        panic!("a decomposed run wrote one whole checkpoint")
    };
    assert_eq!(pieces.len(), ranks);
    let want: Vec<String> = (0..ranks)
        .map(|k| checkpoint::piece_name(clock.steps, k, ranks))
        .collect();
    let there: Vec<String> = names(dir)
        .into_iter()
        .filter(|n| n.starts_with("checkpoint-"))
        .collect();
    assert_eq!(there, want, "the last checkpoint's pieces alone");
    want.iter().map(|n| dir.join(n)).collect()
}

/// A run of `ranks` subdomains in one go, and one stopped after `stop` steps (past its
/// first periodic checkpoint) and resumed on as many: the same files.
fn stopped_and_resumed(ranks: usize, stop: u64) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    let whole = run::run(&sc, &options(&a, ranks)).unwrap();
    pieces_of_last_checkpoint(&a, ranks);
    let part = run::run(
        &sc,
        &RunOptions {
            max_steps: Some(stop),
            ..options(&b, ranks)
        },
    )
    .unwrap();
    assert!(
        part.simulated_time > 0.3 && part.simulated_time < 0.75,
        "stopped at t = {}",
        part.simulated_time
    );
    pieces_of_last_checkpoint(&b, ranks);
    let done = run::resume(&b, &options(&b, ranks)).unwrap();
    assert_eq!(done.steps, whole.steps);
    assert_eq!(done.resumed_from, vec![part.simulated_time]);
    same_output(&a, &b);
    same_bits(&final_state(&a), &final_state(&b));
    (dir, a)
}

#[test]
fn two_ranks_stopped_and_resumed_from_their_pieces_equal_the_run_in_one_go() {
    stopped_and_resumed(2, 125);
}

#[test]
fn three_ranks_resume_from_their_pieces_or_gathered_on_another_count() {
    let (dir, a) = stopped_and_resumed(3, 165);
    // A 3-rank checkpoint taken mid-way resumed on 2 ranks and on one domain: the pieces
    // gathered, the particles alike bit for bit (the diagnostics' sums, added over other
    // ranks, to round-off: not compared).
    let sc = scene(dir.path());
    for (name, ranks) in [("two", Some(2)), ("one", None)] {
        let c = dir.path().join(name);
        run::run(
            &sc,
            &RunOptions {
                max_steps: Some(330),
                ..options(&c, 3)
            },
        )
        .unwrap();
        run::resume(
            &c,
            &RunOptions {
                decompose: ranks,
                ..options(&c, 3)
            },
        )
        .unwrap();
        same_bits(&final_state(&a), &final_state(&c));
        match ranks {
            Some(r) => {
                pieces_of_last_checkpoint(&c, r);
            }
            None => {
                assert!(checkpoint::read::<serde_json::Value>(&c.join(checkpoint::FILE)).is_ok());
                assert!(
                    !names(&c).iter().any(|n| n.starts_with("checkpoint-")),
                    "the 3 ranks' pieces outlived the whole checkpoint that replaced them"
                );
            }
        }
    }
}

#[test]
fn a_missing_or_damaged_piece_is_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let sc = scene(dir.path());
    let out = dir.path().join("r");
    run::run(
        &sc,
        &RunOptions {
            max_steps: Some(40),
            ..options(&out, 2)
        },
    )
    .unwrap();
    let pieces = pieces_of_last_checkpoint(&out, 2);
    let refused = |words: &[&str], file: &Path| {
        let e = run::resume(&out, &options(&out, 2)).unwrap_err();
        let RunError::Checkpoint { path, reason } = &e else {
            panic!("expected a checkpoint error, got {e}")
        };
        assert_eq!(path, file, "{e}");
        for w in words {
            assert!(reason.contains(w), "`{w}` not in: {e}");
        }
    };
    let good = std::fs::read(&pieces[1]).unwrap();
    let mut bad = good.clone();
    let k = bad.len() - 100;
    bad[k] ^= 1;
    std::fs::write(&pieces[1], &bad).unwrap();
    refused(&["damaged", "checksum"], &pieces[1]);
    std::fs::write(&pieces[1], &good[..good.len() / 2]).unwrap();
    refused(&["damaged"], &pieces[1]);
    // Rank 0's piece where rank 1's should be.
    std::fs::copy(&pieces[0], &pieces[1]).unwrap();
    refused(&["not rank 1's piece of 2"], &pieces[1]);
    std::fs::remove_file(&pieces[1]).unwrap();
    refused(&["missing", "rank 1's piece of 2"], &pieces[1]);
    // Put back whole, it resumes.
    std::fs::write(&pieces[1], &good).unwrap();
    run::resume(&out, &options(&out, 2)).unwrap();
}
