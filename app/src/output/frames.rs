//! A finished run's frames, read back for `meshfree render DIR` and `meshfree view DIR`
//! (issue #51): the run's scene (`scene.toml`: dimension, domain, spacing, walls), its
//! frames in time order (the series `particles.pvd` with its times, else the
//! `particles_NNNNN.csv` files with the times of `diagnostics.csv`'s rows, one a frame), and
//! each frame read as the run wrote it (`vtu_read::read_vtu`, `read_frame_csv`).
//!
//! A field the drawing needs that the run did not write (`[output] fields`) is an error
//! naming the field and the fields the frame has (`values`), except the kinds: without
//! them every particle is drawn as fluid (`kinds`).

use std::path::{Path, PathBuf};

use meshfree_core::named::Named;
use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::Scene;
use meshfree_core::solver::frame::{Field, FrameData};
use meshfree_core::solver::Shown;

use super::files::{self, DIAGNOSTICS, SCENE, SERIES, SUMMARY};
use crate::bad_input::BadInput;

/// One recorded frame: its simulated time \[T\] and file.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordedFrame {
    pub time: f64,
    pub path: PathBuf,
}

/// A run's output directory as `render DIR` and `view DIR` read it.
#[derive(Clone, Debug)]
pub struct RecordedRun {
    pub dir: PathBuf,
    /// The run's scene (its copy `scene.toml`).
    pub scene: Scene,
    /// The frames in time order.
    pub frames: Vec<RecordedFrame>,
}

fn bad(msg: String) -> BadInput {
    BadInput(msg)
}

impl RecordedRun {
    /// Open the run in `dir`: its scene copy and its list of frames. Refused (`BadInput`,
    /// exit status 2) where `dir` holds no scene copy, where the run wrote no particle files
    /// (format `none`), or where no frame is there.
    pub fn open(dir: &Path) -> Result<RecordedRun, BadInput> {
        let d = dir.display();
        let scene_path = dir.join(SCENE);
        if !scene_path.is_file() {
            return Err(bad(format!(
                "{d} holds no {SCENE}: not the output directory of `meshfree run` (render \
                 takes a scene file, a built-in scene's name or a run's directory)"
            )));
        }
        let scene = Scene::from_file(&scene_path).map_err(|e| bad(format!("{e}")))?;
        // The format the run wrote, from summary.json where it says (else the scene's).
        let format = std::fs::read_to_string(dir.join(SUMMARY))
            .ok()
            .and_then(|s| serde_json::from_str::<serde_json::Value>(&s).ok())
            .and_then(|v| v.get("output_format")?.as_str().map(str::to_string))
            .unwrap_or_else(|| scene.file.output.format.name().to_string());
        let frames = if dir.join(SERIES).is_file() {
            series(dir)?
        } else {
            csv_frames(dir)?
        };
        if frames.is_empty() {
            let why = if format == "none" {
                "the run wrote no particle files (output format `none`): run the scene \
                 again with `--format vtu` (or `csv`) to render it"
                    .to_string()
            } else {
                format!("no frames there ({SERIES} or particles_NNNNN.csv)")
            };
            return Err(bad(format!("{d}: nothing to render: {why}")));
        }
        Ok(RecordedRun {
            dir: dir.to_path_buf(),
            scene,
            frames,
        })
    }

    /// Read frame `k` (its time set from the list).
    pub fn read(&self, k: usize) -> Result<FrameData, BadInput> {
        let f = &self.frames[k];
        let ext = f.path.extension().and_then(|e| e.to_str());
        let mut frame = match ext {
            Some("csv") => read_frame_csv(&f.path),
            _ => super::vtu_read::read_vtu(&f.path),
        }
        .map_err(bad)?;
        frame.time = f.time;
        Ok(frame)
    }

    /// The index of the frame nearest time `t` (the earlier one on a tie).
    pub fn nearest(&self, t: f64) -> usize {
        let mut best = 0;
        for (k, f) in self.frames.iter().enumerate() {
            if (f.time - t).abs() < (self.frames[best].time - t).abs() {
                best = k;
            }
        }
        best
    }

    /// `n` frame indices evenly spaced from the first frame to the last (repeating frames
    /// where `n` exceeds the run's frames).
    pub fn evenly(&self, n: usize) -> Vec<usize> {
        let last = self.frames.len() - 1;
        match n {
            0 => Vec::new(),
            1 => vec![last],
            n => (0..n)
                .map(|k| ((k * last) as f64 / (n - 1) as f64).round() as usize)
                .collect(),
        }
    }
}

/// The series' data sets (time, file), in time order; a file name must lie directly in `dir`.
fn series(dir: &Path) -> Result<Vec<RecordedFrame>, BadInput> {
    let path = dir.join(SERIES);
    let text =
        std::fs::read_to_string(&path).map_err(|e| bad(format!("{}: {e}", path.display())))?;
    let mut out = Vec::new();
    for line in text.lines().filter(|l| l.contains("<DataSet")) {
        let get = |key: &str| -> Option<&str> {
            let k = format!("{key}=\"");
            let s = line.find(&k)? + k.len();
            Some(&line[s..s + line[s..].find('"')?])
        };
        let (Some(t), Some(file)) = (get("timestep"), get("file")) else {
            return Err(bad(format!(
                "{}: a <DataSet> without timestep or file: {}",
                path.display(),
                line.trim()
            )));
        };
        let time: f64 = t
            .parse()
            .map_err(|_| bad(format!("{}: timestep `{t}` is no number", path.display())))?;
        if !files::is_plain(file) {
            return Err(bad(format!(
                "{}: `{file}` is not a file name inside the run's directory",
                path.display()
            )));
        }
        out.push(RecordedFrame {
            time,
            path: dir.join(file),
        });
    }
    out.sort_by(|a, b| a.time.total_cmp(&b.time));
    Ok(out)
}

/// `particles_NNNNN.csv` in index order, with the times of `diagnostics.csv` (one row per
/// output, in order; a CSV has no time of its own), else numbered by the output interval.
fn csv_frames(dir: &Path) -> Result<Vec<RecordedFrame>, BadInput> {
    let read = std::fs::read_dir(dir).map_err(|e| bad(format!("{}: {e}", dir.display())))?;
    let mut found: Vec<(usize, PathBuf)> = read
        .filter_map(Result::ok)
        .filter_map(|e| {
            let name = e.file_name().into_string().ok()?;
            let k = files::frame_index(&name).filter(|_| name.ends_with(".csv"))?;
            Some((k, e.path()))
        })
        .collect();
    found.sort();
    let times: Vec<f64> = std::fs::read_to_string(dir.join(DIAGNOSTICS))
        .map(|s| {
            s.lines()
                .skip(1)
                .filter_map(|l| l.split(',').nth(1)?.trim().parse().ok())
                .collect()
        })
        .unwrap_or_default();
    let interval = Scene::from_file(dir.join(SCENE))
        .map(|s| s.file.time.output_interval)
        .unwrap_or(0.0);
    Ok(found
        .into_iter()
        .map(|(k, path)| RecordedFrame {
            time: times.get(k).copied().unwrap_or(k as f64 * interval),
            path,
        })
        .collect())
}

/// Read a particle CSV of a run (`write_particles_csv`): the columns it has, by name (kind
/// as its name or code). Errors name the file, the line and the column.
pub fn read_frame_csv(path: &Path) -> Result<FrameData, String> {
    let p = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{p}: {e}"))?;
    let mut lines = text.lines().enumerate();
    let header = lines.next().ok_or(format!("{p}: empty file"))?.1;
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    let col = |name: &str| cols.iter().position(|c| *c == name);
    let group = |names: &[&str]| -> Option<Vec<usize>> { names.iter().map(|n| col(n)).collect() };
    let pos = group(&["x", "y", "z"]).ok_or(format!("{p}: no x,y,z columns"))?;
    let vel = group(&["vx", "vy", "vz"]);
    let stress = group(&["sxx", "syy", "szz", "sxy", "sxz", "syz"]);
    let (density, pressure, kind, id, grp) = (
        col("density"),
        col("pressure"),
        col("kind"),
        col("id"),
        col("group"),
    );
    let mut f = FrameData::default();
    for (k, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let row: Vec<&str> = line.split(',').map(str::trim).collect();
        let at = |i: usize| -> Result<&str, String> {
            row.get(i)
                .copied()
                .ok_or_else(|| format!("{p}: line {}: no `{}` column", k + 1, cols[i]))
        };
        let num = |i: usize| -> Result<f32, String> {
            at(i)?
                .parse::<f32>()
                .map_err(|e| format!("{p}: line {}: `{}`: {e}", k + 1, cols[i]))
        };
        let int = |i: usize| -> Result<u32, String> {
            at(i)?
                .parse::<u32>()
                .map_err(|e| format!("{p}: line {}: `{}`: {e}", k + 1, cols[i]))
        };
        f.position.push([num(pos[0])?, num(pos[1])?, num(pos[2])?]);
        if let Some(v) = &vel {
            f.velocity.push([num(v[0])?, num(v[1])?, num(v[2])?]);
        }
        if let Some(s) = &stress {
            let mut x = [0.0; 6];
            for (x, &i) in x.iter_mut().zip(s) {
                *x = num(i)?;
            }
            f.stress.push(x);
        }
        if let Some(i) = density {
            f.density.push(num(i)?);
        }
        if let Some(i) = pressure {
            f.pressure.push(num(i)?);
        }
        if let Some(i) = id {
            f.id.push(int(i)?);
        }
        if let Some(i) = grp {
            f.group.push(int(i)?);
        }
        if let Some(i) = kind {
            let t = at(i)?;
            let kind = Kind::ALL
                .into_iter()
                .find(|c| c.name() == t || c.code().to_string() == t)
                .ok_or_else(|| format!("{p}: line {}: `kind`: unknown kind `{t}`", k + 1))?;
            f.kind.push(kind.code());
        }
    }
    f.len = f.position.len();
    Ok(f)
}

/// The names of the fields `frame` carries, e.g. "position, velocity, density".
pub fn field_names(frame: &FrameData) -> String {
    let names: Vec<&str> = frame
        .fields()
        .list()
        .into_iter()
        .map(|f| f.name())
        .collect();
    names.join(", ")
}

/// The values that colour the particles by `field`; an error naming the missing field and
/// the fields the frame has where the run did not write it.
pub fn values(frame: &FrameData, field: Shown, what: &str) -> Result<Vec<f32>, BadInput> {
    let need = field.source();
    if !frame.fields().has(need) {
        return Err(bad(format!(
            "{what} has no `{}` field, which --field {} needs; it has: {} (choose another \
             --field, or list `{}` in the scene's `[output] fields`)",
            need.name(),
            field.name(),
            field_names(frame),
            need.name()
        )));
    }
    Ok(match field {
        Shown::Speed => frame
            .velocity
            .iter()
            .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
            .collect(),
        Shown::Pressure => frame.pressure.clone(),
        Shown::Density => frame.density.clone(),
        Shown::Kind => frame.kind.iter().map(|&k| f32::from(k)).collect(),
    })
}

/// The particles' kind codes; without the `kind` field, every particle counts as fluid
/// (so the walls are drawn in colour and `--show-boundary` changes nothing).
pub fn kinds(frame: &FrameData) -> Vec<u8> {
    if frame.fields().has(Field::Kind) {
        frame.kind.clone()
    } else {
        vec![Kind::Fluid.code(); frame.len]
    }
}
