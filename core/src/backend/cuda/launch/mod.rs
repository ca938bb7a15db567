//! Every kernel launch of the CUDA backend, a file per part of `cuda/`: the grid build
//! (`grid.rs`), the neighbour passes (`passes.rs`), the step size and integration
//! (`integrate.rs`), reductions, checks and probes (`reduce.rs`), the total-Lagrangian solids
//! (`tlsph.rs`), a subdomain's exchange (`exchange.rs`) and the viewer's interop
//! (`view.rs`). Each `unsafe` block names the kernel family whose signature (the table in
//! `kernels.rs`, checked against the PTX) its arguments follow, argument for argument, and
//! what the kernel needs of them beyond their types.

use cudarc::driver::{DeviceRepr, LaunchConfig};

use super::buffers::Buffers;
use super::kernels::Scheme;
use crate::consts::MF_BLOCK;
use crate::physics::params::SphParams;

// SAFETY: SphParams is the bindgen image of the C struct in `cuda/sph_params.h` (repr(C),
// plain integers and floats, no pointers); kernels take it by value. `tests/cuda_parity/`
// checks that nvcc's sizeof and offsets equal Rust's.
unsafe impl DeviceRepr for SphParams {}

/// Null for optional array arguments (the kernels test the pointer).
static NULL: u64 = 0;

/// The scheme of the neighbour entries for the scene in `b` (`Scheme::of`).
fn scheme(p: &SphParams, b: &Buffers) -> Scheme {
    Scheme::of(b.cur.stress.is_some(), p)
}

fn cfg(n: usize) -> LaunchConfig {
    LaunchConfig {
        grid_dim: ((n as u32).div_ceil(MF_BLOCK).max(1), 1, 1),
        block_dim: (MF_BLOCK, 1, 1),
        shared_mem_bytes: 0,
    }
}

macro_rules! opt {
    ($b:expr, $o:expr) => {
        match $o {
            Some(s) => $b.arg(s),
            None => $b.arg(&NULL),
        }
    };
}

/// A captured CUDA graph of whole steps, owned by one solver, and the buffer assignment
/// (`Buffers::swapped`) it was captured with: it reads and writes those buffers only.
pub struct StepGraph(pub cudarc::driver::CudaGraph, pub bool);

// SAFETY: a CUDA graph may be used from any thread as long as no two threads use it at once
// (CUDA's graph thread-safety rules); the solver owns it and `Solver` methods take `&mut`,
// so it moves between threads with the solver but is never shared.
unsafe impl Send for StepGraph {}

mod bodies;
mod exchange;
mod grid;
mod integrate;
pub mod open;
mod passes;
mod reduce;
mod tlsph;
#[cfg(feature = "interop")]
mod view;

pub use bodies::*;
pub use exchange::*;
pub use grid::*;
pub use integrate::*;
pub use passes::*;
pub use reduce::*;
pub use tlsph::*;
#[cfg(feature = "interop")]
pub use view::*;
