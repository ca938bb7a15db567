//! The CUDA backend: the stages of `Solver` as kernels in `cuda/*.cu`, the whole state on
//! the GPU. Twin of `src/backend/cpu/`; parity test `tests/cuda_parity/`.
//!
//! Per step nothing is read back: the step size is reduced, computed and consumed on the
//! device, and the simulated time is accumulated there in double precision. The host reads
//! back only for `time`, `check`, `diagnostics`, `particles` and `remove_group`.

mod body_buffers;
mod buffers;
mod capture;
mod device;
mod handover;
mod kernels;
mod launch;
#[cfg(feature = "nccl")]
pub mod nccl;
mod persist;
mod readback;
mod subdomain;
mod tl_buffers;
#[cfg(feature = "interop")]
mod view;

use std::marker::PhantomData;

use cudarc::driver::{sys, CudaSlice};

use crate::backend::error::BackendError;
use crate::backend::fault;
use crate::consts::{
    MF_FAULT_ESCAPED, MF_FAULT_NON_FINITE_POSITION, MF_FAULT_NON_FINITE_VELOCITY,
    MF_FAULT_RECORD_WORDS, MF_FAULT_SLOT_SHIFT,
};
use crate::physics::dim::Dim;
use crate::physics::params::{needs_density_gradient, SphParams, MF_DENSITY_CONTINUITY};
use crate::physics::state::State;
use crate::solver::{BackendInfo, Fault, Setup, Solver};

pub use device::{device_count, driver_version, NVCC_VERSION};
pub use subdomain::CudaHalo;

use body_buffers::BodyBuffers;
use buffers::Buffers;
use capture::Capturer;
use device::Device;
use handover::{By, Mark};
use kernels::{Kernels, LANE_COUNTS};
use launch::StepGraph;
use tl_buffers::TlBuffers;

/// Whether a usable CUDA device answers (driver, device 0, PTX in this build).
pub fn available() -> Result<String, BackendError> {
    Device::open().map(|d| d.name)
}

/// Below this many particles the neighbour kernels split each particle's loop over
/// `SPLIT_LANES` threads (measured on an H200: faster up to ~10^5 particles, slower at
/// 3 x 10^5 and beyond; docs/reference/performance.md); at and above it they take `LARGE_LANES`.
pub const SPLIT_BELOW: usize = 150_000;

/// Threads per particle below `SPLIT_BELOW`, for 2D and 3D.
pub const SPLIT_LANES: [usize; 2] = [4, 8];

/// Threads per particle at and above `SPLIT_BELOW`, for 2D and 3D (1: the CPU's exact
/// summation order; 2, 4 and 8 were slower at 4M particles on an H100, docs/reference/performance.md).
pub const LARGE_LANES: [usize; 2] = [1, 1];

/// Lanes per particle for a system of `n` particles in `dim` dimensions: the size rule,
/// or `MESHFREE_CUDA_LANES` (one of `LANE_COUNTS`) at every size where set, and the threshold
/// `MESHFREE_CUDA_SPLIT_BELOW` where set (both for measurements).
pub fn lanes_for(dim: usize, n: usize) -> usize {
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<usize>().ok());
    if let Some(l) = env("MESHFREE_CUDA_LANES").filter(|l| LANE_COUNTS.contains(l)) {
        return l;
    }
    let d = usize::from(dim == 3);
    if n < env("MESHFREE_CUDA_SPLIT_BELOW").unwrap_or(SPLIT_BELOW) {
        SPLIT_LANES[d]
    } else {
        LARGE_LANES[d]
    }
}

/// The solver with its state in GPU memory.
pub struct CudaSolver<D: Dim> {
    dev: Device,
    k: Kernels,
    params: SphParams,
    buf: Buffers,
    /// The total-Lagrangian bodies (`cuda/tlsph.cu`); `None` under the Jaumann rate or
    /// without solids.
    tl: Option<TlBuffers>,
    /// The floating rigid bodies (`cuda/bodies.cu`); `None` without.
    bodies: Option<BodyBuffers>,
    /// The open boundaries' next id (on the host) and tally (4 doubles per boundary on the
    /// device: `OpenTally`'s fields); `None` without open boundaries.
    open: Option<(u32, CudaSlice<f64>)>,
    /// `Setup::wall_surface` (empty unless `params::needs_wall_surface`); on the device in
    /// `buf`.
    wall_surface: Vec<[f32; 4]>,
    /// `Setup::motion_series`; on the device in `buf`.
    motion_series: Vec<f64>,
    steps: u64,
    /// Whether the grid's cell ranges list the particles at their current positions: set
    /// by `build_grid`, cleared by whatever moves, removes or replaces particles (a drift,
    /// a replayed graph, an upload, `remove_group`). `sample_points` builds a grid where not.
    grid_current: bool,
    /// The probes' points (float4 each) and sums (`MF_SAMPLE_FLOATS` per point) on the
    /// device, grown to the largest request.
    probe_points: Option<CudaSlice<f32>>,
    probe_out: Option<CudaSlice<f32>>,
    /// Host buffers of `snapshot`, kept between frames.
    host_pos: Vec<f32>,
    host_vel: Vec<f32>,
    /// The viewer's vertex buffers, registered at the first `fill_gl` (`view.rs`).
    #[cfg(feature = "interop")]
    gl_view: Option<view::GlView>,
    /// Bytes read back from the device so far (`Readback::device_to_host_bytes`).
    d2h: u64,
    /// The clock [T] and the key of a queued check's fault (`Buffers::time`) as last read
    /// back, while nothing has changed them since (a step, `set_clock`, a queued check).
    clock: Option<(f64, u64)>,
    /// The output frames' download stream and staging sets (made at the first capture).
    capturer: Option<Capturer>,
    /// Two steps of `Solver::step` captured as a CUDA graph (two, so that the grid's buffer
    /// swap comes back to the captured buffers), replayed by `advance`. Dropped whenever the
    /// buffers or the kernels change.
    graph: Option<StepGraph>,
    /// Whether `advance` may capture and replay graphs: `MESHFREE_CUDA_GRAPHS=0` turns them
    /// off (for measurements); a failed capture turns them off for this solver.
    graphs: bool,
    /// The particle count whose size rule (`lanes_for`) sets the neighbour kernels' lanes:
    /// this solver's own at creation, or, for a subdomain of a decomposed run, the whole
    /// scene's (`new_subdomain`), so that every subdomain sums in the one domain's order
    /// (the lane count changes the order of a particle's pair sums).
    lanes_n: usize,
    /// Whether `forces_and_rates` runs the fused kernel: `MESHFREE_CUDA_FUSED=0` runs the two
    /// passes instead (for measurements).
    fused: bool,
    _d: PhantomData<D>,
}

fn oom(n: usize, e: cudarc::driver::DriverError) -> BackendError {
    BackendError::Cuda(format!(
        "allocating device memory for {n} particles failed: {e:?}"
    ))
}

impl<D: Dim> CudaSolver<D> {
    /// The solver on device 0.
    pub fn new(setup: Setup) -> Result<Self, BackendError> {
        Self::new_on(setup, 0)
    }

    /// The solver on device `ordinal` (`Device::open_ordinal`).
    pub fn new_on(setup: Setup, ordinal: usize) -> Result<Self, BackendError> {
        let n = setup.particles.len();
        Self::new_subdomain(setup, n, ordinal)
    }

    /// A solver on device `ordinal` whose neighbour kernels take the lanes of a system of
    /// `whole` particles (`lanes_for`): a subdomain of a decomposed run passes the whole
    /// scene's count, so that its sums come out as the one domain's, bit for bit.
    pub fn new_subdomain(setup: Setup, whole: usize, ordinal: usize) -> Result<Self, BackendError> {
        if let Some(e) = setup.wall_surface_error() {
            return Err(BackendError::Cuda(e));
        }
        if setup.params.gradient_correction != 0 {
            // `--backend auto` takes the CPU for such a scene.
            return Err(BackendError::Cuda(
                "[fluid] gradient_correction runs on the CPU backend only for now: run with \
                 --backend cpu, or without the correction"
                    .into(),
            ));
        }
        let p = setup.params;
        let dev = Device::open_ordinal(ordinal)?;
        let mut k = Kernels::load(&dev, D::D)?;
        let mut state = State::<D>::from_particles(
            &setup.particles,
            p.density_form as u32 == MF_DENSITY_CONTINUITY,
            p.artificial_stress > 0.0,
            p.solid_rho0,
        );
        // A subdomain of a scene with solids holds their arrays from the start, solids or
        // none (`SphParams::own_solids`): they may arrive with a halo.
        if p.own_solids != 0 {
            state = state.with_solid_arrays(p.artificial_stress > 0.0);
        }
        let n = state.len();
        let buf = Buffers::new(
            &dev.stream,
            &state,
            p.n_cells.max(1) as usize,
            &setup.wall_surface,
            &setup.motion_series,
            needs_density_gradient(&p),
        )
        .map_err(|e| oom(n, e))?;
        k.lanes = lanes_for(D::D, whole);
        // The total-Lagrangian bodies' reference configuration, set up on the host by the
        // shared code (`crate::physics::tlsph`) and uploaded once.
        let tl = if crate::physics::tlsph::total_lagrangian(&p) && setup.has_solids() {
            let r = crate::physics::tlsph::Reference::<D>::new(&p, &setup.particles);
            Some(TlBuffers::new(&dev.stream, &r).map_err(|e| oom(n, e))?)
        } else {
            None
        };
        let bodies = if setup.bodies.is_empty() {
            None
        } else {
            Some(BodyBuffers::new(&dev.stream, &setup.bodies).map_err(|e| oom(n, e))?)
        };
        // Open boundaries change the particle count in their stage, which a graph cannot
        // replay: their scenes step without graphs.
        let open = if p.open_count > 0 {
            let start = crate::physics::open::OpenState::start(&p, &setup.particles);
            let tally = dev
                .stream
                .alloc_zeros::<f64>(4 * p.open_count as usize)
                .map_err(|e| oom(n, e))?;
            Some((start.next_id, tally))
        } else {
            None
        };
        Ok(CudaSolver {
            tl,
            bodies,
            open,
            dev,
            k,
            params: p,
            buf,
            wall_surface: setup.wall_surface,
            motion_series: setup.motion_series,
            steps: 0,
            grid_current: false,
            probe_points: None,
            probe_out: None,
            host_pos: Vec::new(),
            host_vel: Vec::new(),
            #[cfg(feature = "interop")]
            gl_view: None,
            d2h: 0,
            clock: None,
            capturer: None,
            graph: None,
            graphs: p.open_count == 0
                && std::env::var("MESHFREE_CUDA_GRAPHS").map_or(true, |v| v != "0"),
            fused: std::env::var("MESHFREE_CUDA_FUSED").map_or(true, |v| v != "0"),
            lanes_n: whole,
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
        let mut read = 0;
        let st = self
            .buf
            .read_state::<D>(&self.dev.stream, &mut read)
            .unwrap_or_else(|e| self.sync_err("reading the state back", e));
        self.d2h += read;
        st
    }

    /// Overwrite the arrays (same length) with `state`; the grid stays. For parity tests.
    pub fn upload_state(&mut self, state: &State<D>) {
        if let Err(e) = self.buf.write_state(&self.dev.stream, state) {
            self.sync_err("uploading a state", e)
        }
        self.grid_current = false;
    }

    /// The total-Lagrangian bodies' displacements u in solid space (read back), where the
    /// scene has them. For parity tests.
    pub fn tl_displacement(&mut self) -> Option<Vec<D::V>> {
        let t = self.tl.as_ref()?;
        Some(
            t.read_disp::<D>(&self.dev.stream)
                .unwrap_or_else(|e| self.sync_err("reading the displacements back", e)),
        )
    }

    /// Set the simulated time [T] and the last step size [T] on the device (a queued
    /// check's fault, if any, stays).
    fn set_clock(&mut self, time: f64, dt: f32) {
        self.clock = None;
        let s = &self.dev.stream;
        let r = s
            .memcpy_htod(&[time][..], &mut self.buf.time.slice_mut(..1))
            .and_then(|_| s.memcpy_htod(&[dt, dt][..], &mut self.buf.dt));
        if let Err(e) = r {
            self.sync_err("setting the clock", e)
        }
    }

    /// The clock [T] and the key of a queued check's fault (0: none), read back together
    /// unless nothing changed them since the last read.
    fn read_clock(&mut self) -> (f64, u64) {
        if let Some(c) = self.clock {
            return c;
        }
        self.d2h += 16;
        let t = self
            .dev
            .stream
            .clone_dtoh(&self.buf.time.slice(..2))
            .unwrap_or_else(|e| self.sync_err("reading the clock", e));
        let c = (t[0], t[1].to_bits());
        self.clock = Some(c);
        c
    }

    /// The fault of the health check's `key` (the complement of `sph_check`'s (slot <<
    /// MF_FAULT_SLOT_SHIFT) | class) at step `step` and time `time`, of the particle `id`
    /// of kind `kind` with position `x`, velocity `v` and density `rho`.
    #[allow(clippy::too_many_arguments)]
    fn fault_of(
        &self,
        key: u64,
        (step, time): (u64, f64),
        id: u32,
        kind: crate::physics::particle::Kind,
        x: [f32; 3],
        v: [f32; 3],
        rho: f32,
    ) -> Fault {
        let code = (!key & ((1 << MF_FAULT_SLOT_SHIFT) - 1)) as u32;
        let value = match code {
            MF_FAULT_NON_FINITE_POSITION => x
                .iter()
                .copied()
                .find(|c| !c.is_finite())
                .unwrap_or(f32::NAN),
            MF_FAULT_NON_FINITE_VELOCITY => v
                .iter()
                .copied()
                .find(|c| !c.is_finite())
                .unwrap_or(f32::NAN),
            MF_FAULT_ESCAPED => (0..D::D)
                .find(|&a| {
                    self.params.periodic[a] == 0
                        && (x[a] < self.params.domain_min[a] || x[a] > self.params.domain_max[a])
                })
                .map_or(f32::NAN, |a| x[a]),
            _ => rho,
        };
        fault(step, time, id, kind, code, value)
    }

    /// Map the total-Lagrangian solid space onto the storage (after a reorder).
    fn tl_map_slots(&mut self) {
        if let Some(t) = self.tl.as_mut() {
            launch::tl_slots(&self.k, &self.dev.stream, &self.buf, t);
        }
    }

    /// Whether the last grid build applied the equation of state (continuity density without
    /// artificial stress), leaving the density pass nothing to do. For parity tests.
    pub fn grid_applied_eos(&self) -> bool {
        self.buf.handover.holds(Mark::EosApplied, By::Solver)
    }

    /// Whether the next rates pass takes its candidates from the forces pass's record of
    /// accepted ones (`Mark::PairsRecorded`, one lane per particle) instead of testing
    /// them. For parity tests.
    pub fn rates_replay_pairs(&self) -> bool {
        self.buf.handover.holds(Mark::PairsRecorded, By::Solver) && self.k.lanes == 1
    }

    /// Whether the neighbour passes skip, for a dynamic wall, the candidate rows of walls at
    /// rest alone now (the last grid build stamped the cells near moving particles:
    /// `Mark::Stamped`). For parity tests.
    pub fn skips_walls_at_rest(&self) -> bool {
        self.buf.handover.holds(Mark::Stamped, By::Solver)
    }

    /// The step size of the last `time_step` \[T\] (read back).
    pub fn dt(&mut self) -> f32 {
        launch::settle_step_size(&self.k, &self.dev.stream, &self.params, &mut self.buf);
        self.d2h += 4;
        self.dev
            .stream
            .clone_dtoh(&self.buf.dt.slice(..1))
            .unwrap_or_else(|e| self.sync_err("reading dt", e))[0]
    }

    /// Force (`Some(lanes)`, one of `LANE_COUNTS`: 1, 2, 4, 8) or reset to the size rule
    /// (`None`) the threads per particle of the neighbour kernels. For tests and benchmarks.
    pub fn set_lanes(&mut self, lanes: Option<usize>) {
        let l = lanes.unwrap_or_else(|| lanes_for(D::D, self.lanes_n));
        assert!(
            LANE_COUNTS.contains(&l),
            "set_lanes: {l} lanes has no kernel entry (have {LANE_COUNTS:?})"
        );
        self.k.lanes = l;
        self.graph = None;
    }

    /// Threads per particle of the neighbour kernels now.
    pub fn lanes(&self) -> usize {
        self.k.lanes
    }

    /// Record two calls of the trait's `step` as a CUDA graph (nothing runs while it is
    /// recorded; the step counter is restored). `None`, and no more graphs for this solver,
    /// where the driver refuses.
    fn capture_pair(&mut self) -> Option<StepGraph> {
        let s = self.dev.stream.clone();
        let (steps, swapped) = (self.steps, self.buf.swapped);
        let mode = sys::CUstreamCaptureMode::CU_STREAM_CAPTURE_MODE_THREAD_LOCAL;
        let graph = match s.begin_capture(mode) {
            Ok(()) => {
                self.step();
                self.step();
                s.end_capture(sys::CUgraphInstantiate_flags(0))
            }
            Err(e) => Err(e),
        };
        self.steps = steps;
        match graph {
            Ok(Some(g)) => Some(StepGraph(g, swapped)),
            Ok(None) | Err(_) => {
                eprintln!(
                    "note: CUDA graph capture refused on {}; stepping kernel by kernel",
                    self.dev.name
                );
                self.graphs = false;
                None
            }
        }
    }

    /// Device memory held by this solver's arrays \[bytes\].
    pub fn device_bytes(&self) -> usize {
        self.buf.bytes
    }

    /// Wait for all queued work.
    pub fn synchronize(&self) {
        if let Err(e) = self.dev.stream.synchronize() {
            self.sync_err("synchronising", e)
        }
    }

    /// nvcc's view of SphParams: (sizeof, offsetof dt, offsetof gravity, dim received).
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
    fn open_boundaries(&mut self) {
        let Some((next_id, tally)) = self.open.as_mut() else {
            return;
        };
        let words = subdomain::halo_words::<D>(self.buf.cur.stress.is_some());
        let s = self.dev.stream.clone();
        let r = launch::open::open_boundaries::<D>(
            &self.k,
            &s,
            &self.params,
            &mut self.buf,
            tally,
            *next_id,
            (words, buffers::nsym::<D>()),
        );
        let done = match r {
            Ok(d) => d,
            Err(e) => self.sync_err("making and removing the open boundaries' particles", e),
        };
        if done.born + done.removed == 0 {
            return;
        }
        if let Some((next_id, _)) = self.open.as_mut() {
            *next_id += done.born as u32;
        }
        // Every particle made or removed is fluid.
        self.buf.kinds[0] = self.buf.kinds[0] + done.born - done.removed;
        // The cells the last drift filed are those of the old slots.
        if self.buf.handover.take(Mark::CellsFiled, By::Storage) {
            if let Err(e) = self.dev.stream.memset_zeros(&mut self.buf.count) {
                self.sync_err("clearing the cell counts", e)
            }
        }
        self.grid_current = false;
        self.graph = None;
    }
    fn build_grid(&mut self) {
        launch::build_grid(&self.k, &self.dev.stream, &self.params, &mut self.buf);
        self.tl_map_slots();
        self.grid_current = true;
    }
    fn density(&mut self) {
        launch::density(
            &self.k,
            &self.dev.stream,
            &self.params,
            &mut self.buf,
            self.bodies.as_ref(),
        );
        launch::open::buffer_density(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn solid_interface(&mut self) {
        launch::solid_interface(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn density_gradient(&mut self) {
        launch::grad_rho(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn rates(&mut self) {
        launch::rates(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn solid_stress(&mut self) {
        if let Some(t) = self.tl.as_mut() {
            launch::tl_stress(&self.k, &self.dev.stream, &self.params, &mut self.buf, t);
        }
    }
    fn forces(&mut self) {
        launch::forces(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }
    fn solid_forces(&mut self) {
        if let Some(t) = self.tl.as_ref() {
            launch::tl_forces(&self.k, &self.dev.stream, &self.params, &mut self.buf, t);
        }
    }
    /// One neighbour pass for both (`cuda/forces_rates.cu`), unless `MESHFREE_CUDA_FUSED=0`.
    fn forces_and_rates(&mut self) {
        if self.fused {
            launch::forces_rates(&self.k, &self.dev.stream, &self.params, &mut self.buf);
        } else {
            self.rates();
            self.forces();
        }
    }
    /// Due from the forces pass's maxima: the kick or the drift-kick that follows takes it
    /// (`Mark::StepSizeDue`; anything else runs `sph_step_size` first).
    fn time_step(&mut self) {
        launch::settle_step_size(&self.k, &self.dev.stream, &self.params, &mut self.buf);
        self.buf
            .handover
            .leave(Mark::StepSizeDue, true, By::TimeStep);
    }
    fn kick(&mut self) {
        // The bodies' loads from the state the force stage saw, before the kick.
        if let Some(bb) = self.bodies.as_mut() {
            launch::body_loads(&self.k, &self.dev.stream, &self.params, &self.buf, bb);
        }
        launch::kick(&self.k, &self.dev.stream, &self.params, &mut self.buf);
        if let Some(bb) = self.bodies.as_mut() {
            launch::body_kick(&self.k, &self.dev.stream, &self.params, &mut self.buf, bb);
        }
    }
    fn drift(&mut self) {
        if let Some(bb) = self.bodies.as_mut() {
            launch::body_drift(&self.k, &self.dev.stream, &self.params, &mut self.buf, bb);
        }
        if let Some(t) = self.tl.as_mut() {
            launch::tl_drift(&self.k, &self.dev.stream, &self.params, &mut self.buf, t);
        }
        launch::drift(&self.k, &self.dev.stream, &self.params, &mut self.buf);
        self.grid_current = false;
        self.clock = None;
        self.steps += 1;
    }
    /// One kernel for both (`cuda/integrate.cu`).
    fn drift_kick(&mut self) {
        // The displacement first: it takes the old velocity, as the positions do.
        if let Some(t) = self.tl.as_mut() {
            launch::tl_drift(&self.k, &self.dev.stream, &self.params, &mut self.buf, t);
        }
        launch::drift_kick(&self.k, &self.dev.stream, &self.params, &mut self.buf);
        self.grid_current = false;
        self.clock = None;
        self.steps += 1;
    }
    fn advance(&mut self, steps: u64) {
        let mut left = steps;
        if self.graphs && left >= 2 {
            // A graph starts from the cell counts a drift leaves (`Mark::CellsFiled`: not so after
            // an upload) and from the buffer assignment it was captured with (not so after an
            // odd number of single steps): single steps until both hold (two at most).
            let ready = |s: &Self| {
                s.buf.handover.holds(Mark::CellsFiled, By::Solver)
                    && s.graph.as_ref().is_none_or(|g| g.1 == s.buf.swapped)
            };
            while left > 0 && !ready(self) {
                self.step();
                left -= 1;
            }
            if self.graph.is_none() && left >= 2 {
                self.graph = self.capture_pair();
            }
            if let Some(g) = &self.graph {
                let pairs = left / 2;
                for _ in 0..pairs {
                    if let Err(e) = g.0.launch() {
                        self.sync_err("launching the captured step graph", e)
                    }
                }
                left -= 2 * pairs;
                self.steps += 2 * pairs;
                if pairs > 0 {
                    self.grid_current = false;
                    self.clock = None;
                }
            }
        }
        for _ in 0..left {
            self.step();
        }
    }
    /// Read back with a queued check's fault (`read_clock`), once per change.
    fn time(&mut self) -> f64 {
        self.read_clock().0
    }
    fn steps(&self) -> u64 {
        self.steps
    }
    fn check(&mut self) -> Result<(), Fault> {
        let key = launch::check(&self.k, &self.dev.stream, &self.params, &mut self.buf)
            .unwrap_or_else(|e| self.sync_err("running the health check", e));
        self.d2h += 8;
        if key == 0 {
            return Ok(());
        }
        let slot = (!key >> MF_FAULT_SLOT_SHIFT) as usize;
        let st = self.download_state();
        let q = st.particle(slot);
        let (x, v) = (D::to3(st.pos[slot]), D::to3(st.vel[slot]));
        let at = (self.steps, self.time());
        Err(self.fault_of(key, at, q.id, q.kind, x, v, st.rho[slot]))
    }
    /// `sph_check` and `sph_check_record` queued: the first fault stays on the device
    /// until `queued_fault` reads it with the clock.
    fn queue_check(&mut self) -> Result<(), Fault> {
        let steps = self.steps;
        launch::queue_check(
            &self.k,
            &self.dev.stream,
            &self.params,
            &mut self.buf,
            steps,
        )
        .unwrap_or_else(|e| self.sync_err("queueing the health check", e));
        self.clock = None;
        Ok(())
    }
    fn queued_fault(&mut self) -> Result<(), Fault> {
        let key = self.read_clock().1;
        if key == 0 {
            return Ok(());
        }
        self.d2h += 4 * MF_FAULT_RECORD_WORDS as u64;
        let r = self
            .dev
            .stream
            .clone_dtoh(&self.buf.fault_rec)
            .unwrap_or_else(|e| self.sync_err("reading the health check's fault", e));
        let f = |w: u32| f32::from_bits(w);
        let kind = crate::physics::particle::Kind::from_code(r[1] as u8)
            .expect("sph_check_record writes a particle's kind code");
        let step = u64::from(r[9]) | (u64::from(r[10]) << 32);
        let time = f64::from_bits(u64::from(r[11]) | (u64::from(r[12]) << 32));
        let x = [f(r[2]), f(r[3]), f(r[4])];
        let v = [f(r[5]), f(r[6]), f(r[7])];
        Err(self.fault_of(key, (step, time), r[0], kind, x, v, f(r[8])))
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
            let buf = Buffers::new(
                &self.dev.stream,
                &st,
                self.buf.n_cells,
                &self.wall_surface,
                &self.motion_series,
                needs_density_gradient(&self.params),
            )
            .unwrap_or_else(|e| panic!("{}", oom(n, e)));
            self.buf = buf;
            self.set_clock(time, dt);
            // The removed solids keep slot NONE; the rest are mapped onto the new storage.
            if let Some(t) = self.tl.as_mut() {
                if let Err(e) = t.clear_slots(&self.dev.stream) {
                    self.sync_err("clearing the total-Lagrangian slot map", e)
                }
            }
            self.tl_map_slots();
            self.graph = None;
            self.grid_current = false;
        }
        removed
    }
}

/// The CUDA solver in the scene's dimension, or why there is none.
pub fn create(setup: Setup) -> Result<Box<dyn Solver>, BackendError> {
    if setup.params.dim == 2 {
        Ok(Box::new(CudaSolver::<crate::physics::dim::D2>::new(setup)?))
    } else {
        Ok(Box::new(CudaSolver::<crate::physics::dim::D3>::new(setup)?))
    }
}

/// The CUDA solvers of `n` subdomains (`backend::Layout::Threads`), all on device 0, their
/// halos on the device (`CudaHalo`); each takes the lanes of the whole scene's particle
/// count, so that the subdomains sum in the one domain's order
/// (`CudaSolver::new_subdomain`).
pub fn decomposed(setup: Setup, n: usize) -> Result<Box<dyn Solver>, BackendError> {
    use crate::exchange::Decomposed;
    let whole = setup.particles.len();
    Ok(if setup.params.dim == 2 {
        Box::new(Decomposed::new(setup, n, |s| {
            CudaSolver::<crate::physics::dim::D2>::new_subdomain(s, whole, 0)
        })?)
    } else {
        Box::new(Decomposed::new(setup, n, |s| {
            CudaSolver::<crate::physics::dim::D3>::new_subdomain(s, whole, 0)
        })?)
    })
}

/// One subdomain on each of `n` GPUs through NCCL (`backend::Layout::Gpus`; `nccl`).
#[cfg(feature = "nccl")]
pub fn multi_gpu(setup: Setup, n: usize) -> Result<Box<dyn Solver>, BackendError> {
    nccl::multi_gpu(setup, n)
}

/// Never: this build has the `nccl` feature off.
#[cfg(not(feature = "nccl"))]
pub fn multi_gpu(_: Setup, _: usize) -> Result<Box<dyn Solver>, BackendError> {
    Err(BackendError::CudaUnavailable(
        "this build has the `nccl` feature off".into(),
    ))
}
