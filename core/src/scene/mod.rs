//! Scenes: TOML files (or the built-ins in `scenes/*.toml`) that describe a simulation.
//!
//! ```toml
//! dimension = 2                      # 2 or 3, first
//! name = "my-scene"                  # output goes to out/<name> by default
//! description = "..."                # optional
//! gravity = [0.0, -9.81]             # optional, default zero; `dimension` numbers
//!
//! [domain]                           # particles leaving it on a closed axis stop the run
//! min = [-0.1, -0.1]
//! max = [4.1, 2.6]
//! periodic = [false, false]          # optional; a periodic axis needs >= 3 cells of 2h
//!
//! [discretisation]
//! spacing = 0.02                     # dx; also the default Lennard-Jones r0
//! h_factor = 1.3                     # default 1.3: h = h_factor * dx
//! kernel = "cubic-spline"            # default | "wendland-c2"
//!
//! [time]
//! end = 2.0
//! output_interval = 0.02
//! courant = 0.2                      # default 0.2
//! # dt = 1e-4                        # optional fixed step (default adaptive)
//! integrator = "symplectic-euler"    # default | "euler" (the paper's forward Euler)
//! figures = [1.0, 2.0]               # optional: moments for `meshfree render --figures`
//!
//! [fluid]
//! density = 1000.0                   # rho0
//! sound_speed = 45.0                 # c0
//! gamma = 7.0                        # default 7, eq. (9)
//! density_form = "continuity"        # default | "summation" (eq. 8)
//! alpha = 0.02                       # default 0, eq. (10)
//! beta = 0.0                         # default 0, eq. (10)
//! viscosity = 0.0                    # nu, default 0 = off
//! xsph = 0.5                         # default 0, eq. (18)
//! cohesion = 0.0                     # gamma, default 0 = off: Akinci et al. 2013 fluid cohesion
//! density_diffusion = 0.1            # default 0 = off; delta-SPH (Molteni & Colagrossi 2009), continuity only
//! density_diffusion_form = "fourtakas" # default "molteni-colagrossi"; "fourtakas": diffuse only the
//!                                    # departure from hydrostatics (Fourtakas et al. 2019); "antuono":
//!                                    # only the departure from a linear density (Antuono et al. 2010)
//! shifting = 0.2                     # default 0 = off; particle shifting (Lind et al. 2012, Sun et al. 2017)
//! background_pressure = 0.0          # default 0 = off; added to eq. (9): confined flows only, no free surface
//!
//! [solid]                            # only with solid objects
//! density = 600.0
//! sound_speed = 40.0                 # P = c^2 (rho - rho0)
//! shear_modulus = 1e5                # mu_s, eq. (12)
//! artificial_stress = 0.0            # default 0 = off (the paper)
//! artificial_stress_exponent = 4.0   # default 4
//! interface = "pressure"             # default: the body meets fluid, walls and other
//!                                    # bodies through pressure only (Antoci et al. 2007) |
//!                                    # "stress": its whole stress, the paper's eq. (16)
//! wall_contact = true                # default: bodies and walls meet (eq. (17), the
//!                                    # dynamic walls' pressure and density) | false: they
//!                                    # skip each other, both ways; a body meets only the
//!                                    # fluid and other bodies (a gate's free end on the floor)
//! artificial_stress_from = "stress"  # default: R from sigma = -P I + S (Gray et al. 2001) |
//!                                    # "deviatoric": from S alone (docs/accuracy.md, plate)
//! density_diffusion = 0.02           # default 0 = off; delta-SPH inside each body (Antuono et al.
//!                                    # 2010's form: leaves a bending alone), continuity only
//!
//! [boundary]                         # only with walls; eq. (17)
//! strength = 2500.0                  # C0
//! r0 = 0.02                          # default: spacing
//! p1 = 12                            # default 12
//! p2 = 6                             # default 6
//! attractive = false                 # default false
//! wall_coupling = "dynamic"          # default | "lennard-jones-only" (the paper)
//! no_slip = "wall-velocity"          # default: walls enter the laminar viscosity with their
//!                                    # own velocity | "morris": extrapolated across the wall
//!                                    # surface (Morris, Fox & Zhu 1997; dynamic walls, nu > 0)
//! no_slip_beta_max = 1.5             # default 1.5: cap of Morris's 1 + d_B / d_A
//! wall_density_floor = false         # default false; true: dynamic walls' density >= rho0
//!                                    # (DualSPHysics' DBC; docs/accuracy.md, dam break)
//!
//! [[fluid_blocks]]
//! min = [0.0, 0.0]
//! max = [1.0, 1.0]
//! velocity = [0.0, 0.0]              # default zero
//! hydrostatic = true                 # default false
//!
//! [[solids]]
//! shape = "disc"                     # "box" {min, max} | "disc" (2D) | "sphere" (3D) {center, radius}
//! center = [2.0, 1.5]
//! radius = 0.2
//! velocity = [0.0, 0.0]              # default zero
//! # motion = [0.0, 0.0]              # optional: driven, moves at this velocity: a clamp,
//! #                                  # bonded to every solid it touches (stress passes into
//! #                                  # the body it holds; a box clamp must sit on the
//! #                                  # lattice of a box it touches: min differs by k dx)
//!
//! [[walls]]
//! shape = "box-container"            # | "box" {min, max} | "cylinder" {center, radius, layers}
//!                                    # | "segment" (2D) {from, to, layers}: rows on the left
//!                                    #   of from -> to; fluid behind it is not generated
//! min = [0.0, 0.0]
//! max = [4.0, 2.0]
//! layers = 3                         # default 3
//! open_top = true                    # default true
//! remove_at = 0.5                    # optional: a gate, removed at this time
//! # motion = [20.0, 0.0]             # optional: driven (a piston), moves at this velocity;
//! #                                  # at most one driven object (wall or solid) per scene
//!
//! [inflow]                           # optional: fluid in the band moves at `velocity`
//! axis = "x"                         # "x" | "y" | "z" (within dimension)
//! min = 0.0                          # band: min <= x[axis] < max, inside the domain
//! max = 1.0
//! velocity = [15.0, 0.0]             # set every step instead of integrated
//!
//! [[monitors]]                       # optional: force of the fluid on a wall object
//! name = "forces"                    # default "forces": writes forces.csv
//! wall = 0                           # index in [[walls]]
//! interval = 0.02                    # time between samples
//! reference_velocity = 15.0          # U: Cd = Fx / (0.5 rho0 U^2 D^(d-1)), St = f D / U
//! reference_length = 2.0             # D; blockage ratio D / (domain extent along y)
//! ```
//!
//! See `generate.rs` for how shapes become particles and how overlaps are resolved.

mod error;
pub mod format;
mod generate;
pub mod paper_exact;
mod validate;

use std::path::{Path, PathBuf};

pub use error::SceneError;
pub use format::SceneFile;

use crate::params::{
    self, SphParams, MF_DIFFUSION_ANTUONO, MF_DIFFUSION_FOURTAKAS, MF_DIFFUSION_MOLTENI,
};
use crate::particle::{Kind, Particle};
use crate::solver::Setup;

/// The built-in scenes: (name, TOML text). The files in `scenes/` are these.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "dam-break-2d",
        include_str!("../../../scenes/dam-break-2d.toml"),
    ),
    (
        "dam-break-3d",
        include_str!("../../../scenes/dam-break-3d.toml"),
    ),
    (
        "impinging-2d",
        include_str!("../../../scenes/impinging-2d.toml"),
    ),
    (
        "impinging-3d",
        include_str!("../../../scenes/impinging-3d.toml"),
    ),
    ("nozzle", include_str!("../../../scenes/nozzle.toml")),
    ("tank-2d", include_str!("../../../scenes/tank-2d.toml")),
    ("tank-3d", include_str!("../../../scenes/tank-3d.toml")),
    (
        "vortex-street-re105",
        include_str!("../../../scenes/vortex-street-re105.toml"),
    ),
    (
        "vortex-street-re140",
        include_str!("../../../scenes/vortex-street-re140.toml"),
    ),
];

/// Names of the built-in scenes.
pub fn builtin_names() -> Vec<&'static str> {
    BUILTIN.iter().map(|(n, _)| *n).collect()
}

/// Where a scene came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneSource {
    File(PathBuf),
    Builtin(String),
    /// `Scene::from_toml` with a caller-chosen origin.
    Text(String),
}

impl std::fmt::Display for SceneSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SceneSource::File(p) => write!(f, "{}", p.display()),
            SceneSource::Builtin(n) => write!(f, "builtin:{n}"),
            SceneSource::Text(o) => write!(f, "{o}"),
        }
    }
}

/// Particle numbers by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Counts {
    pub fluid: usize,
    pub solid: usize,
    pub boundary: usize,
    pub total: usize,
}

impl Counts {
    pub fn of(particles: &[Particle]) -> Counts {
        let mut c = Counts::default();
        for p in particles {
            match p.kind {
                Kind::Fluid => c.fluid += 1,
                Kind::Solid => c.solid += 1,
                Kind::Boundary => c.boundary += 1,
            }
        }
        c.total = particles.len();
        c
    }
}

/// A parsed and validated scene. `file` may be edited (e.g. `file.time.end`); call
/// `revalidate` afterwards, or use `with_overrides`.
#[derive(Clone, Debug)]
pub struct Scene {
    pub file: SceneFile,
    pub source: SceneSource,
    /// The TOML text it was read from.
    pub text: String,
}

/// Values the command line may override.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overrides {
    pub t_end: Option<f64>,
    pub output_interval: Option<f64>,
}

impl Scene {
    /// Read and validate a scene file.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError::Io {
            origin: origin.clone(),
            reason: format!("cannot read the file: {e}"),
        })?;
        let mut scene = Scene::from_toml(&text, &origin)?;
        scene.source = SceneSource::File(path.to_path_buf());
        Ok(scene)
    }

    /// Parse and validate TOML text; `origin` names it in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Scene, SceneError> {
        let de = toml::Deserializer::new(text);
        let file: SceneFile = serde_path_to_error::deserialize(de)
            .map_err(|e| SceneError::from_toml(origin, text, e))?;
        validate::validate(&file, origin)?;
        Ok(Scene {
            file,
            source: SceneSource::Text(origin.to_string()),
            text: text.to_string(),
        })
    }

    /// A built-in scene by name (see `builtin_names`).
    pub fn builtin(name: &str) -> Result<Scene, SceneError> {
        let (n, text) =
            BUILTIN
                .iter()
                .find(|(n, _)| *n == name)
                .ok_or_else(|| SceneError::UnknownBuiltin {
                    name: name.to_string(),
                    known: builtin_names().join(", "),
                })?;
        let mut scene = Scene::from_toml(text, &format!("builtin:{n}"))?;
        scene.source = SceneSource::Builtin(n.to_string());
        Ok(scene)
    }

    /// A path to an existing file, else a built-in name.
    pub fn load(name_or_path: &str) -> Result<Scene, SceneError> {
        let path = Path::new(name_or_path);
        if path.is_file() || name_or_path.ends_with(".toml") || name_or_path.contains(['/', '\\']) {
            Scene::from_file(path)
        } else {
            Scene::builtin(name_or_path)
        }
    }

    pub fn name(&self) -> &str {
        &self.file.name
    }

    /// The origin as errors name it: the file path or `builtin:<name>`.
    pub fn origin(&self) -> String {
        self.source.to_string()
    }

    /// Check `file` again (after editing it).
    pub fn revalidate(&self) -> Result<(), SceneError> {
        validate::validate(&self.file, &self.origin())
    }

    /// A copy with the end time and output interval replaced where given, validated.
    pub fn with_overrides(&self, o: &Overrides) -> Result<Scene, SceneError> {
        let mut s = self.clone();
        if let Some(t) = o.t_end {
            s.file.time.end = t;
        }
        if let Some(t) = o.output_interval {
            s.file.time.output_interval = t;
        }
        s.revalidate()?;
        Ok(s)
    }

    /// A copy at another particle spacing [L], validated: the Lennard-Jones strength C0
    /// scales with 1/r0 (it is 5 g H / r0 in the built-ins), an explicit r0 with the
    /// spacing, and the domain grows by the thicker wall layers on its non-periodic axes.
    pub fn with_spacing(&self, spacing: f64) -> Result<Scene, SceneError> {
        let mut s = self.clone();
        let old = s.file.discretisation.spacing;
        s.file.discretisation.spacing = spacing;
        if let Some(b) = s.file.boundary.as_mut() {
            b.strength *= old / spacing;
            if let Some(r0) = b.r0.as_mut() {
                *r0 *= spacing / old;
            }
        }
        let layers = s.file.walls.iter().map(|w| w.layers()).max().unwrap_or(0) as f64;
        let grow = (layers * (spacing - old)).max(0.0);
        // Periodic axes keep their length: the lattice must still wrap without a seam.
        let periodic = s.file.domain.periodic.clone().unwrap_or_default();
        for a in 0..s.file.domain.min.len() {
            if !periodic.get(a).copied().unwrap_or(false) {
                s.file.domain.min[a] -= grow;
                s.file.domain.max[a] += grow;
            }
        }
        s.revalidate()?;
        Ok(s)
    }

    /// The parameter struct: every primary field from the scene, then `params::derive`.
    pub fn params(&self) -> SphParams {
        scene_params(&self.file)
    }

    /// The particles, ordered by id (see `generate.rs`).
    pub fn particles(&self) -> Vec<Particle> {
        generate::generate(&self.file)
    }

    /// Parameters and particles for `backend::create`. Errors when the scene yields no
    /// particle or no fluid/solid particle.
    pub fn setup(&self) -> Result<Setup, SceneError> {
        let particles = self.particles();
        let counts = Counts::of(&particles);
        if counts.fluid + counts.solid == 0 {
            return Err(SceneError::Invalid {
                origin: self.origin(),
                field: "fluid_blocks".into(),
                reason: format!(
                    "the scene generates no fluid or solid particle ({} boundary particles): objects \
                     smaller than the spacing, or covered by walls?",
                    counts.boundary
                ),
            });
        }
        let mut params = self.params();
        // The wall surface for Morris et al.'s no-slip walls: per boundary particle only.
        let wall_surface = if params.no_slip as u32 == params::MF_NO_SLIP_WALL_VELOCITY {
            Vec::new()
        } else {
            let (first, surface) = generate::wall_surface(&self.file, &particles);
            params.wall_first_id = first;
            surface
        };
        Ok(Setup {
            params,
            particles,
            wall_surface,
        })
    }

    /// The particle group of wall `index` of `[[walls]]` (groups number the objects in the
    /// order fluid_blocks, solids, walls).
    pub fn wall_group(&self, index: usize) -> u32 {
        (self.file.fluid_blocks.len() + self.file.solids.len() + index) as u32
    }

    /// Gates: (group, removal time), in removal order.
    pub fn gates(&self) -> Vec<(u32, f64)> {
        let base = self.wall_group(0);
        let mut g: Vec<(u32, f64)> = self
            .file
            .walls
            .iter()
            .enumerate()
            .filter_map(|(i, w)| w.remove_at().map(|t| (base + i as u32, t)))
            .collect();
        g.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        g
    }
}

/// The driven object (a `motion` on a solid or a wall; validation allows one): its group
/// id and prescribed velocity [L/T].
pub(crate) fn driven_object(s: &SceneFile) -> Option<(u32, &Vec<f64>)> {
    let n_fluid = s.fluid_blocks.len();
    let solids = s
        .solids
        .iter()
        .enumerate()
        .filter_map(|(i, o)| o.motion().map(|m| ((n_fluid + i) as u32, m)));
    let base = n_fluid + s.solids.len();
    let walls = s
        .walls
        .iter()
        .enumerate()
        .filter_map(|(i, w)| w.motion().map(|m| ((base + i) as u32, m)));
    solids.chain(walls).next()
}

fn scene_params(s: &SceneFile) -> SphParams {
    use format::*;
    let dim = s.dimension as usize;
    let dx = s.discretisation.spacing;
    let mut p = SphParams {
        dim: s.dimension as i32,
        ..Default::default()
    };
    for a in 0..3 {
        if a < dim {
            p.domain_min[a] = s.domain.min[a] as f32;
            p.domain_max[a] = s.domain.max[a] as f32;
            p.periodic[a] = s.domain.periodic.as_ref().map(|v| v[a] as i32).unwrap_or(0);
            p.gravity[a] = s.gravity.as_ref().map(|g| g[a] as f32).unwrap_or(0.0);
        } else {
            // A 2D scene: a thin slab around z = 0.
            p.domain_min[a] = -dx as f32;
            p.domain_max[a] = dx as f32;
        }
    }
    p.kernel = match s.discretisation.kernel {
        KernelChoice::CubicSpline => params::MF_KERNEL_CUBIC_SPLINE,
        KernelChoice::WendlandC2 => params::MF_KERNEL_WENDLAND_C2,
    } as i32;
    p.dx = dx as f32;
    p.h = (s.discretisation.h_factor * dx) as f32;

    let f = &s.fluid;
    p.density_mode = match f.density_form {
        DensityForm::Continuity => params::MF_DENSITY_CONTINUITY,
        DensityForm::Summation => params::MF_DENSITY_SUMMATION,
    } as i32;
    p.rho0 = f.density as f32;
    p.c0 = f.sound_speed as f32;
    p.tait_gamma = f.gamma as f32;
    p.alpha = f.alpha as f32;
    p.beta = f.beta as f32;
    p.nu = f.viscosity as f32;
    p.xsph_eps = f.xsph as f32;
    p.cohesion = f.cohesion as f32;
    p.delta_sph = f.density_diffusion as f32;
    p.delta_form = match f.density_diffusion_form {
        format::DiffusionForm::MolteniColagrossi => MF_DIFFUSION_MOLTENI,
        format::DiffusionForm::Fourtakas => MF_DIFFUSION_FOURTAKAS,
        format::DiffusionForm::Antuono => MF_DIFFUSION_ANTUONO,
    } as i32;
    p.shifting = f.shifting as f32;
    p.p_background = f.background_pressure as f32;

    // Without solids the solid fields mirror the fluid's, so nothing divides by zero.
    match &s.solid {
        Some(m) => {
            p.solid_rho0 = m.density as f32;
            p.solid_c0 = m.sound_speed as f32;
            p.shear_modulus = m.shear_modulus as f32;
            p.art_stress_eps = m.artificial_stress as f32;
            p.solid_delta_sph = m.density_diffusion as f32;
            p.art_stress_n = m.artificial_stress_exponent as f32;
            p.interface_stress = (m.interface == SolidInterface::Stress) as i32;
            p.solid_skips_walls = (!m.wall_contact) as i32;
            p.art_stress_deviatoric =
                (m.artificial_stress_from == ArtStressFrom::Deviatoric) as i32;
        }
        None => {
            p.solid_rho0 = p.rho0;
            p.solid_c0 = p.c0;
            p.shear_modulus = 0.0;
            p.art_stress_eps = 0.0;
            p.art_stress_n = 4.0;
            p.interface_stress = 0;
            p.solid_skips_walls = 0;
        }
    }

    match &s.boundary {
        Some(b) => {
            p.lj_c0 = b.strength as f32;
            p.lj_r0 = b.r0.unwrap_or(dx) as f32;
            p.lj_p1 = b.p1;
            p.lj_p2 = b.p2;
            p.lj_attractive = b.attractive as i32;
            p.wall_pressure = (b.wall_coupling == WallCoupling::Dynamic) as i32;
            p.no_slip = match b.no_slip {
                NoSlip::WallVelocity => params::MF_NO_SLIP_WALL_VELOCITY,
                NoSlip::Morris => params::MF_NO_SLIP_MORRIS,
            } as i32;
            p.no_slip_beta_max = b.no_slip_beta_max as f32;
            p.wall_rho_floor = b.wall_density_floor as i32;
        }
        None => {
            p.lj_c0 = 0.0;
            p.lj_r0 = dx as f32;
            p.lj_p1 = 12;
            p.lj_p2 = 6;
            p.lj_attractive = 0;
            p.wall_pressure = 1;
            p.no_slip = params::MF_NO_SLIP_WALL_VELOCITY as i32;
            p.no_slip_beta_max = default_beta_max() as f32;
            p.wall_rho_floor = 0;
        }
    }

    if let Some(b) = &s.inflow {
        p.inflow = 1;
        p.inflow_axis = b.axis.index() as i32;
        p.inflow_lo = b.min as f32;
        p.inflow_hi = b.max as f32;
        for (o, v) in p.inflow_velocity.iter_mut().zip(&b.velocity) {
            *o = *v as f32;
        }
    }

    p.integrator = match s.time.integrator {
        IntegratorChoice::SymplecticEuler => params::MF_INTEGRATOR_SYMPLECTIC_EULER,
        IntegratorChoice::Euler => params::MF_INTEGRATOR_EULER,
    } as i32;
    p.courant = s.time.courant as f32;
    p.dt_fixed = s.time.dt.unwrap_or(0.0) as f32;
    if let Some((group, motion)) = driven_object(s) {
        p.driven = 1;
        p.driven_group = group as i32;
        for (a, u) in motion.iter().enumerate() {
            p.driven_velocity[a] = *u as f32;
        }
    }
    params::derive(&mut p);
    p
}
