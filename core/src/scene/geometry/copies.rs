//! A run's copies of its surfaces' files: each file a scene's surfaces were read from is
//! copied into the run's directory as `surface-N.<ext>` (`run_files::surface_file`), and the
//! run's copy of the scene names those, so that `run --resume`, `render` and `view` read the
//! run's directory alone, wherever the original files have gone.

use super::objects::surfaces;
use super::surface::From;
use crate::scene::{Scene, SceneError};

/// A file to write into the run's directory.
pub struct SurfaceCopy {
    /// Its name there (`surface-N.<ext>`).
    pub name: String,
    pub bytes: Vec<u8>,
}

impl Scene {
    /// The scene as a run's directory holds it: its surfaces' files renamed to their copies
    /// (in the text, every comment kept, and in `file`, the surfaces read kept), and the
    /// copies to write beside it. Unchanged, with no copy, where no surface is read from a
    /// file. Err where a file cannot be read again.
    pub fn with_surface_copies(&self) -> Result<(Scene, Vec<SurfaceCopy>), SceneError> {
        let mut scene = self.clone();
        let mut copies = Vec::new();
        let mut doc: Option<toml_edit::DocumentMut> = None;
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
            let doc = match doc.as_mut() {
                Some(d) => d,
                None => doc.insert(
                    self.text
                        .parse()
                        .map_err(|e| err(format!("the scene's text: {e}")))?,
                ),
            };
            set_file(doc, &placed.field, &name)
                .ok_or_else(|| err("the key is not where the scene's text holds it".into()))?;
            copies.push(SurfaceCopy { name, bytes });
        }
        let Some(doc) = doc else {
            return Ok((scene, copies));
        };
        scene.text = doc.to_string();
        // The same renaming in the parsed file; the surfaces read stay.
        let names: Vec<String> = copies.iter().map(|c| c.name.clone()).collect();
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
        Ok((scene, copies))
    }
}

/// Sets the `file` of the surface at `field` (`walls[2].mesh`) in `doc`.
fn set_file(doc: &mut toml_edit::DocumentMut, field: &str, name: &str) -> Option<()> {
    let (array, rest) = field.split_once('[')?;
    let (index, key) = rest.split_once("].")?;
    let index: usize = index.parse().ok()?;
    let table = doc.get_mut(array)?.get_mut(index)?.get_mut(key)?;
    let value = table.get_mut("file")?.as_value_mut()?;
    let decor = value.decor().clone();
    *value = toml_edit::Value::from(name);
    *value.decor_mut() = decor;
    Some(())
}
