//! What a backend adds to its `Solver` to serve as one subdomain of a decomposed run.

use crate::exchange::Slab;
use crate::solver::checkpoint::SolverCheckpoint;
use crate::solver::Solver;

/// A solver that holds one slab's particles (`set_owned`) and, during a step, copies of the
/// particles its neighbours own within the halo width (`halo`, `append`), and that lets the
/// step size be agreed over every subdomain (`extremes`, `set_step`). Between steps it holds
/// its owned particles alone (`retain_owned`), so that its reductions (diagnostics, the
/// health check, the particles of an output) count each particle once.
pub trait Subdomain: Solver + Sized {
    /// Copies of particles on their way to another subdomain, where the backend keeps them:
    /// host arrays on the CPU, device arrays on a GPU (never staged through the host).
    type Halo: Send;

    /// From now on own the particles in `slab` (`SphParams::own_slab`): the step size's
    /// extremes and the wall forces count only these.
    fn set_owned(&mut self, slab: Slab);
    /// Copies of this solver's particles within `width` \[L\] of `target` along its axis
    /// (`Slab::gap`, the shorter way round on a periodic axis spanning `periodic`), in
    /// storage order; `None` where there is none.
    fn halo(
        &mut self,
        target: &Slab,
        width: f32,
        periodic: Option<(f32, f32)>,
    ) -> Option<Self::Halo>;
    /// The number of particles `halo` holds.
    fn halo_len(halo: &Self::Halo) -> usize;
    /// The bytes `halo` holds: what a transport between devices carries.
    fn halo_bytes(halo: &Self::Halo) -> usize;
    /// Add the copies to the storage (the next `build_grid` sorts them in).
    fn append(&mut self, halos: Vec<Self::Halo>);
    /// Drop every particle outside the owned slab: the halo, and the owned particles the
    /// drift carried into a neighbour's slab (which that neighbour's copy of them, stepped
    /// alike, now owns).
    fn retain_owned(&mut self);
    /// [max |v| [L/T], max |a| [L/T^2], max sound speed [L/T]] over the owned fluid and
    /// solid particles: what `time_step` reduces (eq. (19)).
    fn extremes(&mut self) -> [f32; 3];
    /// Take the step size from the extremes of every subdomain, as `time_step` takes it
    /// from its own (`backend::cpu::step_size`).
    fn set_step(&mut self, extremes: [f32; 3]);
    /// Device memory this subdomain holds \[bytes\], its spare capacity included (0 on the
    /// CPU).
    fn device_bytes(&self) -> usize {
        0
    }
    /// Replace the particles with `part` (any set of this scene's particles, the arrays of a
    /// checkpoint), and the clock, step count and step size with its own.
    fn replace(&mut self, part: &SolverCheckpoint) -> Result<(), String>;
}
