//! Where a scene's surface files are read from: beside the scene file, or among the assets
//! compiled into the binary for the built-in scenes.

use std::path::{Path, PathBuf};

/// Where a scene's surface files are: beside the scene file, or (a built-in scene) among the
/// assets compiled into the binary (`ASSETS`).
#[derive(Clone, Debug)]
pub enum Base {
    Dir(PathBuf),
    Builtin,
}

/// The surface files the built-in scenes use, by the name they give (relative to `scenes/`,
/// so that the files in `scenes/` read the same files from the repository); their sources
/// and licences are in `assets/meshes/LICENSES.md`.
pub const ASSETS: &[(&str, &[u8])] = &[(
    "../assets/meshes/spot.obj",
    include_bytes!("../../../../assets/meshes/spot.obj"),
)];

/// The directory a scene file's surfaces are read from: the file's own.
pub fn base_of(scene_file: &Path) -> Base {
    Base::Dir(
        scene_file
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default(),
    )
}
