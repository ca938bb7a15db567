//! The particles' vertex buffers (the layout of [`crate::ParticleBuffers`]: the fluid, then
//! the solids, then the other kinds, so that a pass draws the range of the kinds it shows)
//! and their draw (`shaders/particle.vert`), shared by the sphere pass and the surface's
//! sprites.
//!
//! One vertex per sprite: each is a point (`GL_POINTS`, `gl_PointSize` the bounding box
//! of the sphere's projection, plus a pixel), drawn with the viewport widened by half the
//! widest point on each side and a scissor to the view, so that a point whose centre lies
//! off screen still draws its part. Points have a size limit (the driver's, at most
//! [`POINT_CAP`]): where a sprite may exceed it, or the eye may be in or beside a sphere,
//! the points take those that fit and a second draw of instanced 4-vertex strips (the
//! quads the sprites were before) takes the rest. Whether the second draw is needed comes
//! from the box that holds the particles (the domain: a particle outside it is a fault of
//! the solver's health check) through [`widest_sprite_px`]; a particle outside that box
//! that would need a quad is drawn as a point clamped to the limit.
//!
//! Draw order: sphere impostors are depth-tested early only where nearer ones are already
//! drawn (`layout(depth_greater)` in the fragment shaders), so the draw goes front to back
//! as well as the buffer's order allows. Sources keep their particles in cell order
//! (meshfree's neighbour grid: x fastest, z slowest), ascending along every axis; where the
//! eye sits on the positive side of the view's dominant world axis, the buffer is drawn in
//! chunks from the last to the first ([`front_to_back_reversed`]). The order changes which
//! sphere wins only where two are at the same depth to the last bit.

use glam::{Mat4, Vec3};
use glow::HasContext;

use crate::error::gl_err;
use crate::outline::box_corners;
use crate::shaders::{ParticleUniforms, SpriteProgram};
use crate::{ParticleBuffers, ViewerError};

/// A reversed draw takes at least this many particles per chunk ...
const MIN_CHUNK: usize = 4096;
/// ... and at most this many chunks.
const MAX_CHUNKS: usize = 256;
/// The widest point drawn [px] (where the driver allows it; Mesa llvmpipe: 255): wider
/// sprites cover so many pixels that their vertices no longer matter.
pub(crate) const POINT_CAP: f32 = 256.0;

pub(crate) struct Sprites {
    /// Instanced attributes (one particle per 4-vertex strip) ...
    vao: glow::VertexArray,
    /// ... and per-vertex ones (one particle per point).
    points_vao: glow::VertexArray,
    pos: glow::Buffer,
    val: glow::Buffer,
    kind: glow::Buffer,
    /// Particles the buffers hold.
    capacity: usize,
    /// The widest point this context draws [px], and its largest viewport.
    point_max: f32,
    max_viewport: (i32, i32),
}

/// Attribute `index`'s buffer, components, type and bytes per particle.
type Attribute = (glow::Buffer, i32, u32, usize);

/// The frame the sprites are drawn in.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SpriteView {
    /// The viewport (pixels, from the target's origin).
    pub size: (u32, u32),
    /// The particles drawn, `first` .. `first + count` of the buffers, and their order (see
    /// the module's note).
    pub first: usize,
    pub count: usize,
    pub reverse: bool,
    /// World box holding every particle's centre.
    pub bounds: (Vec3, Vec3),
    /// Every sprite a quad (the reference the points are tested against).
    pub quads_only: bool,
}

impl Sprites {
    pub(crate) fn new(gl: &glow::Context) -> Result<Sprites, ViewerError> {
        // SAFETY: the context rule (renderer.rs; every object named is created here); the
        // two queries write 2 values each, the slices' lengths.
        unsafe {
            let mut range = [0.0f32; 2];
            gl.get_parameter_f32_slice(glow::POINT_SIZE_RANGE, &mut range);
            let mut dims = [0i32; 2];
            gl.get_parameter_i32_slice(glow::MAX_VIEWPORT_DIMS, &mut dims);
            let s = Sprites {
                vao: gl.create_vertex_array().map_err(gl_err)?,
                points_vao: gl.create_vertex_array().map_err(gl_err)?,
                pos: gl.create_buffer().map_err(gl_err)?,
                val: gl.create_buffer().map_err(gl_err)?,
                kind: gl.create_buffer().map_err(gl_err)?,
                capacity: 0,
                point_max: range[1].min(POINT_CAP),
                max_viewport: (dims[0], dims[1]),
            };
            for (vao, divisor) in [(s.vao, 1), (s.points_vao, 0)] {
                gl.bind_vertex_array(Some(vao));
                for i in 0..3 {
                    gl.enable_vertex_attrib_array(i);
                    gl.vertex_attrib_divisor(i, divisor);
                }
                s.point_attributes(gl, 0);
            }
            gl.bind_vertex_array(None);
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
            Ok(s)
        }
    }

    pub(crate) fn destroy(&self, gl: &glow::Context) {
        // SAFETY: the context rule (renderer.rs): these objects are this struct's, deleted
        // only here, once.
        unsafe {
            for b in [self.pos, self.val, self.kind] {
                gl.delete_buffer(b);
            }
            gl.delete_vertex_array(self.vao);
            gl.delete_vertex_array(self.points_vao);
        }
    }

    fn attributes(&self) -> [Attribute; 3] {
        [
            (self.pos, 3, glow::FLOAT, ParticleBuffers::POSITION_BYTES),
            (self.val, 1, glow::FLOAT, ParticleBuffers::VALUE_BYTES),
            (
                self.kind,
                1,
                glow::UNSIGNED_BYTE,
                ParticleBuffers::KIND_BYTES,
            ),
        ]
    }

    /// Points the bound VAO's attributes at particle `first` (instance or vertex 0 reads it).
    unsafe fn point_attributes(&self, gl: &glow::Context, first: usize) {
        // SAFETY: the context rule (this fn's contract, with one of this struct's VAOs
        // bound); an attribute pointer is an offset into the buffer, not read until a draw,
        // and the draws read particles below `capacity` only (`draw`).
        unsafe {
            for (i, (b, n, ty, bytes)) in self.attributes().into_iter().enumerate() {
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(b));
                gl.vertex_attrib_pointer_f32(
                    i as u32,
                    n,
                    ty,
                    false,
                    bytes as i32,
                    (first * bytes) as i32,
                );
            }
        }
    }

    /// Grows the buffers to hold `n` (they never shrink) and returns their names.
    pub(crate) fn buffers(&mut self, gl: &glow::Context, n: usize) -> ParticleBuffers {
        if n > self.capacity {
            // SAFETY: the context rule (renderer.rs); the buffers are this struct's, given
            // new storage of n particles' bytes each (no data read).
            unsafe {
                for (b, _, _, bytes) in self.attributes() {
                    gl.bind_buffer(glow::ARRAY_BUFFER, Some(b));
                    gl.buffer_data_size(glow::ARRAY_BUFFER, (n * bytes) as i32, glow::DYNAMIC_DRAW);
                }
                gl.bind_buffer(glow::ARRAY_BUFFER, None);
            }
            self.capacity = n;
        }
        ParticleBuffers {
            positions: self.pos.0.get(),
            values: self.val.0.get(),
            kinds: self.kind.0.get(),
            capacity: self.capacity,
        }
    }

    /// Copies host particles into the buffers (grown to hold them).
    pub(crate) fn upload(&mut self, gl: &glow::Context, pos: &[u8], val: &[u8], kind: &[u8]) {
        if kind.is_empty() {
            return;
        }
        self.buffers(gl, kind.len());
        // SAFETY: the context rule (renderer.rs); the buffers hold at least kind.len()
        // particles (grown just above), and the callers give pos and val for as many
        // (renderer.rs `upload`: 12 and 4 bytes for each kind byte), so each write of
        // `data` at offset 0 lies within its buffer.
        unsafe {
            for (b, data) in [(self.pos, pos), (self.val, val), (self.kind, kind)] {
                gl.bind_buffer(glow::ARRAY_BUFFER, Some(b));
                gl.buffer_sub_data_u8_slice(glow::ARRAY_BUFFER, 0, data);
            }
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
        }
    }

    pub(crate) fn capacity(&self) -> usize {
        self.capacity
    }

    /// Draws the sprites of `v` with `prog`: points, then quads for what the points leave
    /// where any may (see the module's note); each program in use with `u` (the colour map
    /// `cmap`) and the float uniforms `extra` set on it. Leaves the program in use, the
    /// viewport at `v.size` and the scissor test off.
    pub(crate) unsafe fn draw(
        &self,
        gl: &glow::Context,
        prog: &SpriteProgram,
        u: &ParticleUniforms,
        v: &SpriteView,
        cmap: glow::Texture,
        extra: &[(&str, f32)],
    ) {
        let first = v.first.min(self.capacity);
        let count = v.count.min(self.capacity - first);
        let (w, h) = (v.size.0 as i32, v.size.1 as i32);
        if count == 0 {
            return;
        }
        // SAFETY: the context rule (this fn's contract; the programs and VAOs are the
        // caller's and this struct's); the draws take particles first .. first + count,
        // within `capacity` (clamped above), so no attribute reads past its buffer.
        unsafe {
            let ray = pixel_ray(u, v.size);
            // The guard band: half the widest point, within the largest viewport.
            let room = (self.max_viewport.0 - w).min(self.max_viewport.1 - h) / 2;
            let guard = ((0.5 * self.point_max).ceil() as i32).min(room);
            let point_max = self.point_max.min((2 * guard) as f32);
            let points = !v.quads_only && point_max >= 2.0;
            let quads = !points
                || match widest_sprite_px(u, v.bounds.0, v.bounds.1) {
                    Some(px) => px > point_max,
                    None => true,
                };
            // Puts `p` in use with its uniforms, all but u_clip_scale (set by each draw below).
            let start = |p: glow::Program| {
                gl.use_program(Some(p));
                u.set(gl, p, cmap);
                for &(name, value) in extra {
                    gl.uniform_1_f32(gl.get_uniform_location(p, name).as_ref(), value);
                }
                let loc = move |n: &str| gl.get_uniform_location(p, n);
                gl.uniform_4_f32_slice(loc("u_ray").as_ref(), &ray);
                gl.uniform_1_i32(loc("u_split").as_ref(), (points && quads) as i32);
                gl.uniform_1_f32(loc("u_point_max").as_ref(), point_max);
                loc
            };
            if points {
                let loc = start(prog.points);
                gl.uniform_2_f32(
                    loc("u_clip_scale").as_ref(),
                    w as f32 / (w + 2 * guard) as f32,
                    h as f32 / (h + 2 * guard) as f32,
                );
                gl.viewport(-guard, -guard, w + 2 * guard, h + 2 * guard);
                gl.enable(glow::SCISSOR_TEST);
                gl.scissor(0, 0, w, h);
                gl.enable(glow::PROGRAM_POINT_SIZE);
                gl.bind_vertex_array(Some(self.points_vao));
                self.in_order(first, count, v.reverse, |at, n| {
                    gl.draw_arrays(glow::POINTS, at as i32, n as i32);
                });
                gl.disable(glow::PROGRAM_POINT_SIZE);
                gl.disable(glow::SCISSOR_TEST);
                gl.viewport(0, 0, w, h);
            }
            if quads {
                let loc = start(prog.quads);
                gl.uniform_2_f32(loc("u_clip_scale").as_ref(), 1.0, 1.0);
                gl.bind_vertex_array(Some(self.vao));
                // Attributes with a divisor start at the pointer: moved per chunk.
                self.in_order(first, count, v.reverse, |at, n| {
                    if at != 0 {
                        self.point_attributes(gl, at);
                    }
                    gl.draw_arrays_instanced(glow::TRIANGLE_STRIP, 0, 4, n as i32);
                    if at != 0 {
                        self.point_attributes(gl, 0);
                    }
                });
            }
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
            gl.bind_vertex_array(None);
        }
    }

    /// Calls `f(at, n)` over the particles `first` .. `first + count`: one call, or with
    /// `reverse` chunks from the last to the first.
    fn in_order(&self, first: usize, count: usize, reverse: bool, mut f: impl FnMut(usize, usize)) {
        if !reverse {
            f(first, count);
            return;
        }
        let chunk = MIN_CHUNK.max(count.div_ceil(MAX_CHUNKS));
        let mut end = first + count;
        while end > first {
            let at = end.saturating_sub(chunk).max(first);
            f(at, end - at);
            end = at;
        }
    }
}

/// A pixel centre's ray in a view of `size` pixels (`sphere.glsl`'s u_ray): the pixel at
/// window position (X, Y) looks through (X ray[0] + ray[1], Y ray[2] + ray[3]) at view depth
/// -1 (perspective), or is that view x and y (orthographic).
pub(crate) fn pixel_ray(u: &ParticleUniforms, size: (u32, u32)) -> [f32; 4] {
    // Its NDC x = 2 X / w - 1 ...
    let (p00, p11) = (u.proj.x_axis.x, u.proj.y_axis.y);
    let (ox, oy) = if u.ortho {
        // ... is P00 x + P30 (a box) ...
        (u.proj.w_axis.x, u.proj.w_axis.y)
    } else {
        // ... or P00 x / -z (a symmetric frustum: camera.rs).
        (0.0, 0.0)
    };
    [
        2.0 / (size.0 as f32 * p00),
        (-1.0 - ox) / p00,
        2.0 / (size.1 as f32 * p11),
        (-1.0 - oy) / p11,
    ]
}

/// An upper bound on the point size (pixels, `particle.vert`'s `size`) of the sprite of any
/// sphere of `u.radius` whose centre lies in the world box `lo`..`hi`; `None` where a
/// sphere may reach the eye's plane (`particle.vert` then draws the square, a quad).
///
/// In perspective the sprite spans the slopes x / -z (and y / -z) of the points of the
/// cube of side 2r about the centre (the sphere and the disc in its nearest plane). Along
/// a segment in that cube the slope X / D changes by at most |dX| / D + |X / D| |dD| / D,
/// so the span is at most 2r (1 + s) / D with D the least depth -z and s the greatest
/// |slope| over the box grown by r (a ratio of linear functions: both at its corners).
pub(crate) fn widest_sprite_px(u: &ParticleUniforms, lo: Vec3, hi: Vec3) -> Option<f32> {
    let r = u.radius;
    // The shader's margins: 1/20 pixel each side of the box, one pixel on the point.
    let margins = 0.1 + 1.0;
    if u.ortho {
        return Some(2.0 * r * u.px_scale + margins);
    }
    let (lo, hi) = (lo - Vec3::splat(r), hi + Vec3::splat(r));
    let mut depth = f32::INFINITY;
    let mut slope = 0.0f32;
    for c in box_corners(lo, hi) {
        let v = u.view.transform_point3(c);
        let d = -v.z;
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        depth = depth.min(d);
        slope = slope.max(v.x.abs().max(v.y.abs()) / d);
    }
    // A thousandth for the rounding of either side's arithmetic.
    let span = 2.0 * r * (1.0 + slope) / depth * u.px_scale;
    Some(span * 1.001 + margins)
}

/// Whether a perspective view with this world-to-view matrix draws the cell-ordered
/// buffer from its end: the eye lies towards + along the world axis nearest to the
/// view direction. Orthographic (2D) views keep the buffer's order.
pub(crate) fn front_to_back_reversed(view: Mat4, ortho: bool) -> bool {
    if ortho {
        return false;
    }
    // The view's +z (towards the eye) in world axes: the rotation's third row.
    let back = view.transpose().z_axis.truncate();
    let a = back.abs();
    let c = if a.x >= a.y && a.x >= a.z {
        back.x
    } else if a.y >= a.z {
        back.y
    } else {
        back.z
    };
    c > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `particle.vert`'s point size of the sprite of the sphere of radius r about the view
    /// point c (in f64), `None` for its square (drawn as a quad).
    fn sprite_px(c: [f64; 3], r: f64, px_scale: f64) -> Option<f64> {
        let slopes = |x: f64, z: f64| -> Option<(f64, f64)> {
            let t2 = x * x + z * z - r * r;
            if t2 <= 0.0 {
                return None;
            }
            let t = t2.sqrt();
            let a = (x * t - z * r, x * r + z * t);
            let b = (x * t + z * r, z * t - x * r);
            if a.1 >= 0.0 || b.1 >= 0.0 {
                return None;
            }
            let (sa, sb) = (a.0 / -a.1, b.0 / -b.1);
            Some((sa.min(sb), sa.max(sb)))
        };
        let zq = c[2] + r;
        if zq >= 0.0 {
            return None;
        }
        let (sx, sy) = (slopes(c[0], c[2])?, slopes(c[1], c[2])?);
        let m = 0.05 / px_scale;
        let lo = [
            sx.0.min((c[0] - r) / -zq) - m,
            sy.0.min((c[1] - r) / -zq) - m,
        ];
        let hi = [
            sx.1.max((c[0] + r) / -zq) + m,
            sy.1.max((c[1] + r) / -zq) + m,
        ];
        Some((hi[0] - lo[0]).max(hi[1] - lo[1]) * px_scale + 1.0)
    }

    #[test]
    fn the_widest_sprite_bounds_every_sprite_in_the_box() {
        // A fixed pseudo-random sequence (xorshift).
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut rand = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (lo, hi) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 0.5));
        let (mut bounded, mut tight) = (0, 0.0f64);
        for _ in 0..200 {
            let eye = Vec3::new(
                -2.0 + 6.0 * rand() as f32,
                -1.0 + 3.0 * rand() as f32,
                -1.5 + 3.5 * rand() as f32,
            );
            let view = Mat4::look_at_rh(eye, Vec3::new(1.0, 0.5, 0.25), Vec3::Y);
            let proj = Mat4::perspective_rh_gl(0.3 + rand() as f32, 1.5, 0.01, 100.0);
            let u = ParticleUniforms {
                view,
                proj,
                radius: 0.005 + 0.05 * rand() as f32,
                range: (0.0, 1.0),
                hidden: 0,
                grey_boundary: false,
                ortho: false,
                px_scale: 0.5 * 600.0 * proj.y_axis.y,
            };
            let bound = widest_sprite_px(&u, lo, hi);
            let mut widest = 0.0f64;
            for _ in 0..2000 {
                let p = lo + (hi - lo) * Vec3::new(rand() as f32, rand() as f32, rand() as f32);
                let c = view.transform_point3(p);
                let c = [c.x as f64, c.y as f64, c.z as f64];
                match sprite_px(c, u.radius as f64, u.px_scale as f64) {
                    Some(px) => widest = widest.max(px),
                    // A square: only where the bound gives up.
                    None => assert!(bound.is_none(), "eye {eye}: a square under {bound:?}"),
                }
            }
            if let Some(b) = bound {
                assert!(
                    widest <= b as f64,
                    "eye {eye}: a sprite of {widest} px over {b}"
                );
                bounded += 1;
                tight = tight.max(widest / b as f64);
            }
        }
        // The bound holds somewhere, and is not vacuous.
        assert!(
            bounded > 50 && tight > 0.5,
            "{bounded} views bounded, tightest {tight}"
        );
    }

    #[test]
    fn reversed_when_the_eye_is_on_the_positive_side() {
        let look = |eye: Vec3| Mat4::look_at_rh(eye, Vec3::ZERO, Vec3::Y);
        // The default orbit camera's eye, towards +x, +y and most of all +z.
        assert!(front_to_back_reversed(
            look(Vec3::new(0.52, 0.42, 0.74)),
            false
        ));
        assert!(!front_to_back_reversed(
            look(Vec3::new(0.52, 0.42, -0.74)),
            false
        ));
        assert!(!front_to_back_reversed(
            look(Vec3::new(-0.9, 0.3, 0.2)),
            false
        ));
        assert!(front_to_back_reversed(
            look(Vec3::new(0.9, -0.3, -0.2)),
            false
        ));
        assert!(!front_to_back_reversed(
            look(Vec3::new(0.52, 0.42, 0.74)),
            true
        ));
    }
}
