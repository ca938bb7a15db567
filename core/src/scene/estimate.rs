//! How many particles a scene generates and how large its neighbour grid is, from the
//! scene file alone, in f64 and without allocating: `validate` refuses what the solver
//! cannot index, and `meshfree check` / `run` compare it with the machine's memory before
//! generating anything. The particle count is an upper bound: each object's lattice points
//! (the generator's rules, `generate.rs`), before fluid or solids that another object
//! covers are left out; `tests/scene_limits.rs` holds it against the built-in scenes.

use super::format::{SolidObject, Wall};
use crate::params::MF_CELL_REACH;
use crate::scheme::SceneFile;

/// Particle ids are u32 (`Particle::id`), one value kept for "none".
pub const MAX_PARTICLES: f64 = (u32::MAX - 1) as f64;
/// The neighbour grid's cell count is an i32 (`SphParams::n_cells`).
pub const MAX_CELLS: f64 = i32::MAX as f64;
/// [bytes] host memory per particle while a run starts: the generated `Particle`s, the
/// state's arrays and the set-up's neighbour search (the peak, measured on the 3D scenes
/// within a factor 1.5).
pub const HOST_BYTES_PER_PARTICLE: f64 = 400.0;

/// A scene's size before generation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// At most this many particles (f64: a mistyped spacing gives 1e60).
    pub particles: f64,
    /// Neighbour-grid cells (cells h wide: `params::derive`).
    pub cells: f64,
}

impl Estimate {
    /// [bytes] host memory a run needs at its start (`HOST_BYTES_PER_PARTICLE`).
    pub fn host_bytes(&self) -> f64 {
        self.particles * HOST_BYTES_PER_PARTICLE
    }
}

/// Lattice points on [0, len) at spacing dx (`generate::axis`).
fn points(len: f64, dx: f64) -> f64 {
    (len / dx + 1e-6).floor().max(0.0)
}

/// Lattice points of the box [min, max] over the first `dim` axes.
fn lattice(min: &[f64], max: &[f64], dx: f64, dim: usize) -> f64 {
    (0..dim).map(|a| points(max[a] - min[a], dx)).product()
}

/// The estimate of `s`. Meaningful for a scene whose vectors have `dimension` entries (the
/// validation checks those first).
pub fn estimate(s: &SceneFile) -> Estimate {
    let dim = s.dimension as usize;
    let dx = s.discretisation.spacing;
    let mut n = 0.0;
    for b in &s.fluid_blocks {
        n += lattice(&b.min, &b.max, dx, dim);
    }
    for o in &s.solids {
        n += match o {
            SolidObject::Box { min, max, .. } => lattice(min, max, dx, dim),
            SolidObject::Disc { radius, .. } | SolidObject::Sphere { radius, .. } => {
                points(2.0 * radius, dx).powi(dim as i32)
            }
        };
    }
    let depth = if dim == 3 {
        points(s.domain.max[2] - s.domain.min[2], dx)
    } else {
        1.0
    };
    for w in &s.walls {
        n += match w {
            Wall::BoxContainer {
                min, max, layers, ..
            } => {
                let inner: Vec<f64> = (0..dim).map(|a| points(max[a] - min[a], dx)).collect();
                let outer: f64 = inner.iter().map(|k| k + 2.0 * *layers as f64).product();
                outer - inner.iter().product::<f64>()
            }
            Wall::Box { min, max, .. } => lattice(min, max, dx, dim),
            Wall::Segment {
                from, to, layers, ..
            } => {
                let len = (to[0] - from[0]).hypot(to[1] - from[1]);
                ((len / dx).round().max(1.0)) * *layers as f64
            }
            Wall::Cylinder { radius, layers, .. } => {
                let rings = (2.0 * std::f64::consts::PI * radius / dx).round().max(1.0) + 1.0;
                rings * *layers as f64 * depth
            }
        };
    }
    let support = 2.0 * s.discretisation.h_factor * dx;
    let cells = (0..dim)
        .map(|a| {
            let len = s.domain.max[a] - s.domain.min[a];
            (len * MF_CELL_REACH as f64 / support).floor().max(1.0)
        })
        .product();
    Estimate {
        particles: n,
        cells,
    }
}

/// [bytes] the memory this machine has available now (Linux: `MemAvailable` of
/// /proc/meminfo); `None` where it cannot tell.
pub fn available_memory() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

impl super::Scene {
    /// The scene's estimate, refused (naming `discretisation.spacing`) where it exceeds
    /// `max_particles` or needs more memory at the start than the machine has available:
    /// before anything is generated.
    pub fn check_size(&self, max_particles: Option<u64>) -> Result<Estimate, super::SceneError> {
        let e = estimate(&self.file);
        let refuse = |reason: String| super::SceneError::Invalid {
            origin: self.origin(),
            field: "discretisation.spacing".into(),
            reason,
        };
        if let Some(max) = max_particles {
            if e.particles > max as f64 {
                return Err(refuse(format!(
                    "the objects would hold up to {:.3e} particles at this spacing, more than \
                     --max-particles {max}",
                    e.particles
                )));
            }
        }
        if let Some(free) = available_memory() {
            if e.host_bytes() > free {
                return Err(refuse(format!(
                    "up to {:.3e} particles need about {:.1} GB of memory to start, and this \
                     machine has {:.1} GB available: a coarser spacing, or a larger machine",
                    e.particles,
                    e.host_bytes() / 1e9,
                    free / 1e9
                )));
            }
        }
        Ok(e)
    }
}
