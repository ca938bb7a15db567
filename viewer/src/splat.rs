//! The spheres drawn from a visibility splat that the source runs on its GPU with the fill
//! ([`SplatView`], [`crate::LiveSource::fill_buffers`]; meshfree's `cuda/view.cu`) instead
//! of the sprites' pass: the source finds each pixel's nearest sphere and writes its centre,
//! value and kind into one buffer of this renderer; a full-screen pass (`shaders/splat.frag`)
//! reads that buffer through two buffer textures (no copy: a copy into 2D textures took
//! longer than the sprites' pass saved) and ray-casts and lights each pixel's sphere as the
//! sprites' fragment shader does. The sprites' pass shades every fragment of every sprite
//! on the few SMs that run graphics on an H100 or H200; the splat runs on all of them.
//!
//! The splat is asked for with the next fill and drawn only where the view it was made for
//! is the view being drawn: a moved camera, a resized view, a change of the shown kinds draw
//! the sprites once, and the splat again from the next frame. It is asked for only in
//! perspective, with every sprite at most [`SPLAT_MAX_PX`] across (each sphere's pixels are
//! one GPU thread's loop) and no sphere reaching the eye's plane, and where the context
//! gives `glTexBuffer` (core since OpenGL 3.1; glow does not wrap it: [`TexBufferFn`]).

use glow::HasContext;

use crate::error::gl_err;
use crate::shaders::{compile, sphere_fs, ParticleUniforms, SphereFs, FULLSCREEN_VS};
use crate::sprites::{pixel_ray, widest_sprite_px, SpriteView};
use crate::{SplatView, ViewerError};

/// The widest sprite [px] that a view may have to be splatted.
pub(crate) const SPLAT_MAX_PX: f32 = 32.0;

/// Bytes per pixel of the splat's buffer: a centre and value (4 `f32`), then the kind.
const PIXEL_BYTES: usize = 17;

/// `glTexBuffer(target, internal format, buffer)`, from the context's loader.
pub(crate) type TexBufferFn = unsafe extern "system" fn(u32, u32, u32);

/// `glTexBuffer` as the context's loader `proc_address` gives it (null: `None`).
pub(crate) fn tex_buffer_fn(
    proc_address: impl Fn(&std::ffi::CStr) -> *const std::ffi::c_void,
) -> Option<TexBufferFn> {
    let f = proc_address(c"glTexBuffer");
    // SAFETY: a non-null glTexBuffer of the loader has OpenGL's signature (GLenum target,
    // GLenum internalformat, GLuint buffer: three 32-bit unsigned integers, no result).
    (!f.is_null())
        .then(|| unsafe { std::mem::transmute::<*const std::ffi::c_void, TexBufferFn>(f) })
}

pub(crate) struct Splat {
    prog: glow::Program,
    /// The context's `glTexBuffer` (`None`: no splat).
    tex_buffer: Option<TexBufferFn>,
    /// The most texels a buffer texture may address (`GL_MAX_TEXTURE_BUFFER_SIZE`): the
    /// kinds' texture addresses every byte of the buffer, so a view of more than a
    /// seventeenth of it in pixels (7.9 M where it is 2^27) keeps the sprites.
    max_texels: usize,
    /// The buffer the source writes (created at the first view asked for).
    buffer: Option<glow::Buffer>,
    /// Its buffer textures: the pixels' centre and value (RGBA32F texels from its start)
    /// and kinds (R8UI texels: byte 16 pixels + p is pixel p's).
    centres: glow::Texture,
    kinds: glow::Texture,
    /// The view size the buffer holds.
    size: (u32, u32),
    vao: glow::VertexArray,
    /// The view asked of the next fill ...
    pub(crate) want: Option<SplatView>,
    /// ... and the one the last fill splatted.
    pub(crate) done: Option<SplatView>,
    /// Whether the last frame was filled on the device (else uploaded: no splat is asked).
    pub(crate) device: bool,
}

impl Splat {
    pub(crate) fn new(
        gl: &glow::Context,
        tex_buffer: Option<TexBufferFn>,
    ) -> Result<Splat, ViewerError> {
        // SAFETY: the context rule (renderer.rs; every object named is created here).
        unsafe {
            let prog = compile(gl, FULLSCREEN_VS, &sphere_fs(SphereFs::Splat))?;
            let max_texels = gl.get_parameter_i32(glow::MAX_TEXTURE_BUFFER_SIZE).max(0) as usize;
            Ok(Splat {
                prog,
                tex_buffer,
                max_texels,
                buffer: None,
                centres: gl.create_texture().map_err(gl_err)?,
                kinds: gl.create_texture().map_err(gl_err)?,
                size: (0, 0),
                vao: gl.create_vertex_array().map_err(gl_err)?,
                want: None,
                done: None,
                device: false,
            })
        }
    }

    pub(crate) fn destroy(&self, gl: &glow::Context) {
        // SAFETY: the context rule (renderer.rs): these objects are this struct's, deleted
        // only here, once.
        unsafe {
            gl.delete_program(self.prog);
            if let Some(b) = self.buffer {
                gl.delete_buffer(b);
            }
            gl.delete_texture(self.centres);
            gl.delete_texture(self.kinds);
            gl.delete_vertex_array(self.vao);
        }
    }

    /// The splat of the sprites `v` drawn with `u`, where it may stand for them (see the
    /// module's note), its buffer and textures sized for the view; else `None`.
    pub(crate) fn view_for(
        &mut self,
        gl: &glow::Context,
        u: &ParticleUniforms,
        v: &SpriteView,
    ) -> Option<SplatView> {
        let small =
            widest_sprite_px(u, v.bounds.0, v.bounds.1).is_some_and(|px| px <= SPLAT_MAX_PX);
        let bytes = v.size.0 as usize * v.size.1 as usize * PIXEL_BYTES;
        if self.tex_buffer.is_none()
            || bytes > self.max_texels
            || !self.device
            || u.ortho
            || v.quads_only
            || v.count == 0
            || !small
        {
            return None;
        }
        let buffer = self.resize(gl, v.size).ok()?;
        let m = u.view;
        let row = |r: usize| [m.x_axis[r], m.y_axis[r], m.z_axis[r], m.w_axis[r]];
        let mut view = [0.0; 12];
        for r in 0..3 {
            view[4 * r..4 * r + 4].copy_from_slice(&row(r));
        }
        Some(SplatView {
            buffer,
            width: v.size.0,
            height: v.size.1,
            view,
            ray: pixel_ray(u, v.size),
            radius: u.radius,
            first: v.first,
            count: v.count,
            hidden: (u.hidden & 0xff) as u8,
        })
    }

    /// Sizes the buffer for `size` pixels (its textures over it); returns its name.
    fn resize(&mut self, gl: &glow::Context, size: (u32, u32)) -> Result<u32, ViewerError> {
        let tex_buffer = self
            .tex_buffer
            .ok_or_else(|| gl_err("no glTexBuffer".to_string()))?;
        // SAFETY: the context rule (renderer.rs): the buffer and textures are this
        // struct's; the buffer gets new storage (no data read). `tex_buffer` is the
        // glTexBuffer loaded from this context (`tex_buffer_fn`), called with a buffer
        // texture of it bound to GL_TEXTURE_BUFFER and a buffer of it.
        unsafe {
            let b = match self.buffer {
                Some(b) => b,
                None => {
                    let b = gl.create_buffer().map_err(gl_err)?;
                    self.buffer = Some(b);
                    self.size = (0, 0);
                    b
                }
            };
            if self.size != size {
                let bytes = size.0 as usize * size.1 as usize * PIXEL_BYTES;
                gl.bind_buffer(glow::TEXTURE_BUFFER, Some(b));
                gl.buffer_data_size(glow::TEXTURE_BUFFER, bytes as i32, glow::DYNAMIC_COPY);
                gl.bind_buffer(glow::TEXTURE_BUFFER, None);
                for (t, format) in [(self.centres, glow::RGBA32F), (self.kinds, glow::R8UI)] {
                    gl.bind_texture(glow::TEXTURE_BUFFER, Some(t));
                    tex_buffer(glow::TEXTURE_BUFFER, format, b.0.get());
                }
                gl.bind_texture(glow::TEXTURE_BUFFER, None);
                self.size = size;
                self.done = None;
            }
            Ok(b.0.get())
        }
    }

    /// Draws the spheres of the last splat (`done`, which the caller checked is the view
    /// drawn) with `u` and the colour map `cmap` into every pixel of the bound framebuffer's
    /// viewport, which is the splat's, and `background` with the far depth where no sphere
    /// is: the view needs no clear before it (the caller leaves the depth test on and makes
    /// it pass always).
    pub(crate) unsafe fn draw(
        &self,
        gl: &glow::Context,
        u: &ParticleUniforms,
        cmap: glow::Texture,
        background: [f32; 3],
    ) {
        let Some(sv) = self.done else {
            return;
        };
        // SAFETY: the context rule (this fn's contract; the program, textures and VAO are
        // this struct's). The shader fetches texels of the buffer textures only, which
        // cover the buffer sized for `self.size` (`resize`); the draw of 3 vertices reads no
        // attribute (the empty VAO).
        unsafe {
            gl.use_program(Some(self.prog));
            u.set(gl, self.prog, cmap);
            let loc = |n: &str| gl.get_uniform_location(self.prog, n);
            gl.uniform_4_f32_slice(loc("u_ray").as_ref(), &sv.ray);
            gl.uniform_3_f32_slice(loc("u_background").as_ref(), &background);
            gl.uniform_1_i32(loc("u_px").as_ref(), 1);
            gl.uniform_1_i32(loc("u_pk").as_ref(), 2);
            gl.uniform_1_i32(loc("u_width").as_ref(), self.size.0 as i32);
            gl.uniform_1_i32(
                loc("u_kinds_at").as_ref(),
                16 * (self.size.0 * self.size.1) as i32,
            );
            gl.active_texture(glow::TEXTURE1);
            gl.bind_texture(glow::TEXTURE_BUFFER, Some(self.centres));
            gl.active_texture(glow::TEXTURE2);
            gl.bind_texture(glow::TEXTURE_BUFFER, Some(self.kinds));
            gl.active_texture(glow::TEXTURE0);
            gl.bind_vertex_array(Some(self.vao));
            gl.draw_arrays(glow::TRIANGLES, 0, 3);
            gl.bind_vertex_array(None);
            for unit in [glow::TEXTURE2, glow::TEXTURE1] {
                gl.active_texture(unit);
                gl.bind_texture(glow::TEXTURE_BUFFER, None);
            }
            gl.active_texture(glow::TEXTURE0);
        }
    }
}
