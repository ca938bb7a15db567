//! Reductions over the particles (`cuda/reduce.cu`, `cuda/monitor.cu`, `cuda/probes.cu`): the
//! walls' forces, the diagnostics, the health checks, the probes and the parameters' layout.

use std::sync::Arc;

use cudarc::driver::{CudaSlice, CudaStream, CudaView, DriverError, LaunchConfig, PushKernelArg};

use super::{cfg, grid::build_grid, integrate::settle_step_size, NULL};
use crate::backend::cuda::buffers::Buffers;
use crate::backend::cuda::handover::{By, Mark};
use crate::backend::cuda::kernels::{Family, Kernels};
use crate::consts::{MF_BLOCK, MF_LANES_MAX, MF_SAMPLE_FLOATS};
use crate::physics::params::SphParams;

/// Most blocks of one wall group's pass (`sph_wall_force_*`): its threads stride over the
/// storage, so any grid covers it; this bounds the partial sums of a large system (a few
/// kB per group) and the final pass's work.
pub(crate) const WALL_FORCE_BLOCKS: usize = 1024;

/// The force [M L T^-2] on the wall particles of each of `groups` (`Readback::wall_forces`),
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
    if !b.handover.holds(Mark::EosApplied, By::WallForces) {
        let c = &mut b.cur;
        let ke = k.get(Family::MonitorEos);
        let mut l = s.launch_builder(&ke.f);
        l.arg(p).arg(&n).arg(&c.kind).arg(&c.rho);
        opt!(l, &c.rho_dev);
        l.arg(&mut c.p).arg(&mut c.vel);
        // SAFETY: the arguments of `Family::MonitorEos` (kernels.rs); rho_dev null without
        // solids; vel is written only in its w slots.
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
        // SAFETY: the arguments of `Family::WallForce` or `Family::WallForceFluid` (one
        // signature); stress null without solids (the fluid-only entries never read it, the
        // others need it); surf null unless no_slip (read only then: float4 per boundary
        // particle by id - wall_first_id); partial holds (slot + 1) x grid x 3 doubles at
        // least; grid of at most WALL_FORCE_BLOCKS blocks of MF_BLOCK.
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
pub(super) fn sum_partials(
    k: &Kernels,
    s: &Arc<CudaStream>,
    n_blocks: u32,
    slots: u32,
    partial: &CudaSlice<f64>,
    out: &mut CudaSlice<f64>,
) {
    assert!(partial.len() >= (slots * n_blocks * 3) as usize && out.len() >= 3 * slots as usize);
    let ks = k.get(Family::SumPartials);
    // SAFETY: the arguments of `Family::SumPartials`; one block of MF_BLOCK per slot,
    // partial holds slots x n_blocks x 3 doubles and out 3 per slot (asserted above).
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
/// current positions (`Readback::sample_points`).
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
