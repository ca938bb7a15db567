//! One declaration per physics switch: every key of the scene file's scheme tables
//! (`[discretisation]`, `[time]`, `[fluid]`, `[solid]`, `[boundary]`), each declared once
//! below with its doc and citation, type, default and the reason for it, the paper's value,
//! its validation and the `SphParams` field it becomes (in the spirit of SPlisHSPlasH's
//! `initParameters()`).
//!
//! From these declarations come: the serde structs (`deny_unknown_fields`; defaults filled
//! in from here), their validation (`validate`, called by `scene::validate`), the scene to
//! parameter conversion (`write_params`, called by `Scene::params`), the paper's own scheme
//! (`set_paper`, called by `Scene::with_paper_exact`) and the scene reference
//! `docs/reference/scene.md` (`reference::markdown`, written by `meshfree scenes
//! --reference`; a test fails when the committed file is stale).
//!
//! A *switch* selects or weights a term of the scheme: its paper value is fixed
//! (`Paper::Is`: the paper's choice, or the default where another switch's paper value
//! leaves its term out) or computed from the scene (`Paper::From`). A *value* is what the
//! scene gives whatever the scheme (materials, resolution, run control, what the paper
//! leaves open: `Paper::Scene`). `--paper-exact` sets every switch and keeps every value.
//!
//! The `SphParams` fields no key writes are listed below: `FROM_SCENE` (the scene's
//! geometry and objects), `DERIVED` (`params::derive`) and `FROM_RUN` (a decomposed run's
//! subdomain); a test checks that every field of the header is a key's, or in one of them.

mod assignment;
#[macro_use]
pub mod declare;
mod needs;
pub mod reference;

pub use assignment::Assignment;
pub use declare::{single_precision, Check, Key, KeyDefault, Paper, Param, Refusal, Rule, Table};
use needs::*;

use serde::{Deserialize, Serialize};

use crate::scene::format::{
    DampingZone, Domain, FluidBlock, Gauge, Inflow, Monitor, OpenBoundary, Output, Probe,
    SolidObject, Wall,
};

/// [-] Quadratic artificial viscosity of the paper's own scheme (`--paper-exact`), eq. (10)
/// (the paper's 0 < beta < 1).
pub const PAPER_BETA: f64 = 0.0;
/// [-] XSPH epsilon in the paper's own scheme, eq. (18) (Monaghan 1989's usual value).
pub const PAPER_XSPH: f64 = 0.5;

/// A whole scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// 2 or 3.
    pub dimension: u32,
    /// Short name; the default output directory of a built-in scene, `out/<name>` (a scene
    /// file's is `out/<file stem>`).
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
    /// Inlets and outlets: buffers that make and remove particles (an open channel).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub open_boundaries: Vec<OpenBoundary>,
    /// A sponge layer that slows the fluid (a flume's passive absorption).
    #[serde(default)]
    pub damping_zone: Option<DampingZone>,
    /// Force monitors on wall objects (forces.csv, Strouhal number, Cd, Cl).
    #[serde(default)]
    pub monitors: Vec<Monitor>,
    /// What each output writes: format, fields, cluster count.
    #[serde(default)]
    pub output: Output,
    /// Probes: pressure, velocity and density interpolated at points (probes.csv).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub probes: Vec<Probe>,
    /// Free-surface gauges along lines (gauges.csv).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub gauges: Vec<Gauge>,
}

choice! {
    /// The smoothing kernel W of eqs. (1)-(4); both have support radius 2h.
    pub enum KernelChoice {
        /// Monaghan 1992's cubic B-spline.
        CubicSpline = "cubic-spline" => MF_KERNEL_CUBIC_SPLINE,
        /// Wendland 1995's C2 function, free of the pairing instability (Dehnen & Aly 2012).
        WendlandC2 = "wendland-c2" => MF_KERNEL_WENDLAND_C2,
    }
}

choice! {
    /// The time integrator.
    pub enum IntegratorChoice {
        /// The symplectic Euler made second order (a kick-drift leapfrog; the default):
        /// velocities at half steps (the first kick a half kick, then
        /// v += (dt_prev + dt) / 2 a) and the rates (continuity, XSPH, shifting, stress
        /// rate) at the drift's midpoint x + dt/2 v (a pair in the kernel's core, q below
        /// |grad W|'s peak, at x), with the same two neighbour passes a step. Stable at
        /// Courant 0.4 on the dam breaks, its default Courant number.
        Leapfrog = "leapfrog" => MF_INTEGRATOR_LEAPFROG,
        /// Semi-implicit Euler: v first, then x with the new v (first order; validated at
        /// Courant 0.2, its default Courant number; the default integrator until
        /// 2026-11-28).
        SymplecticEuler = "symplectic-euler" => MF_INTEGRATOR_SYMPLECTIC_EULER,
        /// The paper's forward Euler, eq. (19) (default Courant number 0.2).
        Euler = "euler" => MF_INTEGRATOR_EULER,
    }
}

impl IntegratorChoice {
    /// [-] The Courant number of eq. (19) a scene gets with this integrator when it sets
    /// none: the number each was validated at (docs/reference/accuracy.md).
    pub fn default_courant(self) -> f64 {
        match self {
            IntegratorChoice::Leapfrog => 0.4,
            IntegratorChoice::SymplecticEuler | IntegratorChoice::Euler => 0.2,
        }
    }
}

impl Time {
    /// [-] The Courant number of eq. (19): the scene's `courant`, else its integrator's
    /// default.
    pub fn courant_number(&self) -> f64 {
        self.courant
            .unwrap_or_else(|| self.integrator.default_courant())
    }
}

choice! {
    /// How the fluid's density is found.
    pub enum DensityForm {
        /// d rho_i / dt = rho_i sum_j m_j / rho_j v_ij . grad_i W_ij.
        Continuity = "continuity" => MF_DENSITY_CONTINUITY,
        /// rho_i = sum_j m_j W_ij, eq. (8), as the paper.
        Summation = "summation" => MF_DENSITY_SUMMATION,
    }
}

choice! {
    /// What the fluid's density diffusion (`density_diffusion`) acts on.
    pub enum DiffusionForm {
        /// The density itself (Molteni & Colagrossi 2009). Under gravity its one-sided sums
        /// at a free surface and a wall diffuse the hydrostatic density, and water at rest
        /// moves.
        MolteniColagrossi = "molteni-colagrossi" => MF_DIFFUSION_MOLTENI,
        /// The density's departure from hydrostatics under `gravity` (Fourtakas, Dominguez,
        /// Vacondio & Rogers 2019): water at rest diffuses nothing.
        Fourtakas = "fourtakas" => MF_DIFFUSION_FOURTAKAS,
        /// The density less its linear part, read off renormalised density gradients
        /// (Antuono, Colagrossi, Marrone & Molteni 2010, the delta-SPH of Marrone et al.
        /// 2011): any linear density diffuses nothing, water at rest included, at the cost
        /// of a gradient pass.
        Antuono = "antuono" => MF_DIFFUSION_ANTUONO,
    }
}

choice! {
    /// What a pair across two objects (fluid and body, two bodies, a body and a wall)
    /// exchanges in eq. (16); within one body it is always the whole stress -P I + S.
    pub enum SolidInterface {
        /// The pressure part -P I only (Antoci, Gallati & Sibilla 2007: an inviscid fluid
        /// carries no shear traction; the pair force is central).
        Pressure = "pressure" => MF_INTERFACE_PRESSURE,
        /// The whole stress -P I + S across every pair: the paper's eq. (16).
        Stress = "stress" => MF_INTERFACE_STRESS,
    }
}

choice! {
    /// What pressure an elastic body's particles present to the fluid in a fluid-body pair.
    pub enum SolidFluidPressure {
        /// The fluid's pressure extrapolated to them (Adami, Hu & Adams 2012), with its Tait
        /// density: the body's particles meet the fluid as walls do, as fluid of their
        /// volume, and take the reaction of the force they put on it.
        Extrapolated = "extrapolated" => MF_SOLID_FLUID_PRESSURE_EXTRAPOLATED,
        /// The body's own pressure c_s^2 (rho - rho0_s) from its continuity density, which
        /// sums the fluid neighbours too: the paper's.
        Own = "own" => MF_SOLID_FLUID_PRESSURE_OWN,
    }
}

choice! {
    /// The stress whose principal tensions give the artificial stress R (Gray, Monaghan &
    /// Swift 2001).
    pub enum ArtStressFrom {
        /// The whole stress sigma = -P I + S, eq. (11): Gray et al. 2001.
        Stress = "stress" => MF_ART_STRESS_FROM_STRESS,
        /// The deviatoric stress S alone: the pressure of the continuity density left out.
        Deviatoric = "deviatoric" => MF_ART_STRESS_FROM_DEVIATORIC,
    }
}

choice! {
    /// How an elastic body's stress is found.
    pub enum SolidFormulation {
        /// Updated Lagrangian: the Jaumann stress rate, eqs. (11)-(16), integrated in
        /// time, and the solid's pressure from its continuity density (the paper's).
        Jaumann = "jaumann" => MF_SOLID_JAUMANN,
        /// Total Lagrangian (O'Connor & Rogers 2021; Ganzenmueller 2015's hourglass control):
        /// the deformation gradient on the reference configuration with a corrected kernel
        /// gradient, the Saint Venant-Kirchhoff stress, mu = shear_modulus,
        /// lambda = rho c^2 - 2 mu / 3; free of the tensile instability.
        TotalLagrangian = "total-lagrangian" => MF_SOLID_TOTAL_LAGRANGIAN,
    }
}

choice! {
    /// How wall particles act on the fluid and the bodies.
    pub enum WallCoupling {
        /// Dynamic walls (Crespo, Gomez-Gesteira & Dalrymple 2007): wall particles take
        /// density and pressure like fluid but do not move; they enter the pressure and
        /// viscosity sums (no leaks, no-slip), and the Lennard-Jones force acts as well.
        Dynamic = "dynamic" => MF_WALL_COUPLING_DYNAMIC,
        /// Modified dynamic walls (English et al. 2022, Comput. Part. Mech. 9, 1-15; mDBC):
        /// as dynamic walls, but each wall particle takes its density from its ghost node,
        /// its mirror across the wall surface into the fluid, by a first-order corrected
        /// interpolation of the fluid there, extrapolated back along the normal. The fluid
        /// comes up to the wall surface (no gap of about h) and the walls read the fluid's
        /// pressure; needs every wall particle's normal (`check` says where one is missing).
        Mdbc = "mdbc" => MF_WALL_COUPLING_MDBC,
        /// The paper's form: the Lennard-Jones force of eq. (17) only.
        LennardJonesOnly = "lennard-jones-only" => MF_WALL_COUPLING_LENNARD_JONES_ONLY,
    }
}

choice! {
    /// How dynamic walls enter the laminar viscosity.
    pub enum NoSlip {
        /// With the wall particles' own velocity (zero, or a driven wall's): the wall slips
        /// by O(dx) (docs/reference/accuracy.md, Poiseuille).
        WallVelocity = "wall-velocity" => MF_NO_SLIP_WALL_VELOCITY,
        /// Morris, Fox & Zhu 1997: for the viscous term only, wall particle B takes the
        /// velocity v_w - (d_B / d_A) (v_A - v_w) extrapolated across the wall surface from
        /// fluid particle A (d = distance from the surface), with beta = 1 + d_B / d_A
        /// capped at `no_slip_beta_max`. Needs `fluid.viscosity` > 0 and dynamic walls.
        Morris = "morris" => MF_NO_SLIP_MORRIS,
    }
}

table! {
    /// `[discretisation]`: the particle lattice and the kernel.
    pub struct Discretisation at discretisation {
        /// \[L\] initial particle spacing dx (also the default Lennard-Jones r0).
        spacing: f64 {
            default: [required],
            paper: [scene "the resolution"],
            check: [Positive],
            param: [p.dx],
        },
        /// [-] h = h_factor * dx.
        h_factor: f64 {
            default: [1.3, "a support 2h = 2.6 dx: about 21 neighbours in 2D, 74 in 3D"],
            paper: [scene "the paper does not give h"],
            check: [Positive; support_within_reason, "at most 8"],
            param: [p.h = |s: &SceneFile, _: &f64| s.discretisation.h() as f32],
        },
        /// The smoothing kernel, eqs. (1)-(4).
        kernel: KernelChoice {
            default: [KernelChoice::CubicSpline, "Monaghan 1992's, the usual one for these benchmarks"],
            paper: [scene "the paper does not name its kernel"],
            check: [Any],
            param: [p.kernel],
        },
    }
}

impl Discretisation {
    /// \[L\] The smoothing length h = `h_factor` x `spacing`: the h of the kernel W(r, h),
    /// eqs. (1)-(4) (the paper's "radius of influence"); every built-in kernel's support is
    /// 2h (`kernel.rs`). The one place it is computed: the solver's `SphParams::h`, the
    /// scene's checks and estimates and `--paper-exact`'s step all take it from here.
    pub fn h(&self) -> f64 {
        self.h_factor * self.spacing
    }
}

table! {
    /// `[time]`: the run's length, its outputs and the time step.
    pub struct Time at time {
        /// \[T\] end time.
        end: f64 {
            default: [required],
            paper: [scene "run control"],
            check: [Positive],
            param: [none "the run driver"],
        },
        /// \[T\] time between outputs (VTK file, CSV row).
        output_interval: f64 {
            default: [required],
            paper: [scene "run control"],
            check: [Positive],
            param: [none "the run driver"],
        },
        /// [-] Courant number of the CFL limit, eq. (19).
        courant: Option<f64> {
            default: [absent "the integrator's own (`IntegratorChoice::default_courant`): 0.4 with the leapfrog, stable at 0.4 on every built-in scene and validate case; 0.2 with the symplectic and forward Euler schemes, where they were validated (docs/reference/accuracy.md); the force and viscous limits apply as well"],
            paper: [scene "eq. (19)'s number (unused at --paper-exact's fixed step)"],
            check: [Positive],
            param: [p.courant = |f: &SceneFile, _: &Option<f64>| f.time.courant_number() as f32],
        },
        /// \[T\] fixed time step.
        dt: Option<f64> {
            default: [absent "adaptive: the CFL limit, eq. (19), with the force and viscous limits"],
            paper: [from "0.05 h / c (`paper_exact::DT_FRACTION`), c the largest sound speed, fluid or solid: eq. (19) asks dt < h / c, and forward Euler grows every undamped oscillation (docs/reference/paper-scenes.md)"],
            check: [Positive],
            param: [p.dt = |_: &SceneFile, dt: &Option<f64>| dt.unwrap_or(0.0) as f32],
        },
        /// The time integrator.
        integrator: IntegratorChoice {
            default: [IntegratorChoice::Leapfrog, "second order, and stable at twice the symplectic Euler's step with the same two neighbour passes: every validate check the symplectic Euler passes, in half the steps (docs/reference/accuracy.md); elastic and acoustic modes grow under forward Euler at the same step (ARCHITECTURE.md)"],
            paper: [is IntegratorChoice::Euler, "eq. (19)"],
            check: [Any],
            param: [p.integrator],
        },
        /// \[T\] the moments the paper's figures show, ascending (`meshfree render
        /// --figures`); they may lie past `end` (a shortened run renders those it reaches).
        figures: Vec<f64> {
            default: [Vec::new(), "none: `render --figures` then draws five even moments"],
            paper: [scene "output"],
            check: [Any; ascending_moments, "zero or positive, ascending"],
            param: [none "meshfree render --figures"],
            serde: [skip_serializing_if = "Vec::is_empty"],
        },
    }
}

table! {
    /// `[fluid]`: the fluid's material and the terms of its scheme.
    pub struct FluidMaterial at fluid {
        /// [M L^-d] reference density rho0.
        density: f64 {
            default: [required],
            paper: [scene "a material constant"],
            check: [Positive],
            param: [p.rho0],
        },
        /// [L/T] speed of sound c0.
        sound_speed: f64 {
            default: [required],
            paper: [scene "a material constant (the paper's scenes do not give it)"],
            check: [Positive],
            param: [p.c0],
        },
        /// [-] Tait exponent gamma, eq. (9).
        gamma: f64 {
            default: [7.0, "water's (Batchelor 1967), as in eq. (9)"],
            paper: [scene "a material constant"],
            check: [Positive],
            param: [p.tait_gamma],
        },
        /// How the density is found.
        density_form: DensityForm {
            default: [DensityForm::Continuity, "the summation falls short at a free surface and a wall, where the Tait pressure then holds the surface like a skin (docs/reference/paper-scenes.md)"],
            paper: [is DensityForm::Summation, "eq. (8)"],
            check: [Any],
            param: [p.density_form],
        },
        /// [-] artificial viscosity, linear term alpha, eq. (10).
        alpha: f64 {
            default: [0.0, "no viscosity the scene does not ask for"],
            paper: [from "max(the scene's alpha, the alpha of its viscosity: nu = alpha h c / 8 in 2D, / 10 in 3D (Monaghan 2005), `paper_exact::ALPHA_MIN` = 0.3): alpha damps forward Euler's growth (docs/reference/paper-scenes.md)"],
            check: [NonNegative],
            param: [p.alpha],
        },
        /// [-] artificial viscosity, quadratic term beta, eq. (10).
        beta: f64 {
            default: [0.0, "no viscosity the scene does not ask for"],
            paper: [is PAPER_BETA, "eq. (10) (docs/reference/paper-scenes.md)"],
            check: [NonNegative],
            param: [p.beta],
        },
        /// [L^2/T] laminar kinematic viscosity nu (Morris, Fox & Zhu 1997).
        viscosity: f64 {
            default: [0.0, "off: inviscid, as the paper's eq. (7)"],
            paper: [is 0.0, "the paper has the artificial viscosity only; the scene's nu goes into alpha"],
            check: [NonNegative],
            param: [p.viscosity],
        },
        /// [-] XSPH epsilon, eq. (18).
        xsph: f64 {
            default: [0.0, "off: the velocity is the particles' own"],
            paper: [is PAPER_XSPH, "eq. (18) with Monaghan 1989's usual value; without it the paper-exact tank blows up (docs/reference/paper-scenes.md)"],
            check: [Fraction("eq. 18")],
            param: [p.xsph],
        },
        /// [L^(d+1) M^-1 T^-2] gamma of the fluid-fluid cohesion force of Akinci, Akinci &
        /// Teschner 2013 (droplets, surface tension).
        cohesion: f64 {
            default: [0.0, "off: the paper has no cohesion"],
            paper: [is 0.0, "not in the paper"],
            check: [NonNegative],
            param: [p.cohesion],
        },
        /// [-] delta of the density diffusion of Molteni & Colagrossi 2009 (continuity
        /// density only, fluid-fluid pairs), usually 0.1.
        density_diffusion: f64 {
            default: [0.0, "off: the paper has no density diffusion"],
            paper: [is 0.0, "not in the paper"],
            check: [Fraction("Molteni & Colagrossi 2009 use 0.1"); continuity_only, "with the continuity density only"],
            param: [p.density_diffusion],
        },
        /// What the density diffusion diffuses.
        density_diffusion_form: DiffusionForm {
            default: [DiffusionForm::MolteniColagrossi, "the plain form; \"fourtakas\" or \"antuono\" for water under gravity"],
            paper: [is DiffusionForm::MolteniColagrossi, "inert: the paper has no density diffusion"],
            check: [Any],
            param: [p.density_diffusion_form],
        },
        /// [-] C of the particle shifting of Lind et al. 2012 with Sun et al. 2017's
        /// anti-clumping term (fluid particles, none at a free surface), usually 0.2: keeps
        /// the particles evenly spaced where the flow stretches them.
        shifting: f64 {
            default: [0.0, "off: the paper has no shifting"],
            paper: [is 0.0, "not in the paper"],
            check: [Fraction("0.2 is the usual value; larger moves particles by more than the flow does")],
            param: [p.shifting],
        },
        /// true: the fluid-fluid pressure term of eq. (7) takes the kernel gradient
        /// renormalised (Bonet & Lok 1999; Oger et al. 2007) by the mean of the pair's
        /// matrices L = (sum_j V_j (x_j - x_i) (x) grad_i W_ij)^-T, which keeps momentum
        /// conserved; blended to the plain gradient where the particle's kernel sum
        /// sum_j V_j W_ij falls below 0.95, none below 0.7 (a free surface's top row, spray).
        /// Gravity waves then run at their linear speed: the plain gradient makes a standing
        /// wave 4-7 % fast at every resolution and damps it 2x faster (docs/journal,
        /// 2026-12-07 waves); CPU backend only for now.
        gradient_correction: bool {
            default: [false, "off: the paper's eq. (7); the CUDA backend has no correction yet"],
            paper: [is false, "eq. (7) as it stands"],
            check: [Any],
            param: [p.gradient_correction],
        },
        /// [M L^-d L^2/T^2] background pressure added to the equation of state (fluid and
        /// dynamic walls), for confined flows whose pressure dips below zero (wakes, vortex
        /// cores), where the fluid would otherwise tear; not for a free surface.
        background_pressure: f64 {
            default: [0.0, "off: a free surface needs p = 0"],
            paper: [is 0.0, "eq. (9) as it stands"],
            check: [NonNegative; below_tait_stiffness, "<= the Tait stiffness rho0 c0^2 / gamma"],
            param: [p.background_pressure],
        },
    }
}

table! {
    /// `[solid]`: the elastic bodies' material and the terms of their scheme (needed only
    /// when the scene has `[[solids]]`).
    pub struct SolidMaterial at solid (optional) {
        /// [M L^-d] reference density.
        density: f64 {
            default: [required],
            paper: [scene "a material constant"],
            check: [Positive],
            param: [p.solid_rho0],
        },
        /// [L/T] bulk sound speed: P = c^2 (rho - rho0).
        sound_speed: f64 {
            default: [required],
            paper: [scene "a material constant"],
            check: [Positive],
            param: [p.solid_c0],
        },
        /// [M L^-d L^2/T^2] shear modulus mu_s, eq. (12).
        shear_modulus: f64 {
            default: [required],
            paper: [scene "a material constant"],
            check: [NonNegative],
            param: [p.shear_modulus],
        },
        /// [-] epsilon of the artificial stress of Gray, Monaghan & Swift 2001.
        artificial_stress: f64 {
            default: [0.0, "off: the paper uses none"],
            paper: [is 0.0, "not in the paper"],
            check: [NonNegative],
            param: [p.artificial_stress],
        },
        /// [-] exponent n of the artificial stress's f_ij^n.
        artificial_stress_exponent: f64 {
            default: [4.0, "Gray, Monaghan & Swift 2001"],
            paper: [is 4.0, "inert: the paper has no artificial stress"],
            check: [Positive],
            param: [p.artificial_stress_exponent],
        },
        /// What a body exchanges with the fluid, walls and other bodies.
        interface: SolidInterface {
            default: [SolidInterface::Pressure, "the whole stress across the interface tore the impinging square apart (docs/reference/paper-scenes.md)"],
            paper: [is SolidInterface::Stress, "eq. (16)"],
            check: [Any],
            param: [p.interface],
        },
        /// What pressure a body's particles present to the fluid.
        fluid_pressure: SolidFluidPressure {
            default: [SolidFluidPressure::Own, "the paper's, for now: \"extrapolated\" keeps a body free under water running where this blows up within 0.04 s, but blows the Antoci gate up at 8 across (docs/reference/accuracy.md)"],
            paper: [is SolidFluidPressure::Own, "eqs. (7), (16) with the body's own pressure"],
            check: [Any; pressure_interface, "\"extrapolated\" with interface = \"pressure\""],
            param: [p.solid_fluid_pressure],
        },
        /// Whether bodies and walls meet (the Lennard-Jones force, eq. (17), the dynamic
        /// walls' pressure and density sums); false: they skip each other, both ways, and a
        /// body meets only the fluid and other bodies (a gate's free end on the floor).
        wall_contact: bool {
            default: [true, "bodies and walls meet, as in the paper"],
            paper: [is true, "eq. (17) between bodies and walls"],
            check: [Any; skips_walls_there_are, "false only with [[walls]]"],
            param: [p.wall_contact],
        },
        /// The stress the artificial stress is taken from.
        artificial_stress_from: ArtStressFrom {
            default: [ArtStressFrom::Stress, "Gray, Monaghan & Swift 2001"],
            paper: [is ArtStressFrom::Stress, "inert: the paper has no artificial stress"],
            check: [Any],
            param: [p.artificial_stress_from],
        },
        /// [-] delta of the density diffusion between the particles of one body (continuity
        /// density only), in the form of Antuono et al. 2010 that leaves a linear density
        /// alone: damps a particle-scale (odd-even) pressure mode, not a bending.
        density_diffusion: f64 {
            default: [0.0, "off: the paper has no density diffusion"],
            paper: [is 0.0, "not in the paper"],
            check: [Fraction("Molteni & Colagrossi 2009 use 0.1"); continuity_only, "with the continuity density only"],
            param: [p.solid_density_diffusion],
        },
        /// How a body's stress is found: the paper's Jaumann rate, or total Lagrangian
        /// (the stress from the deformation since the start; `density_diffusion` is inert
        /// there: the density is rho0 / det F).
        formulation: SolidFormulation {
            default: [SolidFormulation::Jaumann, "the paper's, for now"],
            paper: [is SolidFormulation::Jaumann, "eqs. (11)-(16)"],
            check: [Any; total_lagrangian_without_artificial_stress, "\"total-lagrangian\" with artificial_stress = 0"],
            param: [p.solid_formulation],
        },
        /// [-] alpha of Ganzenmueller 2015's hourglass control (total Lagrangian only):
        /// damps the zero-energy modes that the deformation gradient does not see.
        hourglass: f64 {
            default: [5.0, "the penalty vanishes for quadratic fields under the second-order reference gradient, so it acts on the zero-energy modes: a clamped cantilever at 9 across bends 4.2 % past the plane-strain continuum at 0.1, 1.4 % at 5; 10 blows up at 5 across"],
            paper: [is 0.1, "inert: the paper's solids are updated Lagrangian"],
            check: [NonNegative],
            param: [p.hourglass],
        },
    }
}

table! {
    /// `[boundary]`: the wall particles, eq. (17) (needed only when the scene has
    /// `[[walls]]`).
    pub struct BoundaryMaterial at boundary (optional) {
        /// [L/T^2] C0 of eq. (17).
        strength: f64 {
            default: [required],
            paper: [scene "the paper does not give C0 (5 g H / r0 in the built-ins)"],
            check: [NonNegative],
            param: [p.lj_c0],
        },
        /// \[L\] r0 of eq. (17).
        r0: Option<f64> {
            default: [absent "the spacing dx"],
            paper: [scene "the paper does not give r0"],
            check: [Positive],
            param: [p.lj_r0 = |s: &SceneFile, r0: &Option<f64>| r0.unwrap_or(s.discretisation.spacing) as f32],
        },
        /// The exponent p1 of eq. (17).
        p1: i32 {
            default: [12, "the Lennard-Jones form's (Monaghan 1994)"],
            paper: [scene "eq. (17) leaves the exponents open"],
            check: [Any; lennard_jones_exponents, "p1 > p2 > 0"],
            param: [p.lj_p1],
        },
        /// The exponent p2 of eq. (17).
        p2: i32 {
            default: [6, "the Lennard-Jones form's"],
            paper: [scene "eq. (17) leaves the exponents open"],
            check: [Any],
            param: [p.lj_p2],
        },
        /// true: the force also attracts beyond r0 (up to the support).
        attractive: bool {
            default: [false, "purely repulsive walls (Monaghan 1994)"],
            paper: [is false, "eq. (17) acts within r0 only"],
            check: [Any],
            param: [p.attractive],
        },
        /// How wall particles act on the fluid and the bodies.
        wall_coupling: WallCoupling {
            default: [WallCoupling::Dynamic, "no leaks, no-slip, and a resting tank stays at rest (Crespo et al. 2007)"],
            paper: [is WallCoupling::LennardJonesOnly, "eq. (17) alone"],
            check: [Any],
            param: [p.wall_coupling],
        },
        /// How dynamic walls enter the laminar viscosity.
        no_slip: NoSlip {
            default: [NoSlip::WallVelocity, "needs no wall surface; Morris's walls need nu > 0"],
            paper: [is NoSlip::WallVelocity, "the paper has no laminar viscosity"],
            check: [Any; morris_walls, "\"morris\" needs dynamic walls and fluid.viscosity > 0"],
            param: [p.no_slip],
        },
        /// [-] Cap of Morris's beta = 1 + d_B / d_A, which binds on the first fluid row of
        /// a lattice (d_A = dx/2); 4 does not within the support (docs/reference/accuracy.md,
        /// Poiseuille). The viscous step limit does not count beta.
        no_slip_beta_max: f64 {
            default: [1.5, "Morris, Fox & Zhu 1997"],
            paper: [is 1.5, "inert: the paper has no laminar viscosity"],
            check: [Any; beta_cap, ">= 1 with \"morris\""],
            param: [p.no_slip_beta_max],
        },
        /// true: dynamic wall particles within a kernel support (2h) of a `hydrostatic`
        /// fluid block start at its column's pressure at their own depth (eq. (9) for their
        /// density), so still water starts in equilibrium with its walls. For water that
        /// stays; where the water leaves a wall (a dam break) the wall keeps that pressure,
        /// since the continuity density of a wall changes only with the fluid's motion (the
        /// dam break's full tier blew up at dx = 0.01 with it, docs/reference/accuracy.md).
        hydrostatic_walls: bool {
            default: [false, "walls start at rho0, p = 0: walls the water leaves would keep the column's pressure"],
            paper: [is false, "inert: the paper's walls carry no pressure"],
            check: [Any],
            param: [none "the particle generator (generate.rs: wall_hydrostatic)"],
        },
        /// true: a dynamic wall particle's continuity density never falls below rho0 (the
        /// DBC of DualSPHysics, Crespo et al. 2007; Dominguez et al. 2022). Unclamped, a
        /// wall the water runs off keeps the dilatation it read (a dam break's floor and
        /// back wall fell to 0.73 rho0, p = -2.5e5 Pa): it pulls on nothing
        /// (`wall_pair_stress`), but it is soft to the water that comes back until that has
        /// compressed it by a quarter, and the column rang with particle-scale pressure
        /// noise (docs/reference/accuracy.md, dam break).
        wall_density_floor: bool {
            default: [false, "the other cases' results unchanged; on in the dam break"],
            paper: [is false, "inert: the paper's walls carry no density"],
            check: [Any],
            param: [p.wall_density_floor],
        },
    }
}

/// Every key of every scheme table, in the file's order.
pub fn keys() -> impl Iterator<Item = &'static Key> {
    TABLES.iter().flat_map(|t| t.iter())
}

/// The key of a dotted path (`fluid.density_diffusion`).
pub fn key(path: &str) -> Option<&'static Key> {
    keys().find(|k| k.path == path)
}

/// The keys of each scheme table.
pub const TABLES: &[&[Key]] = &[
    Discretisation::KEYS,
    Time::KEYS,
    FluidMaterial::KEYS,
    SolidMaterial::KEYS,
    BoundaryMaterial::KEYS,
];

/// `SphParams` fields that no key writes, set from the scene's geometry and objects by
/// `scene_params` (or `Scene::setup`): (field, where from).
pub const FROM_SCENE: &[(&str, &str)] = &[
    ("dim", "dimension"),
    ("periodic", "[domain] periodic"),
    (
        "domain_min",
        "[domain] min (a 2D scene: a slab of +-dx in z)",
    ),
    ("domain_max", "[domain] max"),
    ("gravity", "gravity"),
    ("driven", "the `motion`s of [[solids]] and [[walls]]"),
    ("driven_motion", "each object's group and `motion`"),
    ("inflow", "[inflow]"),
    ("inflow_axis", "[inflow] axis"),
    ("inflow_lo", "[inflow] min"),
    ("inflow_hi", "[inflow] max"),
    ("inflow_velocity", "[inflow] velocity"),
    ("inflow_ramp", "[inflow] ramp"),
    ("open_count", "[[open_boundaries]]"),
    (
        "open",
        "each of [[open_boundaries]]: its box, normal, velocity and groups",
    ),
    ("damping", "[damping_zone]"),
    ("damping_axis", "[damping_zone] axis"),
    ("damping_start", "[damping_zone] start"),
    ("damping_end", "[damping_zone] end"),
    ("damping_rate", "[damping_zone] strength"),
    (
        "wall_first_id",
        "Scene::setup: the first boundary particle's id",
    ),
];

/// `SphParams` fields filled by `params::derive` from the others (marked "derived" in the
/// header).
/// The `SphParams` fields the run sets, not the scene: a decomposed run's subdomain
/// (`crate::exchange`, `meshfree run --decompose`); off in one domain.
pub const FROM_RUN: &[&str] = &["own_slab", "own_axis", "own_lo", "own_hi", "own_solids"];

pub const DERIVED: &[&str] = &[
    "grid_dims",
    "n_cells",
    "cell_size",
    "support",
    "support2",
    "kernel_norm",
    "tait_b",
    "av_eta2",
    "visc_eta2",
    "inv_w_dx",
    "lj_range",
    "fluid_density_gradient",
];

/// Check every key of the scene's tables: (field, reason) of the first refusal.
pub(crate) fn validate(s: &SceneFile) -> Result<(), (String, String)> {
    for k in keys() {
        (k.validate)(s).map_err(|r| (format!("{}{}", k.path, r.at), r.reason))?;
    }
    Ok(())
}

/// Write every key's header field. A scene without solids (walls) reads as a `[solid]`
/// (`[boundary]`) of its defaults, the solid's required values mirroring the fluid's
/// density and sound speed (nothing divides by zero) with no shear modulus (no C0).
pub fn write_params(s: &SceneFile, p: &mut crate::physics::params::SphParams) {
    s.discretisation.write_params(s, p);
    s.time.write_params(s, p);
    s.fluid.write_params(s, p);
    let solid = s.solid.clone().unwrap_or_else(|| {
        with_required(&[
            ("density", s.fluid.density),
            ("sound_speed", s.fluid.sound_speed),
            ("shear_modulus", 0.0),
        ])
    });
    solid.write_params(s, p);
    let boundary = s
        .boundary
        .clone()
        .unwrap_or_else(|| with_required(&[("strength", 0.0)]));
    boundary.write_params(s, p);
}

/// A table with these required values and every other key at its default.
fn with_required<T: Table + serde::de::DeserializeOwned>(required: &[(&str, f64)]) -> T {
    let table: toml::Table = required
        .iter()
        .map(|(k, v)| (k.to_string(), toml::Value::Float(*v)))
        .collect();
    toml::Value::Table(table)
        .try_into()
        .expect("a table with its required keys")
}

/// Set every switch with a fixed paper value (`Paper::Is`) to it, in the tables the scene
/// has. The computed ones (`Paper::From`) are `Scene::with_paper_exact`'s.
pub fn set_paper(s: &mut SceneFile) {
    for k in keys() {
        if let Some(set) = k.set_paper {
            set(s);
        }
    }
}
