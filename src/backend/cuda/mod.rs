//! The CUDA backend: the stages of `Solver` as kernels in `cuda/*.cu`, the whole state on
//! the GPU. Twin of `src/backend/cpu/`; parity test `tests/cuda_parity.rs`.
//!
//! Per step nothing is read back: the step size is reduced, computed and consumed on the
//! device, and the simulated time is accumulated there in double precision. The host reads
//! back only for `time`, `check`, `diagnostics`, `particles` and `remove_group`.

mod buffers;
mod device;
mod launch;

use std::marker::PhantomData;

use crate::backend::cpu::fault;
use crate::backend::BackendError;
use crate::dim::Dim;
use crate::params::{SphParams, MF_DENSITY_CONTINUITY};
use crate::particle::Particle;
use crate::solver::{
    fault_codes as fc, BackendInfo, Diagnostics, Fault, Setup, Shown, Snapshot, Solver,
};
use crate::state::State;

pub use device::{driver_version, NVCC_VERSION};

use buffers::Buffers;
use device::Device;
use launch::Kernels;

/// Whether a usable CUDA device answers (driver, device 0, PTX in this build).
pub fn available() -> Result<String, BackendError> {
    Device::open().map(|d| d.name)
}

/// Below this many particles the density and forces kernels split each particle's
/// neighbour loop over several threads (measured on an H200: faster up to ~10^5 particles,
/// slower at 3 x 10^5 and beyond; docs/performance.md).
pub const SPLIT_BELOW: usize = 150_000;

/// `SPLIT_BELOW`, or `MESHFREE_CUDA_SPLIT_BELOW` where set (for measurements).
fn split_below() -> usize {
    std::env::var("MESHFREE_CUDA_SPLIT_BELOW")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(SPLIT_BELOW)
}

/// The solver with its state in GPU memory.
pub struct CudaSolver<D: Dim> {
    dev: Device,
    k: Kernels,
    params: SphParams,
    buf: Buffers,
    steps: u64,
    /// Host buffers of `snapshot`, kept between frames.
    host_pos: Vec<f32>,
    host_vel: Vec<f32>,
    _d: PhantomData<D>,
}

fn oom(n: usize, e: cudarc::driver::DriverError) -> BackendError {
    BackendError::Cuda(format!(
        "allocating device memory for {n} particles failed: {e:?}"
    ))
}

impl<D: Dim> CudaSolver<D> {
    pub fn new(setup: Setup) -> Result<Self, BackendError> {
        let dev = Device::open()?;
        let mut k = Kernels::load(&dev, D::D)?;
        let p = setup.params;
        let state = State::<D>::from_particles(
            &setup.particles,
            p.density_mode as u32 == MF_DENSITY_CONTINUITY,
            p.art_stress_eps > 0.0,
        );
        let n = state.len();
        let buf =
            Buffers::new(&dev.stream, &state, p.n_cells.max(1) as usize).map_err(|e| oom(n, e))?;
        k.split = n < split_below();
        Ok(CudaSolver {
            dev,
            k,
            params: p,
            buf,
            steps: 0,
            host_pos: Vec::new(),
            host_vel: Vec::new(),
            _d: PhantomData,
        })
    }

    fn sync_err(&self, what: &str, e: cudarc::driver::DriverError) -> ! {
        panic!(
            "CUDA error while {what} on {} ({} particles): {e:?}",
            self.dev.name, self.buf.n
        )
    }

    /// The raw arrays in storage order (read back).
    pub fn download_state(&mut self) -> State<D> {
        self.buf
            .read_state::<D>(&self.dev.stream)
            .unwrap_or_else(|e| self.sync_err("reading the state back", e))
    }

    /// Overwrite the arrays (same length) with `state`; the grid stays. For parity tests.
    pub fn upload_state(&mut self, state: &State<D>) {
        if let Err(e) = self.buf.write_state(&self.dev.stream, state) {
            self.sync_err("uploading a state", e)
        }
    }

    /// The step size of the last `time_step` [T] (read back).
    pub fn dt(&mut self) -> f32 {
        self.dev
            .stream
            .clone_dtoh(&self.buf.dt)
            .unwrap_or_else(|e| self.sync_err("reading dt", e))[0]
    }

    /// Force (`Some`) or reset to the size rule (`None`) the split of each particle's
    /// neighbour loop over several threads. For tests and benchmarks.
    pub fn set_lane_split(&mut self, split: Option<bool>) {
        self.k.split = split.unwrap_or(self.buf.n < split_below());
    }

    /// Device memory held by this solver's arrays [bytes].
    pub fn device_bytes(&self) -> usize {
        self.buf.bytes
    }

    /// Wait for all queued work.
    pub fn synchronize(&self) {
        if let Err(e) = self.dev.stream.synchronize() {
            self.sync_err("synchronising", e)
        }
    }

    /// nvcc's view of SphParams: (sizeof, offsetof dt_fixed, offsetof gravity, dim received).
    pub fn params_layout(&mut self) -> [u32; 4] {
        launch::params_layout(
            &self.k,
            &self.dev.stream,
            &self.params,
            &mut self.buf.layout,
        )
        .unwrap_or_else(|e| self.sync_err("probing the SphParams layout", e))
    }
}

impl<D: Dim> Solver for CudaSolver<D> {
    fn info(&self) -> BackendInfo {
        BackendInfo {
            backend: "cuda".into(),
            device: self.dev.name.clone(),
        }
    }
    fn params(&self) -> &SphParams {
        &self.params
    }
    fn len(&self) -> usize {
        self.buf.n
    }
    fn has_solids(&self) -> bool {
        self.buf.cur.stress.is_some()
    }
    fn build_grid(&mut self) {
        launch::build_grid(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn density(&mut self) {
        launch::density(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn rates(&mut self) {
        launch::rates(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn forces(&mut self) {
        launch::forces(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn time_step(&mut self) {
        launch::step_size(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn kick(&mut self) {
        launch::kick(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn drift(&mut self) {
        launch::drift(&self.k, &self.dev.stream, &self.params, &mut self.buf);
        self.steps += 1;
    }
    fn time(&mut self) -> f64 {
        self.dev
            .stream
            .clone_dtoh(&self.buf.time)
            .unwrap_or_else(|e| self.sync_err("reading the time", e))[0]
    }
    fn steps(&self) -> u64 {
        self.steps
    }
    fn check(&mut self) -> Result<(), Fault> {
        let first = launch::check(&self.k, &self.dev.stream, &self.params, &mut self.buf)
            .unwrap_or_else(|e| self.sync_err("running the health check", e));
        if first == u64::MAX {
            return Ok(());
        }
        let (slot, code) = ((first >> 8) as usize, (first & 0xff) as u32);
        let st = self.download_state();
        let x = D::to3(st.pos[slot]);
        let v = D::to3(st.vel[slot]);
        let value = match code {
            fc::NON_FINITE_POSITION => x
                .iter()
                .copied()
                .find(|c| !c.is_finite())
                .unwrap_or(f32::NAN),
            fc::NON_FINITE_VELOCITY => v
                .iter()
                .copied()
                .find(|c| !c.is_finite())
                .unwrap_or(f32::NAN),
            fc::ESCAPED => (0..D::D)
                .find(|&a| {
                    self.params.periodic[a] == 0
                        && (x[a] < self.params.domain_min[a] || x[a] > self.params.domain_max[a])
                })
                .map_or(f32::NAN, |a| x[a]),
            _ => st.rho[slot],
        };
        let time = self.time();
        Err(fault(self.steps, time, st.particle(slot), code, value))
    }
    fn diagnostics(&mut self) -> Diagnostics {
        let s = &self.dev.stream;
        let r = launch::diagnostics(&self.k, s, &self.params, &mut self.buf).and_then(|_| {
            Ok((
                s.clone_dtoh(&self.buf.diag_sums)?,
                s.clone_dtoh(&self.buf.diag_max)?,
                s.clone_dtoh(&self.buf.diag_counts)?,
                s.clone_dtoh(&self.buf.dt)?,
                s.clone_dtoh(&self.buf.time)?,
            ))
        });
        let (sums, maxes, counts, dt, time) =
            r.unwrap_or_else(|e| self.sync_err("reducing diagnostics", e));
        Diagnostics {
            step: self.steps,
            time: time[0],
            dt: if self.steps == 0 { 0.0 } else { dt[0] },
            kinetic_energy: sums[0],
            max_speed: f32::from_bits(maxes[0]),
            density_error: f32::from_bits(maxes[1]),
            momentum: [sums[1], sums[2], sums[3]],
            fluid: counts[0] as usize,
            solid: counts[1] as usize,
            boundary: counts[2] as usize,
        }
    }
    fn particles(&mut self) -> Vec<Particle> {
        self.download_state().to_particles()
    }
    /// Copies only positions, kinds and the shown quantity (one read-back per drawn frame,
    /// into buffers that keep their size from frame to frame).
    fn snapshot(&mut self, shown: Shown, out: &mut Snapshot) {
        let n = self.buf.n;
        let vs = buffers::vstride::<D>();
        let s = self.dev.stream.clone();
        let c = &self.buf.cur;
        self.host_pos.resize(n * vs, 0.0);
        out.kinds.resize(n, 0);
        out.values.resize(n, 0.0);
        let r = (|| {
            s.memcpy_dtoh(&c.pos, &mut self.host_pos)?;
            s.memcpy_dtoh(&c.kind, &mut out.kinds)?;
            match shown {
                Shown::Speed => {
                    self.host_vel.resize(n * vs, 0.0);
                    s.memcpy_dtoh(&c.vel, &mut self.host_vel)?;
                }
                Shown::Pressure => s.memcpy_dtoh(&c.p, &mut out.values)?,
                Shown::Density => s.memcpy_dtoh(&c.rho, &mut out.values)?,
                Shown::Kind => {}
            }
            s.synchronize()
        })();
        if let Err(e) = r {
            self.sync_err("reading a snapshot back", e)
        }
        out.positions.clear();
        out.positions.extend(
            self.host_pos
                .chunks_exact(vs)
                .map(|x| [x[0], x[1], if vs == 4 { x[2] } else { 0.0 }]),
        );
        match shown {
            Shown::Speed => {
                for (v, x) in out.values.iter_mut().zip(self.host_vel.chunks_exact(vs)) {
                    *v = x.iter().take(D::D).map(|c| c * c).sum::<f32>().sqrt();
                }
            }
            Shown::Kind => {
                for (v, k) in out.values.iter_mut().zip(&out.kinds) {
                    *v = *k as f32;
                }
            }
            Shown::Pressure | Shown::Density => {}
        }
    }
    fn remove_group(&mut self, group: u32) -> usize {
        let mut st = self.download_state();
        let before = st.len();
        let g = st.group.clone();
        st.retain(|i| g[i] != group);
        let removed = before - st.len();
        if removed > 0 {
            let time = self.time();
            let dt = self.dt();
            let n = st.len();
            let mut buf = Buffers::new(&self.dev.stream, &st, self.buf.n_cells)
                .unwrap_or_else(|e| panic!("{}", oom(n, e)));
            let s = &self.dev.stream;
            let r = s
                .memcpy_htod(&[time][..], &mut buf.time)
                .and_then(|_| s.memcpy_htod(&[dt][..], &mut buf.dt));
            if let Err(e) = r {
                self.sync_err("restoring the clock", e)
            }
            self.buf = buf;
        }
        removed
    }
}

/// The CUDA solver in the scene's dimension, or why there is none.
pub fn create(setup: Setup) -> Result<Box<dyn Solver>, BackendError> {
    if setup.params.dim == 2 {
        Ok(Box::new(CudaSolver::<crate::dim::D2>::new(setup)?))
    } else {
        Ok(Box::new(CudaSolver::<crate::dim::D3>::new(setup)?))
    }
}
