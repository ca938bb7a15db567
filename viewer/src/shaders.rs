//! The GLSL sources (`shaders/`), one file per stage; the particle passes' fragment
//! shaders and the surface's shading share `sphere.glsl` (ray-cast, window depth).

pub(crate) const PARTICLE_VS: &str = include_str!("shaders/particle.vert");
pub(crate) const FULLSCREEN_VS: &str = include_str!("shaders/fullscreen.vert");
pub(crate) const BLUR_FS: &str = include_str!("shaders/surface_blur.frag");
pub(crate) const OUTLINE_VS: &str = include_str!("shaders/outline.vert");
pub(crate) const OUTLINE_FS: &str = include_str!("shaders/outline.frag");

const SPHERE: &str = include_str!("shaders/sphere.glsl");

/// The fragment shaders built on `sphere.glsl`.
#[derive(Debug, Clone, Copy)]
pub(crate) enum SphereFs {
    /// Lit spheres.
    Shaded,
    /// The surface's eye distance.
    SurfaceDepth,
    /// The surface's thickness.
    SurfaceThickness,
    /// The surface's shading (a full-screen pass; it uses `window_depth`).
    SurfaceShade,
}

/// The full source of a particle fragment shader: version, the sphere ray-cast, the body.
pub(crate) fn sphere_fs(which: SphereFs) -> String {
    let body = match which {
        SphereFs::Shaded => include_str!("shaders/particle.frag"),
        SphereFs::SurfaceDepth => include_str!("shaders/surface_depth.frag"),
        SphereFs::SurfaceThickness => include_str!("shaders/surface_thickness.frag"),
        SphereFs::SurfaceShade => include_str!("shaders/surface_shade.frag"),
    };
    format!("#version 330 core\n{SPHERE}\n{body}")
}
