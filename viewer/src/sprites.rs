//! The particles' vertex buffers (the layout of [`crate::ParticleBuffers`]) and their one
//! draw call: an instanced 4-vertex strip per particle (`shaders/particle.vert`), shared by
//! the sphere pass and the surface's passes.
//!
//! Draw order: sphere impostors are depth-tested early only where nearer ones are already
//! drawn (`layout(depth_greater)` in the fragment shaders), so the draw goes front to back
//! as well as the buffer's order allows. Sources keep their particles in cell order
//! (meshfree's neighbour grid: x fastest, z slowest), ascending along every axis; where the
//! eye sits on the positive side of the view's dominant world axis, the buffer is drawn in
//! chunks from the last to the first ([`front_to_back_reversed`]). The order changes which
//! sphere wins only where two are at the same depth to the last bit.

use glam::Mat4;
use glow::HasContext;

use crate::error::gl_err;
use crate::{ParticleBuffers, ViewerError};

/// A reversed draw takes at least this many particles per chunk ...
const MIN_CHUNK: usize = 4096;
/// ... and at most this many chunks.
const MAX_CHUNKS: usize = 256;

pub(crate) struct Sprites {
    vao: glow::VertexArray,
    pos: glow::Buffer,
    val: glow::Buffer,
    kind: glow::Buffer,
    /// Particles the buffers hold.
    capacity: usize,
}

/// Attribute `index`'s buffer, components, type and bytes per particle.
type Attribute = (glow::Buffer, i32, u32, usize);

impl Sprites {
    pub(crate) fn new(gl: &glow::Context) -> Result<Sprites, ViewerError> {
        unsafe {
            let vao = gl.create_vertex_array().map_err(gl_err)?;
            let s = Sprites {
                vao,
                pos: gl.create_buffer().map_err(gl_err)?,
                val: gl.create_buffer().map_err(gl_err)?,
                kind: gl.create_buffer().map_err(gl_err)?,
                capacity: 0,
            };
            gl.bind_vertex_array(Some(vao));
            for i in 0..3 {
                gl.enable_vertex_attrib_array(i);
                gl.vertex_attrib_divisor(i, 1);
            }
            s.point_attributes(gl, 0);
            gl.bind_vertex_array(None);
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
            Ok(s)
        }
    }

    pub(crate) fn destroy(&self, gl: &glow::Context) {
        unsafe {
            for b in [self.pos, self.val, self.kind] {
                gl.delete_buffer(b);
            }
            gl.delete_vertex_array(self.vao);
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

    /// Points the bound VAO's attributes at particle `first` (instance 0 reads it).
    unsafe fn point_attributes(&self, gl: &glow::Context, first: usize) {
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

    /// Grows the buffers to hold `n` (they never shrink) and returns their names.
    pub(crate) fn buffers(&mut self, gl: &glow::Context, n: usize) -> ParticleBuffers {
        if n > self.capacity {
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

    /// Draws the first `count` particles with the program in use; `reverse`: chunks from
    /// the last to the first (see the module's note).
    pub(crate) unsafe fn draw(&self, gl: &glow::Context, count: usize, reverse: bool) {
        let count = count.min(self.capacity);
        if count == 0 {
            return;
        }
        gl.bind_vertex_array(Some(self.vao));
        if reverse {
            let chunk = MIN_CHUNK.max(count.div_ceil(MAX_CHUNKS));
            let mut end = count;
            while end > 0 {
                let first = end.saturating_sub(chunk);
                self.point_attributes(gl, first);
                gl.draw_arrays_instanced(glow::TRIANGLE_STRIP, 0, 4, (end - first) as i32);
                end = first;
            }
            self.point_attributes(gl, 0);
        } else {
            gl.draw_arrays_instanced(glow::TRIANGLE_STRIP, 0, 4, count as i32);
        }
        gl.bind_buffer(glow::ARRAY_BUFFER, None);
        gl.bind_vertex_array(None);
    }
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
    use glam::Vec3;

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
