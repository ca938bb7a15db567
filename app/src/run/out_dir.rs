//! A run's output directory: where it goes when none is given, and the guard that keeps a
//! run from writing over an earlier run's files (`RunOptions::overwrite`).

use std::path::{Path, PathBuf};

use meshfree_core::scene::{paper_exact, Scene, SceneSource};

use super::{io_err, RunError};
use crate::output::files;

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

/// Make `dir` ready for a fresh run of a scene whose force monitors are named
/// `monitors` (the contract: `output::files`). An earlier run's output (its summary, scene
/// copy, series or checkpoint) is refused unless `overwrite`; with it, exactly the earlier
/// run's files go: those its `summary.json` lists, its frames, series, checkpoint and
/// temporaries. Any other file bearing a name this run writes is refused (never
/// overwritten, never followed where it is a link); any other file stays.
pub(super) fn prepare_out_dir(
    dir: &Path,
    overwrite: bool,
    monitors: &[String],
) -> Result<(), RunError> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(io_err(dir)(e)),
    };
    let mut names = Vec::new();
    for entry in entries {
        let entry = entry.map_err(io_err(dir))?;
        // The entry's own type: a link is a link, not what it points to.
        let is_dir = entry.file_type().map_err(io_err(dir))?.is_dir();
        names.push((entry.file_name().to_string_lossy().into_owned(), is_dir));
    }
    names.sort();
    let marker = names.iter().map(|(n, _)| n.as_str()).find(|n| {
        [
            files::SUMMARY,
            files::SCENE,
            files::SERIES,
            files::CHECKPOINT,
        ]
        .contains(n)
    });
    let earlier = marker.is_some();
    if let Some(marker) = marker.filter(|_| !overwrite) {
        return Err(in_use(
            dir,
            format!(
                "holds an earlier run's output (`{marker}` and its other files); pass \
                 --overwrite to replace it, or --out to write elsewhere"
            ),
        ));
    }
    let listed = if earlier {
        earlier_files(dir)?
    } else {
        Vec::new()
    };
    let (mut ours, mut foreign) = (Vec::new(), Vec::new());
    for (name, is_dir) in names {
        let base = name.strip_suffix(".tmp").unwrap_or(&name);
        if earlier && !is_dir && (files::by_pattern(base) || listed.iter().any(|l| l == base)) {
            ours.push(name);
        } else if files::would_write(&name, monitors) {
            foreign.push(name);
        }
    }
    if let Some(name) = foreign.first() {
        let whose = if earlier {
            "the earlier run's summary.json does not list it"
        } else {
            "no run's output is there"
        };
        return Err(in_use(
            dir,
            format!(
                "holds `{name}`, a name this run writes, and {whose}: it is not replaced; \
                 move it or choose another --out"
            ),
        ));
    }
    for name in ours {
        let path = dir.join(&name);
        std::fs::remove_file(&path).map_err(io_err(&path))?;
    }
    Ok(())
}

/// The files the earlier run in `dir` listed in its `summary.json` (`RunSummary::files`):
/// plain names only. Refused where it cannot be read or lists none (a run of an earlier
/// release, or a damaged summary): the user removes that output.
fn earlier_files(dir: &Path) -> Result<Vec<String>, RunError> {
    let path = dir.join(files::SUMMARY);
    let listed = std::fs::read(&path)
        .ok()
        .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
        .and_then(|v| serde_json::from_value::<Vec<String>>(v.get("files")?.clone()).ok());
    let why = match &listed {
        None => "its summary.json is missing, damaged or from an earlier release, which lists \
                 no files"
            .to_string(),
        Some(l) => match l.iter().find(|n| !files::is_plain(n)) {
            Some(bad) => format!("its summary.json lists `{bad}`, which is not a file of the run"),
            None => return Ok(listed.unwrap_or_default()),
        },
    };
    Err(in_use(
        dir,
        format!(
            "holds an earlier run's output, but {why}: --overwrite removes only the files a \
             run lists; remove that output by hand, or choose another --out"
        ),
    ))
}

fn in_use(dir: &Path, reason: String) -> RunError {
    RunError::OutputInUse {
        dir: dir.to_path_buf(),
        reason,
    }
}
