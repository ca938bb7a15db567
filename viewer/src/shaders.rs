//! The GLSL sources (`shaders/`), one file per stage; the particle passes' fragment
//! shaders and the surface's shading share `sphere.glsl` (ray-cast, window depth); the
//! program build (`compile`) and the particle passes' shared uniforms.

use glam::Mat4;
use glow::HasContext;

use crate::error::gl_err;
use crate::ViewerError;

const PARTICLE_VS: &str = include_str!("shaders/particle.vert");
pub(crate) const FULLSCREEN_VS: &str = include_str!("shaders/fullscreen.vert");
pub(crate) const BLUR_FS: &str = include_str!("shaders/surface_blur.frag");
pub(crate) const OUTLINE_VS: &str = include_str!("shaders/outline.vert");
pub(crate) const OUTLINE_FS: &str = include_str!("shaders/outline.frag");

const SPHERE: &str = include_str!("shaders/sphere.glsl");
/// A sphere's colour and shading level: in the sprites' vertex shader and the splat's
/// resolve (`with_colour`).
const COLOUR: &str = include_str!("shaders/colour.glsl");

/// The fragment shaders built on `sphere.glsl`.
#[derive(Debug, Clone, Copy)]
pub(crate) enum SphereFs {
    /// Lit spheres.
    Shaded,
    /// The surface's eye distance (depth-tested) ...
    SurfaceDepth,
    /// ... and its thickness (additive, at half resolution).
    SurfaceThickness,
    /// The surface's shading (a full-screen pass; it uses `window_depth`).
    SurfaceShade,
    /// The visibility splat's resolve (a full-screen pass, `splat.rs`).
    Splat,
}

/// The full source of a particle fragment shader: version, the sphere ray-cast, the body
/// (the sprite passes' ones build it through [`SpriteProgram`], with their defines).
/// `GL_ARB_conservative_depth` (core in GL 4.2; NVIDIA's and Mesa's contexts have it) lets
/// the impostors declare that their depth lies behind the quad's (`depth_greater`), which
/// keeps the early depth test on; without it they still draw, tested late.
pub(crate) fn sphere_fs(which: SphereFs) -> String {
    let body = match which {
        SphereFs::Shaded => include_str!("shaders/particle.frag"),
        SphereFs::SurfaceDepth => include_str!("shaders/surface_depth.frag"),
        SphereFs::SurfaceThickness => include_str!("shaders/surface_thickness.frag"),
        SphereFs::SurfaceShade => include_str!("shaders/surface_shade.frag"),
        SphereFs::Splat => include_str!("shaders/splat.frag"),
    };
    let colour = if matches!(which, SphereFs::Splat) {
        COLOUR
    } else {
        ""
    };
    format!(
        "#version 330 core\n#extension GL_ARB_conservative_depth : enable\n{SPHERE}\n{colour}\n{body}"
    )
}

/// `src` (a vertex shader) with `colour.glsl` after its first line (the `#version`).
fn with_colour(src: &str) -> String {
    let (version, rest) = src.split_once('\n').unwrap_or((src, ""));
    format!("{version}\n{COLOUR}\n{rest}")
}

/// `src` with `#define`s of `defines` after its first line (the `#version`).
fn with_defines(src: &str, defines: &[&str]) -> String {
    let (version, rest) = src.split_once('\n').unwrap_or((src, ""));
    let defs: String = defines.iter().map(|d| format!("#define {d}\n")).collect();
    format!("{version}\n{defs}{rest}")
}

/// A sprite pass's two programs, `particle.vert` with one fragment shader of `sphere.glsl`:
/// one for points and one for instanced quads (built with `SPRITE_QUADS`, the only one
/// whose sprites interpolate a point per fragment), so that a point carries only its flat
/// outputs ([`crate::sprites::Sprites::draw`] picks them).
#[derive(Debug, Clone, Copy)]
pub(crate) struct SpriteProgram {
    pub points: glow::Program,
    pub quads: glow::Program,
}

impl SpriteProgram {
    pub(crate) unsafe fn new(
        gl: &glow::Context,
        which: SphereFs,
    ) -> Result<SpriteProgram, ViewerError> {
        let fs = sphere_fs(which);
        // SAFETY: the context rule (this fn's contract), which `compile` asks.
        let build = |defines: &[&str]| unsafe {
            compile(
                gl,
                &with_defines(&with_colour(PARTICLE_VS), defines),
                &with_defines(&fs, defines),
            )
        };
        let points = build(&["SPRITE_FS"])?;
        match build(&["SPRITE_FS", "SPRITE_QUADS"]) {
            Ok(quads) => Ok(SpriteProgram { points, quads }),
            Err(e) => {
                // SAFETY: the context rule (this fn's contract); `points` was made just
                // above and is deleted once, here.
                unsafe { gl.delete_program(points) };
                Err(e)
            }
        }
    }

    pub(crate) unsafe fn delete(&self, gl: &glow::Context) {
        // SAFETY: the context rule (this fn's contract): the two programs are this pass's,
        // deleted once (by its owner's `destroy`).
        unsafe {
            gl.delete_program(self.points);
            gl.delete_program(self.quads);
        }
    }
}

/// Compiles and links a program of one vertex and one fragment shader.
pub(crate) unsafe fn compile(
    gl: &glow::Context,
    vs: &str,
    fs: &str,
) -> Result<glow::Program, ViewerError> {
    // SAFETY: the context rule (this fn's contract; every object named is created here and
    // the shaders deleted once, after the link or on failure).
    unsafe {
        let prog = gl.create_program().map_err(gl_err)?;
        let mut shaders = Vec::new();
        for (kind, src) in [(glow::VERTEX_SHADER, vs), (glow::FRAGMENT_SHADER, fs)] {
            let s = gl.create_shader(kind).map_err(gl_err)?;
            gl.shader_source(s, src);
            gl.compile_shader(s);
            if !gl.get_shader_compile_status(s) {
                let log = gl.get_shader_info_log(s);
                gl.delete_shader(s);
                gl.delete_program(prog);
                return Err(gl_err(format!("shader compile: {log}")));
            }
            gl.attach_shader(prog, s);
            shaders.push(s);
        }
        gl.link_program(prog);
        for s in shaders {
            gl.detach_shader(prog, s);
            gl.delete_shader(s);
        }
        if !gl.get_program_link_status(prog) {
            let log = gl.get_program_info_log(prog);
            gl.delete_program(prog);
            return Err(gl_err(format!("program link: {log}")));
        }
        Ok(prog)
    }
}

/// The uniforms of the particle vertex shader (`shaders/particle.vert`), which every
/// particle pass shares.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ParticleUniforms {
    pub view: Mat4,
    pub proj: Mat4,
    /// Sphere radius [L].
    pub radius: f32,
    pub range: (f32, f32),
    /// Bit k hides kind k.
    pub hidden: i32,
    pub grey_boundary: bool,
    pub ortho: bool,
    /// Pixels per world unit (at unit depth in perspective).
    pub px_scale: f32,
}

impl ParticleUniforms {
    /// Sets them on `prog` (in use) and binds the colour map to texture unit 0.
    pub(crate) unsafe fn set(&self, gl: &glow::Context, prog: glow::Program, cmap: glow::Texture) {
        // SAFETY: the context rule (this fn's contract: prog and cmap are the caller's, of
        // this context); the matrices are 16 floats each, as the uniforms' mat4.
        unsafe {
            let loc = |n: &str| gl.get_uniform_location(prog, n);
            gl.uniform_matrix_4_f32_slice(
                loc("u_view").as_ref(),
                false,
                &self.view.to_cols_array(),
            );
            gl.uniform_matrix_4_f32_slice(
                loc("u_proj").as_ref(),
                false,
                &self.proj.to_cols_array(),
            );
            gl.uniform_1_f32(loc("u_radius").as_ref(), self.radius.max(1e-9));
            gl.uniform_2_f32(loc("u_range").as_ref(), self.range.0, self.range.1);
            gl.uniform_1_i32(loc("u_hidden").as_ref(), self.hidden);
            gl.uniform_1_i32(loc("u_grey_boundary").as_ref(), self.grey_boundary as i32);
            gl.uniform_1_i32(loc("u_ortho").as_ref(), self.ortho as i32);
            gl.uniform_1_f32(loc("u_px_scale").as_ref(), self.px_scale);
            gl.uniform_1_i32(loc("u_cmap").as_ref(), 0);
            gl.active_texture(glow::TEXTURE0);
            gl.bind_texture(glow::TEXTURE_2D, Some(cmap));
        }
    }
}
