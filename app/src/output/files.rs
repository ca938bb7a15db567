//! A run's directory and its contract (README, "The output directory"; issue #52).
//!
//! Every file a run writes is named in `meshfree_core::run_files` (whose names scene
//! validation keeps monitors from taking) and re-exported here: the fixed names, a force monitor's
//! `<name>.csv`, the frames `particles_NNNNN.vtu` (or `.csv`) with their series
//! `particles.pvd`, the checkpoint `checkpoint.bin` (a decomposed run's pieces
//! `checkpoint-step*-rank*of*.bin` beside it) and, for an instant, `<any of them>.tmp`
//! (`Atomic`). Each is created anew (never through a link planted at its name) or renamed
//! into place. `summary.json` lists under `files` the run's files that are not frames,
//! series or checkpoint; `--overwrite` removes exactly those and the frames, series,
//! checkpoint and temporaries of the earlier run, nothing else (`run::out_dir`). A run
//! or a resume holds the directory's lock (`DirLock`) from before it touches a file to its
//! end, so a second writer is refused.

use std::fs::File;
use std::io;
use std::path::{Path, PathBuf};

pub use meshfree_core::run_files::{
    frame_file, monitor_file, BODIES, CHECKPOINT, CLUSTERS, DIAGNOSTICS, FILES, FLOATING, GAUGES,
    OPEN_BOUNDARIES, PROBES, SCENE, SERIES, SUMMARY, VOIDS,
};

/// The output index of a particle file's name (`frame`'s inverse).
pub fn frame_index(name: &str) -> Option<usize> {
    let rest = name.strip_prefix("particles_")?;
    let (digits, ext) = rest.split_once('.')?;
    let frame = (ext == "vtu" || ext == "csv")
        && digits.len() >= 5
        && digits.bytes().all(|b| b.is_ascii_digit());
    frame.then(|| digits.parse().ok()).flatten()
}

/// Whether `name` names a file directly inside the run's directory: not empty, no path
/// separator, not `.` or `..`, no control character. A checkpoint or a summary names no
/// other (a crafted one could otherwise reach outside the directory).
pub fn is_plain(name: &str) -> bool {
    !name.is_empty()
        && name != "."
        && name != ".."
        && !name.contains(['/', '\\'])
        && !name.chars().any(char::is_control)
}

/// Whether `name` is one of a run's files by its pattern alone: the frames, the series, the
/// summary, the scene copy and its surfaces' and motion series' copies, the checkpoint and
/// its pieces.
pub fn by_pattern(name: &str) -> bool {
    name == SERIES
        || name == SUMMARY
        || name == SCENE
        || name == CHECKPOINT
        || is_piece_name(name)
        || frame_index(name).is_some()
        || meshfree_core::run_files::surface_index(name).is_some()
        || meshfree_core::run_files::motion_index(name).is_some()
        || meshfree_core::run_files::inflow_index(name).is_some()
}

/// The file name of rank `rank`'s piece of `ranks` at step `steps` (a decomposed run's
/// checkpoint, `output::checkpoint`).
pub fn piece_name(steps: u64, rank: usize, ranks: usize) -> String {
    format!("checkpoint-step{steps}-rank{rank}of{ranks}.bin")
}

/// Whether `name` is a checkpoint piece's (`piece_name`).
pub fn is_piece_name(name: &str) -> bool {
    name.starts_with("checkpoint-step") && name.ends_with(".bin")
}

/// Whether a file of that name could be written by a run of a scene with force monitors
/// named `monitors`: every fixed name, a monitor's CSV, a pattern's file, and their
/// temporaries.
pub fn would_write(name: &str, monitors: &[String]) -> bool {
    let name = name.strip_suffix(".tmp").unwrap_or(name);
    FILES.contains(&name) || by_pattern(name) || monitors.iter().any(|m| monitor_file(m) == name)
}

/// `path` with `.tmp` appended: where `Atomic` writes it first.
pub fn tmp_path(path: &Path) -> PathBuf {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    PathBuf::from(tmp)
}

/// Create `path` anew for writing: refused where anything is there already (a planted
/// link is never followed).
pub fn create_new(path: &Path) -> io::Result<File> {
    File::options().write(true).create_new(true).open(path)
}

/// A file being written in full under `<path>.tmp`, renamed over `path` by `commit`, so a
/// reader never sees half a file; dropped uncommitted (a failed write), the temporary goes.
pub struct Atomic {
    tmp: PathBuf,
    path: PathBuf,
    done: bool,
}

impl Atomic {
    /// The temporary created anew (a stale one from a killed write removed first).
    pub fn create(path: &Path) -> io::Result<(Atomic, File)> {
        let tmp = tmp_path(path);
        match std::fs::remove_file(&tmp) {
            Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(e),
            _ => {}
        }
        let file = create_new(&tmp)?;
        let atomic = Atomic {
            tmp,
            path: path.to_path_buf(),
            done: false,
        };
        Ok((atomic, file))
    }

    /// Rename the temporary over the file (the file's writer closed it first).
    pub fn commit(mut self) -> io::Result<()> {
        std::fs::rename(&self.tmp, &self.path)?;
        self.done = true;
        Ok(())
    }
}

impl Drop for Atomic {
    fn drop(&mut self) {
        if !self.done {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// Write `bytes` to `path` atomically (`Atomic`).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    use std::io::Write as _;
    let (atomic, mut file) = Atomic::create(path)?;
    file.write_all(bytes)?;
    drop(file);
    atomic.commit()
}

/// The advisory lock (`flock`) on a run's directory, held by a run or a resume until it
/// ends; released by the system at any exit, `kill -9` included.
pub struct DirLock {
    _dir: File,
}

/// Why a directory's lock was not taken (`RunError` takes it: `OutputInUse`, exit 2, where
/// another process holds it; an I/O error otherwise).
#[derive(Debug)]
pub enum LockError {
    Held(PathBuf),
    Io(PathBuf, io::Error),
}

impl DirLock {
    /// Take the lock on the directory `dir` (which exists), without waiting.
    pub fn take(dir: &Path) -> Result<DirLock, LockError> {
        let io = |e: io::Error| LockError::Io(dir.to_path_buf(), e);
        let file = File::open(dir).map_err(io)?;
        match file.try_lock() {
            Ok(()) => Ok(DirLock { _dir: file }),
            Err(std::fs::TryLockError::WouldBlock) => Err(LockError::Held(dir.to_path_buf())),
            Err(std::fs::TryLockError::Error(e)) => Err(io(e)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_and_names() {
        assert_eq!(frame_file(7, "vtu"), "particles_00007.vtu");
        assert_eq!(frame_index("particles_00007.vtu"), Some(7));
        assert_eq!(frame_index("particles_123456.csv"), Some(123456));
        for not in [
            "particles_7.vtu",
            "particles_00007.png",
            "particles_0000x.vtu",
            "x.vtu",
        ] {
            assert_eq!(frame_index(not), None, "{not}");
        }
        for bad in ["", ".", "..", "../x", "/etc/passwd", "a/b", "a\\b", "a\nb"] {
            assert!(!is_plain(bad), "{bad:?}");
        }
        assert!(is_plain("diagnostics.csv") && is_plain("drag.csv"));
        let monitors = vec!["drag".to_string()];
        for ours in [
            "drag.csv",
            "diagnostics.csv",
            "summary.json.tmp",
            "particles_00001.vtu",
        ] {
            assert!(would_write(ours, &monitors), "{ours}");
        }
        for theirs in ["notes.csv", "plot.png", "lift.csv", "data.bin"] {
            assert!(!would_write(theirs, &monitors), "{theirs}");
        }
    }

    #[test]
    fn a_second_lock_is_refused_and_a_dropped_one_released() {
        let dir = std::env::temp_dir().join(format!("meshfree-lock-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let first = DirLock::take(&dir).expect("the first lock");
        assert!(matches!(DirLock::take(&dir), Err(LockError::Held(_))));
        drop(first);
        assert!(DirLock::take(&dir).is_ok());
        let _ = std::fs::remove_dir(&dir);
    }

    #[cfg(unix)]
    #[test]
    fn an_atomic_write_replaces_a_planted_link_without_following_it() {
        let dir = std::env::temp_dir().join(format!("meshfree-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let victim = dir.join("victim");
        std::fs::write(&victim, "keep").unwrap();
        let path = dir.join(SUMMARY);
        let _ = std::fs::remove_file(&path);
        let _ = std::fs::remove_file(tmp_path(&path));
        std::os::unix::fs::symlink(&victim, &path).unwrap();
        std::os::unix::fs::symlink(&victim, tmp_path(&path)).unwrap();
        write_atomic(&path, b"{}").unwrap();
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "{}");
        assert!(!tmp_path(&path).exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
