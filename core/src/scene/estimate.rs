//! How many particles a scene generates and how large its neighbour grid is, from the
//! scene file alone, in f64 and without allocating: `validate` refuses what the solver
//! cannot index, and `meshfree check` / `run` compare the memory both need with what this
//! process may have (`memory_limit`: the free memory, the address-space limit and the
//! cgroup's limit) before generating anything. The particle count is an upper bound: each object's lattice points
//! (the generator's rules, `generate.rs`), before fluid or solids that another object
//! covers are left out; `tests/scene_limits.rs` holds it against the built-in scenes.

use super::format::{SolidObject, Wall};
use crate::physics::params::MF_CELL_REACH;
use crate::scene::scheme::SceneFile;

/// Particle ids are u32 (`Particle::id`), one value kept for "none".
pub const MAX_PARTICLES: f64 = (u32::MAX - 1) as f64;
/// The neighbour grid's cell count is an i32 (`SphParams::n_cells`).
pub const MAX_CELLS: f64 = i32::MAX as f64;
/// \[bytes\] host memory per particle while a run starts: the generated `Particle`s, the
/// state's arrays and the set-up's neighbour search (the peak, measured on the 3D scenes
/// within a factor 1.5).
pub const HOST_BYTES_PER_PARTICLE: f64 = 400.0;
/// \[bytes\] host memory per neighbour-grid cell: the CPU backend's `Grid` (`cell_start` and
/// `cell_end`, a u32 each, `backend/cpu/grid.rs`), which force monitors also build on the
/// host under every backend (`monitor.rs`). The grid spans the whole domain, wherever the
/// particles are.
pub const HOST_BYTES_PER_CELL: f64 = 8.0;
/// \[bytes\] device memory per neighbour-grid cell under the CUDA backend: `count`, the
/// scan's `local` and `cell_start` (a u32 each) and, in 3D, the 1-byte `stamp`
/// (`backend/cuda/buffers.rs`). Allocated on the GPU, which refuses what it cannot hold.
pub const DEVICE_BYTES_PER_CELL: f64 = 13.0;
/// A grid of more cells than this, and more than `MAX_CELLS_PER_PARTICLE` per particle, is
/// refused by the validation: it costs `HOST_BYTES_PER_CELL` each (over 0.5 GB here) and
/// is cleared at every step, for particles that fill a small part of the domain.
pub const SPARSE_GRID_CELLS: f64 = (1u64 << 26) as f64;
/// See `SPARSE_GRID_CELLS`. (A domain filled with fluid has about 0.06 cells per particle
/// in 3D and 0.15 in 2D at h = 1.3 dx; 1,000 is a domain 40 times wider than its fluid on
/// every axis in 3D, 80 times in 2D.)
pub const MAX_CELLS_PER_PARTICLE: f64 = 1000.0;

/// A scene's size before generation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// At most this many particles (f64: a mistyped spacing gives 1e60).
    pub particles: f64,
    /// Neighbour-grid cells (cells h wide: `params::derive`).
    pub cells: f64,
}

impl Estimate {
    /// \[bytes\] host memory a run needs at its start: its particles
    /// (`HOST_BYTES_PER_PARTICLE`) and its neighbour grid (`HOST_BYTES_PER_CELL`).
    pub fn host_bytes(&self) -> f64 {
        self.particles * HOST_BYTES_PER_PARTICLE + self.grid_host_bytes()
    }

    /// \[bytes\] the neighbour grid's part of `host_bytes`.
    pub fn grid_host_bytes(&self) -> f64 {
        self.cells * HOST_BYTES_PER_CELL
    }

    /// \[bytes\] the neighbour grid's memory on a GPU (`DEVICE_BYTES_PER_CELL`).
    pub fn grid_device_bytes(&self) -> f64 {
        self.cells * DEVICE_BYTES_PER_CELL
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
    // A surface's box (read with the scene), or nothing where it was not read: the checks
    // refuse such a scene.
    let boxed = |o: &super::format::Outline, grow: f64| {
        o.loaded.get().map_or(0.0, |m| {
            let lo: Vec<f64> = m.info.lo.iter().map(|x| x - grow).collect();
            let hi: Vec<f64> = m.info.hi.iter().map(|x| x + grow).collect();
            lattice(&lo, &hi, dx, dim) + 1.0
        })
    };
    for b in &s.fluid_blocks {
        n += lattice(&b.min, &b.max, dx, dim);
    }
    // An inlet's buffer from the start; an outlet's fills as the fluid enters it (the fluid
    // it holds left the domain's count as much as it joined it: a bound, not the count).
    for o in &s.open_boundaries {
        n += lattice(&o.min, &o.max, dx, dim);
    }
    for o in &s.solids {
        n += match o {
            SolidObject::Box { min, max, .. } => lattice(min, max, dx, dim),
            SolidObject::Disc { radius, .. } | SolidObject::Sphere { radius, .. } => {
                points(2.0 * radius, dx).powi(dim as i32)
            }
            SolidObject::Mesh { mesh: o, .. } | SolidObject::Polygon { polygon: o, .. } => {
                boxed(o, dx)
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
            // The box of the surface with its rows (the rows of a tank fill a thin band of it:
            // a loose bound). An open surface's rows (a sea bed, a terrain) lie on one side:
            // at most twice its area times the rows' depth and a spacing, and in 2D the
            // discs at its two ends, where that is less.
            Wall::Mesh {
                mesh: o, layers, ..
            }
            | Wall::Polygon {
                polygon: o, layers, ..
            } => {
                let depth = (*layers as f64 + 1.0) * dx;
                let band = o.loaded.get().filter(|m| m.info.open).map(|m| {
                    let ends = if dim == 2 {
                        2.0 * std::f64::consts::PI * (depth / dx).powi(2)
                    } else {
                        0.0
                    };
                    2.0 * m.info.area * depth / dx.powi(dim as i32) + ends
                });
                let boxed = boxed(o, depth);
                band.map_or(boxed, |b| b.min(boxed))
            }
        };
    }
    let support = 2.0 * s.discretisation.h();
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

/// \[bytes\] the memory this process may still take, and what limits it: the least of the
/// machine's available memory (Linux: `MemAvailable` of /proc/meminfo), the room left
/// under the address-space limit (`ulimit -v`, RLIMIT_AS: the soft limit of
/// /proc/self/limits less this process's `VmSize`) and the room left under its cgroup's
/// memory limit (v2 `memory.max` less `memory.current`, v1 `memory.limit_in_bytes` less
/// `memory.usage_in_bytes`); `None` where none can be read.
pub fn memory_limit() -> Option<(f64, &'static str)> {
    let read = |p: &str| std::fs::read_to_string(p).ok();
    let available = read("/proc/meminfo")
        .and_then(|t| meminfo_available(&t))
        .map(|b| (b, "available memory"));
    let address_space = read("/proc/self/limits")
        .and_then(|t| address_space_limit(&t))
        .map(|lim| {
            let used = read("/proc/self/status")
                .and_then(|t| vm_size(&t))
                .unwrap_or(0.0);
            (
                (lim - used).max(0.0),
                "room under the address-space limit (ulimit -v)",
            )
        });
    let cgroup = cgroup_room().map(|b| (b, "room under the cgroup's memory limit"));
    [available, address_space, cgroup]
        .into_iter()
        .flatten()
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// \[bytes\] the machine's available memory; `None` where it cannot tell.
pub fn available_memory() -> Option<f64> {
    meminfo_available(&std::fs::read_to_string("/proc/meminfo").ok()?)
}

/// \[bytes\] `MemAvailable` of a /proc/meminfo text.
pub fn meminfo_available(meminfo: &str) -> Option<f64> {
    kib_field(meminfo, "MemAvailable:")
}

/// \[bytes\] `VmSize` (the address space in use) of a /proc/self/status text.
pub fn vm_size(status: &str) -> Option<f64> {
    kib_field(status, "VmSize:")
}

fn kib_field(text: &str, name: &str) -> Option<f64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// \[bytes\] the soft address-space limit of a /proc/self/limits text; `None` where
/// unlimited.
pub fn address_space_limit(limits: &str) -> Option<f64> {
    let line = limits
        .lines()
        .find(|l| l.starts_with("Max address space"))?;
    let soft = line["Max address space".len()..]
        .split_whitespace()
        .next()?;
    soft.parse().ok()
}

/// \[bytes\] a cgroup limit less its usage, from the texts of its limit file and usage
/// file; `None` where unlimited (`max`, or v1's 2^63 rounded to pages).
pub fn cgroup_headroom(limit: &str, usage: Option<&str>) -> Option<f64> {
    let limit: f64 = limit.trim().parse().ok()?;
    if limit >= (1u64 << 60) as f64 {
        return None;
    }
    let used: f64 = usage.and_then(|u| u.trim().parse().ok()).unwrap_or(0.0);
    Some((limit - used).max(0.0))
}

/// The room under this process's cgroup memory limit (v2, then v1), where one is set.
fn cgroup_room() -> Option<f64> {
    let groups = std::fs::read_to_string("/proc/self/cgroup").unwrap_or_default();
    let path_of = |prefix: &str| {
        groups
            .lines()
            .find_map(|l| l.strip_prefix(prefix))
            .map(str::to_string)
    };
    let mut candidates: Vec<(String, &str, &str)> = Vec::new();
    if let Some(p) = path_of("0::") {
        let dir = format!("/sys/fs/cgroup{}", p.trim_end_matches('/'));
        candidates.push((dir, "memory.max", "memory.current"));
    }
    candidates.push(("/sys/fs/cgroup".into(), "memory.max", "memory.current"));
    let v1 = groups.lines().find_map(|l| {
        let (_, rest) = l.split_once(':')?;
        let (controllers, path) = rest.split_once(':')?;
        controllers
            .split(',')
            .any(|c| c == "memory")
            .then(|| path.to_string())
    });
    if let Some(p) = v1 {
        let dir = format!("/sys/fs/cgroup/memory{}", p.trim_end_matches('/'));
        candidates.push((dir, "memory.limit_in_bytes", "memory.usage_in_bytes"));
    }
    candidates.push((
        "/sys/fs/cgroup/memory".into(),
        "memory.limit_in_bytes",
        "memory.usage_in_bytes",
    ));
    candidates.iter().find_map(|(dir, limit, usage)| {
        let limit = std::fs::read_to_string(format!("{dir}/{limit}")).ok()?;
        let usage = std::fs::read_to_string(format!("{dir}/{usage}")).ok();
        cgroup_headroom(&limit, usage.as_deref())
    })
}

impl super::Scene {
    /// The scene's estimate, refused where it exceeds `max_particles` (naming
    /// `discretisation.spacing`) or needs more memory at the start than this process may
    /// have (`memory_limit`; naming `domain.max` where the neighbour grid needs most of
    /// it): before anything is generated.
    pub fn check_size(&self, max_particles: Option<u64>) -> Result<Estimate, super::SceneError> {
        let e = estimate(&self.file);
        let refuse = |field: &str, reason: String| super::SceneError::Invalid {
            origin: self.origin(),
            field: field.into(),
            reason,
        };
        if let Some(max) = max_particles {
            if e.particles > max as f64 {
                return Err(refuse(
                    "discretisation.spacing",
                    format!(
                        "the objects would hold up to {:.3e} particles at this spacing, more \
                         than --max-particles {max}",
                        e.particles
                    ),
                ));
            }
        }
        if let Some((room, what)) = memory_limit() {
            if e.host_bytes() > room {
                let need = format!(
                    "up to {:.3e} particles ({:.2} GB) and a neighbour grid of {:.3e} cells over \
                     the whole domain ({:.2} GB) need about {:.2} GB of memory to start, and the \
                     {what} is {:.2} GB",
                    e.particles,
                    e.particles * HOST_BYTES_PER_PARTICLE / 1e9,
                    e.cells,
                    e.grid_host_bytes() / 1e9,
                    e.host_bytes() / 1e9,
                    room / 1e9
                );
                return Err(
                    if e.grid_host_bytes() > e.particles * HOST_BYTES_PER_PARTICLE {
                        refuse(
                            "domain.max",
                            format!("{need}: a smaller domain, or a larger spacing or h_factor"),
                        )
                    } else {
                        refuse(
                            "discretisation.spacing",
                            format!("{need}: a coarser spacing, or a larger machine"),
                        )
                    },
                );
            }
        }
        Ok(e)
    }
}
