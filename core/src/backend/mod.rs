//! Backends and the one place that builds a solver: `create`.
pub mod cpu;
#[cfg(feature = "cuda")]
pub mod cuda;
/// The `cuda` feature off: the same entry points, each saying so (`stub.rs`).
#[cfg(not(feature = "cuda"))]
#[path = "stub.rs"]
pub mod cuda;

mod error;
pub use error::{fault, BackendError};

use crate::physics::dim::{D2, D3};
use crate::solver::{Setup, Solver};

/// Which backend to run on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BackendChoice {
    /// CUDA where a driver and a device answer, else the CPU.
    #[default]
    Auto,
    /// rayon on every core.
    Cpu,
    /// NVIDIA GPU; an error where none is usable.
    Cuda,
}

impl crate::named::Named for BackendChoice {
    const ALL: &'static [(Self, &'static str, &'static str)] = &[
        (
            BackendChoice::Auto,
            "auto",
            "CUDA where a driver and a device answer, else the CPU",
        ),
        (BackendChoice::Cpu, "cpu", "rayon on every core"),
        (
            BackendChoice::Cuda,
            "cuda",
            "NVIDIA GPU; an error where none is usable",
        ),
    ];
}

/// Where a solver's particles live: one domain, or slabs of the scene stepped together
/// (`crate::exchange::Decomposed`: slabs along the longest axis, one rank each), which give
/// one domain's results (bit for bit in every particle; the diagnostics' sums to
/// round-off). A run in several processes (`meshfree run --mpi`) is the app's: its ranks
/// talk through MPI (`app/src/mpi.rs`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Layout {
    /// One domain.
    #[default]
    One,
    /// This many subdomains in this process, one thread each, every one a solver of the
    /// chosen backend (`run --decompose N`); on CUDA all on device 0, their halos on the
    /// device.
    Threads(usize),
    /// One subdomain on each of this many GPUs of this machine, talking through NCCL (`run
    /// --gpus N`): CUDA whatever the choice.
    Gpus(usize),
}

/// Build the solver for `setup` on `choice`, laid out as `layout`, in the scene's
/// dimension. `Auto` takes CUDA where a driver, a device and PTX answer, otherwise the CPU
/// (`Solver::info` says which was taken).
pub fn create(
    choice: BackendChoice,
    layout: Layout,
    mut setup: Setup,
) -> Result<Box<dyn Solver>, BackendError> {
    if layout != Layout::One && !setup.bodies.is_empty() {
        return Err(BackendError::Decomposition(format!(
            "the scene has {} floating bodies, which run in one domain for now (their force \
             would be summed over one subdomain's particles): run it without --decompose, \
             --gpus or --mpi",
            setup.bodies.len()
        )));
    }
    if layout != Layout::One
        && setup.params.wall_coupling as u32 == crate::physics::params::MF_WALL_COUPLING_MDBC
    {
        return Err(BackendError::Decomposition(
            "mDBC walls run in one domain for now (a wall particle's ghost node, up to twice \
             the wall's depth away, reads fluid beyond a subdomain's halo): run it without \
             --decompose, --gpus or --mpi, or with [boundary] wall_coupling = \"dynamic\""
                .into(),
        ));
    }
    if setup.params.open_count > 0 && layout != Layout::One {
        // Open boundaries (`physics::open`) change the particle count: in one domain only
        // for now (issue #55).
        return Err(BackendError::Decomposition(
            "the scene has open boundaries, which run in one domain for now: run it without \
             --decompose, --gpus or --mpi"
                .into(),
        ));
    }
    if setup.params.gradient_correction != 0 && layout != Layout::One {
        // A halo particle's matrix would miss the neighbours beyond the halo.
        return Err(BackendError::Decomposition(
            "[fluid] gradient_correction runs in one domain for now (a particle's matrix at \
             the halo's edge would miss its neighbours beyond it): run it without \
             --decompose, --gpus or --mpi"
                .into(),
        ));
    }
    if layout != Layout::One {
        // Every subdomain holds the solids' arrays where the scene has solids: its halo may
        // bring some (`SphParams::own_solids`).
        setup.params.own_solids = setup.has_solids() as i32;
    }
    match (layout, choice) {
        (Layout::One, BackendChoice::Cpu) => Ok(cpu_solver(setup)),
        (Layout::One, BackendChoice::Cuda) => cuda::create(setup),
        (Layout::One, BackendChoice::Auto) => {
            cuda::create(setup.clone()).or_else(|_| Ok(cpu_solver(setup)))
        }
        (Layout::Threads(n), BackendChoice::Cpu) => cpu_decomposed(setup, n),
        (Layout::Threads(n), BackendChoice::Cuda) => cuda::decomposed(setup, n),
        (Layout::Threads(n), BackendChoice::Auto) => match cuda::available() {
            Ok(_) => cuda::decomposed(setup, n),
            Err(_) => cpu_decomposed(setup, n),
        },
        (Layout::Gpus(n), _) => cuda::multi_gpu(setup, n),
    }
}

fn cpu_decomposed(setup: Setup, n: usize) -> Result<Box<dyn Solver>, BackendError> {
    use crate::exchange::Decomposed;
    Ok(if setup.params.dim == 2 {
        Box::new(Decomposed::new(setup, n, |s| {
            Ok::<_, BackendError>(cpu::CpuSolver::<D2>::new(s))
        })?)
    } else {
        Box::new(Decomposed::new(setup, n, |s| {
            Ok::<_, BackendError>(cpu::CpuSolver::<D3>::new(s))
        })?)
    })
}

/// The CPU solver in the scene's dimension.
pub fn cpu_solver(setup: Setup) -> Box<dyn Solver> {
    if setup.params.dim == 2 {
        Box::new(cpu::CpuSolver::<D2>::new(setup))
    } else {
        Box::new(cpu::CpuSolver::<D3>::new(setup))
    }
}
