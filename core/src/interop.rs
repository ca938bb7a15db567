//! The interop wing (the `interop` feature): what a backend with the particles in device
//! memory does for the viewer without a read-back. It fills the renderer's OpenGL vertex
//! buffers in place (CUDA-OpenGL interop; `backend/cuda/view.rs`, its launches in
//! `backend/cuda/launch/view.rs`, the kernels in `cuda/view.cu`). Only the GL buffers' names
//! cross this line: the solver crate links no GL library. A backend without it (the CPU's, a
//! decomposed run's) answers `Readback::gl_interop` with `None`, and the viewer uploads a
//! `Readback::snapshot` instead.

use crate::solver::Shown;

/// The extension of `Readback` that the CUDA solver implements (`Readback::gl_interop`).
pub trait GlInterop {
    /// Fills the viewer's vertex buffers `gl` from device memory (positions, quantity `shown`
    /// and kinds of the fluid, then of the solids, then of the other kinds, each in storage
    /// order, as `Readback::snapshot` gives them), and reduces the colour range on the device
    /// unless `fixed_range` (then nothing comes back to the host); `hidden`'s bit k keeps
    /// kind k out of the range; with `splat`, also the spheres' visibility (`GlSplat`).
    /// `Err`: what failed.
    fn fill_gl(
        &mut self,
        gl: &GlBuffers,
        shown: Shown,
        hidden: u8,
        fixed_range: bool,
        splat: Option<&GlSplat>,
    ) -> Result<GlFill, String>;
}

/// The viewer's particle vertex buffers, by their OpenGL names in the context current on the
/// calling thread, which a backend with the particles in device memory fills in place
/// (`GlInterop::fill_gl`): per particle, the position as three f32 \[L\] (z = 0 in 2D), the
/// shown quantity as one f32, the kind as one u8; each buffer holds `capacity` particles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GlBuffers {
    pub positions: u32,
    pub values: u32,
    pub kinds: u32,
    pub capacity: usize,
}

/// What `GlInterop::fill_gl` wrote: `count` particles, `kinds` of them of each kind class in
/// the buffers' order (fluid, solid, every other kind), and the least and greatest shown
/// value of the particles that set the colour range (finite, neither boundary nor hidden),
/// where the range was reduced and any particle set it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GlFill {
    pub count: usize,
    pub kinds: [usize; 3],
    pub range: Option<(f32, f32)>,
    /// Whether the splat asked for was written.
    pub splat: bool,
}

/// A visibility splat asked of `GlInterop::fill_gl` with the fill (the viewer's `SplatView`):
/// of the particles `first .. first + count` of the filled buffers whose kind is not
/// `hidden` (bit k: kind k), the nearest sphere of `radius` \[L\] at each pixel of a `width` x
/// `height` perspective view, written to the OpenGL buffer `buffer`: `width * height`
/// quadruples of `f32` (the sphere's world centre and shown value), then as many kind bytes
/// (255 where no sphere is), pixel (X, Y) at Y width + X. `view`: the world-to-view rows
/// (3 x 4); a pixel centre (X + 1/2, Y + 1/2) looks along
/// `(X' ray[0] + ray[1], Y' ray[2] + ray[3], -1)` in view space (X', Y' the centre's
/// coordinates).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GlSplat {
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

impl GlSplat {
    /// Bytes of `buffer`.
    pub fn bytes(&self) -> usize {
        self.width as usize * self.height as usize * 17
    }
}
