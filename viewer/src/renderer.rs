//! The one renderer shared by the live window and the headless path: sphere
//! impostors for the particles, a colour bar and text overlay. It draws into
//! whatever framebuffer is bound (the window's, or the headless FBO).
//!
//! ## GL calls and `unsafe`
//!
//! glow's calls are `unsafe`: the GL API must be used validly ([`glow::HasContext`]). For
//! every call of this crate that rests on one rule, which the `SAFETY` comments call *the
//! context rule*: the `glow::Context` passed is the one loaded from the context that is
//! current on this thread, and the GL objects named are that context's and alive. It holds
//! because the two owners of a context, [`crate::HeadlessRenderer`] and the window's `Gfx`,
//! make their context current on the thread that creates them and keep it so (nothing here
//! makes another current or releases it; the glutin context they hold is not `Send`, so
//! they stay on that thread), and pass only their own `glow::Context` to the [`Renderer`]
//! they made and its parts; and each part (`Sprites`, `Splat`, `Surface`, `Outlines`, the
//! programs, `GpuTimers`) names only objects it created there, deleted once, in its
//! `destroy`, which the owner calls last, before the context goes. One thread holds one
//! such context at a time (a second `HeadlessRenderer` on the same thread would make its
//! own current). The crate's `unsafe fn`s that take `gl` ask the context rule of their
//! caller; what else a block needs (sizes, bindings) its comment says.

use glow::HasContext;

use crate::colormap::{colormap_table, fmt_value};
use crate::error::gl_err;
use crate::font;
use crate::gpu_timers::{GpuTimers, PassTime};
use crate::outline::Outlines;
use crate::panel::{self, Action};
use crate::shaders::{compile, ParticleUniforms, SphereFs, SpriteProgram};
use crate::splat::{Splat, TexBufferFn};
use crate::sprites::{front_to_back_reversed, SpriteView, Sprites};
use crate::surface::{Surface, SurfaceView};
use crate::{Camera, Field, FrameData, ParticleBuffers, RenderOptions, SplatView, ViewerError};

const OVERLAY_VS: &str = r#"#version 330 core
layout(location = 0) in vec2 a_pos;
layout(location = 1) in vec2 a_uv;
layout(location = 2) in vec4 a_color;
uniform vec2 u_screen;
out vec2 v_uv;
out vec4 v_color;
void main() {
    v_uv = a_uv;
    v_color = a_color;
    gl_Position = vec4(a_pos.x / u_screen.x * 2.0 - 1.0, 1.0 - a_pos.y / u_screen.y * 2.0, 0.0, 1.0);
}
"#;

const OVERLAY_FS: &str = r#"#version 330 core
in vec2 v_uv;
in vec4 v_color;
uniform sampler2D u_font;
out vec4 o_color;
void main() {
    o_color = vec4(v_color.rgb, v_color.a * texture(u_font, v_uv).r);
}
"#;

/// Floats per overlay vertex: x, y, u, v, r, g, b, a.
const OV_STRIDE: usize = 8;

/// Where the time slider of a recorded run lies in the window ([`DrawInfo::slider`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Slider {
    pub x: f32,
    pub width: f32,
    pub y: f32,
    pub height: f32,
}

impl Slider {
    /// The fraction of the run at a click or drag at (`px`, `py`), where it is on the band.
    pub fn fraction(&self, px: f32, py: f32, dragging: bool) -> Option<f64> {
        let on_band = py >= self.y && py < self.y + self.height;
        let on_track =
            px >= self.x - self.height / 2.0 && px <= self.x + self.width + self.height / 2.0;
        (dragging || (on_band && on_track))
            .then(|| f64::from(((px - self.x) / self.width.max(1.0)).clamp(0.0, 1.0)))
    }
}

/// What [`Renderer::draw`] used, for the caller's overlay or camera.
#[derive(Debug, Clone)]
pub(crate) struct DrawInfo {
    /// The camera after resolving [`Camera::Auto`].
    pub camera: Camera,
    /// The colour range drawn.
    pub range: (f32, f32),
    /// The panel's clickable rows: x, y, width, height in pixels from the top left.
    pub panel_rows: Vec<([f32; 4], Action)>,
    /// A recorded run's time slider, where drawn: its track's x from the left and width, and
    /// the clickable band's y from the top and height, in pixels.
    pub slider: Option<Slider>,
    /// Whether the spheres came from the source's visibility splat (`splat.rs`).
    pub splat: bool,
}

pub(crate) struct Renderer {
    particle_prog: SpriteProgram,
    overlay_prog: glow::Program,
    cmap_tex: glow::Texture,
    font_tex: glow::Texture,
    font_w: u32,
    sprites: Sprites,
    /// The spheres from the source's visibility splat, where it made one for this view.
    splat: Splat,
    /// The particles in the buffers of each kind class, in their order there: fluid,
    /// solid, every other kind ([`crate::ParticleBuffers`]).
    counts: [usize; 3],
    /// The host path's particles in that order (reused from frame to frame).
    ordered: (Vec<[f32; 3]>, Vec<f32>, Vec<u8>),
    overlay_vao: glow::VertexArray,
    overlay_vbo: glow::Buffer,
    overlay_capacity: usize,
    verts: Vec<f32>,
    surface: Surface,
    outlines: Outlines,
    /// GPU time per pass (the particles, the surface's passes).
    timers: GpuTimers,
}

unsafe fn texture(
    gl: &glow::Context,
    w: u32,
    h: u32,
    internal: u32,
    format: u32,
    data: &[u8],
    filter: u32,
) -> Result<glow::Texture, ViewerError> {
    // SAFETY: the context rule (this fn's contract); `data` is the w x h image in `format`
    // bytes that the caller made for it, read at unpack alignment 1 (set here).
    unsafe {
        let t = gl.create_texture().map_err(gl_err)?;
        gl.bind_texture(glow::TEXTURE_2D, Some(t));
        gl.pixel_store_i32(glow::UNPACK_ALIGNMENT, 1);
        gl.tex_image_2d(
            glow::TEXTURE_2D,
            0,
            internal as i32,
            w as i32,
            h as i32,
            0,
            format,
            glow::UNSIGNED_BYTE,
            Some(data),
        );
        gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MIN_FILTER, filter as i32);
        gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAG_FILTER, filter as i32);
        gl.tex_parameter_i32(
            glow::TEXTURE_2D,
            glow::TEXTURE_WRAP_S,
            glow::CLAMP_TO_EDGE as i32,
        );
        gl.tex_parameter_i32(
            glow::TEXTURE_2D,
            glow::TEXTURE_WRAP_T,
            glow::CLAMP_TO_EDGE as i32,
        );
        gl.bind_texture(glow::TEXTURE_2D, None);
        Ok(t)
    }
}

fn f32_bytes(v: &[f32]) -> &[u8] {
    // SAFETY: f32 has no padding and any byte pattern may be read as u8.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast::<u8>(), std::mem::size_of_val(v)) }
}

fn vec3_bytes(v: &[[f32; 3]]) -> &[u8] {
    // SAFETY: [f32; 3] has no padding and any byte pattern may be read as u8.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast::<u8>(), std::mem::size_of_val(v)) }
}

/// The kind class of kind `k` (the buffers' order, [`crate::ParticleBuffers`]): 0 fluid,
/// 1 solid, 2 the boundary and any other kind.
pub(crate) fn kind_class(k: u8) -> usize {
    usize::from(k.min(crate::kind::BOUNDARY))
}

/// The colour range for `frame`: `opts.range`, or from the visible particles' values.
pub(crate) fn value_range(frame: &FrameData, field: Field, hide: [bool; 3]) -> (f32, f32) {
    if field == Field::Kind {
        return (0.0, 2.0);
    }
    let mut lo = f32::INFINITY;
    let mut hi = f32::NEG_INFINITY;
    for (v, k) in frame.values.iter().zip(&frame.kinds) {
        // Boundary particles are drawn grey, so they do not set the range.
        if v.is_finite() && !hide.get(*k as usize).copied().unwrap_or(false) && *k != 2 {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
    }
    range_from(lo, hi, field)
}

/// The colour range from the least and greatest value of the particles that set it
/// (infinite where none did): speed from 0, a flat range widened.
pub(crate) fn range_from(mut lo: f32, mut hi: f32, field: Field) -> (f32, f32) {
    if field == Field::Kind {
        return (0.0, 2.0);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if field == Field::Speed {
        lo = 0.0;
    }
    if hi <= lo {
        hi = lo + (lo.abs() * 1e-3).max(1e-6);
    }
    (lo, hi)
}

/// The range (first, count) of buffers holding `c` particles of each kind class, in that
/// order, that holds the classes not in `hidden` (bit k hides class k): from the first shown
/// class to the last (a hidden class between them is culled by the shaders).
fn span(c: [usize; 3], hidden: i32) -> (usize, usize) {
    let starts = [0, c[0], c[0] + c[1]];
    let mut shown = (0..3).filter(|&k| hidden & (1 << k) == 0 && c[k] > 0);
    match shown.next() {
        Some(a) => {
            let b = shown.next_back().unwrap_or(a);
            (starts[a], starts[b] + c[b] - starts[a])
        }
        None => (0, 0),
    }
}

impl Renderer {
    pub(crate) fn new(
        gl: &glow::Context,
        tex_buffer: Option<TexBufferFn>,
    ) -> Result<Renderer, ViewerError> {
        // SAFETY: the context rule (the caller's context, current on this thread; every
        // object named is created here). The textures get the colour map's 256 RGBA texels
        // and the font atlas's fw x fh bytes, as `colormap_table` and `font::atlas` make
        // them; the overlay's attributes lie within its OV_STRIDE floats a vertex.
        unsafe {
            let particle_prog = SpriteProgram::new(gl, SphereFs::Shaded)?;
            let overlay_prog = compile(gl, OVERLAY_VS, OVERLAY_FS)?;
            let table = colormap_table(256);
            let cmap_tex = texture(gl, 256, 1, glow::RGBA8, glow::RGBA, &table, glow::LINEAR)?;
            let (fw, fh, fpx) = font::atlas();
            let font_tex = texture(gl, fw, fh, glow::R8, glow::RED, &fpx, glow::NEAREST)?;

            let overlay_vao = gl.create_vertex_array().map_err(gl_err)?;
            gl.bind_vertex_array(Some(overlay_vao));
            let overlay_vbo = gl.create_buffer().map_err(gl_err)?;
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(overlay_vbo));
            let stride = (OV_STRIDE * 4) as i32;
            for (i, (n, off)) in [(2, 0), (2, 8), (4, 16)].into_iter().enumerate() {
                gl.enable_vertex_attrib_array(i as u32);
                gl.vertex_attrib_pointer_f32(i as u32, n, glow::FLOAT, false, stride, off);
            }
            gl.bind_vertex_array(None);
            gl.bind_buffer(glow::ARRAY_BUFFER, None);

            Ok(Renderer {
                particle_prog,
                overlay_prog,
                cmap_tex,
                font_tex,
                font_w: fw,
                sprites: Sprites::new(gl)?,
                splat: Splat::new(gl, tex_buffer)?,
                counts: [0; 3],
                ordered: Default::default(),
                overlay_vao,
                overlay_vbo,
                overlay_capacity: 0,
                verts: Vec::new(),
                surface: Surface::new(gl)?,
                outlines: Outlines::new(gl)?,
                timers: GpuTimers::default(),
            })
        }
    }

    /// Frees the GL objects (the context must be current).
    pub(crate) fn destroy(&self, gl: &glow::Context) {
        // SAFETY: the context rule: these objects are this renderer's, deleted only here
        // (its owner calls `destroy` once, before the context goes).
        unsafe {
            self.particle_prog.delete(gl);
            gl.delete_program(self.overlay_prog);
            gl.delete_texture(self.cmap_tex);
            gl.delete_texture(self.font_tex);
            gl.delete_buffer(self.overlay_vbo);
            gl.delete_vertex_array(self.overlay_vao);
        }
        self.sprites.destroy(gl);
        self.splat.destroy(gl);
        self.surface.destroy(gl);
        self.outlines.destroy(gl);
        self.timers.destroy(gl);
    }

    /// The mean GPU time of each pass drawn since the last call ([`GpuTimers::take`]).
    pub(crate) fn take_pass_times(&mut self, gl: &glow::Context) -> Vec<PassTime> {
        // SAFETY: the context rule: the caller's context is the one the timers' queries
        // were made in (the renderer's).
        unsafe { self.timers.take(gl) }
    }

    /// Copies the particles to the GPU in the buffers' kind order (the fluid, the solids,
    /// the rest, each in the frame's order: what a device fill writes); buffers grow only
    /// when the count grows.
    pub(crate) fn upload(
        &mut self,
        gl: &glow::Context,
        frame: &FrameData,
    ) -> Result<(), ViewerError> {
        frame.validate()?;
        let (pos, val, kinds) = &mut self.ordered;
        pos.clear();
        val.clear();
        kinds.clear();
        let mut counts = [0; 3];
        for (class, count) in counts.iter_mut().enumerate() {
            for (i, &k) in frame.kinds.iter().enumerate() {
                if kind_class(k) == class {
                    pos.push(frame.positions[i]);
                    val.push(frame.values[i]);
                    kinds.push(k);
                    *count += 1;
                }
            }
        }
        self.sprites
            .upload(gl, vec3_bytes(pos), f32_bytes(val), kinds);
        self.counts = counts;
        Ok(())
    }

    /// The particle buffers, grown to hold `n`, for a fill outside the renderer
    /// (`device_fill.rs`); `set_count` then says how many the next draw takes.
    pub(crate) fn particle_buffers(&mut self, gl: &glow::Context, n: usize) -> ParticleBuffers {
        self.sprites.buffers(gl, n)
    }

    /// The splat to ask of the next fill (`splat.rs`): the view last drawn, where a splat
    /// may stand for its sprites.
    pub(crate) fn splat_wanted(&self) -> Option<SplatView> {
        self.splat.want
    }

    /// Whether the last frame's particles were filled on the device (else uploaded), and
    /// the splat that fill wrote.
    pub(crate) fn set_splatted(&mut self, device: bool, done: Option<SplatView>) {
        self.splat.device = device;
        self.splat.done = done;
    }

    /// How many particles of each kind class (fluid, solid, the rest) the buffers hold, in
    /// that order, for the next draw (in all at most their capacity: else none are drawn).
    pub(crate) fn set_counts(&mut self, counts: [usize; 3]) {
        self.counts = if counts.iter().sum::<usize>() <= self.sprites.capacity() {
            counts
        } else {
            [0; 3]
        };
    }

    /// Draws the uploaded particles (using `frame` for the domain, radius, outlines and
    /// range), the outlines, the colour bar, the overlay and the panel into the bound
    /// framebuffer. In 3D with [`RenderOptions::surface`] the fluid is drawn as one
    /// screen-space surface ([`Surface`]), the other kinds as spheres.
    pub(crate) fn draw(
        &mut self,
        gl: &glow::Context,
        frame: &FrameData,
        opts: &RenderOptions,
    ) -> DrawInfo {
        let (w, h) = (opts.width.max(1), opts.height.max(1));
        let s = if opts.ui_scale > 0 {
            opts.ui_scale
        } else if h >= 700 {
            2
        } else {
            1
        };
        let panel = if opts.colorbar {
            (96 * s).min(w / 2)
        } else {
            0
        };
        let sw = (w - panel).max(1);
        let aspect = sw as f32 / h as f32;
        let margin = frame.particle_radius.max(0.0);
        // 2D frames the domain; 3D the outlined container (or the domain).
        let (lo, hi) = if frame.dim == 3 {
            frame.focus()
        } else {
            (frame.domain_min, frame.domain_max)
        };
        let camera = opts.camera.resolve(frame.dim, lo, hi, margin, aspect);
        let m = camera.matrices(frame.dim, lo, hi, margin, aspect);
        let range = opts
            .range
            .unwrap_or_else(|| value_range(frame, opts.field, opts.hide_kinds));
        let hidden =
            opts.hide_kinds.iter().enumerate().fold(
                0i32,
                |acc, (k, &hide)| if hide { acc | (1 << k) } else { acc },
            );
        let surface = opts.surface && frame.dim == 3 && !m.ortho && !opts.hide_kinds[0];
        let uniforms = ParticleUniforms {
            view: m.view,
            proj: m.proj,
            radius: frame.particle_radius,
            range,
            // The surface draws the fluid.
            hidden: hidden | surface as i32,
            grey_boundary: opts.field != Field::Kind,
            ortho: m.ortho,
            px_scale: 0.5 * h as f32 * m.proj.y_axis.y,
        };
        // Kinds 3 and above share class 2 with the boundary: drawn where it is shown.
        let (first, count) = span(self.counts, uniforms.hidden & 7);
        let sprites = SpriteView {
            size: (sw, h),
            first,
            count,
            reverse: front_to_back_reversed(m.view, m.ortho),
            bounds: (frame.domain_min.into(), frame.domain_max.into()),
            quads_only: opts.quads_only,
        };
        let bg = opts.background;
        let mut drew_splat = false;

        // SAFETY: the context rule (the caller's context, whose framebuffer is bound; the
        // programs, textures and buffers named are this renderer's); the sprite and splat
        // draws read at most `capacity` particles (`SpriteView`'s first and count are
        // clamped there) and the splat's buffer is the one sized for this view.
        unsafe {
            let target = gl.get_parameter_framebuffer(glow::DRAW_FRAMEBUFFER_BINDING);
            self.timers.collect(gl);
            gl.disable(glow::SCISSOR_TEST);
            // Particles: from the splat where the last fill made it for this view, else the
            // sprites.
            gl.viewport(0, 0, sw as i32, h as i32);
            let splat = if opts.sprites_only {
                None
            } else {
                self.splat.view_for(gl, &uniforms, &sprites)
            };
            let resolve = count > 0 && splat.is_some() && splat == self.splat.done;
            // The clear: the splat's resolve covers the particles' view (splat.frag), so then
            // only the panel beside it (a full clear took 0.2-0.3 ms of the H200's graphics).
            gl.viewport(0, 0, w as i32, h as i32);
            gl.clear_color(bg[0], bg[1], bg[2], 1.0);
            gl.clear_depth_f64(1.0);
            gl.depth_mask(true);
            if !resolve {
                gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
            } else if sw < w {
                gl.enable(glow::SCISSOR_TEST);
                gl.scissor(sw as i32, 0, (w - sw) as i32, h as i32);
                gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
                gl.disable(glow::SCISSOR_TEST);
            }
            gl.viewport(0, 0, sw as i32, h as i32);
            if count > 0 {
                self.timers.pass(gl, "particles");
                gl.enable(glow::DEPTH_TEST);
                // The resolve writes every pixel of the view: what was there is no part of
                // the test.
                gl.depth_func(if resolve { glow::ALWAYS } else { glow::LESS });
                gl.disable(glow::BLEND);
                gl.disable(glow::CULL_FACE);
                drew_splat = resolve;
                if resolve {
                    self.splat.draw(gl, &uniforms, self.cmap_tex, bg);
                } else {
                    self.sprites.draw(
                        gl,
                        &self.particle_prog,
                        &uniforms,
                        &sprites,
                        self.cmap_tex,
                        &[],
                    );
                }
                gl.depth_func(glow::LESS);
                self.timers.end(gl);
            }
            self.splat.want = splat;
            // Outlines, then the surface over them: the water lets them through.
            let lines = !frame.outlines.is_empty() || !frame.edges.is_empty();
            if frame.dim == 3 && opts.outlines && lines {
                self.outlines.draw(
                    gl,
                    &frame.outlines,
                    &frame.edges,
                    m.proj * m.view,
                    (sw as f32, h as f32),
                    1.5 * s as f32,
                );
            }
            if surface && self.counts[0] > 0 {
                let view = SurfaceView {
                    uniforms,
                    spacing: 2.0 * frame.particle_radius,
                    scene_size: {
                        let (lo, hi) = frame.focus();
                        (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f32>().sqrt()
                    },
                    // The fluid: the buffers' first class.
                    sprites: SpriteView {
                        first: 0,
                        count: self.counts[0],
                        ..sprites
                    },
                };
                self.surface.draw(
                    gl,
                    target,
                    &self.sprites,
                    self.cmap_tex,
                    &view,
                    &mut self.timers,
                );
            }

            // Overlay: colour bar and text, in pixels over the whole target.
            gl.viewport(0, 0, w as i32, h as i32);
            gl.disable(glow::DEPTH_TEST);
            gl.enable(glow::BLEND);
            gl.blend_func(glow::SRC_ALPHA, glow::ONE_MINUS_SRC_ALPHA);
        }

        self.verts.clear();
        if opts.colorbar {
            self.colorbar(sw as f32, w as f32, h as f32, s as f32, opts.field, range);
        }
        let sf = s as f32;
        let (cw, lh) = (font::CELL_W as f32 * sf, (font::CELL_H as f32 + 3.0) * sf);
        let mut y = 2.0 * sf;
        if !opts.overlay.is_empty() {
            y = self.text_box(y, sf, &opts.overlay, cw, lh);
        }
        let mut panel_rows = Vec::new();
        if let Some(p) = &opts.panel {
            let rows = panel::rows(p, opts, frame.dim, range);
            let lines: Vec<String> = rows.iter().map(|r| r.0.clone()).collect();
            let top = y + 4.0 * sf;
            self.text_box(top, sf, &lines, cw, lh);
            let width =
                lines.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f32 * cw + 8.0 * sf;
            for (i, (_, action)) in rows.iter().enumerate() {
                if let Some(a) = action {
                    let ry = top + 4.0 * sf + i as f32 * lh - 1.5 * sf;
                    panel_rows.push(([2.0 * sf, ry, width, lh], *a));
                }
            }
        }
        let slider = opts
            .panel
            .as_ref()
            .and_then(|p| p.timeline)
            .map(|tl| self.slider(sw as f32, h as f32, sf, tl));
        // SAFETY: the context rule, as above; the overlay's buffer is this renderer's.
        unsafe {
            self.flush_overlay(gl, w as f32, h as f32);
            gl.disable(glow::BLEND);
            gl.use_program(None);
        }
        DrawInfo {
            camera,
            range,
            panel_rows,
            slider,
            splat: drew_splat,
        }
    }

    /// A recorded run's time slider along the bottom of the scene (`sw` wide, `h` high):
    /// the track, the part played and a handle at the frame shown.
    fn slider(&mut self, sw: f32, h: f32, sf: f32, tl: crate::Timeline) -> Slider {
        let (x, width) = (14.0 * sf, (sw - 28.0 * sf).max(1.0));
        let y = h - 12.0 * sf;
        let played = if tl.frames > 1 {
            tl.frame as f32 / (tl.frames - 1) as f32
        } else {
            1.0
        };
        self.rect(x, y, width, 4.0 * sf, [0.55, 0.55, 0.55, 0.6]);
        self.rect(x, y, width * played, 4.0 * sf, [0.35, 0.65, 1.0, 0.9]);
        let hx = x + width * played;
        self.rect(
            hx - 3.0 * sf,
            y - 5.0 * sf,
            6.0 * sf,
            14.0 * sf,
            [0.95, 0.95, 0.95, 1.0],
        );
        Slider {
            x,
            width,
            y: y - 8.0 * sf,
            height: 20.0 * sf,
        }
    }

    /// A dark box with `lines` of text from `top` down; returns the y below it.
    fn text_box(&mut self, top: f32, sf: f32, lines: &[String], cw: f32, lh: f32) -> f32 {
        let lw = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0) as f32;
        let bw = lw * cw + 8.0 * sf;
        let bh = lines.len() as f32 * lh + 6.0 * sf;
        self.rect(2.0 * sf, top, bw, bh, [0.0, 0.0, 0.0, 0.55]);
        for (i, line) in lines.iter().enumerate() {
            let y = top + 4.0 * sf + i as f32 * lh;
            self.text(6.0 * sf, y, sf, line, [0.95, 0.95, 0.95, 1.0]);
        }
        top + bh
    }

    fn colorbar(&mut self, x0: f32, w: f32, h: f32, s: f32, field: Field, range: (f32, f32)) {
        let bx = x0 + 10.0 * s;
        let bw = 12.0 * s;
        let top = 26.0 * s;
        let bottom = h - 14.0 * s;
        if bottom - top < 8.0 {
            return;
        }
        let white = [0.92, 0.92, 0.92, 1.0];
        self.text(x0 + 6.0 * s, 8.0 * s, s, field.label(), white);
        // Frame, then the gradient in slices (the slice colours come from the colour map).
        self.rect(
            bx - s,
            top - s,
            bw + 2.0 * s,
            bottom - top + 2.0 * s,
            [0.7, 0.7, 0.7, 1.0],
        );
        let n = 64;
        for i in 0..n {
            let t0 = i as f32 / n as f32;
            let t1 = (i + 1) as f32 / n as f32;
            let c = crate::colormap((t0 + t1) * 0.5);
            let y1 = bottom - (bottom - top) * t0;
            let y0 = bottom - (bottom - top) * t1;
            self.rect(bx, y0, bw, y1 - y0, [c[0], c[1], c[2], 1.0]);
        }
        let lx = bx + bw + 5.0 * s;
        let half = font::CELL_H as f32 * s * 0.5;
        let labels: Vec<(f32, String)> = if field == Field::Kind {
            vec![
                (0.0, "fluid".into()),
                (0.5, "solid".into()),
                (1.0, "bound".into()),
            ]
        } else {
            vec![
                (0.0, fmt_value(range.0)),
                (0.5, fmt_value(0.5 * (range.0 + range.1))),
                (1.0, fmt_value(range.1)),
            ]
        };
        let max_chars = ((w - lx) / (font::CELL_W as f32 * s)).floor().max(0.0) as usize;
        for (t, label) in labels {
            let y = bottom - (bottom - top) * t - half;
            let label: String = label.chars().take(max_chars).collect();
            self.text(lx, y, s, &label, white);
        }
    }

    fn quad(&mut self, x: f32, y: f32, w: f32, h: f32, uv: [f32; 4], c: [f32; 4]) {
        let [u0, v0, u1, v1] = uv;
        let corners = [(x, y, u0, v0), (x + w, y, u1, v0), (x + w, y + h, u1, v1)];
        let corners2 = [(x, y, u0, v0), (x + w, y + h, u1, v1), (x, y + h, u0, v1)];
        for (px, py, u, v) in corners.into_iter().chain(corners2) {
            self.verts
                .extend_from_slice(&[px, py, u, v, c[0], c[1], c[2], c[3]]);
        }
    }

    fn cell_uv(&self, cell: usize) -> [f32; 4] {
        let fw = self.font_w as f32;
        let u0 = (cell as u32 * font::CELL_W) as f32 / fw;
        let u1 = ((cell as u32 + 1) * font::CELL_W) as f32 / fw;
        [u0, 0.0, u1, 1.0]
    }

    fn rect(&mut self, x: f32, y: f32, w: f32, h: f32, c: [f32; 4]) {
        let [u0, _, u1, _] = self.cell_uv(font::SOLID);
        let (u, v) = ((u0 + u1) * 0.5, 0.5);
        self.quad(x, y, w, h, [u, v, u, v], c);
    }

    fn text(&mut self, x: f32, y: f32, s: f32, text: &str, c: [f32; 4]) {
        let (cw, ch) = (font::CELL_W as f32 * s, font::CELL_H as f32 * s);
        for (i, ch_) in text.chars().enumerate() {
            if ch_ == ' ' {
                continue;
            }
            let uv = self.cell_uv(font::glyph_index(ch_));
            self.quad(x + i as f32 * cw, y, cw, ch, uv, c);
        }
    }

    unsafe fn flush_overlay(&mut self, gl: &glow::Context, w: f32, h: f32) {
        if self.verts.is_empty() {
            return;
        }
        // SAFETY: the context rule (this fn's contract); the buffer is (re)allocated to
        // at least `bytes.len()` before a sub-data write of `bytes` at 0, and the draw
        // takes the verts.len() / OV_STRIDE whole vertices just written.
        unsafe {
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(self.overlay_vbo));
            let bytes = f32_bytes(&self.verts);
            if bytes.len() > self.overlay_capacity {
                gl.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytes, glow::DYNAMIC_DRAW);
                self.overlay_capacity = bytes.len();
            } else {
                gl.buffer_sub_data_u8_slice(glow::ARRAY_BUFFER, 0, bytes);
            }
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
            let p = self.overlay_prog;
            gl.use_program(Some(p));
            gl.uniform_2_f32(gl.get_uniform_location(p, "u_screen").as_ref(), w, h);
            gl.uniform_1_i32(gl.get_uniform_location(p, "u_font").as_ref(), 0);
            gl.active_texture(glow::TEXTURE0);
            gl.bind_texture(glow::TEXTURE_2D, Some(self.font_tex));
            gl.bind_vertex_array(Some(self.overlay_vao));
            gl.draw_arrays(glow::TRIANGLES, 0, (self.verts.len() / OV_STRIDE) as i32);
            gl.bind_vertex_array(None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(values: Vec<f32>, kinds: Vec<u8>) -> FrameData {
        FrameData {
            dim: 2,
            positions: vec![[0.0; 3]; values.len()],
            values,
            kinds,
            domain_min: [0.0; 3],
            domain_max: [1.0, 1.0, 0.0],
            particle_radius: 0.01,
            outlines: Vec::new(),
            edges: Vec::new(),
        }
    }

    #[test]
    fn ranges() {
        let f = frame(vec![1.0, 3.0, 100.0, f32::NAN], vec![0, 1, 2, 0]);
        assert_eq!(value_range(&f, Field::Speed, [false; 3]), (0.0, 3.0));
        assert_eq!(value_range(&f, Field::Pressure, [false; 3]), (1.0, 3.0));
        assert_eq!(
            value_range(&f, Field::Pressure, [false, true, false]),
            (1.0, 1.001)
        );
        assert_eq!(value_range(&f, Field::Kind, [false; 3]), (0.0, 2.0));
        let z = frame(vec![0.0; 3], vec![0; 3]);
        assert_eq!(value_range(&z, Field::Speed, [false; 3]), (0.0, 1e-6));
    }

    #[test]
    fn a_pass_walks_only_the_kinds_it_draws() {
        // 5 fluid, 2 solid, 3 boundary particles, in that order in the buffers.
        let c = [5, 2, 3];
        assert_eq!(span(c, 0), (0, 10));
        assert_eq!(span(c, 0b100), (0, 7), "walls hidden");
        assert_eq!(span(c, 0b001), (5, 5), "the fluid drawn as a surface");
        assert_eq!(span(c, 0b101), (5, 2), "only the solids");
        assert_eq!(
            span(c, 0b010),
            (0, 10),
            "the solids between: culled by the shader"
        );
        assert_eq!(span(c, 0b111), (0, 0));
        // No solids: the surface's sphere pass with the walls hidden draws nothing.
        assert_eq!(span([5, 0, 3], 0b101), (0, 0));
        assert_eq!(span([5, 0, 3], 0b001), (5, 3));
    }

    #[test]
    fn value_labels() {
        assert_eq!(fmt_value(0.0), "0");
        assert_eq!(fmt_value(1.5), "1.500");
        assert_eq!(fmt_value(1000.0), "1000");
        assert_eq!(fmt_value(-0.25), "-0.2500");
        assert_eq!(fmt_value(123456.0), "1.23e5");
    }
}
