//! CPU vs CUDA, stage by stage (`src/backend/cpu/*.rs` <-> `cuda/*.cu`), in 2D and 3D with
//! fluid, an elastic body, wall particles and a periodic axis, in four variants (dynamic
//! walls / Lennard-Jones-only walls, summation / continuity density, forward / symplectic
//! Euler, with / without artificial stress, with / without density diffusion; two also
//! with an inflow band, two more and a long run with the band's ramped start); the stages
//! run in the order of `Solver::step` for the variant's integrator (forward Euler: the
//! GPU's fused `forces_and_rates` pass against the CPU's two stages). Then diagnostics after 200 steps; the fused pass against the GPU's two separate
//! passes, bit for bit; and the `SphParams` layout as nvcc sees it. Morris's no-slip walls
//! (`no_slip`) run in five stage scenes, a long run and the fused-pass check. Probes
//! (`Readback::sample_points`, `cuda/probes.cu`) sample the same values as the CPU's at points
//! over the domain, and sampling leaves the GPU's stepping unchanged, bit for bit. The force
//! monitors' device sums (`Readback::wall_forces`, `cuda/monitor.cu`) against the read-back
//! path (`monitor::wall_force`) on wall objects in flow, with and without bodies.
//! Total-Lagrangian bodies (`cuda/tlsph.cu`): the stage scenes with `solid_stress`,
//! `solid_forces` and the displacements compared too (2D and 3D, both integrators), and runs
//! of 100-200 steps through captured graphs, one with a body removed halfway. Open
//! boundaries (`cuda/open.cu`): a channel's particles made, removed and moved alike.
//!
//! The tests that need a GPU are `#[ignore]`d unless the build had `MESHFREE_REQUIRE_CUDA=1`
//! (`build.rs` turns it into the cfg `meshfree_require_cuda`); `-- --include-ignored` runs
//! them too. A test that runs fails without a usable GPU: it never passes by skipping.
//!
//! Each stage starts from identical inputs: after comparing a stage, the CPU state is
//! uploaded to the GPU (`CudaSolver::upload_state`), so differences do not carry over.
//!
//! The files: `setups` builds the scenes, `compare` runs and compares the stages, and the
//! tests are grouped by what they compare: `stages`, `schemes`, `passes`, `device`, `probes`,
//! `monitors`, `floating`, `open` and `total_lagrangian`.
#![cfg(feature = "cuda")]

#[path = "../common/mod.rs"]
mod common;

use meshfree_core::backend::cpu::{self, CpuSolver};
use meshfree_core::backend::cuda::CudaSolver;
use meshfree_core::measure::monitor;
use meshfree_core::physics::dim::{Dim, D2, D3};
use meshfree_core::physics::params::{
    self, SphParams, MF_DENSITY_CONTINUITY, MF_DENSITY_SUMMATION, MF_DIFFUSION_ANTUONO,
    MF_DIFFUSION_FOURTAKAS, MF_DIFFUSION_MOLTENI, MF_INTEGRATOR_EULER, MF_SOLID_TOTAL_LAGRANGIAN,
};
use meshfree_core::physics::params::{
    MF_INTEGRATOR_LEAPFROG, MF_INTEGRATOR_SYMPLECTIC_EULER, MF_KIND_BOUNDARY,
    MF_SOLID_FLUID_PRESSURE_EXTRAPOLATED, MF_SOLID_FLUID_PRESSURE_OWN,
};
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::physics::state::State;
use meshfree_core::solver::{PointSample, Setup, Solver};

mod compare;
mod setups;
use compare::*;
use setups::*;

mod device;
mod floating;
mod monitors;
mod open;
mod passes;
mod probes;
mod schemes;
mod stages;
mod total_lagrangian;
