//! A run's output directory: where it goes when none is given, and the guard that keeps a
//! run from writing over an earlier run's files (`RunOptions::overwrite`).

use std::path::{Path, PathBuf};

use meshfree_core::scene::{paper_exact, Scene, SceneSource};

use super::{io_err, RunError};

/// The output directory of a scene when none is given: `out/<file stem>` for a scene file
/// (a copy of a built-in keeps its `name`, not its directory), `out/<name>` otherwise;
/// `-paper-exact` appended for the paper's form (`Scene::with_paper_exact`).
pub fn default_out_dir(scene: &Scene) -> PathBuf {
    let stem = match &scene.source {
        SceneSource::File(p) => p.file_stem().map(|s| s.to_string_lossy().into_owned()),
        _ => None,
    };
    let Some(mut stem) = stem else {
        return Path::new("out").join(scene.name());
    };
    if scene.name().ends_with(paper_exact::NAME_SUFFIX) {
        stem.push_str(paper_exact::NAME_SUFFIX);
    }
    Path::new("out").join(stem)
}

/// The files a run writes into its directory: particle files, the series, CSVs, JSON, the
/// scene copy and temporaries of the atomic writes.
fn is_run_file(name: &str) -> bool {
    name == "scene.toml"
        || [".vtu", ".pvd", ".csv", ".json", ".tmp", ".png", ".bin"]
            .iter()
            .any(|e| name.ends_with(e))
}

/// Make `dir` ready for a run: refuse an earlier run's output unless `overwrite`, and then
/// remove only files a run writes (a directory with anything else is refused either way).
pub(super) fn prepare_out_dir(dir: &Path, overwrite: bool) -> Result<(), RunError> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(io_err(dir)(e)),
    };
    let (mut ours, mut others) = (Vec::new(), Vec::new());
    for entry in entries {
        let entry = entry.map_err(io_err(dir))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let file = entry.file_type().map(|t| t.is_file()).unwrap_or(false);
        if file && is_run_file(&name) {
            ours.push(entry.path());
        } else {
            others.push(name);
        }
    }
    let run_there = ours.iter().any(|p| {
        p.file_name()
            .is_some_and(|n| n == "summary.json" || n == "scene.toml" || n == "particles.pvd")
    });
    if !run_there {
        return Ok(());
    }
    if !overwrite {
        return Err(RunError::OutputInUse {
            dir: dir.to_path_buf(),
            reason: format!(
                "holds an earlier run's output ({} files: summary.json, frames, CSVs); pass \
                 --overwrite to replace it, or --out to write elsewhere",
                ours.len()
            ),
        });
    }
    if !others.is_empty() {
        others.sort();
        return Err(RunError::OutputInUse {
            dir: dir.to_path_buf(),
            reason: format!(
                "--overwrite clears only a run's own files, and this directory also holds {} \
                 (`{}`{}): move them or choose another --out",
                others.len(),
                others[0],
                if others.len() > 1 { ", ..." } else { "" }
            ),
        });
    }
    for path in ours {
        std::fs::remove_file(&path).map_err(io_err(&path))?;
    }
    Ok(())
}
