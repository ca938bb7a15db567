//! Every kernel launch of the CUDA backend. Each `unsafe` block names the kernel signature
//! (in `cuda/*.cu`) whose argument list it matches, argument for argument.

use std::sync::Arc;

use cudarc::driver::{
    CudaFunction, CudaSlice, CudaStream, DeviceRepr, DriverError, LaunchConfig, PushKernelArg,
};

use super::buffers::Buffers;
use super::device::Device;
use crate::backend::BackendError;
use crate::consts::{MF_BLOCK, MF_LANES_MAX, MF_SCAN_BLOCK, MF_SCAN_CELLS};
use crate::params::{lean_scheme, SphParams, MF_DENSITY_CONTINUITY};

// SAFETY: SphParams is the bindgen image of the C struct in `cuda/sph_params.h` (repr(C),
// plain integers and floats, no pointers); kernels take it by value. `tests/cuda_parity.rs`
// checks that nvcc's sizeof and offsets equal Rust's.
unsafe impl DeviceRepr for SphParams {}

/// Null for optional array arguments (the kernels test the pointer).
static NULL: u64 = 0;

fn cfg(n: usize) -> LaunchConfig {
    LaunchConfig {
        grid_dim: ((n as u32).div_ceil(MF_BLOCK).max(1), 1, 1),
        block_dim: (MF_BLOCK, 1, 1),
        shared_mem_bytes: 0,
    }
}

/// One loaded kernel and where it came from (for error messages).
pub struct Kernel {
    f: CudaFunction,
    module: &'static str,
    name: String,
}

impl Kernel {
    fn load(dev: &Device, module: &'static str, name: String) -> Result<Kernel, BackendError> {
        Ok(Kernel {
            f: dev.function(module, &name)?,
            module,
            name,
        })
    }
    fn check(&self, r: Result<(), DriverError>) {
        if let Err(e) = r {
            panic!(
                "CUDA launch of kernel `{}` (module `{}`) failed: {e:?}",
                self.name, self.module
            );
        }
    }
}

/// Lane counts with kernel entries, in index order: the powers of two from 1 to
/// `MF_LANES_MAX` (`MF_LANES_EACH` in `cuda/sph_consts.h`).
pub const LANE_COUNTS: [usize; MF_LANES_MAX.trailing_zeros() as usize + 1] = {
    let mut l = [1; MF_LANES_MAX.trailing_zeros() as usize + 1];
    let mut k = 1;
    while k < l.len() {
        l[k] = 2 * l[k - 1];
        k += 1;
    }
    l
};

/// The neighbour kernels of one family, one per lane count of `LANE_COUNTS`.
pub struct PerLanes([Kernel; 4]);

impl PerLanes {
    fn load(
        dev: &Device,
        module: &'static str,
        name: &str,
        dim: usize,
    ) -> Result<Self, BackendError> {
        let k = |l: usize| Kernel::load(dev, module, format!("{name}_{l}_{dim}d"));
        Ok(PerLanes([k(1)?, k(2)?, k(4)?, k(8)?]))
    }
    /// The entry for `lanes` (one of `LANE_COUNTS`).
    fn get(&self, lanes: usize) -> &Kernel {
        let i = LANE_COUNTS
            .iter()
            .position(|&l| l == lanes)
            .unwrap_or_else(|| panic!("no kernel entry for {lanes} lanes (have {LANE_COUNTS:?})"));
        &self.0[i]
    }
}

/// All kernels of one dimension.
pub struct Kernels {
    hist: Kernel,
    scan_local: Kernel,
    scan_top: Kernel,
    scatter: Kernel,
    gather: Kernel,
    density: PerLanes,
    forces: PerLanes,
    forces_fluid: PerLanes,
    rates: PerLanes,
    rates_fluid: PerLanes,
    forces_rates: PerLanes,
    forces_rates_fluid: PerLanes,
    forces_lean: PerLanes,
    rates_lean: PerLanes,
    forces_rates_lean: PerLanes,
    grad_rho: Kernel,
    /// Threads per particle in the neighbour kernels (density, forces, rates), one of
    /// `LANE_COUNTS`; set by the solver from the system size.
    pub lanes: usize,
    step_size: Kernel,
    kick: Kernel,
    drift: Kernel,
    drift_kick: Kernel,
    diagnostics: Kernel,
    check: Kernel,
    layout: Kernel,
}

impl Kernels {
    pub fn load(dev: &Device, dim: usize) -> Result<Kernels, BackendError> {
        let d = |s: &str| format!("{s}_{dim}d");
        let plain = |s: &str| s.to_string();
        Ok(Kernels {
            hist: Kernel::load(dev, "grid", d("sph_grid_hist"))?,
            scan_local: Kernel::load(dev, "grid", plain("sph_scan_local"))?,
            scan_top: Kernel::load(dev, "grid", plain("sph_scan_top"))?,
            scatter: Kernel::load(dev, "grid", plain("sph_grid_scatter"))?,
            gather: Kernel::load(dev, "grid", d("sph_grid_gather"))?,
            density: PerLanes::load(dev, "density", "sph_density", dim)?,
            forces: PerLanes::load(dev, "forces", "sph_forces", dim)?,
            forces_fluid: PerLanes::load(dev, "forces", "sph_forces_fluid", dim)?,
            rates: PerLanes::load(dev, "rates", "sph_rates", dim)?,
            rates_fluid: PerLanes::load(dev, "rates", "sph_rates_fluid", dim)?,
            forces_rates: PerLanes::load(dev, "forces_rates", "sph_forces_rates", dim)?,
            forces_rates_fluid: PerLanes::load(dev, "forces_rates", "sph_forces_rates_fluid", dim)?,
            forces_lean: PerLanes::load(dev, "forces", "sph_forces_lean", dim)?,
            rates_lean: PerLanes::load(dev, "rates", "sph_rates_lean", dim)?,
            forces_rates_lean: PerLanes::load(dev, "forces_rates", "sph_forces_rates_lean", dim)?,
            grad_rho: Kernel::load(dev, "rates", d("sph_grad_rho"))?,
            lanes: 1,
            step_size: Kernel::load(dev, "reduce", plain("sph_step_size"))?,
            kick: Kernel::load(dev, "integrate", d("sph_kick"))?,
            drift: Kernel::load(dev, "integrate", d("sph_drift"))?,
            drift_kick: Kernel::load(dev, "integrate", d("sph_drift_kick"))?,
            diagnostics: Kernel::load(dev, "reduce", d("sph_diagnostics"))?,
            check: Kernel::load(dev, "reduce", d("sph_check"))?,
            layout: Kernel::load(dev, "reduce", plain("sph_params_layout"))?,
        })
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

/// Neighbour grid: hist (unless the last drift did it), scan (2 kernels), scatter, then the
/// sort by id within cells fused with the reorder (gather), which also writes the cell
/// ranges; then the two persistent buffer sets are swapped.
pub fn build_grid(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    let n = b.n as u32;
    let nc = b.n_cells as u32;
    // The scan runs over n_cells + 1 counts (the last, 0, closes the last cell's range).
    let n_scan = nc + 1;
    let nb = n_scan.div_ceil(MF_SCAN_CELLS);
    if n == 0 {
        return;
    }
    // Cells and counts: already filed by the last drift from the positions it wrote, else
    // here. SAFETY: sph_grid_hist_{2,3}d(const SphParams p, unsigned n, const float* pos,
    // unsigned* cell, unsigned* count); pos holds n vectors, cell n, count n_cells + 1 (zero:
    // counted down by the last scatter, cleared by write_state or at allocation).
    if !std::mem::take(&mut b.hist_done) {
        k.hist.check(unsafe {
            s.launch_builder(&k.hist.f)
                .arg(p)
                .arg(&n)
                .arg(&b.cur.pos)
                .arg(&mut b.cell)
                .arg(&mut b.count)
                .launch(cfg(b.n))
                .map(|_| ())
        });
    }
    // SAFETY: sph_scan_local(unsigned n_cells, const unsigned* count, unsigned* local,
    // unsigned* bsum), over n_scan entries; grid of ceil(n_scan / MF_SCAN_CELLS) blocks of
    // MF_SCAN_BLOCK, bsum
    // has that many, local n_scan (16-byte aligned, as count).
    k.scan_local.check(unsafe {
        s.launch_builder(&k.scan_local.f)
            .arg(&n_scan)
            .arg(&b.count)
            .arg(&mut b.local)
            .arg(&mut b.bsum)
            .launch(LaunchConfig {
                grid_dim: (nb, 1, 1),
                block_dim: (MF_SCAN_BLOCK, 1, 1),
                shared_mem_bytes: 0,
            })
            .map(|_| ())
    });
    // SAFETY: sph_scan_top(unsigned n_blocks, unsigned* bsum); one block of MF_SCAN_BLOCK.
    k.scan_top.check(unsafe {
        s.launch_builder(&k.scan_top.f)
            .arg(&nb)
            .arg(&mut b.bsum)
            .launch(LaunchConfig {
                grid_dim: (1, 1, 1),
                block_dim: (MF_SCAN_BLOCK, 1, 1),
                shared_mem_bytes: 0,
            })
            .map(|_| ())
    });
    // SAFETY: sph_grid_scatter(unsigned n, const unsigned* cell, const unsigned* local,
    // const unsigned* bsum, unsigned* count, unsigned* order).
    k.scatter.check(unsafe {
        s.launch_builder(&k.scatter.f)
            .arg(&n)
            .arg(&b.cell)
            .arg(&b.local)
            .arg(&b.bsum)
            .arg(&mut b.count)
            .arg(&mut b.order)
            .launch(cfg(b.n))
            .map(|_| ())
    });
    // Continuity density without artificial stress: the reorder applies the equation of
    // state and the density pass has nothing left to do (`density` skips it).
    let eos = p.density_mode as u32 == MF_DENSITY_CONTINUITY && b.art.is_none();
    let eos_arg = eos as u32;
    {
        let (c, a) = (&b.cur, &mut b.alt);
        // SAFETY: sph_grid_gather_{2,3}d(const SphParams p, unsigned n, unsigned n_cells,
        // unsigned eos, const unsigned* order, const unsigned* local,
        // const unsigned* bsum, unsigned* cell_start, const unsigned* id,
        // const unsigned char* kind, const unsigned* group, const float* pos, const float* vel,
        // const float* rho, const float* pr, const float* stress, then the same eight outputs);
        // cell_start has n_cells + 1 entries; stress null in both sets or in neither; grid of
        // max(n, n_cells + 1) threads.
        let mut l = s.launch_builder(&k.gather.f);
        l.arg(p)
            .arg(&n)
            .arg(&nc)
            .arg(&eos_arg)
            .arg(&b.order)
            .arg(&b.local)
            .arg(&b.bsum)
            .arg(&mut b.cell_start);
        l.arg(&c.id)
            .arg(&c.kind)
            .arg(&c.group)
            .arg(&c.pos)
            .arg(&c.vel);
        l.arg(&c.rho).arg(&c.p);
        opt!(l, &c.stress);
        l.arg(&mut a.id)
            .arg(&mut a.kind)
            .arg(&mut a.group)
            .arg(&mut a.pos)
            .arg(&mut a.vel);
        l.arg(&mut a.rho).arg(&mut a.p);
        opt!(l, &mut a.stress);
        let threads = b.n.max(b.n_cells + 1);
        k.gather
            .check(unsafe { l.launch(cfg(threads)).map(|_| ()) });
    }
    b.eos_done = eos;
    std::mem::swap(&mut b.cur, &mut b.alt);
    b.swapped = !b.swapped;
}

pub fn density(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    if b.n == 0 || std::mem::take(&mut b.eos_done) {
        return;
    }
    let n = b.n as u32;
    let c = &mut b.cur;
    let (kd, lanes) = (k.density.get(k.lanes), k.lanes);
    // SAFETY: sph_density_{1,2,4,8}_{2,3}d(const SphParams p, unsigned n, const unsigned* cell_start,
    // const float* pos, float* vel, const unsigned char* kind, float* rho, float* pr,
    // const float* stress, float* art); vel is written only in its w slots;
    // art null without artificial stress (then stress is not read), else both hold n_sym
    // planes of n.
    let mut l = s.launch_builder(&kd.f);
    l.arg(p)
        .arg(&n)
        .arg(&b.cell_start)
        .arg(&c.pos)
        .arg(&mut c.vel)
        .arg(&c.kind)
        .arg(&mut c.rho)
        .arg(&mut c.p);
    opt!(l, &c.stress);
    opt!(l, &mut b.art);
    kd.check(unsafe { l.launch(cfg(b.n * lanes)).map(|_| ()) });
}

/// The renormalised density gradients for the density diffusion in Antuono et al.'s form
/// (`Buffers::grad_rho`, held only where `needs_density_gradient`), before a rates pass.
fn grad_rho(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    let Some(g) = &mut b.grad_rho else {
        return;
    };
    let n = b.n as u32;
    let c = &b.cur;
    // SAFETY: sph_grad_rho_{2,3}d(const SphParams p, unsigned n, const unsigned*
    // cell_start, const float* pos, const float* vel, const float* rho,
    // const unsigned char* kind, const unsigned* group, float* grad); grad holds D floats per
    // particle.
    k.grad_rho.check(unsafe {
        s.launch_builder(&k.grad_rho.f)
            .arg(p)
            .arg(&n)
            .arg(&b.cell_start)
            .arg(&c.pos)
            .arg(&c.vel)
            .arg(&c.rho)
            .arg(&c.kind)
            .arg(&c.group)
            .arg(g)
            .launch(cfg(b.n))
            .map(|_| ())
    });
}

/// d rho/dt, XSPH and the Jaumann stress rate from the current velocities.
pub fn rates(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    if b.n == 0 {
        return;
    }
    grad_rho(k, s, p, b);
    let n = b.n as u32;
    let c = &b.cur;
    let lanes = k.lanes;
    let kr = match (c.stress.is_some(), lean_scheme(p)) {
        (true, _) => k.rates.get(lanes),
        (false, false) => k.rates_fluid.get(lanes),
        (false, true) => k.rates_lean.get(lanes),
    };
    // SAFETY: sph_rates[_fluid]_{1,2,4,8}_{2,3}d(const SphParams p, unsigned n, const unsigned*
    // cell_start, const float* pos, const float* vel, const float* rho,
    // const unsigned char* kind, const unsigned* group, const float* stress,
    // const float* grad_rho, float* drho, float* xsph, float* rate); drho null without the
    // continuity density; stress and rate null without solids (the fluid variants read
    // neither); grad_rho null without the density diffusion inside bodies.
    let mut l = s.launch_builder(&kr.f);
    l.arg(p)
        .arg(&n)
        .arg(&b.cell_start)
        .arg(&c.pos)
        .arg(&c.vel)
        .arg(&c.rho)
        .arg(&c.kind)
        .arg(&c.group);
    opt!(l, &c.stress);
    opt!(l, &b.grad_rho);
    opt!(l, &mut b.drho);
    l.arg(&mut b.xsph);
    opt!(l, &mut b.stress_rate);
    kr.check(unsafe { l.launch(cfg(b.n * lanes)).map(|_| ()) });
}

pub fn forces(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    launch_forces(k, s, p, b, false);
}

/// `forces` and `rates` of one state in one neighbour pass (the forward Euler's order).
pub fn forces_rates(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    launch_forces(k, s, p, b, true);
}

/// The forces pass, alone or fused with the rates (`fused`): one argument list, to which the
/// fused kernel appends the rates' outputs. Fluid-only scenes take the variants without
/// tensor terms, and of those the lean ones where `lean_scheme` holds (same signatures).
fn launch_forces(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers, fused: bool) {
    if b.n == 0 {
        return;
    }
    if fused {
        grad_rho(k, s, p, b);
    }
    let n = b.n as u32;
    let c = &b.cur;
    let lanes = k.lanes;
    let kf = match (fused, c.stress.is_some(), lean_scheme(p)) {
        (false, true, _) => k.forces.get(lanes),
        (false, false, false) => k.forces_fluid.get(lanes),
        (false, false, true) => k.forces_lean.get(lanes),
        (true, true, _) => k.forces_rates.get(lanes),
        (true, false, false) => k.forces_rates_fluid.get(lanes),
        (true, false, true) => k.forces_rates_lean.get(lanes),
    };
    // SAFETY: sph_forces[_fluid]_{1,2,4,8}_{2,3}d(const SphParams p, unsigned n, const unsigned* cell_start,
    // const float* pos, const float* vel, const float* rho, const float* pr,
    // const unsigned char* kind, const unsigned* group, const float* stress, const float* art,
    // const unsigned* id, const float* surf, float* acc, unsigned* red); stress, art, surf may
    // be null (surf is read only under no_slip, when Buffers holds it: float4 per boundary
    // particle by id - wall_first_id); red holds 3 words.
    // sph_forces_rates[_fluid]_{1,2,4,8}_{2,3}d takes the same arguments followed by rates'
    // inputs and outputs, const float* grad_rho, float* drho, float* xsph, float* rate
    // (grad_rho, drho and rate may be null, as for the rates kernel).
    let mut l = s.launch_builder(&kf.f);
    l.arg(p)
        .arg(&n)
        .arg(&b.cell_start)
        .arg(&c.pos)
        .arg(&c.vel)
        .arg(&c.rho)
        .arg(&c.p);
    l.arg(&c.kind).arg(&c.group);
    opt!(l, &c.stress);
    opt!(l, &b.art);
    l.arg(&c.id);
    opt!(l, &b.wall_surface);
    l.arg(&mut b.acc).arg(&mut b.red);
    if fused {
        opt!(l, &b.grad_rho);
        opt!(l, &mut b.drho);
        l.arg(&mut b.xsph);
        opt!(l, &mut b.stress_rate);
    }
    kf.check(unsafe { l.launch(cfg(b.n * lanes)).map(|_| ()) });
}

pub fn step_size(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    // SAFETY: sph_step_size(const SphParams p, unsigned* red, float* dt_out); red 3 words.
    k.step_size.check(unsafe {
        s.launch_builder(&k.step_size.f)
            .arg(p)
            .arg(&mut b.red)
            .arg(&mut b.dt)
            .launch(cfg(1))
            .map(|_| ())
    });
}

/// v += dt a (dt read on the device); v = inflow_velocity in the inflow band; the driven
/// group's velocity set.
pub fn kick(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    if b.n == 0 {
        return;
    }
    let n = b.n as u32;
    let c = &mut b.cur;
    // SAFETY: sph_kick_{2,3}d(const SphParams p, unsigned n, const float* dt_dev,
    // const unsigned char* kind, const unsigned* group, const float* pos, float* vel,
    // const float* acc).
    k.kick.check(unsafe {
        s.launch_builder(&k.kick.f)
            .arg(p)
            .arg(&n)
            .arg(&b.dt)
            .arg(&c.kind)
            .arg(&c.group)
            .arg(&c.pos)
            .arg(&mut c.vel)
            .arg(&b.acc)
            .launch(cfg(b.n))
            .map(|_| ())
    });
}

/// x += dt (v + xsph), rho += dt d rho/dt, S += dt dS/dt, time += dt (all on the device).
pub fn drift(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    drift_with(&k.drift, false, s, p, b);
}

/// The forward Euler's drift then kick in one kernel (`Solver::drift_kick`).
pub fn drift_kick(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    drift_with(&k.drift_kick, true, s, p, b);
}

/// Launches sph_drift (`kick` false) or sph_drift_kick (true), which take the same arguments
/// but for the kick's accelerations, and marks the cells filed for the next grid build.
fn drift_with(f: &Kernel, kick: bool, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    let n = b.n as u32;
    let c = &mut b.cur;
    // SAFETY: sph_drift_{2,3}d(const SphParams p, unsigned n, const float* dt_dev,
    // double* time, const unsigned char* kind, const unsigned* group, float* pos,
    // const float* vel, const float* xsph, float* rho, const float* drho, float* stress,
    // const float* rate, unsigned* cell, unsigned* count); sph_drift_kick_{2,3}d the same
    // with float* vel and const float* acc before cell. drho, stress and rate may be null;
    // cell and count as in sph_grid_hist. Launched even for n = 0: it advances the clock.
    let mut l = s.launch_builder(&f.f);
    l.arg(p)
        .arg(&n)
        .arg(&b.dt)
        .arg(&mut b.time)
        .arg(&c.kind)
        .arg(&c.group)
        .arg(&mut c.pos)
        .arg(&mut c.vel);
    l.arg(&b.xsph).arg(&mut c.rho);
    opt!(l, &b.drho);
    opt!(l, &mut c.stress);
    opt!(l, &b.stress_rate);
    if kick {
        l.arg(&b.acc);
    }
    l.arg(&mut b.cell).arg(&mut b.count);
    f.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
    b.hist_done = true;
}

pub fn diagnostics(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
) -> Result<(), DriverError> {
    s.memset_zeros(&mut b.diag_sums)?;
    s.memset_zeros(&mut b.diag_max)?;
    s.memset_zeros(&mut b.diag_counts)?;
    if b.n == 0 {
        return Ok(());
    }
    let n = b.n as u32;
    let c = &b.cur;
    // SAFETY: sph_diagnostics_{2,3}d(const SphParams p, unsigned n, const unsigned char* kind,
    // const float* pos, const float* vel, const float* rho, double* sums (4),
    // unsigned* maxes (2), unsigned* counts (3)).
    unsafe {
        s.launch_builder(&k.diagnostics.f)
            .arg(p)
            .arg(&n)
            .arg(&c.kind)
            .arg(&c.pos)
            .arg(&c.vel)
            .arg(&c.rho)
            .arg(&mut b.diag_sums)
            .arg(&mut b.diag_max)
            .arg(&mut b.diag_counts)
            .launch(cfg(b.n))?;
    }
    Ok(())
}

pub fn check(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
) -> Result<u64, DriverError> {
    s.memcpy_htod(&[u64::MAX][..], &mut b.first)?;
    if b.n > 0 {
        let n = b.n as u32;
        let c = &b.cur;
        // SAFETY: sph_check_{2,3}d(const SphParams p, unsigned n, const unsigned char* kind,
        // const float* pos, const float* vel, const float* rho, unsigned long long* first).
        unsafe {
            s.launch_builder(&k.check.f)
                .arg(p)
                .arg(&n)
                .arg(&c.kind)
                .arg(&c.pos)
                .arg(&c.vel)
                .arg(&c.rho)
                .arg(&mut b.first)
                .launch(cfg(b.n))?;
        }
    }
    Ok(s.clone_dtoh(&b.first)?[0])
}

/// nvcc's (sizeof(SphParams), offsetof dt_fixed, offsetof gravity, p.dim as received).
pub fn params_layout(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    out: &mut CudaSlice<u32>,
) -> Result<[u32; 4], DriverError> {
    // SAFETY: sph_params_layout(const SphParams p, unsigned* out); out holds 4 words.
    unsafe {
        s.launch_builder(&k.layout.f)
            .arg(p)
            .arg(&mut *out)
            .launch(cfg(1))?;
    }
    let v = s.clone_dtoh(&*out)?;
    Ok([v[0], v[1], v[2], v[3]])
}
