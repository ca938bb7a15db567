//! The total-Lagrangian solids (`cuda/tlsph.cu`): the slot map, the stress, the internal force
//! and the drift of the solids' displacement.

use std::sync::Arc;

use cudarc::driver::{CudaStream, PushKernelArg};

use super::{
    cfg,
    integrate::{clear_red, settle_step_size},
    NULL,
};
use crate::backend::cuda::buffers::Buffers;
use crate::backend::cuda::kernels::{Family, Kernels};
use crate::backend::cuda::tl_buffers::TlBuffers;
use crate::physics::params::SphParams;

/// Map the total-Lagrangian solid space onto the storage after a reorder: slot[a] = the
/// storage slot of solid a (`cuda/tlsph.cu`, twin `TlBodies::map_slots`).
pub fn tl_slots(k: &Kernels, s: &Arc<CudaStream>, b: &Buffers, t: &mut TlBuffers) {
    if b.n == 0 || t.n_solid == 0 {
        return;
    }
    let (n, n_index) = (b.n as u32, t.n_index as u32);
    let c = &b.cur;
    let kt = k.get(Family::TlSlots);
    // SAFETY: the arguments of `Family::TlSlots` (kernels.rs); id and kind hold n entries,
    // index n_index (every id of the storage is below it: `Reference::index_of_id`), whose
    // entries are solid indices below n_solid or NONE; slot holds n_solid.
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
    // SAFETY: the arguments of `Family::TlStress`; slot, vol hold n_solid entries, start
    // n_solid + 1, nbr start[n_solid] (solid indices), x0 and disp n_solid vectors, grad
    // n_solid D x D blocks, corr and pk1_corr n_solid blocks of Q = basis_len(D) columns of D
    // floats, quad n_solid floats; face n_solid blocks of Q floats and face_clamp n_solid solid indices or NONE;
    // every slot is NONE or below n; stress n_sym planes of n (present: the scene has
    // solids).
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
    let kt = k.get(Family::TlForces);
    // SAFETY: the arguments of `Family::TlForces`; the solid-space arrays as in `tl_stress`;
    // face_start holds n_solid + 1 offsets into face_pts (D + 1 + Q floats per point);
    // pos and acc hold n vectors and every slot is NONE or below n; distinct solids have
    // distinct slots, so each thread writes its own acc entry; red holds 3 words (the forces
    // pass's maxima, |a| of these particles left out: `ForceSum::finish`).
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
    let kt = k.get(Family::TlDrift);
    // SAFETY: the arguments of `Family::TlDrift`; dt_dev holds 2 floats; time the clock
    // (`Buffers::time`, 3 doubles); slot and disp as in `tl_stress`; group, pos, vel (float4)
    // and xsph hold n entries; series the driven motions' knots.
    kt.check(unsafe {
        s.launch_builder(&kt.f)
            .arg(p)
            .arg(&ns)
            .arg(&b.dt)
            .arg(&b.time)
            .arg(&t.slot)
            .arg(&b.cur.group)
            .arg(&b.cur.pos)
            .arg(&b.cur.vel)
            .arg(&b.xsph)
            .arg(&mut t.disp)
            .arg(&b.motion_series)
            .launch(cfg(t.n_solid))
            .map(|_| ())
    });
}
