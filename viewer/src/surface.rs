//! The screen-space fluid surface of van der Laan, Green & Sainz (2009, "Screen space fluid
//! rendering with curvature flow"), with a bilateral filter in place of their curvature
//! flow: the fluid particles' spheres give the eye distance of the nearest fluid in each
//! pixel of a half-resolution target (through a depth buffer, front to back, so that hidden
//! spheres are rejected before they are shaded) and, drawn again at half the resolution,
//! the fluid's thickness along it (additive blending); the distance is smoothed, and the
//! shading pass, at the view's resolution, takes it up (bilinear over the texels of the
//! nearest sheet), makes normals from it, and adds Fresnel reflection of a sky and
//! Beer-Lambert absorption over the thickness, over what is already drawn. A pass's cost
//! is about 2 ns per sprite drawn (an H200) plus its spheres' pixels, hundreds deep in a
//! large block of water: the resolutions cut the second. Our own shaders
//! (`shaders/surface_*`).

use glam::{Mat3, Vec3};
use glow::HasContext;

use crate::error::gl_err;
use crate::gpu_timers::GpuTimers;
use crate::shaders::{
    compile, sphere_fs, ParticleUniforms, SphereFs, SpriteProgram, BLUR_FS, FULLSCREEN_VS,
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
/// The eye distance is drawn and smoothed at the view's resolution over this (each axis);
/// the shading takes it up to the view's.
const DEPTH_DIV: u32 = 2;
/// The thickness at the view's resolution over this: every sphere adds to it, so none of
/// its fragments is rejected early, and the shading reads it averaged over about a
/// particle spacing anyway.
const THICKNESS_DIV: u32 = 2;

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

struct Targets {
    size: (u32, u32),
    /// The eye distance, with a depth buffer of its own (`depth_buffer`), and the blur's
    /// ping-pong targets: the view's size over [`DEPTH_DIV`].
    depth: Target,
    depth_buffer: glow::Renderbuffer,
    blur: [Target; 2],
    /// The thickness, at the view's size over [`THICKNESS_DIV`].
    thickness: Target,
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
    depth_prog: SpriteProgram,
    thickness_prog: SpriteProgram,
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
    // SAFETY: the context rule (this fn's contract; the texture and framebuffer named are
    // created here); the image is given no data (`None`), only its storage.
    unsafe {
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
}

/// Whether the bound framebuffer is complete.
unsafe fn complete(gl: &glow::Context) -> Result<(), ViewerError> {
    // SAFETY: the context rule (this fn's contract); the query names no object.
    let status = unsafe { gl.check_framebuffer_status(glow::FRAMEBUFFER) };
    if status != glow::FRAMEBUFFER_COMPLETE {
        return Err(gl_err(format!(
            "surface framebuffer incomplete: 0x{status:x}"
        )));
    }
    Ok(())
}

impl Target {
    unsafe fn destroy(&self, gl: &glow::Context) {
        // SAFETY: the context rule (this fn's contract): the target's own objects, deleted
        // once (its owner, `Targets`, is dropped after).
        unsafe {
            gl.delete_framebuffer(self.fbo);
            gl.delete_texture(self.tex);
        }
    }
}

impl Targets {
    unsafe fn new(gl: &glow::Context, size: (u32, u32)) -> Result<Targets, ViewerError> {
        // SAFETY: the context rule (this fn's contract; every object named is created
        // here); the renderbuffer is given storage only.
        unsafe {
            let ds = reduced(size, DEPTH_DIV);
            let depth = make_target(gl, ds, glow::R32F, false)?;
            let depth_buffer = gl.create_renderbuffer().map_err(gl_err)?;
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(depth_buffer));
            gl.renderbuffer_storage(
                glow::RENDERBUFFER,
                glow::DEPTH_COMPONENT32F,
                ds.0 as i32,
                ds.1 as i32,
            );
            gl.bind_renderbuffer(glow::RENDERBUFFER, None);
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(depth.fbo));
            gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::DEPTH_ATTACHMENT,
                glow::RENDERBUFFER,
                Some(depth_buffer),
            );
            complete(gl)?;
            Ok(Targets {
                size,
                depth,
                depth_buffer,
                blur: [
                    make_target(gl, ds, glow::R32F, false)?,
                    make_target(gl, ds, glow::R32F, false)?,
                ],
                thickness: make_target(gl, reduced(size, THICKNESS_DIV), glow::R16F, true)?,
            })
        }
    }

    unsafe fn destroy(&self, gl: &glow::Context) {
        // SAFETY: the context rule (this fn's contract): the targets' own objects, deleted
        // once (the caller drops the `Targets` after).
        unsafe {
            for t in [&self.depth, &self.thickness, &self.blur[0], &self.blur[1]] {
                t.destroy(gl);
            }
            gl.delete_renderbuffer(self.depth_buffer);
        }
    }
}

impl Surface {
    pub(crate) fn new(gl: &glow::Context) -> Result<Surface, ViewerError> {
        // SAFETY: the context rule (renderer.rs; every object named is created here).
        unsafe {
            Ok(Surface {
                depth_prog: SpriteProgram::new(gl, SphereFs::SurfaceDepth)?,
                thickness_prog: SpriteProgram::new(gl, SphereFs::SurfaceThickness)?,
                blur_prog: compile(gl, FULLSCREEN_VS, BLUR_FS)?,
                shade_prog: compile(gl, FULLSCREEN_VS, &sphere_fs(SphereFs::SurfaceShade))?,
                empty_vao: gl.create_vertex_array().map_err(gl_err)?,
                targets: None,
                failed: None,
            })
        }
    }

    pub(crate) fn destroy(&self, gl: &glow::Context) {
        // SAFETY: the context rule (renderer.rs): these objects are this struct's, deleted
        // only here, once.
        unsafe {
            self.depth_prog.delete(gl);
            self.thickness_prog.delete(gl);
            for p in [self.blur_prog, self.shade_prog] {
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
                // SAFETY: the context rule (this fn's contract); the targets are taken out
                // of `self`, so destroyed once.
                unsafe { t.destroy(gl) };
            }
        }
        if self.targets.is_none() {
            // SAFETY: the context rule (this fn's contract).
            match unsafe { Targets::new(gl, size) } {
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
        let (depth_prog, thickness_prog, blur_prog, shade_prog, empty_vao) = (
            self.depth_prog,
            self.thickness_prog,
            self.blur_prog,
            self.shade_prog,
            self.empty_vao,
        );
        // SAFETY: the context rule (this fn's contract: `target` is the caller's
        // framebuffer of this context, or the default one; the programs, VAO and targets
        // are this struct's). The sprite draws take the caller's `v.sprites`, which
        // `Sprites::draw` clamps to its buffers; the full-screen passes draw 3 vertices from
        // the empty VAO (no attributes read).
        unsafe {
            let Some(t) = self.targets(gl, (w, h)) else {
                gl.bind_framebuffer(glow::FRAMEBUFFER, target);
                return;
            };
            let mut u = v.uniforms;
            u.radius *= SPHERE_SCALE;
            u.hidden = !1; // every kind but the fluid

            // 1a. The eye distance of the nearest sphere: depth-tested, front to back.
            timers.pass(gl, "surface depth");
            let (ud, depth_view) = at_size(&u, &v.sprites, reduced((w, h), DEPTH_DIV));
            let (dw, dh) = depth_view.size;
            gl.viewport(0, 0, dw as i32, dh as i32);
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(t.depth.fbo));
            gl.clear_buffer_f32_slice(glow::COLOR, 0, &[NO_FLUID, 0.0, 0.0, 0.0]);
            gl.clear_buffer_f32_slice(glow::DEPTH, 0, &[1.0]);
            gl.enable(glow::DEPTH_TEST);
            gl.depth_func(glow::LESS);
            gl.depth_mask(true);
            gl.disable(glow::BLEND);
            sprites.draw(gl, &depth_prog, &ud, &depth_view, cmap, &[]);
            gl.disable(glow::DEPTH_TEST);

            // 1b. Every sphere's chord, summed.
            timers.pass(gl, "surface thickness");
            let (ut, thick_view) = at_size(&u, &v.sprites, reduced((w, h), THICKNESS_DIV));
            let (tw, th) = thick_view.size;
            gl.viewport(0, 0, tw as i32, th as i32);
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(t.thickness.fbo));
            gl.clear_buffer_f32_slice(glow::COLOR, 0, &[0.0; 4]);
            gl.enable(glow::BLEND);
            gl.blend_func(glow::ONE, glow::ONE);
            // Particle volume spacing^3 over the drawn sphere's volume.
            let fill = v.spacing.powi(3) / (4.0 / 3.0 * std::f32::consts::PI * u.radius.powi(3));
            sprites.draw(
                gl,
                &thickness_prog,
                &ut,
                &thick_view,
                cmap,
                &[("u_fill", fill)],
            );
            gl.disable(glow::BLEND);
            // The thickness's mipmaps: the shading reads it averaged over about a particle
            // spacing, so that the spheres' chords do not show as discs.
            timers.pass(gl, "thickness mipmaps");
            gl.bind_texture(glow::TEXTURE_2D, Some(t.thickness.tex));
            gl.generate_mipmap(glow::TEXTURE_2D);
            gl.bind_texture(glow::TEXTURE_2D, None);

            // 2. Bilateral smoothing of the distance, ping-pong between the blur targets.
            gl.viewport(0, 0, dw as i32, dh as i32);
            gl.use_program(Some(blur_prog));
            gl.bind_vertex_array(Some(empty_vao));
            let loc = |n: &str| gl.get_uniform_location(blur_prog, n);
            gl.uniform_1_i32(loc("u_depth").as_ref(), 0);
            gl.uniform_1_f32(loc("u_world_radius").as_ref(), BLUR_SPACINGS * v.spacing);
            gl.uniform_1_f32(loc("u_px_scale").as_ref(), ud.px_scale);
            gl.uniform_1_f32(
                loc("u_depth_sigma").as_ref(),
                DEPTH_SIGMA_SPACINGS * v.spacing,
            );
            gl.uniform_1_i32(loc("u_max_px").as_ref(), BLUR_MAX_PX / DEPTH_DIV as i32);
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
                w as f32 / dw as f32,
                h as f32 / dh as f32,
            );
            gl.uniform_matrix_4_f32_slice(loc("u_proj").as_ref(), false, &u.proj.to_cols_array());
            let to_world = Mat3::from_mat4(u.view).transpose();
            gl.uniform_matrix_3_f32_slice(
                loc("u_to_world").as_ref(),
                false,
                &to_world.to_cols_array(),
            );
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
            gl.uniform_1_f32(loc("u_spacing_px").as_ref(), v.spacing * ut.px_scale);
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
}
