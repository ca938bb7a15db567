//! Backends and the one place that builds a solver: `create`.
pub mod cpu;
#[cfg(feature = "cuda")]
pub mod cuda;
pub mod pair;

use crate::dim::{D2, D3};
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

/// Why a solver could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BackendError {
    #[error("the CUDA backend is unavailable: {0}")]
    CudaUnavailable(String),
    #[error("CUDA error: {0}")]
    Cuda(String),
    #[error("cannot decompose this scene: {0}")]
    Decomposition(String),
    /// The ranks of a run in several processes could not start together (`run --mpi`).
    #[error("starting the ranks: {0}")]
    Launch(String),
}

impl From<crate::exchange::Refused> for BackendError {
    fn from(r: crate::exchange::Refused) -> Self {
        BackendError::Decomposition(r.0)
    }
}

/// Build the solver for `setup` on `choice`, in the scene's dimension.
pub fn create(choice: BackendChoice, setup: Setup) -> Result<Box<dyn Solver>, BackendError> {
    match choice {
        BackendChoice::Cpu => Ok(cpu_solver(setup)),
        BackendChoice::Cuda => cuda_solver(setup),
        // CUDA where a driver, a device and PTX answer; otherwise the CPU (`Solver::info`
        // says which was taken).
        BackendChoice::Auto => cuda_solver(setup.clone()).or_else(|_| Ok(cpu_solver(setup))),
    }
}

/// `n` subdomains of the scene stepped together in this process
/// (`crate::exchange::Decomposed`: slabs along the longest axis, one thread each), each a
/// solver of `choice`; the same results as `create`'s one domain (bit for bit in every
/// particle; the diagnostics' sums to round-off).
pub fn create_decomposed(
    choice: BackendChoice,
    mut setup: Setup,
    n: usize,
) -> Result<Box<dyn Solver>, BackendError> {
    setup.params.own_solids = setup.has_solids() as i32;
    match choice {
        BackendChoice::Cpu => cpu_decomposed(setup, n),
        BackendChoice::Cuda => cuda_decomposed(setup, n),
        BackendChoice::Auto => match cuda_solver_available() {
            Ok(()) => cuda_decomposed(setup, n),
            Err(_) => cpu_decomposed(setup, n),
        },
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

/// The CUDA solvers of `n` subdomains, all on device 0, their halos on the device
/// (`cuda::CudaHalo`); each takes the lanes of the whole scene's particle count, so that the
/// subdomains sum in the one domain's order (`CudaSolver::new_subdomain`).
fn cuda_decomposed(setup: Setup, n: usize) -> Result<Box<dyn Solver>, BackendError> {
    #[cfg(feature = "cuda")]
    {
        use crate::exchange::Decomposed;
        let whole = setup.particles.len();
        Ok(if setup.params.dim == 2 {
            Box::new(Decomposed::new(setup, n, |s| {
                cuda::CudaSolver::<D2>::new_subdomain(s, whole, 0)
            })?)
        } else {
            Box::new(Decomposed::new(setup, n, |s| {
                cuda::CudaSolver::<D3>::new_subdomain(s, whole, 0)
            })?)
        })
    }
    #[cfg(not(feature = "cuda"))]
    {
        let _ = (setup, n);
        Err(BackendError::CudaUnavailable(
            "this build has the `cuda` feature off".into(),
        ))
    }
}

/// One subdomain of the scene on each of `n` GPUs of this machine, talking through NCCL
/// (`run --gpus N`; `cuda::nccl`): the particles of one domain, bit for bit, as
/// `create_decomposed`.
pub fn create_multi_gpu(mut setup: Setup, n: usize) -> Result<Box<dyn Solver>, BackendError> {
    setup.params.own_solids = setup.has_solids() as i32;
    #[cfg(feature = "nccl")]
    {
        cuda::nccl::multi_gpu(setup, n)
    }
    #[cfg(not(feature = "nccl"))]
    {
        let _ = (setup, n);
        Err(BackendError::CudaUnavailable(
            "this build has the `nccl` feature off".into(),
        ))
    }
}

/// The CUDA solver in the scene's dimension, or why there is none.
pub fn cuda_solver(setup: Setup) -> Result<Box<dyn Solver>, BackendError> {
    #[cfg(feature = "cuda")]
    {
        cuda::create(setup)
    }
    #[cfg(not(feature = "cuda"))]
    {
        let _ = setup;
        Err(BackendError::CudaUnavailable(
            "this build has the `cuda` feature off".into(),
        ))
    }
}

/// Whether the CUDA backend can start here (a driver, a device and PTX), without building a
/// solver; the error says why not.
pub fn cuda_solver_available() -> Result<(), BackendError> {
    #[cfg(feature = "cuda")]
    {
        cuda::available().map(|_| ())
    }
    #[cfg(not(feature = "cuda"))]
    {
        Err(BackendError::CudaUnavailable(
            "this build has the `cuda` feature off".into(),
        ))
    }
}

/// The CPU solver in the scene's dimension.
pub fn cpu_solver(setup: Setup) -> Box<dyn Solver> {
    if setup.params.dim == 2 {
        Box::new(cpu::CpuSolver::<D2>::new(setup))
    } else {
        Box::new(cpu::CpuSolver::<D3>::new(setup))
    }
}
