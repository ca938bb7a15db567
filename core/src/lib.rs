//! meshfree-core: the solver. Weakly compressible SPH with elastic solids (Liu, Wang, Ma &
//! Zhang) on the CPU (rayon) and on NVIDIA GPUs (CUDA through cudarc): parameters, scenes,
//! the `Solver` trait and its backends, and the one stepping path (`step`). No command
//! line, plotting or progress bars: those live in the `meshfree` binary (`app/`) and the
//! laboratory (`lab/`). See `ARCHITECTURE.md`.
pub mod backend;
pub mod build_info;
pub mod checkpoint;
pub mod consts;
pub mod dim;
pub mod exchange;
pub mod frame;
#[cfg(feature = "interop")]
pub mod interop;
pub mod kernel;
pub mod monitor;
pub mod named;
pub mod pairs;
pub mod params;
pub mod particle;
pub mod probe;
pub mod run_files;
pub mod scene;
pub mod scheme;
pub mod solver;
pub mod state;
pub mod step;
pub mod tlsph;
pub mod voids;
