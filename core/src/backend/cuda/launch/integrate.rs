//! The step size and the time integration (`cuda/reduce.cu`'s step size, `cuda/integrate.cu`):
//! the kick, the drift and the forward Euler's drift-kick.

use std::sync::Arc;

use cudarc::driver::{CudaStream, PushKernelArg};

use super::{cfg, NULL};
use crate::backend::cuda::buffers::Buffers;
use crate::backend::cuda::handover::{By, Mark};
use crate::backend::cuda::kernels::{Family, Kernel, Kernels};
use crate::physics::params::SphParams;

pub fn step_size(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    let kt = k.get(Family::StepSize);
    // SAFETY: the arguments of `Family::StepSize`; red holds 3 words.
    kt.check(unsafe {
        s.launch_builder(&kt.f)
            .arg(p)
            .arg(&mut b.red)
            .arg(&mut b.dt)
            .launch(cfg(1))
            .map(|_| ())
    });
}

/// `step_size` where it is due (`Mark::StepSizeDue`): before anything but the kick or the
/// drift-kick that would take it.
pub fn settle_step_size(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    if b.handover.take(Mark::StepSizeDue, By::StepSize) {
        step_size(k, s, p, b);
    }
}

/// Before a pass that folds into `red`: the pending step size settled, and `red` zeroed
/// where a kick or drift-kick left it and no grid build cleared it since
/// (`Mark::RedStale`).
pub(super) fn clear_red(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    settle_step_size(k, s, p, b);
    if b.handover.take(Mark::RedStale, By::Forces) {
        if let Err(e) = s.memset_zeros(&mut b.red) {
            panic!("CUDA error while clearing the step size's maxima: {e:?}")
        }
    }
}

/// v += dt a (dt read on the device, or taken from the forces pass's maxima where the step
/// size is due: `Mark::StepSizeDue`); v = inflow_velocity in the inflow band (under a
/// ramped start, `inflow_ramp`, its share at the device clock's time, and the rest
/// accelerated with it); the driven group's velocity set.
pub fn kick(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    if b.n == 0 {
        settle_step_size(k, s, p, b);
        return;
    }
    let n = b.n as u32;
    let due = b.handover.take(Mark::StepSizeDue, By::Kick);
    if due {
        b.handover.leave(Mark::RedStale, true, By::Kick);
    }
    let c = &mut b.cur;
    let kk = k.get(Family::Kick);
    let mut l = s.launch_builder(&kk.f);
    l.arg(p).arg(&n).arg(&mut b.dt);
    opt!(l, due.then_some(&b.red));
    l.arg(&mut b.time)
        .arg(&c.kind)
        .arg(&c.group)
        .arg(&c.pos)
        .arg(&mut c.vel)
        .arg(&b.acc)
        .arg(&b.motion_series);
    // SAFETY: the arguments of `Family::Kick`; dt_dev holds 2 floats; red null or the 3
    // maxima of the forces pass; time the device clock (`Buffers::time`, 3 doubles); series
    // the knots every driven motion's series_first and series_count index.
    kk.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
}

/// x += dt (v + xsph), rho += dt d rho/dt, S += dt dS/dt, time += dt (all on the device).
pub fn drift(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    settle_step_size(k, s, p, b);
    drift_with(k.get(Family::Drift), false, s, p, b);
}

/// The forward Euler's drift then kick in one kernel (`Solver::drift_kick`), which takes
/// the step size itself where it is due (`Mark::StepSizeDue`).
pub fn drift_kick(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    drift_with(k.get(Family::DriftKick), true, s, p, b);
}

/// Launches sph_drift (`kick` false) or sph_drift_kick (true), which take the same arguments
/// but for the kick's accelerations, and marks the cells filed for the next grid build.
fn drift_with(f: &Kernel, kick: bool, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    b.handover.moved();
    let by = if kick { By::DriftKick } else { By::Drift };
    // The drift-kick takes a due step size from red, as the kick does.
    let due = kick && b.handover.take(Mark::StepSizeDue, By::DriftKick);
    if due {
        b.handover.leave(Mark::RedStale, true, By::DriftKick);
    }
    let n = b.n as u32;
    let c = &mut b.cur;
    let mut l = s.launch_builder(&f.f);
    l.arg(p).arg(&n).arg(&mut b.dt);
    if kick {
        opt!(l, due.then_some(&b.red));
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
    if !kick {
        l.arg(&b.motion_series);
    }
    // SAFETY: the arguments of `Family::Drift` (series last: the knots every driven motion
    // indexes) or, with `kick`, `Family::DriftKick` (the same, with red after dt_dev, vel
    // written and acc before cell, and no series); drho, rho_dev, stress and rate may be null; red null or the 3 maxima (as for the kick); cell and count as in
    // sph_grid_hist. Launched even for n = 0: it advances the clock.
    f.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
    b.handover.leave(Mark::CellsFiled, true, by);
}
