//! Domain decomposition: a run split into slabs along one axis, each stepped by its own
//! solver (a rank), exchanging halos (copies of the particles within reach of a slab) once
//! per step and agreeing on the step size.
//!
//! The scheme: a rank owns the particles in its slab (`Slab`, `SphParams::own_slab`) and
//! starts each step with copies of every particle within `halo_width` of it. It steps all of
//! them; a particle's update reads particles at most `passes` supports away, so the owned
//! particles, and the copies within a support of the slab, come out exactly as in one
//! domain (the grid is the whole domain's, so neighbours are visited in the same (cell, id)
//! order). After the drift the rank keeps what lies in its slab: its own particles that
//! stayed, and the copies that moved in, which are bit for bit the particles their old
//! owner stepped and now drops. No migration message is needed; the halo is the only
//! traffic, and the step size is the maximum of the ranks' extremes (`Rank::time_step`).
//!
//! `Transport` carries the traffic (`InProcess` between threads of one process);
//! `Subdomain` is what a backend implements to serve as a rank; `Decomposed` runs N ranks
//! as one `Solver`, calling them through a `Group` (`Call`, `Reply`): `Threads` of this
//! process (`--decompose N`, `--gpus N`), or processes (`meshfree run --mpi`).
mod call;
mod decomposed;
mod group;
mod rank;
mod slab;
mod subdomain;
mod transport;

pub use call::{Call, Reply, Status};
pub use decomposed::{cut, part, refusal, Decomposed, Refused, IMBALANCE};
pub use group::{Group, Threads};
pub use rank::{ExchangeStats, Rank};
pub use slab::{balanced, halo_width, longest_axis, passes, Slab};
pub use subdomain::Subdomain;
pub use transport::{InProcess, Transport};
