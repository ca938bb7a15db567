//! What the viewer asks of a solver (`Readback::snapshot`, `Readback::fill_gl`): the shown
//! quantity, a host snapshot, and the OpenGL buffers a GPU backend fills in place.

use serde::{Deserialize, Serialize};

/// The particle quantity a snapshot carries for display.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Shown {
    #[default]
    Speed,
    Pressure,
    Density,
    Kind,
}

/// What the viewer draws: positions, kinds and one quantity, in storage order, in buffers
/// that are reused from frame to frame.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Snapshot {
    pub positions: Vec<[f32; 3]>,
    pub values: Vec<f32>,
    pub kinds: Vec<u8>,
}

/// The viewer's particle vertex buffers, by their OpenGL names in the context current on the
/// calling thread, which a backend with the particles in device memory fills in place
/// (`Readback::fill_gl`): per particle, the position as three f32 \[L\] (z = 0 in 2D), the
/// shown quantity as one f32, the kind as one u8; each buffer holds `capacity` particles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GlBuffers {
    pub positions: u32,
    pub values: u32,
    pub kinds: u32,
    pub capacity: usize,
}

/// What `Readback::fill_gl` wrote: `count` particles, `kinds` of them of each kind class in
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

/// A visibility splat asked of `Readback::fill_gl` with the fill (the viewer's `SplatView`):
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
