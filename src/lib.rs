//! meshfree: weakly compressible SPH with elastic solids (Liu, Wang, Ma & Zhang), on the
//! CPU (rayon) and on NVIDIA GPUs (CUDA through cudarc). See `ARCHITECTURE.md`.
pub mod analysis;
pub mod backend;
pub mod bench;
pub mod cli;
pub mod compare;
pub mod dim;
pub mod kernel;
pub mod monitor;
pub mod output;
pub mod paper_bench;
pub mod params;
pub mod particle;
pub mod run;
pub mod scene;
pub mod solver;
pub mod stability;
pub mod state;
pub mod validate;
