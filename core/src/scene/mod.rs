//! Scenes: TOML files (or the built-ins in `scenes/*.toml`) that describe a simulation.
//!
//! Every key with its default, the paper's value and its check is in
//! `docs/reference/scene.md`, generated from `crate::scene::scheme` (the scheme's tables) and
//! `format.rs` (geometry and objects) by `meshfree scenes --reference`; the built-in scenes
//! comment each value with its reason. `format.rs`: the serde structs of the geometry and
//! objects (`SceneFile` itself is `crate::scene::scheme`'s); `validate.rs`: the
//! checks serde cannot make; `motion.rs`: a driven object's `motion`, its checks and the
//! solver's form of it; `generate.rs`: how shapes become particles and how overlaps are
//! resolved (through the spatial indices of `spatial.rs`); `paper_exact.rs`: the map to the
//! paper's own scheme; `input_limits.rs`: what a file may cost to read; `estimate.rs`: its
//! size and memory before generation.

mod bodies;
mod ctx;
mod error;
pub mod estimate;
pub mod format;
mod generate;
pub mod geometry;
pub mod input_limits;
mod motion;
pub mod motion_series;
mod open;
pub mod paper_exact;
pub mod scheme;
mod spatial;
mod tagged_field;
mod validate;
mod wall_surface;
pub mod wave;
pub mod wave_spectrum;
mod zones;

use std::path::{Path, PathBuf};

pub use crate::scene::scheme::SceneFile;
pub use error::SceneError;

use crate::physics::params::{self, SphParams};
use crate::physics::particle::{Kind, Particle};
use crate::solver::Setup;

/// The built-in scenes: (name, TOML text). The files in `scenes/` are these.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "channel-open-2d",
        include_str!("../../../scenes/channel-open-2d.toml"),
    ),
    (
        "cow-dam-break-3d",
        include_str!("../../../scenes/cow-dam-break-3d.toml"),
    ),
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
    (
        "floating-box-2d",
        include_str!("../../../scenes/floating-box-2d.toml"),
    ),
    ("flume-2d", include_str!("../../../scenes/flume-2d.toml")),
    ("beach-2d", include_str!("../../../scenes/beach-2d.toml")),
    ("nozzle", include_str!("../../../scenes/nozzle.toml")),
    (
        "nozzle-open",
        include_str!("../../../scenes/nozzle-open.toml"),
    ),
    (
        "sloshing-2d",
        include_str!("../../../scenes/sloshing-2d.toml"),
    ),
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

impl Overrides {
    /// The command-line flag of each overridden scene key.
    pub const FLAGS: [(&'static str, &'static str); 2] = [
        ("time.end", "--t-end"),
        ("time.output_interval", "--output-interval"),
    ];

    /// `e`, a refusal of the scene `origin` with these overrides, as the command line's:
    /// naming the flag of the field it names, else (a check across keys, such as the step
    /// against the end time) the flag given (the first where both are).
    fn blame(&self, e: SceneError, origin: &str) -> SceneError {
        let SceneError::Invalid { field, reason, .. } = &e else {
            return e;
        };
        let given = |key: &str| match key {
            "time.end" => self.t_end.is_some(),
            _ => self.output_interval.is_some(),
        };
        let own = Self::FLAGS.iter().find(|(k, _)| k == field && given(k));
        let (key, flag) = match own.or_else(|| Self::FLAGS.iter().find(|(k, _)| given(k))) {
            Some(kf) => *kf,
            None => return e,
        };
        let reason = if field == key {
            format!("{reason} (it replaces {key} of {origin})")
        } else {
            format!("with this value, {origin}: {field}: {reason}")
        };
        SceneError::Invalid {
            origin: "command line".into(),
            field: flag.into(),
            reason,
        }
    }
}

impl Scene {
    /// Read and validate a scene file (at most `input_limits::MAX_BYTES`).
    pub fn from_file(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        let text = input_limits::read(path, &origin)?;
        let mut scene = Scene::from_toml_in(&text, &origin, &geometry::base_of(path))?;
        scene.source = SceneSource::File(path.to_path_buf());
        Ok(scene)
    }

    /// Parse and validate TOML text; `origin` names it in errors. Text that would cost far
    /// more to parse than a scene does is refused first (`input_limits`). Surface files
    /// (`mesh`, `polygon`) are read relative to the working directory.
    pub fn from_toml(text: &str, origin: &str) -> Result<Scene, SceneError> {
        Scene::from_toml_in(text, origin, &geometry::Base::Dir(PathBuf::new()))
    }

    /// `from_toml`, with surface files read from `base`.
    pub fn from_toml_in(
        text: &str,
        origin: &str,
        base: &geometry::Base,
    ) -> Result<Scene, SceneError> {
        input_limits::check(text, origin)?;
        let de = toml::Deserializer::new(text);
        let file: SceneFile = serde_path_to_error::deserialize(de)
            .map_err(|e| SceneError::from_toml(origin, text, e))?;
        geometry::load_all(&file, origin, base)?;
        motion_series::load_all(&file, origin, base)?;
        validate::validate(&file, origin)?;
        let mut file = file;
        motion_series::make_all(&mut file, origin)?;
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
        let mut scene =
            Scene::from_toml_in(text, &format!("builtin:{n}"), &geometry::Base::Builtin)?;
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

    /// A copy with the end time and output interval replaced where given, validated. A
    /// refusal is the command line's (`Overrides::FLAGS`): this scene passed before, so the
    /// flag's value is the cause (`--t-end nan`, not the file's `time.end`).
    pub fn with_overrides(&self, o: &Overrides) -> Result<Scene, SceneError> {
        let mut s = self.clone();
        if let Some(t) = o.t_end {
            s.file.time.end = t;
        }
        if let Some(t) = o.output_interval {
            s.file.time.output_interval = t;
        }
        s.revalidate().map_err(|e| o.blame(e, &self.origin()))?;
        // An irregular sea's paddle record reaches the new end.
        motion_series::make_all(&mut s.file, &self.origin())
            .map_err(|e| o.blame(e, &self.origin()))?;
        // The text says what runs: the copy a run writes holds the overrides (issue #51).
        let changed = s.file.time != self.file.time;
        if let Some(text) = changed.then(|| overridden_text(&s.text, o)).flatten() {
            s.text = text;
        }
        Ok(s)
    }

    /// A copy at another particle spacing \[L\], validated: the Lennard-Jones strength C0
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
        // The sea's components shorter than 10 spacings are left out: made again.
        motion_series::make_all(&mut s.file, &self.origin())?;
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
        // The wall surface for Morris et al.'s no-slip walls and mDBC: per boundary particle
        // only.
        let wall_surface = if !params::needs_wall_surface(&params) {
            Vec::new()
        } else {
            let (first, surface) = wall_surface::wall_surface(&self.file, &particles);
            params.wall_first_id = first;
            surface
        };
        Ok(Setup {
            params,
            particles,
            wall_surface,
            bodies: bodies::bodies(&self.file, |i| self.wall_group(i)),
            motion_series: motion_series::table(&self.file),
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

/// The driven objects (a `motion` on a solid or a wall; validation allows
/// `MF_MAX_DRIVEN`), solids first, each in the file's order: its group id and motion.
pub(crate) fn driven_objects(s: &SceneFile) -> impl Iterator<Item = (u32, &format::Motion)> {
    let n_fluid = s.fluid_blocks.len();
    let solids = s
        .solids
        .iter()
        .enumerate()
        .filter_map(move |(i, o)| o.motion().map(|m| ((n_fluid + i) as u32, m)));
    let base = n_fluid + s.solids.len();
    let walls = s
        .walls
        .iter()
        .enumerate()
        .filter_map(move |(i, w)| w.motion().map(|m| ((base + i) as u32, m)));
    solids.chain(walls)
}

/// The parameter struct of a scene: its geometry and objects here, every key of the
/// scheme's tables through `scheme::write_params`, then `params::derive`.
fn scene_params(s: &SceneFile) -> SphParams {
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
    crate::scene::scheme::write_params(s, &mut p);
    if let Some(z) = &s.damping_zone {
        p.damping = 1;
        p.damping_axis = z.axis.index() as i32;
        p.damping_start = z.start as f32;
        p.damping_end = z.end as f32;
        p.damping_rate = z.strength as f32;
    }
    if let Some(b) = &s.inflow {
        p.inflow = 1;
        p.inflow_axis = b.axis.index() as i32;
        p.inflow_lo = b.min as f32;
        p.inflow_hi = b.max as f32;
        p.inflow_ramp = b.ramp as f32;
        for (o, v) in p.inflow_velocity.iter_mut().zip(&b.velocity) {
            *o = *v as f32;
        }
    }
    open::write_params(s, &mut p);
    // Each series' knots follow the last one's in `Setup::motion_series`
    // (`motion_series::table`, in the same order).
    let mut first = 0;
    for (k, (group, motion)) in driven_objects(s).enumerate().take(p.driven_motion.len()) {
        p.driven = k as i32 + 1;
        let m = &mut p.driven_motion[k];
        *m = motion.params(group, s.dimension as usize, wave::gravity(s));
        m.series_first = first;
        first += m.series_count;
    }
    // A floating body's group is driven too, by its body (`MfMotion::floating`).
    let base = (s.fluid_blocks.len() + s.solids.len()) as i32;
    for (i, _, _) in bodies::floating_walls(s) {
        let k = p.driven as usize;
        if k < p.driven_motion.len() {
            p.driven = k as i32 + 1;
            p.driven_motion[k] = params::MfMotion {
                group: base + i as i32,
                floating: 1,
                ..Default::default()
            };
        }
    }
    params::derive(&mut p);
    p
}

/// `text` with `[time] end` and `output_interval` set to the overrides, every comment and
/// the rest of the text kept (`toml_edit`); None where the text has no `[time]` table of
/// such keys to edit (the scene keeps its text).
fn overridden_text(text: &str, o: &Overrides) -> Option<String> {
    let mut doc: toml_edit::DocumentMut = text.parse().ok()?;
    let time = doc.get_mut("time")?.as_table_like_mut()?;
    for (key, value) in [("end", o.t_end), ("output_interval", o.output_interval)] {
        let Some(value) = value else { continue };
        let item = time.get_mut(key)?.as_value_mut()?;
        let decor = item.decor().clone();
        *item = toml_edit::Value::from(value);
        *item.decor_mut() = decor;
    }
    Some(doc.to_string())
}
