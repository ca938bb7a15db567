//! The scene file format: serde structs for TOML (`#[serde(deny_unknown_fields)]` on every
//! table, string-tagged enums in kebab-case). The scheme's tables (`[discretisation]`,
//! `[time]`, `[fluid]`, `[solid]`, `[boundary]`) and their choices are declared in
//! `crate::scene::scheme`, key by key, with the whole file's struct `SceneFile`; this file holds
//! the scene's geometry and objects. Every key, its default and the paper's value: `docs/reference/scene.md`
//! (`meshfree scenes --reference`).
//!
//! Arrays of coordinates hold exactly `dimension` numbers; the checks are in `validate.rs`.

use serde::{Deserialize, Serialize};

use crate::named::Named;
use crate::physics::particle::{Kind, Particle};
use crate::solver::frame::{Field, Fields};

mod motion;
pub use motion::{
    Focus, Interpolation, Motion, MotionLaw, Oscillation, Paddle, Rotation, Series, Spectrum,
    SpectrumShape, WaveMaker,
};

/// Coordinate axis names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }
}

/// Fluid particles with `min <= x[axis] < max` have their velocity set to `velocity`
/// every step instead of integrated: with a periodic `axis` a recirculating channel whose
/// band wipes the wake and holds the mean flow.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Inflow {
    pub axis: Axis,
    /// \[L\] band limits along `axis`.
    pub min: f64,
    pub max: f64,
    /// \[L/T\] `dimension` numbers.
    pub velocity: Vec<f64>,
    /// \[T\] T_r, default 0 (the mean flow from the start). > 0: a start from rest: the
    /// generator takes `velocity` off the fluid's initial velocity, and the kick gives it
    /// back over T_r as r(t) = (1 - cos(pi t / T_r)) / 2 (the band at r `velocity`, every
    /// particle it integrates outside the band accelerated by d(r `velocity`)/dt, a uniform
    /// body force: the fluid's frame accelerates as a body started from rest would see
    /// it), instead of every particle at `velocity` at once.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub ramp: f64,
}

pub use super::open::{OpenBoundary, OpenKind, OpenProfile};

/// A sponge layer (`[damping_zone]`): the kick relaxes the velocity of fluid particles in
/// it, v *= exp(-strength r^2 dt), r rising from 0 at `start` to 1 at `end` along `axis`
/// (and 1 beyond): the passive absorption at a flume's far end (DualSPHysics' damping
/// zone, Altomare et al. 2017, Coastal Eng. 127).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingZone {
    pub axis: Axis,
    /// \[L\] where the damping begins along `axis`.
    pub start: f64,
    /// \[L\] where it reaches full strength (either side of `start`).
    pub end: f64,
    /// \[1/T\] the relaxation rate at full strength.
    pub strength: f64,
}

pub(super) fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

/// The force of the fluid (and solids) on one wall object, sampled every `interval`: its
/// peak, the peak's time and its impulse; for a bluff body in a stream, with
/// `reference_velocity` and `reference_length` (both or neither), drag along x and lift
/// along y as coefficients F / (0.5 rho0 U^2 L^(d-1)) and the Strouhal number.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Monitor {
    /// Output file `<name>.csv` and key in summary.json. Default "forces".
    #[serde(default = "default_monitor_name")]
    pub name: String,
    /// Index of the wall in `[[walls]]`.
    pub wall: usize,
    /// \[T\] time between samples.
    pub interval: f64,
    /// \[L/T\] U of the coefficients and the Strouhal number. Default none: no coefficients.
    #[serde(default)]
    pub reference_velocity: Option<f64>,
    /// \[L\] D of the coefficients, the Strouhal number and the blockage ratio D / H.
    #[serde(default)]
    pub reference_length: Option<f64>,
}

fn default_monitor_name() -> String {
    "forces".into()
}

/// A field that a probe samples (`Probe::fields`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ProbeField {
    /// [M L^-d L^2 T^-2] each particle's pressure from its density by its equation of
    /// state, eq. (9).
    Pressure,
    /// \[L/T\] `dimension` components.
    Velocity,
    /// [M L^-d]
    Density,
}

impl ProbeField {
    pub const ALL: [ProbeField; 3] = [
        ProbeField::Pressure,
        ProbeField::Velocity,
        ProbeField::Density,
    ];

    /// The name scene files give it.
    pub fn name(self) -> &'static str {
        match self {
            ProbeField::Pressure => "pressure",
            ProbeField::Velocity => "velocity",
            ProbeField::Density => "density",
        }
    }
}

/// Points where fields are kernel-interpolated with Shepard normalisation every `interval`
/// (`Readback::sample_points`), written to `probes.csv`, one row per point and sample.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Probe {
    /// The probe's name in `probes.csv` (letters, digits, '-' and '_'; unique).
    pub name: String,
    /// \[L\] one or more points, `dimension` numbers each, inside the domain.
    pub points: Vec<Vec<f64>>,
    /// \[T\] time between samples.
    pub interval: f64,
    /// What to sample. Default all: pressure, velocity, density.
    #[serde(default = "all_probe_fields")]
    pub fields: Vec<ProbeField>,
    /// Whether the (dynamic) wall particles enter the interpolation besides the fluid's.
    /// Default false.
    #[serde(default)]
    pub walls: bool,
}

fn all_probe_fields() -> Vec<ProbeField> {
    ProbeField::ALL.to_vec()
}

/// The most points a gauge's line may have (`Gauge::step`; the scene's validation).
pub const MAX_GAUGE_POINTS: usize = 100_000;

/// A free-surface gauge (DualSPHysics' GaugeSWL): the last point along the line `start` ->
/// `end` where the fluid's colour sum_j W m_j / rho_j is at least 1/2, every `interval`,
/// written to `gauges.csv`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Gauge {
    /// The gauge's name in `gauges.csv` (letters, digits, '-' and '_'; unique).
    pub name: String,
    /// \[L\] the line's ends, inside the domain; usually `start` at the bottom and `end` above
    /// the highest surface.
    pub start: Vec<f64>,
    pub end: Vec<f64>,
    /// \[T\] time between samples.
    pub interval: f64,
    /// \[L\] distance between the line's points. Default half the particle spacing.
    #[serde(default)]
    pub step: Option<f64>,
}

/// The simulation box. Particles leaving it on a non-periodic axis stop the run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// \[L\] lower corner.
    pub min: Vec<f64>,
    /// \[L\] upper corner.
    pub max: Vec<f64>,
    /// Per axis: wrap around. Default all false.
    #[serde(default)]
    pub periodic: Option<Vec<bool>>,
}

/// A block of fluid particles on the lattice min + (i + 0.5) dx.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidBlock {
    pub min: Vec<f64>,
    pub max: Vec<f64>,
    /// \[L/T\] initial velocity. Default zero.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    /// Initial pressure and density from the Tait EOS with a hydrostatic column measured
    /// from the block's top (along -gravity), eq. (9); with `[boundary] hydrostatic_walls`
    /// the dynamic walls that hold it too. Default false.
    #[serde(default)]
    pub hydrostatic: bool,
    /// Only the lattice points of the box inside this closed surface (3D: a mesh file; 2D:
    /// a polygon): a tank of any shape filled up to the box's top. Default none: the box.
    #[serde(default)]
    pub inside: Option<Outline>,
}

/// A closed surface put in place: a 3D object's `mesh` (a file: STL binary or ASCII, OBJ,
/// PLY), a 2D object's `polygon` (its corners in `points`, or a text file of `x y` lines),
/// a fluid block's `inside` (`scene::geometry`: read once with the scene, checked, turned
/// outward where wound inward). A wall's surface may be open (`Side`: `solid` = "back" or
/// "front" in 3D, "left" or "right" in 2D): it is then taken as the file orders it, and a
/// 2D line's points are not closed into a loop. The file is scaled, then turned, then moved.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Outline {
    /// The file, relative to the scene file's directory.
    #[serde(default)]
    pub file: Option<String>,
    /// \[L\] 2D: the polygon's corners in order (either way round), instead of a file.
    #[serde(default)]
    pub points: Option<Vec<Vec<f64>>>,
    /// The file's unit in the scene's (0.001 for a file in mm and a scene in m). Default 1.
    #[serde(default = "one")]
    pub scale: f64,
    /// \[deg\] 3D: turns about x, then y, then z (about the origin, after the scale); 2D:
    /// one turn about z. Default none.
    #[serde(default)]
    pub rotate: Option<Vec<f64>>,
    /// \[L\] a move after the turns, `dimension` numbers. Default none.
    #[serde(default)]
    pub translate: Option<Vec<f64>>,
    /// Relax the particles near the surface against it (`geometry::pack`: Zhu et al. 2021),
    /// so that a curved surface is smooth at the particle scale, not stair-stepped. Default
    /// false: the lattice points.
    #[serde(default)]
    pub pack: bool,
    /// \[L\] 2D: the polygon is the cut of a 3D mesh file (STL, OBJ, PLY) by the plane z =
    /// `slice` (in the scene's unit: after the scale, before the turn and the move, which are
    /// the polygon's). Default none.
    #[serde(default)]
    pub slice: Option<f64>,
    /// The surface read from it (`geometry::load`, when the scene is read).
    #[serde(skip)]
    pub loaded: super::geometry::surface::Loaded,
}

impl Outline {
    /// The surface read from it (with the scene: `geometry::load_all`; the scene's checks
    /// refuse an outline not read).
    pub fn surface(&self) -> &super::geometry::Surface {
        self.loaded
            .get()
            .expect("a validated scene's surfaces are read (geometry::check)")
    }
}

fn one() -> f64 {
    1.0
}

/// Which side of its surface a mesh or polygon wall's rows fill (`solid`). A closed surface
/// (turned outward where wound inward) has an inside and an outside; an open one (a
/// terrain, a sea bed, a sheet, a profile line) has two faces, told apart by the order of
/// its corners as the file gives them: the rows lie within `layers` spacings of it on that
/// side, and fluid and solids on that side are not generated (beyond its edges too: the
/// side of a point is that of the surface's closest point). A 2D sea bed with a beach, the
/// water above it: `shape = "polygon"`, `polygon = { points = [[0, 0.1], [2, 0.1], [3,
/// 0.4]] }`, `solid = "right"`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Side {
    /// A closed surface is an obstacle: the rows lie inside it, the fluid around it.
    #[default]
    Inside,
    /// A closed surface holds the fluid (a tank, a channel): the rows lie outside it.
    Outside,
    /// 3D, an open (or any) mesh: the rows lie behind its faces, against their normals
    /// (a triangle's normal points to where its corners turn anticlockwise, as in STL).
    Back,
    /// 3D, an open (or any) mesh: the rows lie in front of its faces.
    Front,
    /// 2D, an open line of `points` (or a file of them): the rows lie on its left, walking
    /// from its first point to its last.
    Left,
    /// 2D, an open line: the rows lie on its right (a sea bed given from the paddle to the
    /// beach, with the water above it).
    Right,
}

impl Side {
    /// The surface is open: its side comes from its faces' orientation, not from an inside.
    pub fn open(self) -> bool {
        !matches!(self, Side::Inside | Side::Outside)
    }

    /// The rows lie where `geometry::Surface::inside` is true: inside a closed surface,
    /// behind an open mesh's faces, left of an open line.
    pub fn inside(self) -> bool {
        matches!(self, Side::Inside | Side::Back | Side::Left)
    }
}

/// An elastic body. `shape` picks the variant; the other keys belong to that shape.
/// `motion` (`Motion`) makes it driven: every particle follows it whatever the forces (a
/// clamp with a zero velocity); at most `MF_MAX_DRIVEN` (8) driven objects (solids or walls)
/// per scene, each at its own velocity. A driven body is bonded to the solid particles it
/// touches (`physics::pairs::same_body`): a clamp holds the body it overlaps, whose root
/// takes up strain through the velocity gradient, eq. (15); two undriven bodies touch only
/// through the pressure and stress terms.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SolidObject {
    Box {
        min: Vec<f64>,
        max: Vec<f64>,
        #[serde(default)]
        velocity: Option<Vec<f64>>,
        #[serde(default)]
        motion: Option<Motion>,
    },
    /// 2D only.
    Disc {
        center: Vec<f64>,
        radius: f64,
        #[serde(default)]
        velocity: Option<Vec<f64>>,
        #[serde(default)]
        motion: Option<Motion>,
    },
    /// 3D only.
    Sphere {
        center: Vec<f64>,
        radius: f64,
        #[serde(default)]
        velocity: Option<Vec<f64>>,
        #[serde(default)]
        motion: Option<Motion>,
    },
    /// 3D only: the domain's lattice points inside a closed surface from a file.
    Mesh {
        mesh: Outline,
        #[serde(default)]
        velocity: Option<Vec<f64>>,
        #[serde(default)]
        motion: Option<Motion>,
    },
    /// 2D only: the domain's lattice points inside a closed polygon.
    Polygon {
        polygon: Outline,
        #[serde(default)]
        velocity: Option<Vec<f64>>,
        #[serde(default)]
        motion: Option<Motion>,
    },
}

impl SolidObject {
    pub fn velocity(&self) -> Option<&Vec<f64>> {
        match self {
            SolidObject::Box { velocity, .. }
            | SolidObject::Disc { velocity, .. }
            | SolidObject::Sphere { velocity, .. }
            | SolidObject::Mesh { velocity, .. }
            | SolidObject::Polygon { velocity, .. } => velocity.as_ref(),
        }
    }
    /// The prescribed motion of a driven body (a clamp: a zero velocity), if any.
    pub fn motion(&self) -> Option<&Motion> {
        match self {
            SolidObject::Box { motion, .. }
            | SolidObject::Disc { motion, .. }
            | SolidObject::Sphere { motion, .. }
            | SolidObject::Mesh { motion, .. }
            | SolidObject::Polygon { motion, .. } => motion.as_ref(),
        }
    }
    /// `motion`, to change (a run's copy renames its series file).
    pub fn motion_mut(&mut self) -> Option<&mut Motion> {
        match self {
            SolidObject::Box { motion, .. }
            | SolidObject::Disc { motion, .. }
            | SolidObject::Sphere { motion, .. }
            | SolidObject::Mesh { motion, .. }
            | SolidObject::Polygon { motion, .. } => motion.as_mut(),
        }
    }
    /// The surface of a mesh or polygon body.
    pub fn outline_mut(&mut self) -> Option<&mut Outline> {
        match self {
            SolidObject::Mesh { mesh: o, .. } | SolidObject::Polygon { polygon: o, .. } => Some(o),
            _ => None,
        }
    }
}

/// Fixed boundary particles. Any wall may be a gate, removed at `remove_at`, or driven:
/// `motion` (`Motion`) moves all its particles rigidly (a piston, a flap, a sloshing
/// tank). A box, cylinder, mesh or polygon wall may instead float: `floating`
/// (`Floating`) makes it a rigid body that the fluid moves. At most `MF_MAX_DRIVEN` (8)
/// driven or floating objects (solids or walls) per scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Wall {
    /// `layers` rows of boundary particles just outside the box [min, max], at
    /// min - (k + 0.5) dx and max + (k + 0.5) dx; no rows above `max[1]` when `open_top`.
    BoxContainer {
        min: Vec<f64>,
        max: Vec<f64>,
        /// Default 3.
        #[serde(default = "default_layers")]
        layers: u32,
        /// Default true.
        #[serde(default = "default_true")]
        open_top: bool,
        #[serde(default)]
        remove_at: Option<f64>,
        #[serde(default)]
        motion: Option<Motion>,
    },
    /// A filled box of boundary particles (obstacle or gate).
    Box {
        min: Vec<f64>,
        max: Vec<f64>,
        #[serde(default)]
        remove_at: Option<f64>,
        #[serde(default)]
        motion: Option<Motion>,
        #[serde(default)]
        floating: Option<Floating>,
    },
    /// 2D: `layers` rows of boundary particles along the segment `from` -> `to`, on its
    /// left looking from `from` to `to` (the side away from the fluid), about dx apart. Fluid
    /// and solids behind it (on its left, within its length) are not generated: a sloped
    /// wall, e.g. a converging nozzle, cuts a fluid block.
    Segment {
        from: Vec<f64>,
        to: Vec<f64>,
        /// Default 3.
        #[serde(default = "default_layers")]
        layers: u32,
        #[serde(default)]
        remove_at: Option<f64>,
        #[serde(default)]
        motion: Option<Motion>,
    },
    /// 3D: `layers` rows of boundary particles, the domain's lattice points within `layers`
    /// spacings of a surface from a file, on its `solid` side (`Side`): inside a closed
    /// surface (an obstacle) or outside it (a tank or a channel that holds the fluid); behind
    /// or in front of an open one (a terrain, a sheet). Fluid and solids on that side are not
    /// generated. Each particle's normal and distance to the surface come from the surface's
    /// closest point.
    Mesh {
        mesh: Outline,
        /// Default "inside".
        #[serde(default)]
        solid: Side,
        /// Default 3.
        #[serde(default = "default_layers")]
        layers: u32,
        #[serde(default)]
        remove_at: Option<f64>,
        #[serde(default)]
        motion: Option<Motion>,
        #[serde(default)]
        floating: Option<Floating>,
    },
    /// 2D: the same along a closed polygon, or (`solid` = "left" or "right") along an open
    /// line through the points in their order.
    Polygon {
        polygon: Outline,
        /// Default "inside".
        #[serde(default)]
        solid: Side,
        /// Default 3.
        #[serde(default = "default_layers")]
        layers: u32,
        #[serde(default)]
        remove_at: Option<f64>,
        #[serde(default)]
        motion: Option<Motion>,
        #[serde(default)]
        floating: Option<Floating>,
    },
    /// Rings of boundary particles inward from `radius` (a cylinder along z in 3D).
    Cylinder {
        center: Vec<f64>,
        radius: f64,
        /// Default 3.
        #[serde(default = "default_layers")]
        layers: u32,
        #[serde(default)]
        remove_at: Option<f64>,
        #[serde(default)]
        motion: Option<Motion>,
        #[serde(default)]
        floating: Option<Floating>,
    },
}

impl Wall {
    /// Rows of boundary particles outside the shape (0 for a filled box).
    pub fn layers(&self) -> u32 {
        match self {
            Wall::BoxContainer { layers, .. }
            | Wall::Cylinder { layers, .. }
            | Wall::Segment { layers, .. }
            | Wall::Mesh { layers, .. }
            | Wall::Polygon { layers, .. } => *layers,
            Wall::Box { .. } => 0,
        }
    }
    pub fn remove_at(&self) -> Option<f64> {
        match self {
            Wall::BoxContainer { remove_at, .. }
            | Wall::Box { remove_at, .. }
            | Wall::Cylinder { remove_at, .. }
            | Wall::Segment { remove_at, .. }
            | Wall::Mesh { remove_at, .. }
            | Wall::Polygon { remove_at, .. } => *remove_at,
        }
    }
    /// The prescribed motion of a driven wall (a piston, a flap, a tank), if any.
    pub fn motion(&self) -> Option<&Motion> {
        match self {
            Wall::BoxContainer { motion, .. }
            | Wall::Box { motion, .. }
            | Wall::Cylinder { motion, .. }
            | Wall::Segment { motion, .. }
            | Wall::Mesh { motion, .. }
            | Wall::Polygon { motion, .. } => motion.as_ref(),
        }
    }
    /// `motion`, to change (a run's copy renames its series file).
    pub fn motion_mut(&mut self) -> Option<&mut Motion> {
        match self {
            Wall::BoxContainer { motion, .. }
            | Wall::Box { motion, .. }
            | Wall::Cylinder { motion, .. }
            | Wall::Segment { motion, .. }
            | Wall::Mesh { motion, .. }
            | Wall::Polygon { motion, .. } => motion.as_mut(),
        }
    }
    /// The rigid body a floating wall is, if it floats.
    pub fn floating(&self) -> Option<&Floating> {
        match self {
            Wall::Box { floating, .. }
            | Wall::Cylinder { floating, .. }
            | Wall::Mesh { floating, .. }
            | Wall::Polygon { floating, .. } => floating.as_ref(),
            Wall::BoxContainer { .. } | Wall::Segment { .. } => None,
        }
    }
    /// The surface of a mesh or polygon wall.
    pub fn outline(&self) -> Option<&Outline> {
        match self {
            Wall::Mesh { mesh: o, .. } | Wall::Polygon { polygon: o, .. } => Some(o),
            _ => None,
        }
    }
    pub fn outline_mut(&mut self) -> Option<&mut Outline> {
        match self {
            Wall::Mesh { mesh: o, .. } | Wall::Polygon { polygon: o, .. } => Some(o),
            _ => None,
        }
    }
}

/// `floating = { density = 500 }`: the wall is a rigid body moved by the fluid's force and
/// torque on its particles and by gravity (`physics::body`), its mass, centre of mass and
/// inertia those of its shape's solid (a box, a disc or a cylinder along z across the
/// domain, the inside of a mesh or polygon) at `density`, or of `mass`. Its particles are
/// the wall's rows; it meets the fluid as a moving dynamic wall.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Floating {
    /// \[M L^-d\] the body's density: its mass is density x its shape's volume (area per unit
    /// depth in 2D). Give this or `mass`.
    #[serde(default)]
    pub density: Option<f64>,
    /// \[M\] the body's mass (per unit depth in 2D), instead of `density`.
    #[serde(default)]
    pub mass: Option<f64>,
    /// The axes along which it may move. Default all of the scene's: `["x", "y"]` in 2D.
    #[serde(default)]
    pub moves: Option<Vec<Axis>>,
    /// The axes about which it may turn. Default all: `["z"]` in 2D, `["x", "y", "z"]` in 3D;
    /// `[]` holds its orientation.
    #[serde(default)]
    pub turns: Option<Vec<Axis>>,
    /// \[L/T\] its initial velocity. Default zero.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
}

fn default_layers() -> u32 {
    3
}
fn default_true() -> bool {
    true
}

/// What each output writes (`[output]`; the times are `time.output_interval`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// The particle files. Default "vtu".
    #[serde(default)]
    pub format: OutputFormat,
    /// The particle fields (`crate::solver::frame::Field`'s names). Default: position, velocity,
    /// density and pressure, and kind, group and stress where the scene needs them
    /// (`Output::fields`). Position is always written.
    #[serde(default)]
    pub fields: Option<Vec<Field>>,
    /// Count the connected fluid clusters (droplets) at each output into `clusters.csv`
    /// and summary.json's `fluid_clusters` (on the writer thread). Default false.
    #[serde(default)]
    pub clusters: bool,
    /// Measure the void metric at each output (`crate::measure::voids`: the share of the fluid
    /// region's cells of side dx with no particle, and the largest empty circle or sphere,
    /// in dx) into `voids.csv` and summary.json's `voids` (on the writer thread, from the
    /// frame). For flows that fill their domain. Default false.
    #[serde(default)]
    pub voids: bool,
    /// \[T\] simulated time between checkpoints (`checkpoint.bin`, from which `meshfree run
    /// --resume` continues). Default none: a checkpoint where the run stops (its end,
    /// `--steps`, a signal) and every 10 minutes of wall time (`run --checkpoint-every`).
    #[serde(default)]
    pub checkpoint_interval: Option<f64>,
}

/// The format of the particle files of each output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OutputFormat {
    /// VTK XML UnstructuredGrid with raw binary appended data, `particles_NNNNN.vtu` and
    /// `particles.pvd` (ParaView, the `vtk` Python module, meshio).
    #[default]
    Vtu,
    /// The same, each array zlib-compressed (smaller, slower to write).
    VtuZlib,
    /// The same, each array LZ4-compressed (VTK's `vtkLZ4DataCompressor`): larger than zlib,
    /// about twice as fast to write.
    VtuLz4,
    /// Plain text, one row per particle, `particles_NNNNN.csv` (`meshfree compare`, pandas).
    Csv,
    /// No particle files (diagnostics, monitors and probes only).
    None,
}

impl Named for OutputFormat {
    const ALL: &'static [(OutputFormat, &'static str, &'static str)] = &[
        (
            OutputFormat::Vtu,
            "vtu",
            "VTK XML with raw binary data, and particles.pvd (ParaView, vtk, meshio)",
        ),
        (
            OutputFormat::VtuZlib,
            "vtu-zlib",
            "the same, zlib-compressed: smaller, slower to write",
        ),
        (
            OutputFormat::VtuLz4,
            "vtu-lz4",
            "the same, LZ4-compressed: larger than zlib, about twice as fast to write",
        ),
        (
            OutputFormat::Csv,
            "csv",
            "plain text, one row per particle (meshfree compare, pandas)",
        ),
        (
            OutputFormat::None,
            "none",
            "no particle files: diagnostics, monitors and probes only",
        ),
    ];
}

impl Output {
    /// The fields each output writes for a scene of these `particles`: those listed, or by
    /// default position, velocity, density and pressure; `kind` where the scene has more than
    /// one kind of particle; `group` where a kind holds more than one scene object; `stress`
    /// where it has solids. `id` only where listed (and in CSV frames, which the run adds it
    /// to): each frame is in storage order, which on a GPU changes from frame to frame, so `id`
    /// is what follows a particle from one to the next (`meshfree compare` matches frames by
    /// it). Position is always written.
    pub fn fields(&self, particles: &[Particle]) -> Fields {
        let chosen = match &self.fields {
            Some(list) => Fields::of(list),
            None => {
                let mut f = Fields::of(&[Field::Velocity, Field::Density, Field::Pressure]);
                // The (kind, group) pairs, in order: one pass (particles of one object are
                // mostly stored together).
                let mut seen = std::collections::HashSet::new();
                let mut last = None;
                for p in particles {
                    if last != Some((p.kind, p.group)) {
                        last = Some((p.kind, p.group));
                        seen.insert((p.kind.code(), p.group));
                    }
                }
                let mut groups: Vec<(u8, u32)> = seen.into_iter().collect();
                groups.sort_unstable();
                if groups.windows(2).any(|w| w[0].0 != w[1].0) {
                    f = f.with(Field::Kind);
                }
                if groups.windows(2).any(|w| w[0].0 == w[1].0) {
                    f = f.with(Field::Group);
                }
                if groups.iter().any(|&(k, _)| k == Kind::Solid.code()) {
                    f = f.with(Field::Stress);
                }
                f
            }
        };
        chosen.with(Field::Position)
    }
}
