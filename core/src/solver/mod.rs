//! The solver contract, in three traits a backend implements:
//! - `Solver` (`stages.rs`): the stages of the paper's Fig. 1, declared once in
//!   `stage_list!`, whose `step` fixes their order (backends implement the stages, never the
//!   order), with the clock and the health checks;
//! - `Readback` (`readback.rs`): what comes back from a solver: diagnostics, particles,
//!   frames, point samples, wall forces, and the viewer's snapshot and buffers (`view.rs`);
//! - `Persist` (`persist.rs`): the state a restart needs.
//!
//! `Solver` has the other two as supertraits, so a `Box<dyn Solver>` is all of them.

use serde::{Deserialize, Serialize};

use crate::physics::params::{needs_wall_surface, MfBody, SphParams};
use crate::physics::particle::{Kind, Particle};

pub mod checkpoint;
pub mod frame;
mod persist;
mod readback;
mod stages;
pub mod step;
mod view;

pub use persist::Persist;
pub use readback::{Diagnostics, ExchangeCost, PointSample, Readback};
pub(crate) use stages::{forward_stages, stage_list};
pub use stages::{Solver, Stage};
pub use view::{Shown, Snapshot};

/// Everything a backend needs to start: the derived parameters and the initial particles.
#[derive(Clone, Debug)]
pub struct Setup {
    pub params: SphParams,
    pub particles: Vec<Particle>,
    /// Per boundary particle, at index id - `params.wall_first_id`: the unit normal of the
    /// nearest wall surface, pointing into the fluid (x, y, z; z = 0 in 2D) [-], and the
    /// particle's distance behind that surface d_B \[L\]. Only where
    /// `params::needs_wall_surface` (Morris, Fox & Zhu 1997's no-slip walls, mDBC); empty
    /// otherwise. One entry per boundary particle, none per fluid
    /// particle.
    pub wall_surface: Vec<[f32; 4]>,
    /// The floating rigid bodies (`floating` walls, `physics::body`) at t = 0, in the order
    /// of their walls; each one's group is a driven group with `MfMotion::floating`.
    pub bodies: Vec<MfBody>,
    /// The driven objects' time series (`series` of a `motion`): their knots, each
    /// `MF_SERIES_STRIDE` numbers (t \[T\], s_x, s_y, s_z \[L\], theta \[rad\], 0 at t = 0),
    /// one object's after another's (`MfMotion::series_first`, `series_count`). Empty
    /// where no motion has a series.
    pub motion_series: Vec<f64>,
}

impl Setup {
    pub fn has_solids(&self) -> bool {
        self.particles.iter().any(|p| p.kind == Kind::Solid)
    }

    /// Why `wall_surface` cannot serve `params.no_slip`: a boundary particle whose id falls
    /// outside it. None when it can, or when no_slip is off.
    pub fn wall_surface_error(&self) -> Option<String> {
        if !needs_wall_surface(&self.params) {
            return None;
        }
        let (first, n) = (self.params.wall_first_id, self.wall_surface.len());
        self.particles
            .iter()
            .find(|q| q.kind == Kind::Boundary && (q.id < first || (q.id - first) as usize >= n))
            .map(|q| {
                format!(
                    "no_slip and mdbc need a wall surface entry for every boundary particle: particle {} \
                     is outside ids {first}..{} of Setup::wall_surface",
                    q.id,
                    first as usize + n
                )
            })
    }
}

/// Which backend built a solver, and on what.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, Eq)]
pub struct BackendInfo {
    /// "cpu" or "cuda".
    pub backend: String,
    /// e.g. "rayon, 2 threads" or "NVIDIA H100 80GB HBM3".
    pub device: String,
}

/// A blow-up: the first bad particle found and what was wrong with it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, thiserror::Error)]
#[error("blow-up at step {step}, t = {time:.6}: particle {particle} ({kind}) has {quantity} = {value} ({reason})")]
pub struct Fault {
    pub step: u64,
    pub time: f64,
    /// The particle's id.
    pub particle: u32,
    pub kind: String,
    /// "position", "velocity", "density", ...
    pub quantity: String,
    /// The offending value (the first bad component for vectors).
    pub value: f64,
    pub reason: String,
}
