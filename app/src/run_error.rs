//! Why a run did not complete (`RunError`, re-exported by `crate::run`): its own module, so
//! that the run driver and the resume of a run (`crate::resume`) both take it without taking
//! each other.

use std::path::PathBuf;

use meshfree_core::backend::BackendError;
use meshfree_core::scene::SceneError;
use meshfree_core::solver::Fault;

use crate::output::writer;
use crate::output::RunSummary;

/// Why a run did not complete.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Backend(#[from] BackendError),
    #[error("{}: {reason}", path.display())]
    Io { path: PathBuf, reason: String },
    /// A checkpoint that cannot be resumed (`meshfree run --resume`): missing, damaged, of
    /// another scene or build layout, or output changed since.
    #[error("{}: {reason}", path.display())]
    Checkpoint { path: PathBuf, reason: String },
    /// The output directory holds an earlier run's files (`RunOptions::overwrite`).
    #[error("{}: {reason}", dir.display())]
    OutputInUse { dir: PathBuf, reason: String },
    /// Stopped by a signal (or the caller's flag): the last frame and `summary.json` are
    /// written.
    #[error("interrupted by {signal} at t = {:.6} after {} steps (last frame, checkpoint and summary.json in {}; `meshfree run --resume {}` continues it)",
            summary.simulated_time, summary.steps, out_dir.display(), out_dir.display())]
    Interrupted {
        signal: String,
        out_dir: PathBuf,
        summary: Box<RunSummary>,
    },
    /// A blow-up: output written so far is kept, `summary.json` holds the fault.
    #[error("{fault} (output so far in {})", out_dir.display())]
    BlowUp {
        fault: Box<Fault>,
        out_dir: PathBuf,
        summary: Box<RunSummary>,
    },
}

impl From<(PathBuf, std::io::Error)> for RunError {
    fn from((path, e): (PathBuf, std::io::Error)) -> Self {
        RunError::Io {
            path,
            reason: e.to_string(),
        }
    }
}

impl From<writer::Failure> for RunError {
    fn from(f: writer::Failure) -> Self {
        RunError::Io {
            path: f.path,
            reason: f.reason,
        }
    }
}

impl From<crate::output::files::LockError> for RunError {
    /// Another process holds the directory's lock: the directory is in use (exit 2).
    fn from(e: crate::output::files::LockError) -> RunError {
        use crate::output::files::LockError;
        match e {
            LockError::Held(dir) => RunError::OutputInUse {
                dir,
                reason: "another meshfree run or resume is writing there (it holds the \
                         directory's lock): wait for it to end, or choose another --out"
                    .into(),
            },
            LockError::Io(path, e) => RunError::Io {
                path,
                reason: e.to_string(),
            },
        }
    }
}
