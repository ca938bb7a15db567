//! meshfree-core: the solver. Weakly compressible SPH with elastic solids (Liu, Wang, Ma &
//! Zhang) on the CPU (rayon) and on NVIDIA GPUs (CUDA through cudarc): parameters, scenes,
//! the `Solver` trait and its backends, and the one stepping path (`solver::step`). No command
//! line, plotting or progress bars: those live in the `meshfree` binary (`app/`) and the
//! laboratory (`lab/`). See `ARCHITECTURE.md`.
//!
//! The modules by subject: `physics` (dimensions, kernels, particles, the state, the
//! parameter struct, pair terms, the total-Lagrangian reference), `solver` (the stage
//! contract, the stepping path, frames, checkpoints), `scene` (scene files and the scheme's
//! declarations), `measure` (monitors, probes, voids), `backend` (CPU and CUDA), `exchange`
//! (domain decomposition) and `interop` (CUDA-OpenGL, behind a feature).
pub mod backend;
pub mod build_info;
pub mod consts;
pub mod exchange;
#[cfg(feature = "interop")]
pub mod interop;
pub mod measure;
pub mod named;
pub mod physics;
pub mod run_files;
pub mod scene;
pub mod solver;
