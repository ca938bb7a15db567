//! Every kernel launch of the CUDA backend. Each `unsafe` block names the kernel family whose
//! signature (the table in `kernels.rs`, checked against the PTX) its arguments follow,
//! argument for argument, and what the kernel needs of them beyond their types.

use std::sync::Arc;

use cudarc::driver::{
    sys, CudaContext, CudaSlice, CudaStream, CudaView, CudaViewMut, DeviceRepr, DriverError,
    LaunchConfig, PushKernelArg,
};

use super::buffers::{self, Buffers, KindScans, TlBuffers};
use super::kernels::{Family, Kernel, Kernels, Scheme};
use crate::consts::{MF_BLOCK, MF_LANES_MAX, MF_SAMPLE_FLOATS, MF_SCAN_BLOCK, MF_SCAN_CELLS};
use crate::params::{SphParams, MF_DENSITY_CONTINUITY};
use crate::solver::GlSplat;

// SAFETY: SphParams is the bindgen image of the C struct in `cuda/sph_params.h` (repr(C),
// plain integers and floats, no pointers); kernels take it by value. `tests/cuda_parity.rs`
// checks that nvcc's sizeof and offsets equal Rust's.
unsafe impl DeviceRepr for SphParams {}

/// Null for optional array arguments (the kernels test the pointer).
static NULL: u64 = 0;

/// The scheme of the neighbour entries for the scene in `b` (`Scheme::of`).
fn scheme(p: &SphParams, b: &Buffers) -> Scheme {
    Scheme::of(b.cur.stress.is_some(), p)
}

fn cfg(n: usize) -> LaunchConfig {
    LaunchConfig {
        grid_dim: ((n as u32).div_ceil(MF_BLOCK).max(1), 1, 1),
        block_dim: (MF_BLOCK, 1, 1),
        shared_mem_bytes: 0,
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

/// The two-pass exclusive scan of `n_scan` words of `input` into `local` (per block) and
/// `bsum` (the blocks' totals, then their offsets): `Family::ScanLocal` over
/// ceil(n_scan / MF_SCAN_CELLS) blocks, then `Family::ScanTop` in one; where that is one
/// or two blocks, `Family::ScanLocal` or `Family::ScanOne` alone, in one block, writes the
/// offsets (0): a small grid's build is a kernel shorter. The caller's buffers hold n_scan
/// entries (`local`, 16-byte aligned as `input`) and that many blocks (`bsum`).
fn scan(
    k: &Kernels,
    s: &Arc<CudaStream>,
    n_scan: u32,
    input: &CudaSlice<u32>,
    local: &mut CudaViewMut<u32>,
    bsum: &mut CudaSlice<u32>,
) {
    let nb = n_scan.div_ceil(MF_SCAN_CELLS);
    // SAFETY: the arguments of `Family::ScanLocal` (or `ScanOne`, the same), over n_scan
    // entries; grid of nb blocks (ScanOne: one, for nb = 2) of MF_SCAN_BLOCK; input and
    // local hold n_scan entries, bsum nb (the caller's word).
    let (ks, blocks) = match nb {
        2 => (k.get(Family::ScanOne), 1),
        _ => (k.get(Family::ScanLocal), nb),
    };
    ks.check(unsafe {
        s.launch_builder(&ks.f)
            .arg(&n_scan)
            .arg(input)
            .arg(local)
            .arg(&mut *bsum)
            .launch(LaunchConfig {
                grid_dim: (blocks, 1, 1),
                block_dim: (MF_SCAN_BLOCK, 1, 1),
                shared_mem_bytes: 0,
            })
            .map(|_| ())
    });
    if nb <= 2 {
        return;
    }
    // SAFETY: the arguments of `Family::ScanTop` over nb block totals; one block of
    // MF_SCAN_BLOCK.
    let kt = k.get(Family::ScanTop);
    kt.check(unsafe {
        s.launch_builder(&kt.f)
            .arg(&nb)
            .arg(bsum)
            .launch(LaunchConfig {
                grid_dim: (1, 1, 1),
                block_dim: (MF_SCAN_BLOCK, 1, 1),
                shared_mem_bytes: 0,
            })
            .map(|_| ())
    });
}

/// The last grid build's stamps of the cells near moving particles, where it wrote them
/// (`Buffers::stamped`), for the neighbour passes' skip of a wall's rows of walls at rest.
fn stamps(stamp: &Option<CudaSlice<u8>>, stamped: bool) -> Option<&CudaSlice<u8>> {
    stamp.as_ref().filter(|_| stamped)
}

/// Neighbour grid: hist (unless the last drift did it), scan (1 or 2 kernels), scatter, then the
/// sort by id within cells fused with the reorder (gather), which also writes the cell
/// ranges; then the two persistent buffer sets are swapped.
pub fn build_grid(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    // The reorder writes alt and the cells change: the forces pass's record goes.
    b.pairs_recorded = false;
    b.stamped = false;
    let n = b.n as u32;
    let nc = b.n_cells as u32;
    // The scan runs over n_cells + 1 counts (the last, 0, closes the last cell's range).
    let n_scan = nc + 1;
    if n == 0 {
        return;
    }
    // Cells and counts: already filed by the last drift from the positions it wrote, else
    // here. SAFETY: the arguments of `Family::GridHist` (kernels.rs); pos holds n vectors,
    // cell n, count n_cells + 1 (zero: counted down by the last scatter, cleared by
    // write_state or at allocation).
    if !std::mem::take(&mut b.hist_done) {
        let kh = k.get(Family::GridHist);
        kh.check(unsafe {
            s.launch_builder(&kh.f)
                .arg(p)
                .arg(&n)
                .arg(&b.cur.pos)
                .arg(&mut b.cell)
                .arg(&mut b.count)
                .launch(cfg(b.n))
                .map(|_| ())
        });
    }
    // order and local live in the spare acc and xsph (`buffers::grid_scratch`).
    let (mut order, mut local) =
        buffers::grid_scratch(&mut b.acc, &mut b.xsph, &mut b.local, b.cap, b.n_cells);
    // count holds n_cells + 1 entries, local n_cells + 1 and bsum n_blocks >= nb (16-byte
    // aligned allocations).
    scan(k, s, n_scan, &b.count, &mut local, &mut b.bsum);
    // The cells near moving particles are stamped (and a wall's rows of walls at rest
    // skipped) in 3D at one lane (`Buffers::stamped`).
    b.stamped = b.stamp.is_some() && k.lanes == 1;
    let mut stamp = b.stamp.as_mut().filter(|_| b.stamped);
    let mut epoch = stamp.as_mut().map(|st| st.slice_mut(b.n_cells..));
    // SAFETY: the arguments of `Family::GridScatter`; cell and order hold n entries, red 3
    // (zeroed: the step size's maxima, which no pass holds during a grid build); epoch null
    // or the last byte of `stamp` (advanced).
    let kc = k.get(Family::GridScatter);
    kc.check(unsafe {
        let mut l = s.launch_builder(&kc.f);
        l.arg(&n)
            .arg(&b.cell)
            .arg(&mut local)
            .arg(&b.bsum)
            .arg(&mut b.count)
            .arg(&mut order)
            .arg(&mut b.red);
        opt!(l, epoch.as_mut());
        l.launch(cfg(b.n)).map(|_| ())
    });
    b.red_stale = false;
    // Continuity density without artificial stress: the reorder applies the equation of
    // state and the density pass has nothing left to do (`density` skips it).
    let eos = p.density_form as u32 == MF_DENSITY_CONTINUITY && b.art.is_none();
    let eos_arg = eos as u32;
    {
        let (c, a) = (&b.cur, &mut b.alt);
        // SAFETY: the arguments of `Family::GridGather` (the nine persistent arrays of
        // `cur`, then the same nine of `alt`); cell_start has n_cells + 1 entries, stamp
        // null or n_cells + 1 (its last: the epoch the scatter advanced); stress
        // and rho_dev null in both sets or in neither (both with solids); grid of
        // max(n, n_cells + 1) threads.
        let kg = k.get(Family::GridGather);
        let mut l = s.launch_builder(&kg.f);
        l.arg(p)
            .arg(&n)
            .arg(&nc)
            .arg(&eos_arg)
            .arg(&mut order)
            .arg(&mut local)
            .arg(&b.bsum)
            .arg(&mut b.cell_start);
        opt!(l, stamp);
        l.arg(&c.id)
            .arg(&c.kind)
            .arg(&c.group)
            .arg(&c.pos)
            .arg(&c.vel);
        l.arg(&c.rho).arg(&c.p);
        opt!(l, &c.stress);
        opt!(l, &c.rho_dev);
        l.arg(&mut a.id)
            .arg(&mut a.kind)
            .arg(&mut a.group)
            .arg(&mut a.pos)
            .arg(&mut a.vel);
        l.arg(&mut a.rho).arg(&mut a.p);
        opt!(l, &mut a.stress);
        opt!(l, &mut a.rho_dev);
        let threads = b.n.max(b.n_cells + 1);
        kg.check(unsafe { l.launch(cfg(threads)).map(|_| ()) });
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
    let (kd, lanes) = (k.neighbour(Family::Density, scheme(p, b)), k.lanes);
    let c = &mut b.cur;
    // SAFETY: the arguments of `Family::Density` (kernels.rs); vel is written only in its w
    // slots; rho_dev null without solids, else n entries; art null without artificial stress
    // (then stress is not read), else both hold n_sym planes of n.
    let mut l = s.launch_builder(&kd.f);
    l.arg(p)
        .arg(&n)
        .arg(&b.cell_start)
        .arg(&c.pos)
        .arg(&mut c.vel)
        .arg(&c.kind)
        .arg(&mut c.rho)
        .arg(&mut c.p);
    opt!(l, &mut c.rho_dev);
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
    // SAFETY: the arguments of `Family::GradRho`; grad holds D floats per particle.
    let kg = k.get(Family::GradRho);
    kg.check(unsafe {
        s.launch_builder(&kg.f)
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
    let (kr, lanes) = (k.neighbour(Family::Rates, scheme(p, b)), k.lanes);
    let replay = b.pairs_recorded && lanes == 1;
    let c = &b.cur;
    // SAFETY: the arguments of `Family::Rates` (every scheme's; stamp as for the forces
    // pass); dt_dev holds 2 floats (the kick wrote this step's dt in its first); drho null
    // without the continuity density; stress and rate null without solids (the fluid-only
    // schemes read neither); grad_rho null unless `needs_density_gradient`; pair_a and
    // pair_b null, or the record of the forces pass at these positions
    // (`Buffers::pairs_recorded`: alt's vel and pos, 4 and vstride words per particle),
    // which the kernel only reads.
    let mut l = s.launch_builder(&kr.f);
    l.arg(p).arg(&n).arg(&b.dt).arg(&b.cell_start);
    opt!(l, stamps(&b.stamp, b.stamped));
    l.arg(&c.pos)
        .arg(&c.vel)
        .arg(&c.rho)
        .arg(&c.kind)
        .arg(&c.group);
    opt!(l, &c.stress);
    opt!(l, &b.grad_rho);
    opt!(l, &mut b.drho);
    l.arg(&mut b.xsph);
    opt!(l, &mut b.stress_rate);
    opt!(l, replay.then_some(&b.alt.vel));
    opt!(l, replay.then_some(&b.alt.pos));
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
/// fused kernel appends the rates' outputs. The entry is the scene's `Scheme` (same
/// signatures).
fn launch_forces(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers, fused: bool) {
    clear_red(k, s, p, b);
    if b.n == 0 {
        return;
    }
    if fused {
        grad_rho(k, s, p, b);
    }
    let n = b.n as u32;
    let family = if fused {
        Family::ForcesRates
    } else {
        Family::Forces
    };
    let (kf, lanes) = (k.neighbour(family, scheme(p, b)), k.lanes);
    let c = &b.cur;
    // SAFETY: the arguments of `Family::Forces` or, fused, `Family::ForcesRates` (stamp:
    // null, or n_cells + 1 bytes from the grid build these positions were filed by): the same
    // followed by grad_rho, drho, xsph and rate (every scheme's); stress, art, surf may be
    // null (surf is read only under no_slip, when Buffers holds it: float4 per boundary
    // particle by id - wall_first_id); red holds 3 words; grad_rho, drho and rate may be
    // null, as for the rates kernel; unfused, pair_a and pair_b: alt's vel and pos, 4 and
    // vstride words per particle, which no stage reads between two grid builds (the
    // record of accepted candidates, `Buffers::pairs_recorded`).
    let mut l = s.launch_builder(&kf.f);
    l.arg(p).arg(&n).arg(&b.cell_start);
    opt!(l, stamps(&b.stamp, b.stamped));
    l.arg(&c.pos).arg(&c.vel).arg(&c.rho).arg(&c.p);
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
    } else {
        l.arg(&mut b.alt.vel).arg(&mut b.alt.pos);
    }
    kf.check(unsafe { l.launch(cfg(b.n * lanes)).map(|_| ()) });
    // At one lane the forces kernel records the accepted candidates of every particle with
    // rates, for a rates pass before anything moves the particles or writes alt.
    b.pairs_recorded |= !fused && lanes == 1;
}

pub fn step_size(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    // SAFETY: the arguments of `Family::StepSize`; red holds 3 words.
    let kt = k.get(Family::StepSize);
    kt.check(unsafe {
        s.launch_builder(&kt.f)
            .arg(p)
            .arg(&mut b.red)
            .arg(&mut b.dt)
            .launch(cfg(1))
            .map(|_| ())
    });
    b.dt_pending = false;
}

/// `step_size` where it is pending (`Buffers::dt_pending`): before anything but the kick
/// or the drift-kick that would take it.
pub fn settle_step_size(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    if b.dt_pending {
        step_size(k, s, p, b);
    }
}

/// Before a pass that folds into `red`: the pending step size settled, and `red` zeroed
/// where a kick or drift-kick left it and no grid build cleared it since
/// (`Buffers::red_stale`).
fn clear_red(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    settle_step_size(k, s, p, b);
    if std::mem::take(&mut b.red_stale) {
        if let Err(e) = s.memset_zeros(&mut b.red) {
            panic!("CUDA error while clearing the step size's maxima: {e:?}")
        }
    }
}

/// v += dt a (dt read on the device, or taken from the forces pass's maxima where the step
/// size is pending: `Buffers::dt_pending`); v = inflow_velocity in the inflow band (under a
/// ramped start, `inflow_ramp`, its share at the device clock's time, and the rest
/// accelerated with it); the driven group's velocity set.
pub fn kick(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    if b.n == 0 {
        settle_step_size(k, s, p, b);
        return;
    }
    let n = b.n as u32;
    let c = &mut b.cur;
    // SAFETY: the arguments of `Family::Kick`; dt_dev holds 2 floats; red null or the 3
    // maxima of the forces pass; time the device clock (1 double).
    let kk = k.get(Family::Kick);
    let mut l = s.launch_builder(&kk.f);
    l.arg(p).arg(&n).arg(&mut b.dt);
    opt!(l, b.dt_pending.then_some(&b.red));
    l.arg(&b.time)
        .arg(&c.kind)
        .arg(&c.group)
        .arg(&c.pos)
        .arg(&mut c.vel)
        .arg(&b.acc);
    kk.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
    b.red_stale |= b.dt_pending;
    b.dt_pending = false;
}

/// x += dt (v + xsph), rho += dt d rho/dt, S += dt dS/dt, time += dt (all on the device).
pub fn drift(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    settle_step_size(k, s, p, b);
    drift_with(k.get(Family::Drift), false, s, p, b);
}

/// The forward Euler's drift then kick in one kernel (`Solver::drift_kick`), which takes
/// the step size itself where it is pending (`Buffers::dt_pending`).
pub fn drift_kick(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    drift_with(k.get(Family::DriftKick), true, s, p, b);
}

/// Launches sph_drift (`kick` false) or sph_drift_kick (true), which take the same arguments
/// but for the kick's accelerations, and marks the cells filed for the next grid build.
fn drift_with(f: &Kernel, kick: bool, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    b.pairs_recorded = false;
    b.stamped = false;
    let n = b.n as u32;
    let c = &mut b.cur;
    // SAFETY: the arguments of `Family::Drift` or, with `kick`, `Family::DriftKick` (the
    // same, with red after dt_dev, vel written and acc before cell); drho, rho_dev, stress
    // and rate may be null; red null or the 3 maxima (as for the kick); cell and count as in
    // sph_grid_hist. Launched even for n = 0: it advances the clock.
    let mut l = s.launch_builder(&f.f);
    l.arg(p).arg(&n).arg(&mut b.dt);
    if kick {
        opt!(l, b.dt_pending.then_some(&b.red));
        b.red_stale |= b.dt_pending;
        b.dt_pending = false;
    }
    l.arg(&mut b.time)
        .arg(&c.kind)
        .arg(&c.group)
        .arg(&mut c.pos)
        .arg(&mut c.vel);
    l.arg(&b.xsph).arg(&mut c.rho);
    opt!(l, &b.drho);
    opt!(l, &mut c.rho_dev);
    opt!(l, &mut c.stress);
    opt!(l, &b.stress_rate);
    if kick {
        l.arg(&b.acc);
    }
    l.arg(&mut b.cell).arg(&mut b.count);
    f.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
    b.hist_done = true;
}

/// Most blocks of one wall group's pass (`sph_wall_force_*`): its threads stride over the
/// storage, so any grid covers it; this bounds the partial sums of a large system (a few
/// kB per group) and the final pass's work.
const WALL_FORCE_BLOCKS: usize = 1024;

/// The force [M L T^-2] on the wall particles of each of `groups` (`Solver::wall_forces`),
/// in their order: the grid rebuilt from the current positions (`build_grid`: the drift
/// moved the particles since the last build, and at t = 0 there was none) and the equation
/// of state of the current density unless that build applied it (`sph_monitor_eos`), as
/// the next step's build and density pass will; then one pass per group
/// (`sph_wall_force_*`, block partial sums) and one for the totals
/// (`sph_sum_partials`), of which only the 3 doubles per group are read back.
pub fn wall_forces(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    groups: &[u32],
) -> Result<Vec<[f64; 3]>, DriverError> {
    if b.n == 0 || groups.is_empty() {
        return Ok(vec![[0.0; 3]; groups.len()]);
    }
    build_grid(k, s, p, b);
    let n = b.n as u32;
    if !b.eos_done {
        let c = &mut b.cur;
        // SAFETY: the arguments of `Family::MonitorEos` (kernels.rs); rho_dev null without
        // solids; vel is written only in its w slots.
        let ke = k.get(Family::MonitorEos);
        let mut l = s.launch_builder(&ke.f);
        l.arg(p).arg(&n).arg(&c.kind).arg(&c.rho);
        opt!(l, &c.rho_dev);
        l.arg(&mut c.p).arg(&mut c.vel);
        ke.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
    }
    let blocks = (b.n * MF_LANES_MAX as usize)
        .div_ceil(MF_BLOCK as usize)
        .clamp(1, WALL_FORCE_BLOCKS);
    let g = groups.len();
    let grow =
        |have: &Option<CudaSlice<f64>>, want: usize| have.as_ref().is_none_or(|d| d.len() < want);
    if grow(&b.wall_partial, g * blocks * 3) {
        b.wall_partial = Some(s.alloc_zeros::<f64>(g * WALL_FORCE_BLOCKS * 3)?);
        b.bytes += g * WALL_FORCE_BLOCKS * 3 * std::mem::size_of::<f64>();
    }
    if grow(&b.wall_force, g * 3) {
        b.wall_force = Some(s.alloc_zeros::<f64>(g * 3)?);
        b.bytes += g * 3 * std::mem::size_of::<f64>();
    }
    let (Some(partial), Some(out)) = (&mut b.wall_partial, &mut b.wall_force) else {
        unreachable!("allocated above");
    };
    let family = if b.cur.stress.is_some() {
        Family::WallForce
    } else {
        Family::WallForceFluid
    };
    let kw = k.get(family);
    let c = &b.cur;
    for (slot, group) in groups.iter().enumerate() {
        let slot = slot as u32;
        // SAFETY: the arguments of `Family::WallForce` or `Family::WallForceFluid` (one
        // signature); stress null without solids (the fluid-only entries never read it, the
        // others need it); surf null unless no_slip (read only then: float4 per boundary
        // particle by id - wall_first_id); partial holds (slot + 1) x grid x 3 doubles at
        // least; grid of at most WALL_FORCE_BLOCKS blocks of MF_BLOCK.
        let mut l = s.launch_builder(&kw.f);
        l.arg(p)
            .arg(&n)
            .arg(group)
            .arg(&slot)
            .arg(&b.cell_start)
            .arg(&c.pos)
            .arg(&c.vel)
            .arg(&c.rho)
            .arg(&c.p)
            .arg(&c.kind)
            .arg(&c.group);
        opt!(l, &c.stress);
        l.arg(&c.id);
        opt!(l, &b.wall_surface);
        l.arg(&mut *partial);
        kw.check(unsafe {
            l.launch(LaunchConfig {
                grid_dim: (blocks as u32, 1, 1),
                block_dim: (MF_BLOCK, 1, 1),
                shared_mem_bytes: 0,
            })
            .map(|_| ())
        });
    }
    sum_partials(k, s, blocks as u32, g as u32, partial, out);
    let v = s.clone_dtoh(&*out)?;
    Ok((0..g)
        .map(|i| [v[3 * i], v[3 * i + 1], v[3 * i + 2]])
        .collect())
}

/// out[3 g + k] = the sum over b < n_blocks of partial[(g n_blocks + b) 3 + k], for each
/// of `slots` slots g, in a fixed order (`sph_sum_partials`).
fn sum_partials(
    k: &Kernels,
    s: &Arc<CudaStream>,
    n_blocks: u32,
    slots: u32,
    partial: &CudaSlice<f64>,
    out: &mut CudaSlice<f64>,
) {
    assert!(partial.len() >= (slots * n_blocks * 3) as usize && out.len() >= 3 * slots as usize);
    // SAFETY: the arguments of `Family::SumPartials`; one block of MF_BLOCK per slot,
    // partial holds slots x n_blocks x 3 doubles and out 3 per slot (asserted above).
    let ks = k.get(Family::SumPartials);
    ks.check(unsafe {
        s.launch_builder(&ks.f)
            .arg(&n_blocks)
            .arg(partial)
            .arg(out)
            .launch(LaunchConfig {
                grid_dim: (slots, 1, 1),
                block_dim: (MF_BLOCK, 1, 1),
                shared_mem_bytes: 0,
            })
            .map(|_| ())
    });
}

/// The diagnostics' reductions: sums in a fixed order (per-block partials, then
/// `sum_partials`: the same bits from run to run), maxima and counts by atomics (exact).
pub fn diagnostics(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
) -> Result<(), DriverError> {
    settle_step_size(k, s, p, b);
    s.memset_zeros(&mut b.diag_sums)?;
    s.memset_zeros(&mut b.diag_max)?;
    s.memset_zeros(&mut b.diag_counts)?;
    if b.n == 0 {
        return Ok(());
    }
    let n = b.n as u32;
    let c = &b.cur;
    let launch = cfg(b.n);
    // SAFETY: the arguments of `Family::Diagnostics`; partial holds 2 x 3 doubles per block
    // of the grid (`Buffers::diag_partial`), maxes 2 words, counts 3.
    unsafe {
        s.launch_builder(&k.get(Family::Diagnostics).f)
            .arg(p)
            .arg(&n)
            .arg(&c.kind)
            .arg(&c.pos)
            .arg(&c.vel)
            .arg(&c.rho)
            .arg(&mut b.diag_partial)
            .arg(&mut b.diag_max)
            .arg(&mut b.diag_counts)
            .launch(launch)?;
    }
    sum_partials(
        k,
        s,
        launch.grid_dim.0,
        2,
        &b.diag_partial,
        &mut b.diag_sums,
    );
    Ok(())
}

/// The health check now: the complement of the first fault's key (`sph_check`), 0 where
/// every particle is healthy (a read-back, which waits for the queued work).
pub fn check(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
) -> Result<u64, DriverError> {
    s.memset_zeros(&mut b.first)?;
    launch_check(k, s, p, b)?;
    let found = s.clone_dtoh(&b.first)?[0];
    // Zero between checks (`queue_check` counts on it).
    s.memset_zeros(&mut b.first)?;
    Ok(found)
}

/// `sph_check` into `b.first` (which holds 0).
fn launch_check(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
) -> Result<(), DriverError> {
    if b.n > 0 {
        let n = b.n as u32;
        let c = &b.cur;
        // SAFETY: the arguments of `Family::Check`; first holds 1 word.
        unsafe {
            s.launch_builder(&k.get(Family::Check).f)
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
    Ok(())
}

/// A health check queued on the stream, nothing read back: `sph_check`, then
/// `sph_check_record`, which keeps the first fault found (its key in `b.time[1]`, read back
/// with the clock, and the particle's record, with `step`, in `b.fault_rec`) and clears
/// `b.first`.
pub fn queue_check(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    step: u64,
) -> Result<(), DriverError> {
    if b.n == 0 {
        return Ok(());
    }
    launch_check(k, s, p, b)?;
    let c = &b.cur;
    // SAFETY: the arguments of `Family::CheckRecord`; first holds 1 word, clock 2 doubles,
    // rec MF_FAULT_RECORD_WORDS words; the slot in a nonzero first is below n (sph_check).
    unsafe {
        s.launch_builder(&k.get(Family::CheckRecord).f)
            .arg(&step)
            .arg(&mut b.first)
            .arg(&mut b.time)
            .arg(&mut b.fault_rec)
            .arg(&c.id)
            .arg(&c.kind)
            .arg(&c.pos)
            .arg(&c.vel)
            .arg(&c.rho)
            .launch(cfg(1))?;
    }
    Ok(())
}

/// The probes' sums at the points `points` (float4 each) into `out` (`MF_SAMPLE_FLOATS`
/// per point), from the grid of the last build, which must list the particles at their
/// current positions (`Solver::sample_points`).
pub fn sample_points(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &Buffers,
    (points, walls): (&CudaView<f32>, bool),
    out: &mut CudaSlice<f32>,
) -> Result<(), DriverError> {
    let n_points = points.len() / 4;
    assert!(out.len() >= MF_SAMPLE_FLOATS as usize * n_points);
    if n_points == 0 || b.n == 0 {
        return Ok(());
    }
    let (np, w) = (n_points as u32, walls as u32);
    let c = &b.cur;
    // SAFETY: the arguments of `Family::SamplePoints`; points holds n_points float4 and out
    // MF_SAMPLE_FLOATS floats per point (asserted above); cell_start n_cells + 1 entries of
    // the last grid build over the n particles of `cur`.
    unsafe {
        s.launch_builder(&k.get(Family::SamplePoints).f)
            .arg(p)
            .arg(&np)
            .arg(points)
            .arg(&w)
            .arg(&b.cell_start)
            .arg(&c.pos)
            .arg(&c.vel)
            .arg(&c.rho)
            .arg(&c.kind)
            .arg(&mut *out)
            .launch(cfg(n_points))?;
    }
    Ok(())
}

/// nvcc's (sizeof(SphParams), offsetof dt, offsetof gravity, p.dim as received).
pub fn params_layout(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    out: &mut CudaSlice<u32>,
) -> Result<[u32; 4], DriverError> {
    // SAFETY: the arguments of `Family::ParamsLayout`; out holds 4 words.
    unsafe {
        s.launch_builder(&k.get(Family::ParamsLayout).f)
            .arg(p)
            .arg(&mut *out)
            .launch(cfg(1))?;
    }
    let v = s.clone_dtoh(&*out)?;
    Ok([v[0], v[1], v[2], v[3]])
}

/// Map the total-Lagrangian solid space onto the storage after a reorder: slot[a] = the
/// storage slot of solid a (`cuda/tlsph.cu`, twin `TlBodies::map_slots`).
pub fn tl_slots(k: &Kernels, s: &Arc<CudaStream>, b: &Buffers, t: &mut TlBuffers) {
    if b.n == 0 || t.n_solid == 0 {
        return;
    }
    let (n, n_index) = (b.n as u32, t.n_index as u32);
    let c = &b.cur;
    // SAFETY: the arguments of `Family::TlSlots` (kernels.rs); id and kind hold n entries,
    // index n_index (every id of the storage is below it: `Reference::index_of_id`), whose
    // entries are solid indices below n_solid or NONE; slot holds n_solid.
    let kt = k.get(Family::TlSlots);
    kt.check(unsafe {
        s.launch_builder(&kt.f)
            .arg(&n)
            .arg(&n_index)
            .arg(&c.id)
            .arg(&c.kind)
            .arg(&t.index)
            .arg(&mut t.slot)
            .launch(cfg(b.n))
            .map(|_| ())
    });
}

/// The total-Lagrangian stress stage (`Solver::solid_stress`): H, P L per solid, and the
/// Cauchy pressure, deviator and density written into the slots' p, stress, rho and vel.w.
pub fn tl_stress(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    t: &mut TlBuffers,
) {
    if b.n == 0 || t.n_solid == 0 {
        return;
    }
    let (n, ns) = (b.n as u32, t.n_solid as u32);
    let c = &mut b.cur;
    // SAFETY: the arguments of `Family::TlStress`; slot, vol hold n_solid entries, start
    // n_solid + 1, nbr start[n_solid] (solid indices), x0 and disp n_solid vectors, grad
    // n_solid D x D blocks, corr and pk1_corr n_solid blocks of Q = basis_len(D) columns of D
    // floats, quad n_solid floats; face n_solid blocks of Q floats and face_clamp n_solid solid indices or NONE;
    // every slot is NONE or below n; stress n_sym planes of n (present: the scene has
    // solids).
    let kt = k.get(Family::TlStress);
    let mut l = s.launch_builder(&kt.f);
    l.arg(p)
        .arg(&n)
        .arg(&ns)
        .arg(&t.slot)
        .arg(&t.start)
        .arg(&t.nbr)
        .arg(&t.x0)
        .arg(&t.vol)
        .arg(&t.corr)
        .arg(&t.quad)
        .arg(&t.face)
        .arg(&t.face_clamp)
        .arg(&t.disp)
        .arg(&mut t.grad)
        .arg(&mut t.pk1_corr);
    opt!(l, &mut c.stress);
    kt.check(unsafe { l.launch(cfg(t.n_solid)).map(|_| ()) });
}

/// The total-Lagrangian internal force and hourglass control (`Solver::solid_forces`), added
/// to the slots' accelerations.
pub fn tl_forces(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers, t: &TlBuffers) {
    clear_red(k, s, p, b);
    if b.n == 0 || t.n_solid == 0 {
        return;
    }
    let ns = t.n_solid as u32;
    // SAFETY: the arguments of `Family::TlForces`; the solid-space arrays as in `tl_stress`;
    // face_start holds n_solid + 1 offsets into face_pts (D + 1 + Q floats per point);
    // pos and acc hold n vectors and every slot is NONE or below n; distinct solids have
    // distinct slots, so each thread writes its own acc entry; red holds 3 words (the forces
    // pass's maxima, |a| of these particles left out: `ForceSum::finish`).
    let kt = k.get(Family::TlForces);
    kt.check(unsafe {
        s.launch_builder(&kt.f)
            .arg(p)
            .arg(&ns)
            .arg(&t.slot)
            .arg(&t.start)
            .arg(&t.nbr)
            .arg(&t.x0)
            .arg(&t.vol)
            .arg(&t.face)
            .arg(&t.face_clamp)
            .arg(&t.face_start)
            .arg(&t.face_pts)
            .arg(&t.disp)
            .arg(&t.grad)
            .arg(&t.pk1_corr)
            .arg(&b.cur.pos)
            .arg(&mut b.acc)
            .arg(&mut b.red)
            .launch(cfg(t.n_solid))
            .map(|_| ())
    });
}

/// u += dt (v + xsph), or dt times the driven velocity (dt read on the device); launched
/// before the drift (or the drift-kick), which then moves the positions by the same amount.
pub fn tl_drift(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    t: &mut TlBuffers,
) {
    settle_step_size(k, s, p, b);
    if b.n == 0 || t.n_solid == 0 {
        return;
    }
    let ns = t.n_solid as u32;
    // SAFETY: the arguments of `Family::TlDrift`; dt_dev holds 2 floats; slot and disp as in
    // `tl_stress`; group, vel (float4) and xsph hold n entries.
    let kt = k.get(Family::TlDrift);
    kt.check(unsafe {
        s.launch_builder(&kt.f)
            .arg(p)
            .arg(&ns)
            .arg(&b.dt)
            .arg(&t.slot)
            .arg(&b.cur.group)
            .arg(&b.cur.vel)
            .arg(&b.xsph)
            .arg(&mut t.disp)
            .launch(cfg(t.n_solid))
            .map(|_| ())
    });
}

/// Which particles a subdomain's selection marks (`sph_exchange_mark`).
#[derive(Clone, Copy, Debug)]
pub enum Select {
    /// Those the solver owns (`SphParams::owns`): what `retain_owned` keeps.
    Owned,
    /// Those within `width` [L] of the slab [lo, hi) of `axis` (`Slab::gap`; round
    /// `periodic` = (min, max) where the axis is periodic): a halo.
    Near {
        axis: usize,
        lo: f32,
        hi: f32,
        width: f32,
        periodic: Option<(f32, f32)>,
    },
}

/// Mark the particles `sel` picks, scan the marks (their compacted slots: `Scratch::local`
/// and `bsum`) and read back their count (one word).
pub fn select(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    sel: Select,
) -> Result<usize, DriverError> {
    let n = b.n;
    if n == 0 {
        return Ok(0);
    }
    let (halo, axis, lo, hi, width, (periodic, pmin, pmax)) = match sel {
        Select::Owned => (
            0u32,
            p.own_axis as u32,
            0.0f32,
            0.0f32,
            0.0f32,
            (0u32, 0.0, 0.0),
        ),
        Select::Near {
            axis,
            lo,
            hi,
            width,
            periodic,
        } => (
            1,
            axis as u32,
            lo,
            hi,
            width,
            periodic.map_or((0, 0.0, 0.0), |(a, b)| (1, a, b)),
        ),
    };
    b.scratch(s)?;
    let (pos, x) = (&b.cur.pos, b.scratch.as_mut().expect("allocated above"));
    let n32 = n as u32;
    // SAFETY: the arguments of `Family::ExchangeMark` (kernels.rs); pos holds n vectors,
    // mark n + 1 words (`Scratch` has cap + 1 >= n + 1); grid of n + 1 threads.
    let km = k.get(Family::ExchangeMark);
    km.check(unsafe {
        s.launch_builder(&km.f)
            .arg(p)
            .arg(&n32)
            .arg(&halo)
            .arg(&axis)
            .arg(&lo)
            .arg(&hi)
            .arg(&width)
            .arg(&periodic)
            .arg(&pmin)
            .arg(&pmax)
            .arg(pos)
            .arg(&mut x.mark)
            .launch(cfg(n + 1))
            .map(|_| ())
    });
    // The grid build's scan over the n + 1 marks (the last, 0, gives the count).
    let n_scan = n32 + 1;
    // mark and local hold cap + 1 >= n_scan (16-byte aligned allocations), bsum
    // ceil((cap + 1) / MF_SCAN_CELLS) >= its blocks.
    scan(
        k,
        s,
        n_scan,
        &x.mark,
        &mut x.local.slice_mut(..),
        &mut x.bsum,
    );
    // SAFETY: the arguments of `Family::ExchangeTotal`; local holds n + 1 entries, bsum
    // n / MF_SCAN_CELLS + 1, total 1; one thread.
    let kc = k.get(Family::ExchangeTotal);
    kc.check(unsafe {
        s.launch_builder(&kc.f)
            .arg(&n32)
            .arg(&x.local)
            .arg(&x.bsum)
            .arg(&mut x.total)
            .launch(cfg(1))
            .map(|_| ())
    });
    Ok(s.clone_dtoh(&x.total)?[0] as usize)
}

/// The particles the last `select` marked, packed as records of `words` words
/// (`cuda/exchange.cu`) into `out` (count x words).
pub fn pack(k: &Kernels, s: &Arc<CudaStream>, b: &Buffers, words: usize, out: &mut CudaSlice<u32>) {
    let x = b.scratch.as_ref().expect("pack follows a select");
    let (n, w) = (b.n as u32, words as u32);
    let c = &b.cur;
    // SAFETY: the arguments of `Family::ExchangePack`; mark, local and bsum of the `select`
    // of these n particles (nothing moved them since); the persistent arrays hold n
    // particles (stress planes n apart; stress and rho_dev null without solids, and then
    // `words` leaves their words out); out holds (marked count) x words.
    let kp = k.get(Family::ExchangePack);
    let mut l = s.launch_builder(&kp.f);
    l.arg(&n)
        .arg(&w)
        .arg(&x.mark)
        .arg(&x.local)
        .arg(&x.bsum)
        .arg(&c.id)
        .arg(&c.kind)
        .arg(&c.group)
        .arg(&c.pos)
        .arg(&c.vel)
        .arg(&c.rho)
        .arg(&c.p);
    opt!(l, &c.stress);
    opt!(l, &c.rho_dev);
    l.arg(out);
    kp.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
}

/// Append the records of `halos` ((count, words) each, `words` words per record) after the
/// `b.n` particles held, which `b.cap` must have room for with them; the stress (`planes`
/// symmetric components) re-laid for the new count. Sets `b.n`.
pub fn unpack(
    k: &Kernels,
    s: &Arc<CudaStream>,
    b: &mut Buffers,
    (words, planes): (usize, usize),
    halos: &[(usize, &CudaSlice<u32>)],
) {
    b.pairs_recorded = false;
    b.stamped = false;
    let n0 = b.n;
    let n1 = n0 + halos.iter().map(|h| h.0).sum::<usize>();
    assert!(n1 <= b.cap, "unpack: {n1} particles, room for {}", b.cap);
    if n1 == n0 {
        return;
    }
    let planes = planes as u32;
    if let (Some(src), Some(dst)) = (&b.cur.stress, &mut b.alt.stress) {
        let (a, z) = (n0 as u32, n1 as u32);
        // SAFETY: the arguments of `Family::ExchangeRestride`; src holds planes x n0 floats
        // and dst planes x n1 (both planes x cap); grid of n0 threads.
        let kr = k.get(Family::ExchangeRestride);
        kr.check(unsafe {
            s.launch_builder(&kr.f)
                .arg(&a)
                .arg(&z)
                .arg(&planes)
                .arg(src)
                .arg(dst)
                .launch(cfg(n0))
                .map(|_| ())
        });
    }
    let (ku, w, stride) = (k.get(Family::ExchangeUnpack), words as u32, n1 as u32);
    let mut base = n0 as u32;
    for &(m, words_in) in halos {
        if m == 0 {
            continue;
        }
        let m32 = m as u32;
        let c = &mut b.cur;
        // SAFETY: the arguments of `Family::ExchangeUnpack`; `in` holds m records of
        // `words` words; slots base .. base + m <= n1 <= cap of every persistent array;
        // the stress (when held) is the other set's, re-laid above with planes n1 apart,
        // and rho_dev null exactly where stress is.
        let mut l = s.launch_builder(&ku.f);
        l.arg(&m32)
            .arg(&base)
            .arg(&stride)
            .arg(&w)
            .arg(words_in)
            .arg(&mut c.id)
            .arg(&mut c.kind)
            .arg(&mut c.group)
            .arg(&mut c.pos)
            .arg(&mut c.vel)
            .arg(&mut c.rho)
            .arg(&mut c.p);
        opt!(l, &mut b.alt.stress);
        opt!(l, &mut c.rho_dev);
        ku.check(unsafe { l.launch(cfg(m)).map(|_| ()) });
        base += m32;
    }
    std::mem::swap(&mut b.cur.stress, &mut b.alt.stress);
    b.n = n1;
}

/// Keep the `kept` particles the last `select` marked, in storage order: moved into the
/// other persistent set, which becomes the current one. Sets `b.n`.
pub fn compact(k: &Kernels, s: &Arc<CudaStream>, b: &mut Buffers, kept: usize) {
    b.pairs_recorded = false;
    b.stamped = false;
    let x = b.scratch.as_ref().expect("compact follows a select");
    let (n, kept32) = (b.n as u32, kept as u32);
    let (c, a) = (&b.cur, &mut b.alt);
    // SAFETY: the arguments of `Family::ExchangeCompact` (the nine persistent arrays of
    // `cur`, n particles with stress planes n apart, then the same nine of `alt`, which
    // receives `kept` <= n with planes kept apart); mark, local and bsum of the `select` of
    // these n particles; stress and rho_dev null in both sets or in neither.
    let kc = k.get(Family::ExchangeCompact);
    let mut l = s.launch_builder(&kc.f);
    l.arg(&n)
        .arg(&kept32)
        .arg(&x.mark)
        .arg(&x.local)
        .arg(&x.bsum)
        .arg(&c.id)
        .arg(&c.kind)
        .arg(&c.group)
        .arg(&c.pos)
        .arg(&c.vel)
        .arg(&c.rho)
        .arg(&c.p);
    opt!(l, &c.stress);
    opt!(l, &c.rho_dev);
    l.arg(&mut a.id)
        .arg(&mut a.kind)
        .arg(&mut a.group)
        .arg(&mut a.pos)
        .arg(&mut a.vel)
        .arg(&mut a.rho)
        .arg(&mut a.p);
    opt!(l, &mut a.stress);
    opt!(l, &mut a.rho_dev);
    kc.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
    std::mem::swap(&mut b.cur, &mut b.alt);
    b.swapped = !b.swapped;
    b.n = kept;
}

// ---- The viewer's vertex buffers: CUDA-OpenGL interop (`view.rs`, `cuda/view.cu`) ----

/// `cuGraphicsGLRegisterBuffer` of `cudaGL.h`, which cudarc does not declare:
/// `CUresult cuGraphicsGLRegisterBuffer(CUgraphicsResource* pCudaResource, GLuint buffer,
/// unsigned int Flags)`.
type GlRegisterBuffer =
    unsafe extern "C" fn(*mut sys::CUgraphicsResource, u32, u32) -> sys::CUresult;

/// The driver's `cuGraphicsGLRegisterBuffer`, looked up by `cuGetProcAddress` (the driver is
/// loaded at run time, as cudarc loads it).
fn gl_register_entry() -> Result<GlRegisterBuffer, DriverError> {
    let mut f: *mut std::ffi::c_void = std::ptr::null_mut();
    let mut found = sys::CUdriverProcAddressQueryResult::CU_GET_PROC_ADDRESS_SYMBOL_NOT_FOUND;
    // SAFETY: the symbol is a NUL-terminated string; f and found are written once each.
    // 3000: the API version that introduced the entry (CUDA 3.0), flags 0: the default.
    unsafe {
        sys::cuGetProcAddress_v2(
            c"cuGraphicsGLRegisterBuffer".as_ptr(),
            &mut f,
            3000,
            0,
            &mut found,
        )
    }
    .result()?;
    if f.is_null() || found != sys::CUdriverProcAddressQueryResult::CU_GET_PROC_ADDRESS_SUCCESS {
        return Err(DriverError(sys::CUresult::CUDA_ERROR_NOT_FOUND));
    }
    // SAFETY: the driver's entry of that name at API version 3000 has the signature of
    // cudaGL.h that `GlRegisterBuffer` declares (a pointer to the resource handle, the GL
    // buffer name as GLuint = u32, the flags as unsigned int = u32).
    Ok(unsafe { std::mem::transmute::<*mut std::ffi::c_void, GlRegisterBuffer>(f) })
}

/// Registers the OpenGL buffer named `buffer` (in the context current on this thread, which
/// must run on the device of `ctx`) for CUDA to overwrite whole (write-discard).
pub fn gl_register(ctx: &CudaContext, buffer: u32) -> Result<sys::CUgraphicsResource, DriverError> {
    let register = gl_register_entry()?;
    ctx.bind_to_thread()?;
    let mut r: sys::CUgraphicsResource = std::ptr::null_mut();
    let flags = sys::CUgraphicsRegisterFlags::CU_GRAPHICS_REGISTER_FLAGS_WRITE_DISCARD as u32;
    // SAFETY: `register` is the driver's cuGraphicsGLRegisterBuffer (gl_register_entry); r
    // receives one handle; the caller's GL context is current (the driver checks that the
    // name is a buffer of it and fails otherwise).
    unsafe { register(&mut r, buffer, flags) }.result()?;
    Ok(r)
}

/// Unregisters a resource of `gl_register` (unmapped; the GL context should still exist).
pub fn gl_unregister(ctx: &CudaContext, r: sys::CUgraphicsResource) -> Result<(), DriverError> {
    ctx.bind_to_thread()?;
    // SAFETY: r came from gl_register and is unregistered once (its owner forgets it).
    unsafe { sys::cuGraphicsUnregisterResource(r) }.result()
}

/// Maps `res` for the work queued on `s` after it (the map waits for OpenGL's work on the
/// buffers) and returns each one's device address and size in bytes.
pub fn gl_map(
    s: &CudaStream,
    res: &mut [sys::CUgraphicsResource],
) -> Result<Vec<(sys::CUdeviceptr, usize)>, DriverError> {
    s.context().bind_to_thread()?;
    // SAFETY: res holds registered, unmapped resources of this context; the map is ordered
    // on s.
    unsafe { sys::cuGraphicsMapResources(res.len() as u32, res.as_mut_ptr(), s.cu_stream()) }
        .result()?;
    res.iter()
        .map(|&r| {
            let (mut ptr, mut size) = (0, 0usize);
            // SAFETY: r is mapped (above); ptr and size are written once each.
            unsafe { sys::cuGraphicsResourceGetMappedPointer_v2(&mut ptr, &mut size, r) }
                .result()
                .map(|_| (ptr, size))
        })
        .collect()
}

/// Unmaps `res` after the work queued on `s` (OpenGL's next use of the buffers waits for it).
pub fn gl_unmap(s: &CudaStream, res: &mut [sys::CUgraphicsResource]) -> Result<(), DriverError> {
    s.context().bind_to_thread()?;
    // SAFETY: res holds the resources `gl_map` mapped on s.
    unsafe { sys::cuGraphicsUnmapResources(res.len() as u32, res.as_mut_ptr(), s.cu_stream()) }
        .result()
}

/// The viewer's vertex fill (`cuda/view.cu`): the marks of the fluid and the solids
/// (`Family::ViewMark`), their scans, then `Family::ViewFill`, which writes the `b.n`
/// particles' positions, quantity `shown` (MF_SHOWN_*) and kinds into the mapped buffers
/// `out` (positions, values, kinds: device addresses of at least 12 n, 4 n and n bytes),
/// each at its place in the kind order (`b.kinds` the class counts, equal to the storage's:
/// checked by the caller), and, where `range` is given (two words, zeroed here), the colour
/// range of the particles that set it (`hidden`: bit k hides kind k).
#[allow(clippy::too_many_arguments)]
pub fn view_fill(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &Buffers,
    shown: u32,
    hidden: u32,
    out: [sys::CUdeviceptr; 3],
    range: Option<&mut CudaSlice<u32>>,
    order: &mut KindScans,
) -> Result<(), DriverError> {
    let n = b.n as u32;
    if n == 0 {
        return Ok(());
    }
    let c = &b.cur;
    let solids = b.kinds[1] > 0;
    let km = k.get(Family::ViewMark);
    {
        let [mf, ms] = &mut order.mark;
        let mut l = s.launch_builder(&km.f);
        l.arg(&n).arg(&c.kind).arg(mf);
        if solids {
            l.arg(ms);
        } else {
            l.arg(&NULL);
        }
        // SAFETY: the arguments of `Family::ViewMark`: kind holds n particles, the marks
        // `order.cap` >= n entries (the caller's check), mark_solid null without solids.
        km.check(unsafe { l.launch(cfg(b.n)) }.map(|_| ()));
    }
    // The grid build's scan over the n marks of each (mark and local hold cap >= n entries,
    // 16-byte aligned allocations; bsum ceil(cap / MF_SCAN_CELLS) blocks).
    for q in 0..if solids { 2 } else { 1 } {
        scan(
            k,
            s,
            n,
            &order.mark[q],
            &mut order.local[q].slice_mut(..),
            &mut order.bsum[q],
        );
    }
    let (n_fluid, n_solid) = (b.kinds[0] as u32, b.kinds[1] as u32);
    let kf = k.get(Family::ViewFill);
    let mut l = s.launch_builder(&kf.f);
    l.arg(p)
        .arg(&n)
        .arg(&shown)
        .arg(&hidden)
        .arg(&c.pos)
        .arg(&c.vel)
        .arg(&c.rho)
        .arg(&c.p)
        .arg(&c.kind)
        .arg(&out[0])
        .arg(&out[1])
        .arg(&out[2]);
    match range {
        Some(r) => {
            s.memset_zeros(&mut *r)?;
            l.arg(r);
        }
        None => {
            l.arg(&NULL);
        }
    }
    l.arg(&order.local[0]).arg(&order.bsum[0]);
    if solids {
        l.arg(&order.local[1]).arg(&order.bsum[1]);
    } else {
        l.arg(&NULL).arg(&NULL);
    }
    l.arg(&n_fluid).arg(&n_solid);
    // SAFETY: the arguments of `Family::ViewFill`: pos, vel, rho, p and kind hold the n
    // current particles; out holds device addresses of mapped buffers of at least 12 n, 4 n
    // and n bytes (checked by the caller, view.rs); range holds 2 words or is null; the
    // scans hold n entries (the solids' null without solids), and n_fluid + n_solid <= n
    // counts the kinds of the storage (`b.kinds`, checked by the caller), so every slot
    // written is below n.
    unsafe { l.launch(cfg(b.n)) }.map(|_| ())
}

/// The viewer's visibility splat (`cuda/view.cu`) over the filled buffers `filled`
/// (positions, values, kinds: device addresses of `view_fill`'s output): `key` zeroed,
/// `Family::ViewSplat` over the particles `sp.first .. sp.first + sp.count`, then
/// `Family::ViewPixels` into the mapped buffer `out` (`sp.bytes()` bytes: the pixels'
/// quadruples, then their kinds). `cam` holds 17 floats, `key` at least width x height words.
pub fn view_splat(
    k: &Kernels,
    s: &Arc<CudaStream>,
    sp: &GlSplat,
    filled: [sys::CUdeviceptr; 3],
    out: sys::CUdeviceptr,
    cam: &mut CudaSlice<f32>,
    key: &mut CudaSlice<u64>,
) -> Result<(), DriverError> {
    let pixels = sp.width as usize * sp.height as usize;
    let mut c = [0.0f32; 17];
    c[..12].copy_from_slice(&sp.view);
    c[12..16].copy_from_slice(&sp.ray);
    c[16] = sp.radius;
    s.memcpy_htod(&c, &mut *cam)?;
    s.memset_zeros(&mut key.slice_mut(..pixels))?;
    let (first, count, hidden) = (sp.first as u32, sp.count as u32, u32::from(sp.hidden));
    let (w, h) = (sp.width, sp.height);
    if count > 0 {
        let ks = k.get(Family::ViewSplat);
        let mut l = s.launch_builder(&ks.f);
        l.arg(&first)
            .arg(&count)
            .arg(&filled[0])
            .arg(&filled[2])
            .arg(&hidden)
            .arg(&*cam)
            .arg(&w)
            .arg(&h)
            .arg(&mut *key);
        // SAFETY: the arguments of `Family::ViewSplat`: pos and kind are filled buffers of
        // at least first + count particles (the caller's check), cam 17 floats, key at least
        // width x height words (every pixel written lies in the view).
        ks.check(unsafe { l.launch(cfg(sp.count)) }.map(|_| ()));
    }
    let kp = k.get(Family::ViewPixels);
    let out_kind = out + 16 * pixels as u64;
    let n = pixels as u32;
    let mut l = s.launch_builder(&kp.f);
    l.arg(&n)
        .arg(&*key)
        .arg(&filled[0])
        .arg(&filled[1])
        .arg(&filled[2])
        .arg(&out)
        .arg(&out_kind);
    // SAFETY: the arguments of `Family::ViewPixels`: key holds the pixels' words, whose
    // particles index the filled buffers (the splat's), and out holds 17 bytes a pixel
    // (the caller's check): 16 from its start, then one from out_kind.
    unsafe { l.launch(cfg(pixels)) }.map(|_| ())
}
