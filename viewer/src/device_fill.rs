//! Particles that the source writes straight into the renderer's vertex buffers on the GPU
//! (in meshfree, CUDA-OpenGL interop in the binary's glue) instead of handing over host
//! vectors: the buffers' GL names and layout ([`ParticleBuffers`]), what a fill reports
//! ([`DeviceFrame`]), and the one step of a frame, shared by the window and the headless
//! renderer, that takes the device path where the source offers it and the upload otherwise.

use crate::renderer::{range_from, Renderer};
use crate::{Field, FrameData, LiveSource, ViewerError};

/// The renderer's particle vertex buffers, by their names in the current OpenGL context, for
/// a source that fills them in device memory ([`LiveSource::fill_buffers`]). Per particle:
/// the position as three `f32` (z = 0 in 2D), the coloured value as one `f32`, the kind as
/// one `u8` (see [`crate::kind`]). The particles lie in kind order: every fluid particle,
/// then every solid one, then the rest (boundary and any other kind), each part in the
/// source's order (the upload of [`LiveSource::frame`] orders them alike), so that a pass
/// walks only the kinds it draws ([`DeviceFrame::kinds`] says where each part ends). Each
/// buffer holds `capacity` particles; the names or the capacity change when the buffers are
/// made anew (register them again).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ParticleBuffers {
    pub positions: u32,
    pub values: u32,
    pub kinds: u32,
    pub capacity: usize,
}

impl ParticleBuffers {
    /// Bytes per particle of `positions`.
    pub const POSITION_BYTES: usize = 12;
    /// Bytes per particle of `values`.
    pub const VALUE_BYTES: usize = 4;
    /// Bytes per particle of `kinds`.
    pub const KIND_BYTES: usize = 1;
}

/// A visibility splat asked of [`LiveSource::fill_buffers`] (`splat.rs`): of the particles
/// `first .. first + count` of the filled buffers whose kind is not `hidden` (bit k: kind k),
/// the nearest sphere of `radius` at each pixel of a `width` x `height` perspective view,
/// written to the OpenGL buffer `buffer`: `width * height` quadruples of `f32` (the sphere's
/// world centre and value), then as many kind bytes (255 where no sphere is), the pixel
/// (X, Y) at Y width + X. `view`: the world-to-view matrix's rows (3 x 4); the pixel centre at
/// window position (X', Y') looks along `(X' ray[0] + ray[1], Y' ray[2] + ray[3], -1)` in
/// view space. A pixel's sphere is the nearest one whose ray-cast hits it (the sprites' test).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SplatView {
    pub buffer: u32,
    pub width: u32,
    pub height: u32,
    pub view: [f32; 12],
    pub ray: [f32; 4],
    pub radius: f32,
    pub first: usize,
    pub count: usize,
    pub hidden: u8,
}

/// What a source's [`LiveSource::fill_buffers`] wrote.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DeviceFrame {
    /// Particles written (at most the buffers' capacity).
    pub count: usize,
    /// Of them, the fluid, the solid and the other particles, in that order in the buffers
    /// (they sum to `count`).
    pub kinds: [usize; 3],
    /// The least and greatest value of the particles that set the colour range (finite,
    /// neither boundary nor hidden), where the source reduced it and any particle set it.
    pub range: Option<(f32, f32)>,
    /// Whether it also wrote the splat asked for.
    pub splat: bool,
}

/// Puts one frame's particles into `renderer`: filled by the source on the GPU where
/// `device` allows and the source offers it, else `source.frame` uploaded. `frame` gets the
/// frame's dimension, domain and radius (and, uploaded, the particles). Returns the colour
/// range to draw with (`range` where fixed; from the device's reduction; `None`: from
/// `frame`'s values) and whether the device path ran.
#[allow(clippy::too_many_arguments)]
pub(crate) fn prepare(
    renderer: &mut Renderer,
    gl: &glow::Context,
    source: &mut dyn LiveSource,
    field: Field,
    hide_kinds: [bool; 3],
    range: Option<(f32, f32)>,
    device: bool,
    frame: &mut FrameData,
) -> Result<(Option<(f32, f32)>, bool), ViewerError> {
    if device {
        let bufs = renderer.particle_buffers(gl, source.status().particles);
        let fixed = range.is_some() || field == Field::Kind;
        let want = renderer.splat_wanted();
        if let Some(r) = source.fill_buffers(field, hide_kinds, fixed, &bufs, want.as_ref(), frame)
        {
            let d = r.map_err(ViewerError::Source)?;
            renderer.set_splatted(true, want.filter(|_| d.splat));
            if d.kinds.iter().sum::<usize>() != d.count {
                return Err(ViewerError::Source(format!(
                    "the fill's kinds {:?} do not sum to its {} particles",
                    d.kinds, d.count
                )));
            }
            renderer.set_counts(d.kinds);
            let (lo, hi) = d.range.unwrap_or((f32::INFINITY, f32::NEG_INFINITY));
            return Ok((
                Some(range.unwrap_or_else(|| range_from(lo, hi, field))),
                true,
            ));
        }
    }
    source.frame(field, frame);
    renderer.set_splatted(false, None);
    renderer.upload(gl, frame)?;
    Ok((range, false))
}
