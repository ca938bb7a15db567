//! The scene file format: serde structs for TOML (`#[serde(deny_unknown_fields)]` on every
//! table, string-tagged enums in kebab-case). Defaults are documented on each field and in
//! `scenes/README` of the crate docs (`crate::scene`).
//!
//! Arrays of coordinates hold exactly `dimension` numbers; the checks are in `validate.rs`.

use serde::{Deserialize, Serialize};

/// A whole scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// 2 or 3.
    pub dimension: u32,
    /// Short name, used for the default output directory `out/<name>`.
    pub name: String,
    /// One or two sentences. Default "".
    #[serde(default)]
    pub description: String,
    /// [L/T^2] body force per unit mass, `dimension` numbers. Default zero.
    #[serde(default)]
    pub gravity: Option<Vec<f64>>,
    pub domain: Domain,
    pub discretisation: Discretisation,
    pub time: Time,
    pub fluid: FluidMaterial,
    /// Needed only when the scene has solid objects.
    #[serde(default)]
    pub solid: Option<SolidMaterial>,
    /// Lennard-Jones wall force, eq. (17). Needed only when the scene has walls.
    #[serde(default)]
    pub boundary: Option<BoundaryMaterial>,
    #[serde(default)]
    pub fluid_blocks: Vec<FluidBlock>,
    #[serde(default)]
    pub solids: Vec<SolidObject>,
    #[serde(default)]
    pub walls: Vec<Wall>,
    /// A band whose fluid moves at a set velocity (a periodic channel's driver).
    #[serde(default)]
    pub inflow: Option<Inflow>,
    /// Force monitors on wall objects (forces.csv, Strouhal number, Cd, Cl).
    #[serde(default)]
    pub monitors: Vec<Monitor>,
}

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
    /// [L] band limits along `axis`.
    pub min: f64,
    pub max: f64,
    /// [L/T] `dimension` numbers.
    pub velocity: Vec<f64>,
}

/// The force of the fluid (and solids) on one wall object, sampled every `interval`.
/// Drag along x, lift along y; coefficients F / (0.5 rho0 U^2 L^(d-1)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Monitor {
    /// Output file `<name>.csv` and key in summary.json. Default "forces".
    #[serde(default = "default_monitor_name")]
    pub name: String,
    /// Index of the wall in `[[walls]]`.
    pub wall: usize,
    /// [T] time between samples.
    pub interval: f64,
    /// [L/T] U of the coefficients and the Strouhal number.
    pub reference_velocity: f64,
    /// [L] D of the coefficients, the Strouhal number and the blockage ratio D / H.
    pub reference_length: f64,
}

fn default_monitor_name() -> String {
    "forces".into()
}

/// The simulation box. Particles leaving it on a non-periodic axis stop the run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// [L] lower corner.
    pub min: Vec<f64>,
    /// [L] upper corner.
    pub max: Vec<f64>,
    /// Per axis: wrap around. Default all false.
    #[serde(default)]
    pub periodic: Option<Vec<bool>>,
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum KernelChoice {
    /// Monaghan 1992 cubic B-spline, support 2h.
    #[default]
    CubicSpline,
    /// Wendland C2, support 2h.
    WendlandC2,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Discretisation {
    /// [L] initial particle spacing dx (also the default Lennard-Jones r0).
    pub spacing: f64,
    /// [-] h = h_factor * dx. Default 1.3.
    #[serde(default = "default_h_factor")]
    pub h_factor: f64,
    /// Default "cubic-spline".
    #[serde(default)]
    pub kernel: KernelChoice,
}

fn default_h_factor() -> f64 {
    1.3
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntegratorChoice {
    /// Semi-implicit Euler: v first, then x with the new v. The default.
    #[default]
    SymplecticEuler,
    /// The paper's forward Euler, eq. (19).
    Euler,
}

impl crate::named::Named for IntegratorChoice {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            IntegratorChoice::SymplecticEuler,
            "symplectic-euler",
            "semi-implicit Euler: v first, then x with the new v (the default)",
        ),
        (
            IntegratorChoice::Euler,
            "euler",
            "the paper's forward Euler, eq. (19)",
        ),
    ];
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Time {
    /// [T] end time.
    pub end: f64,
    /// [T] time between outputs (VTK file, CSV row).
    pub output_interval: f64,
    /// [-] Courant number of the CFL limit, eq. (19). Default 0.2.
    #[serde(default = "default_courant")]
    pub courant: f64,
    /// [T] fixed step; absent = adaptive.
    #[serde(default)]
    pub dt: Option<f64>,
    /// Default "symplectic-euler".
    #[serde(default)]
    pub integrator: IntegratorChoice,
    /// [T] the moments the paper's figures show, ascending (`meshfree render --figures`).
    /// Default none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub figures: Vec<f64>,
}

fn default_courant() -> f64 {
    0.2
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DensityForm {
    /// d rho_i / dt = rho_i sum_j m_j / rho_j v_ij . grad_i W_ij. The default.
    #[default]
    Continuity,
    /// rho_i = sum_j m_j W_ij, eq. (8), as the paper.
    Summation,
}

/// What the density diffusion (`density_diffusion`) acts on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiffusionForm {
    /// The density itself (Molteni & Colagrossi 2009). Under gravity its one-sided sums at a
    /// free surface and a wall diffuse the hydrostatic density, and water at rest moves.
    #[default]
    MolteniColagrossi,
    /// The density's departure from hydrostatics under `gravity` (Fourtakas, Dominguez,
    /// Vacondio & Rogers 2019): water at rest diffuses nothing.
    Fourtakas,
    /// The density less its linear part, read off renormalised density gradients (Antuono,
    /// Colagrossi, Marrone & Molteni 2010, the delta-SPH of Marrone et al. 2011): any linear
    /// density diffuses nothing, water at rest included, at the cost of a gradient pass.
    Antuono,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidMaterial {
    /// [M L^-d] reference density rho0.
    pub density: f64,
    /// [L/T] speed of sound c0.
    pub sound_speed: f64,
    /// [-] Tait exponent, eq. (9). Default 7.
    #[serde(default = "default_gamma")]
    pub gamma: f64,
    /// Default "continuity".
    #[serde(default)]
    pub density_form: DensityForm,
    /// [-] artificial viscosity, linear term, eq. (10). Default 0.
    #[serde(default)]
    pub alpha: f64,
    /// [-] artificial viscosity, quadratic term, eq. (10). Default 0.
    #[serde(default)]
    pub beta: f64,
    /// [L^2/T] laminar kinematic viscosity nu (Morris 1997). Default 0 = off (the paper).
    #[serde(default)]
    pub viscosity: f64,
    /// [-] XSPH epsilon, eq. (18). Default 0.
    #[serde(default)]
    pub xsph: f64,
    /// [L^(d+1) M^-1 T^-2] gamma of the fluid-fluid cohesion force of Akinci, Akinci &
    /// Teschner 2013 (droplets, surface tension). Default 0 = off (the paper).
    #[serde(default)]
    pub cohesion: f64,
    /// [-] delta of the density diffusion of Molteni & Colagrossi 2009 (continuity density
    /// only, fluid-fluid pairs), usually 0.1. Default 0 = off (the paper).
    #[serde(default)]
    pub density_diffusion: f64,
    /// What the density diffusion diffuses. Default "molteni-colagrossi".
    #[serde(default)]
    pub density_diffusion_form: DiffusionForm,
    /// [-] C of the particle shifting of Lind et al. 2012 with Sun et al. 2017's
    /// anti-clumping term (fluid particles, none at a free surface), usually 0.2: keeps the
    /// particles evenly spaced where the flow stretches them. Default 0 = off (the paper).
    #[serde(default)]
    pub shifting: f64,
    /// [M L^-d L^2/T^2] background pressure added to the equation of state (fluid and dynamic
    /// walls), for confined flows whose pressure dips below zero (wakes, vortex cores), where
    /// the fluid would otherwise tear; not for a free surface. Default 0 = off (the paper).
    #[serde(default)]
    pub background_pressure: f64,
}

fn default_gamma() -> f64 {
    7.0
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolidMaterial {
    /// [M L^-d] reference density.
    pub density: f64,
    /// [L/T] bulk sound speed: P = c^2 (rho - rho0).
    pub sound_speed: f64,
    /// [M L^-d L^2/T^2] shear modulus mu_s, eq. (12).
    pub shear_modulus: f64,
    /// [-] Gray-Monaghan-Swift artificial stress epsilon. Default 0 = off (the paper).
    #[serde(default)]
    pub artificial_stress: f64,
    /// [-] exponent n of the artificial stress. Default 4.
    #[serde(default = "default_art_n")]
    pub artificial_stress_exponent: f64,
    /// What a body exchanges with the fluid, walls and other bodies. Default `pressure`.
    #[serde(default)]
    pub interface: SolidInterface,
    /// Whether bodies and walls meet (the Lennard-Jones force, eq. (17), the dynamic walls'
    /// pressure and density sums). Default true; false: they skip each other, both ways,
    /// and a body meets only the fluid and other bodies (a gate's free end on the floor).
    #[serde(default = "default_true")]
    pub wall_contact: bool,
    /// The stress the artificial stress is taken from. Default `stress` (the whole sigma).
    #[serde(default)]
    pub artificial_stress_from: ArtStressFrom,
    /// [-] delta of the density diffusion between the particles of one body (continuity
    /// density only), in the form of Antuono et al. 2010 that leaves a linear density alone:
    /// damps a particle-scale (odd-even) pressure mode, not a bending. Default 0 = off (the
    /// paper).
    #[serde(default)]
    pub density_diffusion: f64,
}

/// The stress whose principal tensions give the artificial stress R (Gray, Monaghan & Swift
/// 2001).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ArtStressFrom {
    /// The whole stress sigma = -P I + S, eq. (11): Gray et al. 2001.
    #[default]
    Stress,
    /// The deviatoric stress S alone: the pressure of the continuity density left out.
    Deviatoric,
}

/// What a pair across two objects (fluid and body, two bodies, a body and a wall) exchanges
/// in eq. (16); within one body it is always the whole stress -P I + S.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SolidInterface {
    /// The pressure part -P I only (Antoci, Gallati & Sibilla 2007: an inviscid fluid
    /// carries no shear traction; the pair force is central).
    #[default]
    Pressure,
    /// The whole stress -P I + S across every pair: the paper's eq. (16).
    Stress,
}

fn default_art_n() -> f64 {
    4.0
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WallCoupling {
    /// Dynamic walls (Crespo, Gomez-Gesteira & Dalrymple 2007): wall particles take density
    /// and pressure like fluid but do not move; they enter the pressure and viscosity sums
    /// (no leaks, no-slip), and the Lennard-Jones force acts as well.
    #[default]
    Dynamic,
    /// The paper's form: the Lennard-Jones force of eq. (17) only.
    LennardJonesOnly,
}

/// How dynamic walls enter the laminar viscosity (`[boundary] no_slip`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NoSlip {
    /// With the wall particles' own velocity (zero, or a driven wall's): the wall slips by
    /// O(dx) (docs/accuracy.md, Poiseuille).
    #[default]
    WallVelocity,
    /// Morris, Fox & Zhu 1997: for the viscous term only, wall particle B takes the velocity
    /// v_w - (d_B / d_A) (v_A - v_w) extrapolated across the wall surface from fluid
    /// particle A (d = distance from the surface), with beta = 1 + d_B / d_A capped at
    /// `no_slip_beta_max`. Needs `fluid.viscosity` > 0 and dynamic walls.
    Morris,
}

pub(crate) fn default_beta_max() -> f64 {
    1.5
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryMaterial {
    /// [L/T^2] C0 of eq. (17).
    pub strength: f64,
    /// [L] r0 of eq. (17). Default: the spacing.
    #[serde(default)]
    pub r0: Option<f64>,
    /// Default 12.
    #[serde(default = "default_p1")]
    pub p1: i32,
    /// Default 6.
    #[serde(default = "default_p2")]
    pub p2: i32,
    /// true: the force also attracts beyond r0 (up to the support). Default false.
    #[serde(default)]
    pub attractive: bool,
    /// Default "dynamic".
    #[serde(default)]
    pub wall_coupling: WallCoupling,
    /// Default "wall-velocity"; "morris": the extrapolated wall velocity of Morris, Fox &
    /// Zhu 1997 in the laminar viscosity.
    #[serde(default)]
    pub no_slip: NoSlip,
    /// [-] Cap of Morris's beta = 1 + d_B / d_A. Default 1.5 (Morris et al. 1997), which
    /// binds on the first fluid row of a lattice (d_A = dx/2); 4 does not within the
    /// support (docs/accuracy.md, Poiseuille). The viscous step limit does not count beta.
    #[serde(default = "default_beta_max")]
    pub no_slip_beta_max: f64,
    /// true: dynamic wall particles within a kernel support (2h) of a `hydrostatic` fluid
    /// block start at its column's pressure at their own depth (eq. (9) for their density),
    /// so still water starts in equilibrium with its walls. For water that stays; where the
    /// water leaves a wall (a dam break) the wall keeps that pressure, since the continuity
    /// density of a wall changes only with the fluid's motion (the dam break's full tier blew
    /// up at dx = 0.01 with it, docs/accuracy.md). Default false: walls start at rho0, p = 0.
    #[serde(default)]
    pub hydrostatic_walls: bool,
    /// true: a dynamic wall particle's continuity density never falls below rho0 (the DBC
    /// of DualSPHysics, Crespo et al. 2007; Dominguez et al. 2022). Unclamped, a wall the
    /// water runs off keeps the dilatation it read (a dam break's floor and back wall fell
    /// to 0.73 rho0, p = -2.5e5 Pa): it pulls on nothing (`wall_pair_stress`), but it is
    /// soft to the water that comes back until that has compressed it by a quarter, and
    /// the column rang with particle-scale pressure noise (docs/accuracy.md, dam break).
    /// Default false (results of the other cases unchanged); on in the dam-break case.
    #[serde(default)]
    pub wall_density_floor: bool,
}

fn default_p1() -> i32 {
    12
}
fn default_p2() -> i32 {
    6
}

/// A block of fluid particles on the lattice min + (i + 0.5) dx.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidBlock {
    pub min: Vec<f64>,
    pub max: Vec<f64>,
    /// [L/T] initial velocity. Default zero.
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    /// Initial pressure and density from the Tait EOS with a hydrostatic column measured
    /// from the block's top (along -gravity), eq. (9); with `[boundary] hydrostatic_walls`
    /// the dynamic walls that hold it too. Default false.
    #[serde(default)]
    pub hydrostatic: bool,
}

/// An elastic body. `shape` picks the variant; the other keys belong to that shape.
/// `motion` [L/T] makes it driven: every particle moves at that velocity whatever the
/// forces (a clamp with zero); at most one driven object (solid or wall) per scene. A
/// driven body is its own group: it touches another body through the pressure and stress
/// terms but is not elastically bonded to it (the velocity gradient, eq. (15), stays within
/// a body).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SolidObject {
    Box {
        min: Vec<f64>,
        max: Vec<f64>,
        #[serde(default)]
        velocity: Option<Vec<f64>>,
        #[serde(default)]
        motion: Option<Vec<f64>>,
    },
    /// 2D only.
    Disc {
        center: Vec<f64>,
        radius: f64,
        #[serde(default)]
        velocity: Option<Vec<f64>>,
        #[serde(default)]
        motion: Option<Vec<f64>>,
    },
    /// 3D only.
    Sphere {
        center: Vec<f64>,
        radius: f64,
        #[serde(default)]
        velocity: Option<Vec<f64>>,
        #[serde(default)]
        motion: Option<Vec<f64>>,
    },
}

impl SolidObject {
    pub fn velocity(&self) -> Option<&Vec<f64>> {
        match self {
            SolidObject::Box { velocity, .. }
            | SolidObject::Disc { velocity, .. }
            | SolidObject::Sphere { velocity, .. } => velocity.as_ref(),
        }
    }
    /// [L/T] the prescribed velocity of a driven body (a clamp: zero), if any.
    pub fn motion(&self) -> Option<&Vec<f64>> {
        match self {
            SolidObject::Box { motion, .. }
            | SolidObject::Disc { motion, .. }
            | SolidObject::Sphere { motion, .. } => motion.as_ref(),
        }
    }
}

/// Fixed boundary particles. Any wall may be a gate, removed at `remove_at`, or driven:
/// `motion` [L/T] moves all its particles at that velocity (a piston); at most one driven
/// object (solid or wall) per scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Wall {
    /// `layers` rows of boundary particles just outside the box [min, max], at
    /// min - (k + 0.5) dx and max + (k + 0.5) dx; no rows above max[1] when `open_top`.
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
        motion: Option<Vec<f64>>,
    },
    /// A filled box of boundary particles (obstacle or gate).
    Box {
        min: Vec<f64>,
        max: Vec<f64>,
        #[serde(default)]
        remove_at: Option<f64>,
        #[serde(default)]
        motion: Option<Vec<f64>>,
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
        motion: Option<Vec<f64>>,
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
        motion: Option<Vec<f64>>,
    },
}

impl Wall {
    /// Rows of boundary particles outside the shape (0 for a filled box).
    pub fn layers(&self) -> u32 {
        match self {
            Wall::BoxContainer { layers, .. }
            | Wall::Cylinder { layers, .. }
            | Wall::Segment { layers, .. } => *layers,
            Wall::Box { .. } => 0,
        }
    }
    pub fn remove_at(&self) -> Option<f64> {
        match self {
            Wall::BoxContainer { remove_at, .. }
            | Wall::Box { remove_at, .. }
            | Wall::Cylinder { remove_at, .. }
            | Wall::Segment { remove_at, .. } => *remove_at,
        }
    }
    /// [L/T] the prescribed velocity of a driven wall (a piston), if any.
    pub fn motion(&self) -> Option<&Vec<f64>> {
        match self {
            Wall::BoxContainer { motion, .. }
            | Wall::Box { motion, .. }
            | Wall::Cylinder { motion, .. }
            | Wall::Segment { motion, .. } => motion.as_ref(),
        }
    }
}

fn default_layers() -> u32 {
    3
}
fn default_true() -> bool {
    true
}
