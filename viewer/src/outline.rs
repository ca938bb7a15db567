//! Outlines of boxes (a container's inside, obstacles) and of wall surfaces (their edges) in
//! 3D: each edge an instanced quad a few pixels wide (core profile lines are one pixel),
//! depth-tested against the particles.

use glam::{Mat4, Vec3};
use glow::HasContext;

use crate::shaders::{compile, OUTLINE_FS, OUTLINE_VS};
use crate::{Outline, ViewerError};

/// The edges' colour (linear RGB and alpha).
const COLOR: [f32; 4] = [0.82, 0.86, 0.92, 0.9];

pub(crate) struct Outlines {
    prog: glow::Program,
    vao: glow::VertexArray,
    vbo: glow::Buffer,
    /// Per edge: from (xyz), to (xyz).
    edges: Vec<f32>,
}

/// The 8 corners of the box `lo`..`hi`: corner i takes hi's x where bit 0 of i is set, its
/// y for bit 1, its z for bit 2 (so corners that differ in one bit share an edge).
pub(crate) fn box_corners(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The 12 edges of a box, as (from, to) pairs of corners.
pub(crate) fn edges(o: &Outline) -> [[Vec3; 2]; 12] {
    let c = box_corners(Vec3::from(o.min), Vec3::from(o.max));
    let corner = |i: usize| c[i];
    // Corners that differ in one bit share an edge.
    let mut out = [[Vec3::ZERO; 2]; 12];
    let mut n = 0;
    for i in 0..8 {
        for bit in [1, 2, 4] {
            if i & bit == 0 {
                out[n] = [corner(i), corner(i | bit)];
                n += 1;
            }
        }
    }
    out
}

impl Outlines {
    pub(crate) fn new(gl: &glow::Context) -> Result<Outlines, ViewerError> {
        let e = |m: String| ViewerError::Gl(m);
        // SAFETY: the context rule (renderer.rs; every object named is created here); the
        // two attributes lie within the 24-byte (6-float) stride of an edge.
        unsafe {
            let prog = compile(gl, OUTLINE_VS, OUTLINE_FS)?;
            let vao = gl.create_vertex_array().map_err(e)?;
            let vbo = gl.create_buffer().map_err(e)?;
            gl.bind_vertex_array(Some(vao));
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(vbo));
            for (i, off) in [(0u32, 0i32), (1, 12)] {
                gl.enable_vertex_attrib_array(i);
                gl.vertex_attrib_pointer_f32(i, 3, glow::FLOAT, false, 24, off);
                gl.vertex_attrib_divisor(i, 1);
            }
            gl.bind_vertex_array(None);
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
            Ok(Outlines {
                prog,
                vao,
                vbo,
                edges: Vec::new(),
            })
        }
    }

    pub(crate) fn destroy(&self, gl: &glow::Context) {
        // SAFETY: the context rule (renderer.rs): these objects are this struct's, deleted
        // only here, once.
        unsafe {
            gl.delete_program(self.prog);
            gl.delete_buffer(self.vbo);
            gl.delete_vertex_array(self.vao);
        }
    }

    /// Draws the boxes' edges and the `segments` `width` pixels wide into the bound
    /// framebuffer, whose particle viewport is `viewport` pixels; depth-tested, not written.
    #[allow(clippy::too_many_arguments)]
    pub(crate) unsafe fn draw(
        &mut self,
        gl: &glow::Context,
        boxes: &[Outline],
        segments: &[[[f32; 3]; 2]],
        view_proj: Mat4,
        viewport: (f32, f32),
        width: f32,
    ) {
        self.edges.clear();
        for b in boxes {
            for [a, c] in edges(b) {
                self.edges
                    .extend_from_slice(&[a.x, a.y, a.z, c.x, c.y, c.z]);
            }
        }
        for [a, c] in segments {
            self.edges.extend_from_slice(a);
            self.edges.extend_from_slice(c);
        }
        // SAFETY: the bytes of the live `edges` (its pointer and its size in bytes, borrowed
        // for as long as `bytes`): f32 has no padding and every byte may be read as a u8.
        let bytes: &[u8] = unsafe {
            std::slice::from_raw_parts(
                self.edges.as_ptr().cast::<u8>(),
                std::mem::size_of_val(self.edges.as_slice()),
            )
        };
        // SAFETY: the context rule (this fn's contract; the program, buffer and VAO are
        // this struct's); the buffer is given `bytes` whole, and the instanced draw takes
        // edges.len() / 6 edges, the ones just written.
        unsafe {
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(self.vbo));
            gl.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytes, glow::STREAM_DRAW);
            gl.bind_buffer(glow::ARRAY_BUFFER, None);
            gl.use_program(Some(self.prog));
            let loc = |n: &str| gl.get_uniform_location(self.prog, n);
            gl.uniform_matrix_4_f32_slice(
                loc("u_view_proj").as_ref(),
                false,
                &view_proj.to_cols_array(),
            );
            gl.uniform_2_f32(loc("u_viewport").as_ref(), viewport.0, viewport.1);
            gl.uniform_1_f32(loc("u_width").as_ref(), width);
            gl.uniform_4_f32(
                loc("u_color").as_ref(),
                COLOR[0],
                COLOR[1],
                COLOR[2],
                COLOR[3],
            );
            gl.enable(glow::DEPTH_TEST);
            gl.depth_func(glow::LEQUAL);
            gl.depth_mask(false);
            gl.enable(glow::BLEND);
            gl.blend_func(glow::SRC_ALPHA, glow::ONE_MINUS_SRC_ALPHA);
            gl.bind_vertex_array(Some(self.vao));
            gl.draw_arrays_instanced(glow::TRIANGLES, 0, 6, (self.edges.len() / 6) as i32);
            gl.bind_vertex_array(None);
            gl.disable(glow::BLEND);
            gl.depth_mask(true);
            gl.depth_func(glow::LESS);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_has_twelve_edges_along_the_axes() {
        let e = edges(&Outline {
            min: [0.0, 0.0, 0.0],
            max: [3.0, 1.6, 0.5],
        });
        let mut lengths: Vec<f32> = e.iter().map(|[a, b]| (*b - *a).length()).collect();
        lengths.sort_by(f32::total_cmp);
        assert_eq!(
            lengths,
            [0.5, 0.5, 0.5, 0.5, 1.6, 1.6, 1.6, 1.6, 3.0, 3.0, 3.0, 3.0]
        );
        // Each edge runs along one axis.
        for [a, b] in e {
            let d = b - a;
            assert_eq!(
                (d.x != 0.0) as u8 + (d.y != 0.0) as u8 + (d.z != 0.0) as u8,
                1
            );
        }
    }
}
