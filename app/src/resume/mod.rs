//! Continuing a run from its checkpoint: `meshfree run --resume DIR` (`run::resume`).
//!
//! A checkpoint (`output::checkpoint`, `checkpoint.bin`) holds the solver's state
//! (`SolverCheckpoint`) and the run's (`RunState`): the run's options, when the next
//! output and checkpoint fall, the stepper's gates and batch size, the monitors' and
//! probes' sample times, the writer's counts, and the length of every CSV file at that
//! moment. The run writes it on the writer thread after every frame queued before it, so
//! the files it describes are on the disk when it lands.
//!
//! Resuming: read the checkpoint and the run's copy of its scene (`DIR/scene.toml`, the
//! text the checkpoint was taken with: its digest must match); then roll the directory
//! back to the checkpoint (`rollback`: the CSV files cut to their lengths, the particle
//! files of later outputs removed, `particles.pvd` rewritten), since a run killed after the
//! checkpoint wrote more; then the run goes on (`run::run_observed`'s resumed path) from a
//! fresh set-up of the scene, its opened gates removed and the solver restored. On the
//! same backend and build the result is the uninterrupted run's, bit for bit: every file
//! but `summary.json` (whose timings differ) is the same (`tests/resume.rs`).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::StepperState;

use crate::monitors::MonitorsState;
use crate::output::checkpoint::{self, Saved};
use crate::output::files::{self, DirLock, LockError};
use crate::output::writer::{Failure, Job, WriterState};
use crate::output::{PvdSeries, Timing};
use crate::probes::ProbesState;
use crate::run_error::RunError;

mod check;

/// The run's part of a checkpoint.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RunState {
    /// The build that wrote it (`meshfree_core::build_info`): a resumed run steps bit for
    /// bit as the uninterrupted one on the same build and backend.
    pub build: String,
    /// The backend that wrote it ("cpu", "cuda").
    pub backend: String,
    /// `digest` of the scene text (`scene.toml`).
    pub scene_digest: String,
    /// \[T\] the run's end time (the scene's, or `--t-end`).
    pub t_end: f64,
    /// \[T\] the run's output interval (the scene's, or `--output-interval`).
    pub output_interval: f64,
    /// The particle files' format (the scene's, or `--format`).
    pub format: OutputFormat,
    /// \[T\] the next output's time.
    pub next_output: f64,
    /// \[T\] the next checkpoint's time (`[output] checkpoint_interval`), if any.
    pub next_checkpoint: Option<f64>,
    pub stepper: StepperState,
    pub monitors: MonitorsState,
    pub probes: ProbesState,
    /// Filled in on the writer thread.
    pub writer: WriterState,
    /// The run's timings so far (every part, where it was resumed before).
    pub timing: Timing,
    /// The checkpoint times \[T\] the run was resumed from before.
    pub resumed_from: Vec<f64>,
}

/// A run's checkpoint, read back with its scene.
pub struct Resume {
    /// The solver's state: whole, or one piece per rank of a decomposed run.
    pub solver: Saved,
    pub run: RunState,
    /// The run's scene (`DIR/scene.toml`).
    pub scene: Scene,
    pub dir: PathBuf,
    /// The directory's lock, taken before the checkpoint was read and held to the run's end.
    pub lock: DirLock,
}

/// FNV-1a (64 bits) of `text`, in hex: enough to tell an edited scene file from the one a
/// checkpoint was taken with.
pub fn digest(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

fn bad(path: &Path, reason: impl Into<String>) -> RunError {
    RunError::Checkpoint {
        path: path.to_path_buf(),
        reason: reason.into(),
    }
}

/// The writer's job that completes the checkpoint `run` (all but the writer's part) of
/// `solver` and writes it to `path` (`Saved::write`: one file, or a piece per rank and
/// their index), on the writer thread after the frames queued before it.
pub fn checkpoint_job(path: PathBuf, solver: Saved, mut run: RunState) -> Job {
    Job::Checkpoint(Box::new(move |w| {
        run.writer = w;
        let bytes = solver.write(&path, &run).map_err(|e| Failure {
            path: path.clone(),
            reason: e.to_string(),
        })?;
        Ok((solver.clock().time, bytes))
    }))
}

/// Take `dir`'s lock and read its checkpoint and scene. Err: another run writing there, no
/// checkpoint (with what to do), an unreadable, damaged or crafted one (`check`), or a
/// scene file that is not the one it was taken with. Nothing in `dir` is changed.
pub fn load(dir: &Path) -> Result<Resume, RunError> {
    let path = dir.join(checkpoint::FILE);
    let lock = match DirLock::take(dir) {
        Ok(lock) => Some(lock),
        // A missing directory: told below as no checkpoint.
        Err(LockError::Io(..)) if !dir.is_dir() => None,
        Err(e) => return Err(e.into()),
    };
    // Its own type: a directory, a FIFO (which would block the read) or a link is refused.
    let kind = std::fs::symlink_metadata(&path).map(|m| m.file_type());
    if let Some(kind) = kind.as_ref().ok().filter(|k| !k.is_file()) {
        let what = if kind.is_dir() {
            "a directory"
        } else if kind.is_symlink() {
            "a link"
        } else {
            "not a regular file"
        };
        return Err(bad(
            &path,
            format!("is {what}, not a checkpoint the run wrote"),
        ));
    }
    let Some(lock) = lock.filter(|_| kind.is_ok()) else {
        let why = if dir.join(files::SUMMARY).is_file() {
            "the run wrote no checkpoint: it was stopped before its first one (set [output] \
             checkpoint_interval to write them during a run; one is written wherever a run \
             stops, not at a blow-up)"
        } else {
            "no run's output is there (pass the --out directory of the run to resume)"
        };
        return Err(bad(&path, why));
    };
    let (solver, run): (Saved, RunState) =
        checkpoint::load(&path).map_err(|(at, r)| bad(&at, r))?;
    let scene_path = dir.join(files::SCENE);
    let scene = Scene::from_file(&scene_path)?;
    if digest(&scene.text) != run.scene_digest {
        return Err(bad(
            &scene_path,
            "is not the scene the checkpoint was taken with (it was edited since): restore \
             it, or start a new run",
        ));
    }
    let r = Resume {
        solver,
        run,
        scene,
        dir: dir.to_path_buf(),
        lock,
    };
    check::check(&r).map_err(|why| bad(&path, format!("cannot be this run's: {why}")))?;
    Ok(r)
}

/// Bring `dir` back to the checkpoint `r`: every CSV file cut to its length there (Err
/// where one is shorter: damaged), the particle files of later outputs (and the
/// temporaries of interrupted writes, and the checkpoint pieces the index does not list)
/// removed, and `particles.pvd` rewritten with the outputs up to it.
pub fn rollback(dir: &Path, r: &Resume) -> Result<(), RunError> {
    let run = &r.run;
    let io = |path: &Path, e: std::io::Error| RunError::Io {
        path: path.to_path_buf(),
        reason: e.to_string(),
    };
    let files = (run.writer.files.iter())
        .chain(&run.monitors.files)
        .chain(&run.probes.files);
    for (name, len) in files {
        // `check` let through only the run's own names; a link planted at one is refused.
        let path = dir.join(name);
        if !std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_file()) {
            return Err(bad(
                &path,
                "is missing or not a regular file: the output was damaged since the checkpoint",
            ));
        }
        let f = std::fs::OpenOptions::new()
            .write(true)
            .open(&path)
            .map_err(|e| io(&path, e))?;
        let now = f.metadata().map_err(|e| io(&path, e))?.len();
        if now < *len {
            return Err(bad(
                &path,
                format!(
                    "holds {now} bytes, fewer than the {len} it held at the checkpoint: the \
                     output was damaged since"
                ),
            ));
        }
        f.set_len(*len).map_err(|e| io(&path, e))?;
    }
    let frames = run.writer.frames;
    check_frames(dir, r)?;
    for entry in std::fs::read_dir(dir).map_err(|e| io(dir, e))? {
        let entry = entry.map_err(|e| io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let index = name
            .strip_prefix("particles_")
            .and_then(|r| r.split('.').next())
            .and_then(|n| n.parse::<usize>().ok());
        // Later outputs, and the temporaries of atomic writes a kill cut short.
        if index.is_some_and(|i| i >= frames) || name.ends_with(".tmp") {
            std::fs::remove_file(entry.path()).map_err(|e| io(&entry.path(), e))?;
        }
    }
    let listed: Vec<String> = match &r.solver {
        Saved::Whole(_) => Vec::new(),
        Saved::Pieces { clock, pieces } => (0..pieces.len())
            .map(|k| checkpoint::piece_name(clock.steps, k, pieces.len()))
            .collect(),
    };
    checkpoint::remove_stale_pieces(dir, &listed).map_err(|e| io(dir, e))?;
    let series = PvdSeries::with_entries(dir.join(files::SERIES), run.writer.series.clone());
    if !run.writer.series.is_empty() {
        series.write().map_err(|e| io(series.path(), e))?;
    }
    Ok(())
}

/// The frames written before the checkpoint are all there, whole: each file present, and
/// their sizes adding up to the bytes the writer counted (a truncated or removed one would
/// otherwise be carried into the finished run without a word).
fn check_frames(dir: &Path, r: &Resume) -> Result<(), RunError> {
    let ext = match r.run.format {
        OutputFormat::Vtu | OutputFormat::VtuZlib | OutputFormat::VtuLz4 => "vtu",
        OutputFormat::Csv => "csv",
        OutputFormat::None => return Ok(()),
    };
    let mut bytes = 0u64;
    for i in 0..r.run.writer.frames {
        let path = dir.join(files::frame_file(i as u64, ext));
        match std::fs::symlink_metadata(&path) {
            Ok(m) if m.is_file() => bytes += m.len(),
            _ => {
                return Err(bad(
                    &path,
                    "is missing or not a regular file, though written before the checkpoint: \
                     the output was damaged since (restore it, or start a new run)",
                ))
            }
        }
    }
    if bytes != r.run.writer.bytes {
        return Err(bad(
            dir,
            format!(
                "its frames hold {bytes} bytes, not the {} written before the checkpoint: one \
                 was changed or truncated since (restore it, or start a new run)",
                r.run.writer.bytes
            ),
        ));
    }
    Ok(())
}
