//! The screen-space fluid surface of van der Laan, Green & Sainz (2009, "Screen space fluid
//! rendering with curvature flow"), with a bilateral filter in place of their curvature
//! flow: the fluid particles' spheres, drawn once into two targets of half the view's
//! resolution, give the eye distance of the nearest fluid in each pixel (MIN blending) and
//! the fluid's thickness along it (additive blending; per-target blend equations,
//! `glBlendEquationi`: OpenGL 4.0); the distance is smoothed at that resolution, and the
//! shading pass, at the view's, takes it up (bilinear over the texels of the nearest sheet),
//! makes normals from it, and adds Fresnel reflection of a sky and Beer-Lambert absorption
//! over the thickness, over what is already drawn. Every sprite drawn costs a pass about the
//! same whatever its size (some 2 ns on an H200), so the spheres are drawn once; what the
//! resolution sets is the spheres' pixels, hundreds deep in a large block of water, every
//! one shaded and blended. Our own shaders (`shaders/surface_*`).

use glam::{Mat3, Vec3};
use glow::HasContext;

use crate::error::gl_err;
use crate::gpu_timers::GpuTimers;
use crate::shaders::{
    compile, sphere_fs, ParticleUniforms, SphereFs, BLUR_FS, FULLSCREEN_VS, PARTICLE_VS,
};
use crate::sprites::{SpriteView, Sprites};
use crate::ViewerError;

/// The surface's spheres are this many particle radii: neighbours overlap and merge.
const SPHERE_SCALE: f32 = 1.5;
/// Bilateral filter: horizontal then vertical passes, this many times.
const BLUR_ITERATIONS: usize = 2;
/// The blur passes' names for the GPU timers, in order.
const BLUR_PASSES: [&str; 2 * BLUR_ITERATIONS] = ["blur 1 x", "blur 1 y", "blur 2 x", "blur 2 y"];
/// The filter's Gaussian spans this many particle spacings in the world (sigma half of it).
const BLUR_SPACINGS: f32 = 2.0;
/// ... and never more than this many pixels of the view either side.
const BLUR_MAX_PX: i32 = 24;
/// Depth differences of this many particle spacings count as another sheet of fluid.
const DEPTH_SIGMA_SPACINGS: f32 = 2.0;
/// Absorption per channel [1/L] times a quarter of the scene's diagonal: red goes first,
/// so thick water turns blue-green, whatever the scene's units.
const ABSORB: [f32; 3] = [8.0, 2.6, 1.5];
/// The colour deep water scatters back (linear RGB).
const WATER: [f32; 3] = [0.14, 0.52, 0.86];
/// The light, view space (the spheres' light too).
const LIGHT: [f32; 3] = [-0.4, 0.6, 0.7];
/// The eye distance of a pixel without fluid, before the blur (`surface_blur.frag`).
const NO_FLUID: f32 = 1e30;
/// The spheres are drawn, and the distance smoothed, at the view's resolution over this
/// (each axis, rounded up); the shading takes them up to the view's.
const SPRITES_DIV: u32 = 2;

/// What the surface needs of one frame.
pub(crate) struct SurfaceView {
    /// The particle pass's uniforms (camera, particle radius, range).
    pub uniforms: ParticleUniforms,
    /// Particle spacing [L].
    pub spacing: f32,
    /// The diagonal of the framed box [L], which sets the absorption's length.
    pub scene_size: f32,
    /// The particle viewport and the sprites drawn ([`Sprites::draw`]).
    pub sprites: SpriteView,
}

/// A single-channel float texture and the framebuffer that draws into it.
struct Target {
    fbo: glow::Framebuffer,
    tex: glow::Texture,
}

/// At the view's size over [`SPRITES_DIV`].
struct Targets {
    /// The view's size.
    size: (u32, u32),
    /// The eye distance (colour attachment 0) and the thickness (1), drawn together.
    sprites: glow::Framebuffer,
    depth: Target,
    thickness: Target,
    blur: [Target; 2],
}

/// The size of a target at `(w, h)` (the view's) over `div`, rounded up.
fn reduced((w, h): (u32, u32), div: u32) -> (u32, u32) {
    (w.div_ceil(div), h.div_ceil(div))
}

/// The particle uniforms and sprite view of `(u, v)` (at the view's size) for drawing into
/// a target of `size`: pixels per world unit scaled to it (the greater of its two axes'
/// scales, so that no sprite's point is too small: the sizes round up).
fn at_size(
    u: &ParticleUniforms,
    v: &SpriteView,
    size: (u32, u32),
) -> (ParticleUniforms, SpriteView) {
    let s = (size.0 as f32 / v.size.0 as f32).max(size.1 as f32 / v.size.1 as f32);
    let mut u = *u;
    u.px_scale *= s;
    (u, SpriteView { size, ..*v })
}

pub(crate) struct Surface {
    sprites_prog: glow::Program,
    blur_prog: glow::Program,
    shade_prog: glow::Program,
    empty_vao: glow::VertexArray,
    targets: Option<Targets>,
    failed: Option<String>,
}

/// `mipmaps`: the texture is sampled through its mipmaps (made after each draw into it).
unsafe fn make_target(
    gl: &glow::Context,
    (w, h): (u32, u32),
    internal: u32,
    mipmaps: bool,
) -> Result<Target, ViewerError> {
    let tex = gl.create_texture().map_err(gl_err)?;
    gl.bind_texture(glow::TEXTURE_2D, Some(tex));
    gl.tex_image_2d(
        glow::TEXTURE_2D,
        0,
        internal as i32,
        w as i32,
        h as i32,
        0,
        glow::RED,
        glow::FLOAT,
        None,
    );
    let (min, mag) = if mipmaps {
        (glow::LINEAR_MIPMAP_LINEAR, glow::LINEAR)
    } else {
        (glow::NEAREST, glow::NEAREST)
    };
    for (k, v) in [
        (glow::TEXTURE_MIN_FILTER, min),
        (glow::TEXTURE_MAG_FILTER, mag),
        (glow::TEXTURE_WRAP_S, glow::CLAMP_TO_EDGE),
        (glow::TEXTURE_WRAP_T, glow::CLAMP_TO_EDGE),
    ] {
        gl.tex_parameter_i32(glow::TEXTURE_2D, k, v as i32);
    }
    gl.bind_texture(glow::TEXTURE_2D, None);
    let fbo = gl.create_framebuffer().map_err(gl_err)?;
    gl.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
    gl.framebuffer_texture_2d(
        glow::FRAMEBUFFER,
        glow::COLOR_ATTACHMENT0,
        glow::TEXTURE_2D,
        Some(tex),
        0,
    );
    gl.draw_buffers(&[glow::COLOR_ATTACHMENT0]);
    complete(gl)?;
    Ok(Target { fbo, tex })
}

/// Whether the bound framebuffer is complete.
unsafe fn complete(gl: &glow::Context) -> Result<(), ViewerError> {
    let status = gl.check_framebuffer_status(glow::FRAMEBUFFER);
    if status != glow::FRAMEBUFFER_COMPLETE {
        return Err(gl_err(format!(
            "surface framebuffer incomplete: 0x{status:x}"
        )));
    }
    Ok(())
}

impl Target {
    unsafe fn destroy(&self, gl: &glow::Context) {
        gl.delete_framebuffer(self.fbo);
        gl.delete_texture(self.tex);
    }
}

impl Targets {
    unsafe fn new(gl: &glow::Context, size: (u32, u32)) -> Result<Targets, ViewerError> {
        let v = gl.version();
        if (v.major, v.minor) < (4, 0) {
            return Err(gl_err(format!(
                "the surface needs OpenGL 4.0 (glBlendEquationi), this context is {}.{}",
                v.major, v.minor
            )));
        }
        let rs = reduced(size, SPRITES_DIV);
        let depth = make_target(gl, rs, glow::R32F, false)?;
        let thickness = make_target(gl, rs, glow::R16F, true)?;
        let sprites = gl.create_framebuffer().map_err(gl_err)?;
        gl.bind_framebuffer(glow::FRAMEBUFFER, Some(sprites));
        for (i, t) in [&depth, &thickness].into_iter().enumerate() {
            gl.framebuffer_texture_2d(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0 + i as u32,
                glow::TEXTURE_2D,
                Some(t.tex),
                0,
            );
        }
        gl.draw_buffers(&[glow::COLOR_ATTACHMENT0, glow::COLOR_ATTACHMENT1]);
        complete(gl)?;
        Ok(Targets {
            size,
            sprites,
            depth,
            thickness,
            blur: [
                make_target(gl, rs, glow::R32F, false)?,
                make_target(gl, rs, glow::R32F, false)?,
            ],
        })
    }

    unsafe fn destroy(&self, gl: &glow::Context) {
        for t in [&self.depth, &self.thickness, &self.blur[0], &self.blur[1]] {
            t.destroy(gl);
        }
        gl.delete_framebuffer(self.sprites);
    }
}

impl Surface {
    pub(crate) fn new(gl: &glow::Context) -> Result<Surface, ViewerError> {
        unsafe {
            Ok(Surface {
                sprites_prog: compile(gl, PARTICLE_VS, &sphere_fs(SphereFs::SurfaceSprites))?,
                blur_prog: compile(gl, FULLSCREEN_VS, BLUR_FS)?,
                shade_prog: compile(gl, FULLSCREEN_VS, &sphere_fs(SphereFs::SurfaceShade))?,
                empty_vao: gl.create_vertex_array().map_err(gl_err)?,
                targets: None,
                failed: None,
            })
        }
    }

    pub(crate) fn destroy(&self, gl: &glow::Context) {
        unsafe {
            for p in [self.sprites_prog, self.blur_prog, self.shade_prog] {
                gl.delete_program(p);
            }
            gl.delete_vertex_array(self.empty_vao);
            if let Some(t) = &self.targets {
                t.destroy(gl);
            }
        }
    }

    /// The off-screen targets at `size`, made on first use and when the size changes.
    unsafe fn targets(&mut self, gl: &glow::Context, size: (u32, u32)) -> Option<&Targets> {
        if self.targets.as_ref().is_some_and(|t| t.size != size) {
            if let Some(t) = self.targets.take() {
                t.destroy(gl);
            }
        }
        if self.targets.is_none() {
            match Targets::new(gl, size) {
                Ok(t) => self.targets = Some(t),
                Err(e) => {
                    // Said once; the frame is then drawn without the fluid.
                    if self.failed.is_none() {
                        eprintln!("meshfree-viewer: no fluid surface: {e}");
                    }
                    self.failed = Some(e.to_string());
                    return None;
                }
            }
        }
        self.targets.as_ref()
    }

    /// Draws the fluid (kind 0) of the particles of `sprites` (`v.sprites`) as a surface
    /// over what `target` holds, depth-tested against it. Leaves `target` bound and blending
    /// off.
    pub(crate) unsafe fn draw(
        &mut self,
        gl: &glow::Context,
        target: Option<glow::Framebuffer>,
        sprites: &Sprites,
        cmap: glow::Texture,
        v: &SurfaceView,
        timers: &mut GpuTimers,
    ) {
        let (w, h) = v.sprites.size;
        let (sprites_prog, blur_prog, shade_prog, empty_vao) = (
            self.sprites_prog,
            self.blur_prog,
            self.shade_prog,
            self.empty_vao,
        );
        let Some(t) = self.targets(gl, (w, h)) else {
            gl.bind_framebuffer(glow::FRAMEBUFFER, target);
            return;
        };
        let mut u = v.uniforms;
        u.radius *= SPHERE_SCALE;
        u.hidden = !1; // every kind but the fluid

        // 1. The spheres: eye distance of the nearest (MIN) and every chord (summed).
        timers.pass(gl, "surface sprites");
        let (us, sprites_view) = at_size(&u, &v.sprites, reduced((w, h), SPRITES_DIV));
        let (rw, rh) = sprites_view.size;
        gl.viewport(0, 0, rw as i32, rh as i32);
        gl.bind_framebuffer(glow::FRAMEBUFFER, Some(t.sprites));
        gl.clear_buffer_f32_slice(glow::COLOR, 0, &[NO_FLUID, 0.0, 0.0, 0.0]);
        gl.clear_buffer_f32_slice(glow::COLOR, 1, &[0.0; 4]);
        gl.disable(glow::DEPTH_TEST);
        gl.enable(glow::BLEND);
        gl.blend_func(glow::ONE, glow::ONE);
        gl.blend_equation_draw_buffer(0, glow::MIN);
        gl.blend_equation_draw_buffer(1, glow::FUNC_ADD);
        gl.use_program(Some(sprites_prog));
        us.set(gl, sprites_prog, cmap);
        // Particle volume spacing^3 over the drawn sphere's volume.
        let fill = v.spacing.powi(3) / (4.0 / 3.0 * std::f32::consts::PI * u.radius.powi(3));
        gl.uniform_1_f32(
            gl.get_uniform_location(sprites_prog, "u_fill").as_ref(),
            fill,
        );
        sprites.draw(gl, sprites_prog, &us, &sprites_view);
        gl.blend_equation(glow::FUNC_ADD);
        gl.disable(glow::BLEND);
        // The thickness's mipmaps: the shading reads it averaged over about a particle
        // spacing, so that the spheres' chords do not show as discs.
        timers.pass(gl, "thickness mipmaps");
        gl.bind_texture(glow::TEXTURE_2D, Some(t.thickness.tex));
        gl.generate_mipmap(glow::TEXTURE_2D);
        gl.bind_texture(glow::TEXTURE_2D, None);

        // 2. Bilateral smoothing of the distance, ping-pong between the blur targets.
        gl.use_program(Some(blur_prog));
        gl.bind_vertex_array(Some(empty_vao));
        let loc = |n: &str| gl.get_uniform_location(blur_prog, n);
        gl.uniform_1_i32(loc("u_depth").as_ref(), 0);
        gl.uniform_1_f32(loc("u_world_radius").as_ref(), BLUR_SPACINGS * v.spacing);
        gl.uniform_1_f32(loc("u_px_scale").as_ref(), us.px_scale);
        gl.uniform_1_f32(
            loc("u_depth_sigma").as_ref(),
            DEPTH_SIGMA_SPACINGS * v.spacing,
        );
        gl.uniform_1_i32(loc("u_max_px").as_ref(), BLUR_MAX_PX / SPRITES_DIV as i32);
        gl.active_texture(glow::TEXTURE0);
        let mut src = t.depth.tex;
        for k in 0..BLUR_ITERATIONS {
            for (dst, dir) in [(&t.blur[0], (1, 0)), (&t.blur[1], (0, 1))] {
                timers.pass(gl, BLUR_PASSES[2 * k + dir.1 as usize]);
                gl.bind_framebuffer(glow::FRAMEBUFFER, Some(dst.fbo));
                gl.bind_texture(glow::TEXTURE_2D, Some(src));
                gl.uniform_2_i32(loc("u_dir").as_ref(), dir.0, dir.1);
                gl.draw_arrays(glow::TRIANGLES, 0, 3);
                src = dst.tex;
            }
        }

        // 3. Shade over the target, depth-tested against what it holds.
        timers.pass(gl, "shade");
        gl.viewport(0, 0, w as i32, h as i32);
        gl.bind_framebuffer(glow::FRAMEBUFFER, target);
        gl.enable(glow::DEPTH_TEST);
        gl.depth_func(glow::LESS);
        gl.enable(glow::BLEND);
        gl.blend_func(glow::ONE, glow::SRC1_COLOR);
        gl.use_program(Some(shade_prog));
        let loc = |n: &str| gl.get_uniform_location(shade_prog, n);
        gl.uniform_1_i32(loc("u_depth").as_ref(), 0);
        gl.uniform_1_i32(loc("u_thickness").as_ref(), 1);
        gl.uniform_2_f32(loc("u_view_size").as_ref(), w as f32, h as f32);
        // View pixels per distance texel on each axis (the sizes rounded up).
        gl.uniform_2_f32(
            loc("u_depth_div").as_ref(),
            w as f32 / rw as f32,
            h as f32 / rh as f32,
        );
        gl.uniform_matrix_4_f32_slice(loc("u_proj").as_ref(), false, &u.proj.to_cols_array());
        let to_world = Mat3::from_mat4(u.view).transpose();
        gl.uniform_matrix_3_f32_slice(loc("u_to_world").as_ref(), false, &to_world.to_cols_array());
        gl.uniform_2_f32(
            loc("u_tan_half").as_ref(),
            1.0 / u.proj.x_axis.x,
            1.0 / u.proj.y_axis.y,
        );
        let light = Vec3::from(LIGHT).normalize();
        gl.uniform_3_f32(loc("u_light").as_ref(), light.x, light.y, light.z);
        let len = 0.25 * v.scene_size.max(1e-9);
        gl.uniform_3_f32(
            loc("u_absorb").as_ref(),
            ABSORB[0] / len,
            ABSORB[1] / len,
            ABSORB[2] / len,
        );
        gl.uniform_3_f32(loc("u_water").as_ref(), WATER[0], WATER[1], WATER[2]);
        gl.uniform_1_f32(loc("u_spacing_px").as_ref(), v.spacing * us.px_scale);
        gl.uniform_1_f32(loc("u_edge_dz").as_ref(), DEPTH_SIGMA_SPACINGS * v.spacing);
        gl.active_texture(glow::TEXTURE1);
        gl.bind_texture(glow::TEXTURE_2D, Some(t.thickness.tex));
        gl.active_texture(glow::TEXTURE0);
        gl.bind_texture(glow::TEXTURE_2D, Some(src));
        gl.draw_arrays(glow::TRIANGLES, 0, 3);
        timers.end(gl);
        gl.disable(glow::BLEND);
        gl.active_texture(glow::TEXTURE1);
        gl.bind_texture(glow::TEXTURE_2D, None);
        gl.active_texture(glow::TEXTURE0);
        gl.bind_texture(glow::TEXTURE_2D, None);
        gl.bind_vertex_array(None);
    }
}
