//! The floating rigid bodies on the device (`cuda/bodies.cu`, launched by `launch/bodies.rs`):
//! their `MfBody` records, advanced in place by the step's kernels, and their loads' partial
//! sums and totals. Allocated once, with the solver (a step's graph allocates nothing).
//! Twin: the `bodies` of `backend/cpu/mod.rs`.

use std::sync::Arc;

use cudarc::driver::{CudaSlice, CudaStream, DeviceRepr, DriverError, ValidAsZeroBits};

use super::launch::WALL_FORCE_BLOCKS;
use crate::physics::params::MfBody;

// SAFETY: `MfBody` is a C struct of i32 and f64 fields (sph_params.h), laid out alike by
// bindgen and nvcc, with no padding a kernel could read as a value.
unsafe impl DeviceRepr for MfBody {}
// SAFETY: all-zero bits are a valid `MfBody` (integers and floats).
unsafe impl ValidAsZeroBits for MfBody {}

pub struct BodyBuffers {
    pub n_bodies: usize,
    /// The bodies (`Setup::bodies`), their state advanced by `sph_body_kick` and
    /// `sph_body_drift`.
    pub bodies: CudaSlice<MfBody>,
    /// The loads' block partial sums: 4 slots of 3 doubles (the fluid's force, its torque,
    /// the contacts' force, their torque) per body and block of `WALL_FORCE_BLOCKS` at most.
    pub partial: CudaSlice<f64>,
    /// The loads: 12 doubles per body, in the slots' order.
    pub load: CudaSlice<f64>,
}

impl BodyBuffers {
    pub fn new(s: &Arc<CudaStream>, bodies: &[MfBody]) -> Result<BodyBuffers, DriverError> {
        let k = bodies.len();
        let partial = 4 * k * WALL_FORCE_BLOCKS * 3;
        Ok(BodyBuffers {
            n_bodies: k,
            bodies: s.clone_htod(bodies)?,
            partial: s.alloc_zeros::<f64>(partial)?,
            load: s.alloc_zeros::<f64>(12 * k)?,
        })
    }

    /// The bodies as they are now.
    pub fn read(&self, s: &Arc<CudaStream>) -> Result<Vec<MfBody>, DriverError> {
        s.clone_dtoh(&self.bodies)
    }

    /// Overwrite the bodies (a restart).
    pub fn write(&mut self, s: &Arc<CudaStream>, bodies: &[MfBody]) -> Result<(), DriverError> {
        s.memcpy_htod(bodies, &mut self.bodies)
    }
}
