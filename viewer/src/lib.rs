//! # meshfree-viewer
//!
//! Live OpenGL window and headless (EGL, no display) renderer for the
//! `meshfree` SPH solver. This crate holds every window and GL dependency
//! (glow, glutin 0.32, glutin-winit 0.5, winit 0.30, png) and does **not**
//! depend on the solver: the two talk through the small [`LiveSource`] trait.
//!
//! ## Talking to the solver
//!
//! The solver implements [`LiveSource`]:
//!
//! * [`LiveSource::advance`] runs `steps` solver steps;
//! * [`LiveSource::frame`] fills a [`FrameData`] snapshot (positions, one
//!   value of the chosen [`Field`] per particle, particle kinds, the domain
//!   and the particle radius). The viewer calls it **once per drawn frame,
//!   never per step**, and always passes the *same* buffer, so an
//!   implementation that does `clear()` + `extend()` on its vectors allocates
//!   only on the first frame;
//! * [`LiveSource::status`] gives time, step count and particle count for the
//!   overlay;
//! * [`LiveSource::reset`] goes back to the initial state (key `r`);
//! * [`LiveSource::fill_buffers`] (optional) writes the particles straight into the
//!   renderer's vertex buffers on the GPU instead of `frame`: the source gets the buffers'
//!   OpenGL names and layout ([`ParticleBuffers`]: per particle three `f32` of position,
//!   one `f32` value, one `u8` kind) and returns how many it wrote and, unless the range is
//!   fixed, the least and greatest value that set the colour range ([`DeviceFrame`]).
//!   meshfree's CUDA backend does it with CUDA-OpenGL interop, so nothing per particle
//!   crosses PCIe; where a source returns `None` (the default) the window and the headless
//!   renderer call `frame` and upload, as before.
//!
//! ## Live window
//!
//! [`run_window`] opens a window (winit 0.30 + glutin 0.32, GLX or EGL,
//! OpenGL 4.0 core, else 3.3) and runs the solver in the render loop until the window is
//! closed. 2D frames get an orthographic pan/zoom camera, 3D frames an orbit
//! camera. A panel at the top left ([`Panel`]) shows the time, step, particle
//! count, solver steps/s and frames/s, and one row per control below; a click on
//! a row does what its key does ([`Action::for_key`]):
//!
//! | key | action |
//! |---|---|
//! | space | pause / resume |
//! | `.` or `n` | single step (pauses) |
//! | `+` / `-` | double / halve the steps per frame |
//! | `f` | cycle the coloured field (speed, pressure, density, kind) |
//! | `l` | hold the colour range where it is / back to automatic |
//! | `b` | show / hide the wall (boundary) particles |
//! | `e` | show / hide the elastic bodies (solid particles) |
//! | `o` | show / hide the outlines of the container and obstacles (3D) |
//! | `s` | fluid as a screen-space surface / as spheres (3D) |
//! | `h` | more / fewer rows in the panel (the keys below) |
//! | `r` | reset the source |
//! | `p` | screenshot to PNG (in [`ViewOptions::screenshot_dir`]) |
//! | `c` | re-frame the camera |
//! | Esc / `q` | close |
//!
//! Mouse: left drag pans (2D) or orbits (3D), right or middle drag pans (3D),
//! the wheel zooms.
//!
//! winit allows one event loop per process, so [`run_window`] can be called
//! only once per process.
//!
//! ## Headless
//!
//! [`render_headless`] (or a reusable [`HeadlessRenderer`]) renders a
//! [`FrameData`] with EGL and no display server (`EGL_EXT_platform_device`,
//! surfaceless context, rendering into a framebuffer object) and returns an
//! [`Image`], which [`Image::save_png`] writes. [`HeadlessRenderer::render_source`] draws a
//! [`LiveSource`]'s state as the window does (the GPU fill where offered), reading the pixels
//! back only when asked, and [`HeadlessRenderer::redraw`] draws the same buffers again (for
//! timing the drawing alone). Both paths share one renderer
//! module and the same shaders, and draw everything the window draws (outlines,
//! surface, the panel when [`RenderOptions::panel`] is set). If no EGL device is
//! found it returns [`ViewerError::NoEglDevice`].
//!
//! ## Look
//!
//! Particles are drawn as lit sphere impostors (instanced quads with ray-cast
//! spheres and correct fragment depth), coloured with the blue–purple–pink–red
//! map of [`colormap()`], with a colour bar that shows the value range, and an
//! overlay and panel drawn with a built-in 5×7 bitmap font. Boundary particles
//! are drawn grey unless the field is [`Field::Kind`]. In 3D a sphere under four
//! pixels across fades to its mean shade, so that a lattice of them does not
//! alias into Moire bands; [`FrameData::outlines`] (the container's inside, the
//! obstacles) are drawn as edges a few pixels wide, and the automatic camera
//! frames them. With [`RenderOptions::surface`] the 3D fluid is one screen-space
//! surface (van der Laan, Green & Sainz 2009: the spheres' depth, a bilateral
//! filter of it, normals from the smoothed depth, Fresnel reflection of a sky and
//! absorption over the fluid's thickness).

mod camera;
mod colormap;
pub mod demo;
mod device_fill;
mod error;
mod font;
mod gpu_timers;
mod headless;
mod image;
mod outline;
mod panel;
mod renderer;
mod shaders;
mod splat;
mod sprites;
mod surface;
mod window;

pub use camera::{Camera, OrbitCamera, OrthoCamera};
pub use colormap::colormap;
pub use device_fill::{DeviceFrame, ParticleBuffers, SplatView};
pub use error::ViewerError;
pub use gpu_timers::PassTime;
pub use headless::{render_headless, HeadlessRenderer};
pub use image::Image;
pub use panel::{Action, Panel};
pub use window::{run_window, ViewOptions};

/// What colours the particles.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Field {
    /// Velocity magnitude.
    #[default]
    Speed,
    /// Pressure.
    Pressure,
    /// Density.
    Density,
    /// Particle kind: 0 fluid, 1 solid, 2 boundary.
    Kind,
}

impl Field {
    /// All fields, in the order the `f` key cycles through them.
    pub const ALL: [Field; 4] = [Field::Speed, Field::Pressure, Field::Density, Field::Kind];

    /// The next field in the `f` cycle.
    pub fn next(self) -> Field {
        match self {
            Field::Speed => Field::Pressure,
            Field::Pressure => Field::Density,
            Field::Density => Field::Kind,
            Field::Kind => Field::Speed,
        }
    }

    /// A short label, shown over the colour bar.
    pub fn label(self) -> &'static str {
        match self {
            Field::Speed => "speed",
            Field::Pressure => "pressure",
            Field::Density => "density",
            Field::Kind => "kind",
        }
    }
}

/// Particle kinds as stored in [`FrameData::kinds`].
pub mod kind {
    /// Fluid particle.
    pub const FLUID: u8 = 0;
    /// Elastic solid particle.
    pub const SOLID: u8 = 1;
    /// Fixed boundary particle.
    pub const BOUNDARY: u8 = 2;
}

/// A snapshot the solver hands over once per drawn frame.
///
/// The viewer reuses one `FrameData` for every frame: fill it with
/// `clear()` + `extend()` so the vectors keep their capacity.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FrameData {
    /// 2 or 3.
    pub dim: u8,
    /// Particle positions; z = 0 in 2D.
    pub positions: Vec<[f32; 3]>,
    /// The chosen field, one value per particle.
    pub values: Vec<f32>,
    /// Particle kinds, one per particle: 0 fluid, 1 solid, 2 boundary (see [`kind`]).
    pub kinds: Vec<u8>,
    /// Lower corner of the domain (z = 0 in 2D).
    pub domain_min: [f32; 3],
    /// Upper corner of the domain (z = 0 in 2D).
    pub domain_max: [f32; 3],
    /// Drawn sphere radius: half the particle spacing.
    pub particle_radius: f32,
    /// Boxes drawn as outlines in 3D (a container's inside, obstacles); the 3D camera
    /// frames their union when there are any, else the domain.
    pub outlines: Vec<Outline>,
    /// Segments (from, to) \[L\] drawn as the outlines are, in 3D: the edges of walls from
    /// surface files, so the picture shows the geometry a user brought.
    pub edges: Vec<[[f32; 3]; 2]>,
}

/// An axis-aligned box drawn as an outline (its 12 edges) in 3D.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outline {
    /// Lower corner \[L\].
    pub min: [f32; 3],
    /// Upper corner \[L\].
    pub max: [f32; 3],
}

impl FrameData {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// The box the automatic 3D camera frames: the union of the outlines, else the domain.
    pub fn focus(&self) -> ([f32; 3], [f32; 3]) {
        let Some(first) = self.outlines.first() else {
            return (self.domain_min, self.domain_max);
        };
        self.outlines
            .iter()
            .fold((first.min, first.max), |(lo, hi), o| {
                (
                    std::array::from_fn(|i| lo[i].min(o.min[i]).min(o.max[i])),
                    std::array::from_fn(|i| hi[i].max(o.max[i]).max(o.min[i])),
                )
            })
    }

    /// Checks that the vectors have matching lengths and `dim` is 2 or 3.
    pub fn validate(&self) -> Result<(), ViewerError> {
        let n = self.positions.len();
        if self.dim != 2 && self.dim != 3 {
            return Err(ViewerError::InvalidFrame(format!(
                "dim is {}, expected 2 or 3",
                self.dim
            )));
        }
        if self.values.len() != n || self.kinds.len() != n {
            return Err(ViewerError::InvalidFrame(format!(
                "{} positions, {} values, {} kinds",
                n,
                self.values.len(),
                self.kinds.len()
            )));
        }
        Ok(())
    }
}

/// Solver progress, shown in the overlay.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Status {
    /// Simulated time.
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    /// Number of particles.
    pub particles: usize,
}

/// Where a recorded run is: the frame shown among the frames it wrote, and their times
/// (the window's time slider, and its keys that step back).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Timeline {
    /// The frame shown, from 0.
    pub frame: usize,
    /// How many frames there are (at least 1).
    pub frames: usize,
    /// The first frame's time and the last's.
    pub times: (f64, f64),
}

impl Timeline {
    /// The frame a step back (`back`) or on goes to, or the first or last, as `to` says.
    pub fn target(&self, to: Seek) -> usize {
        let last = self.frames.saturating_sub(1);
        match to {
            Seek::Back => self.frame.saturating_sub(1),
            Seek::First => 0,
            Seek::Last => last,
            Seek::Fraction(f) => {
                let f = if f.is_finite() {
                    f.clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (f * last as f64).round() as usize
            }
        }
    }
}

/// Where a seek on a recorded run goes ([`Timeline::target`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Seek {
    /// One frame back.
    Back,
    /// The first frame.
    First,
    /// The last frame.
    Last,
    /// The frame at this fraction of the run's frames (0: the first, 1: the last): where the
    /// slider was clicked.
    Fraction(f64),
}

/// The simulation as the live window sees it.
pub trait LiveSource {
    /// Runs `steps` solver steps.
    fn advance(&mut self, steps: u32) -> Result<(), String>;
    /// Fills `out` with the current state, coloured by `field`. `out` is the
    /// same buffer every frame: reuse its vectors.
    fn frame(&mut self, field: Field, out: &mut FrameData);
    /// Time, step and particle count.
    fn status(&self) -> Status;
    /// Goes back to the initial state.
    fn reset(&mut self) -> Result<(), String>;
    /// A recorded run's place among its frames; `None` (the default): a live solver, which
    /// goes forward only.
    fn timeline(&self) -> Option<Timeline> {
        None
    }
    /// Shows frame `k` of a recorded run (clamped to the last); called only where
    /// [`LiveSource::timeline`] is `Some`.
    fn seek(&mut self, _k: usize) -> Result<(), String> {
        Err("a live run goes forward only".into())
    }
    /// Writes the particles coloured by `field` straight into the renderer's vertex buffers
    /// `buffers` on the GPU (e.g. CUDA-OpenGL interop: nothing per particle through the
    /// host), and `out`'s dimension, domain and radius (its vectors stay as they are);
    /// reduces the colour range unless `fixed_range` (`hide_kinds[k]` keeps kind k out of
    /// it). With `splat`, the spheres' visibility too, where the source can
    /// ([`SplatView`]; [`DeviceFrame::splat`] says whether it did). Called in place of
    /// [`LiveSource::frame`], the renderer's GL context current. `None` (the default): this
    /// source cannot, the viewer calls `frame` and uploads.
    fn fill_buffers(
        &mut self,
        _field: Field,
        _hide_kinds: [bool; 3],
        _fixed_range: bool,
        _buffers: &ParticleBuffers,
        _splat: Option<&SplatView>,
        _out: &mut FrameData,
    ) -> Option<Result<DeviceFrame, String>> {
        None
    }
}

/// How to draw one frame (headless, or the starting state of the window).
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The field the frame's values hold (label and range rule of the colour bar).
    pub field: Field,
    /// Colour range; `None`: from the visible particles (speed from 0).
    pub range: Option<(f32, f32)>,
    /// Camera; [`Camera::Auto`] frames the domain.
    pub camera: Camera,
    /// `hide_kinds[k]` hides particles of kind `k` (0 fluid, 1 solid, 2 boundary).
    pub hide_kinds: [bool; 3],
    /// Draw the colour bar (in a panel on the right).
    pub colorbar: bool,
    /// Text lines drawn top-left over the particles.
    pub overlay: Vec<String>,
    /// Background colour, linear RGB 0..1.
    pub background: [f32; 3],
    /// Text scale (pixels per font pixel); 0 picks from the image height.
    pub ui_scale: u32,
    /// 3D: draw the fluid as one screen-space surface (van der Laan, Green & Sainz 2009)
    /// instead of spheres.
    pub surface: bool,
    /// 3D: draw [`FrameData::outlines`].
    pub outlines: bool,
    /// The on-screen panel (below the overlay lines); `None`: no panel.
    pub panel: Option<Panel>,
    /// Draw every sprite as a 4-vertex quad instead of one point (`sprites.rs`): the
    /// reference the points are tested against.
    pub quads_only: bool,
    /// Draw the spheres as sprites even where the source's visibility splat of this view
    /// is at hand (`splat.rs`): the sprites' raster, which `render --frames` times as the
    /// ceiling its drawing is compared with.
    pub sprites_only: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 800,
            height: 600,
            field: Field::Speed,
            range: None,
            camera: Camera::Auto,
            hide_kinds: [false; 3],
            colorbar: true,
            overlay: Vec::new(),
            background: [0.08, 0.08, 0.1],
            ui_scale: 0,
            surface: false,
            outlines: true,
            panel: None,
            quads_only: false,
            sprites_only: false,
        }
    }
}
