//! A run's copies of its input files: each file a scene's surfaces were read from is copied
//! into the run's directory as `surface-N.<ext>` (`run_files::surface_file`), each motion
//! series' file as `motion-N.csv` (`run_files::motion_file`), and the run's copy of the scene
//! names those, so that `run --resume`, `render` and `view` read the run's directory alone,
//! wherever the original files have gone.

use super::objects::surfaces;
use super::surface::From;
use crate::scene::{Scene, SceneError};

/// A file to write into the run's directory.
pub struct SurfaceCopy {
    /// Its name there (`surface-N.<ext>`, `motion-N.csv`).
    pub name: String,
    pub bytes: Vec<u8>,
}

impl Scene {
    /// The scene as a run's directory holds it: its surfaces' and motion series' files
    /// renamed to their copies (in the text, every comment kept, and in `file`, the surfaces
    /// and series read kept), and the copies to write beside it. Unchanged, with no copy,
    /// where nothing is read from a file. Err where a surface file cannot be read again.
    pub fn with_surface_copies(&self) -> Result<(Scene, Vec<SurfaceCopy>), SceneError> {
        let mut scene = self.clone();
        let mut copies = Vec::new();
        // The field of each copy's table in the scene (`walls[2].mesh`), in the copies' order.
        let mut fields: Vec<String> = Vec::new();
        for placed in surfaces(&self.file) {
            let Some(surface) = placed.outline.loaded.get() else {
                continue;
            };
            let Some(file) = placed.outline.file.as_ref() else {
                continue;
            };
            let err = |reason: String| SceneError::Invalid {
                origin: self.origin(),
                field: format!("{}.file", placed.field),
                reason,
            };
            let bytes = match &surface.from {
                From::Path(path) => super::read::bytes_of(path)
                    .map_err(|why| err(format!("{}: {why}", path.display())))?,
                From::Asset(bytes) => bytes.to_vec(),
                From::Points => continue,
            };
            let ext = file
                .rsplit_once('.')
                .map_or("", |(_, e)| e)
                .to_ascii_lowercase();
            let name = crate::run_files::surface_file(copies.len(), &ext);
            fields.push(placed.field.clone());
            copies.push(SurfaceCopy { name, bytes });
        }
        // The series' bytes were kept when they were read.
        let n_surfaces = copies.len();
        let motions = crate::scene::motion_series::series_of(&self.file)
            .into_iter()
            .enumerate()
            .map(|(k, (f, r))| (crate::run_files::motion_file(k), f, r));
        let inlets = crate::scene::motion_series::inlet_series_of(&self.file)
            .into_iter()
            .enumerate()
            .map(|(k, (f, r))| (crate::run_files::inflow_file(k), f, r));
        for (name, field, series) in motions.chain(inlets) {
            let Some(knots) = series.loaded.get() else {
                continue;
            };
            fields.push(field);
            copies.push(SurfaceCopy {
                name,
                bytes: knots.bytes.clone(),
            });
        }
        if copies.is_empty() {
            return Ok((scene, copies));
        }
        // Each copied file's key in the text (`fields[k]`, the table holding `file`) names
        // its copy, every comment kept.
        let mut doc: toml_edit::DocumentMut =
            self.text.parse().map_err(|e| SceneError::Invalid {
                origin: self.origin(),
                field: format!("{}.file", fields[0]),
                reason: format!("the scene's text: {e}"),
            })?;
        for (field, copy) in fields.iter().zip(&copies) {
            set_file(&mut doc, field, &copy.name).ok_or_else(|| SceneError::Invalid {
                origin: self.origin(),
                field: format!("{field}.file"),
                reason: "the key is not where the scene's text holds it".into(),
            })?;
        }
        scene.text = doc.to_string();
        // The same renaming in the parsed file; the surfaces read stay.
        let names: Vec<String> = copies[..n_surfaces]
            .iter()
            .map(|c| c.name.clone())
            .collect();
        let mut k = 0;
        let mut rename = |o: &mut crate::scene::format::Outline| {
            if o.file.is_some() && o.loaded.get().is_some() {
                o.file = Some(names[k].clone());
                k += 1;
            }
        };
        let f = &mut scene.file;
        for b in f.fluid_blocks.iter_mut() {
            if let Some(o) = b.inside.as_mut() {
                rename(o);
            }
        }
        for o in f.solids.iter_mut() {
            if let Some(o) = o.outline_mut() {
                rename(o);
            }
        }
        for w in f.walls.iter_mut() {
            if let Some(o) = w.outline_mut() {
                rename(o);
            }
        }
        let mut k = 0;
        for o in f.solids.iter_mut().filter_map(|o| o.motion_mut()) {
            rename_series(o, &mut k);
        }
        for o in f.walls.iter_mut().filter_map(|w| w.motion_mut()) {
            rename_series(o, &mut k);
        }
        let mut k = 0;
        for o in f.open_boundaries.iter_mut() {
            if let Some(r) = o.series.as_mut().filter(|r| r.loaded.get().is_some()) {
                r.file = crate::run_files::inflow_file(k);
                k += 1;
            }
        }
        Ok((scene, copies))
    }
}

/// A motion's series file renamed to the `k`th copy's name, `k` counting the series read.
fn rename_series(m: &mut crate::scene::format::Motion, k: &mut usize) {
    if let crate::scene::format::Motion::Law(l) = m {
        if let Some(r) = l.series.as_mut().filter(|r| r.loaded.get().is_some()) {
            r.file = crate::run_files::motion_file(*k);
            *k += 1;
        }
    }
}

/// Sets the `file` of the table at `field` (`walls[2].mesh`, `walls[0].motion.series`) in
/// `doc`.
fn set_file(doc: &mut toml_edit::DocumentMut, field: &str, name: &str) -> Option<()> {
    let (array, rest) = field.split_once('[')?;
    let (index, keys) = rest.split_once("].")?;
    let index: usize = index.parse().ok()?;
    let mut table = doc.get_mut(array)?.get_mut(index)?;
    for key in keys.split('.') {
        table = table.get_mut(key)?;
    }
    let value = table.get_mut("file")?.as_value_mut()?;
    let decor = value.decor().clone();
    *value = toml_edit::Value::from(name);
    *value.decor_mut() = decor;
    Some(())
}
