//! The neighbour passes (`cuda/density.cu`, `forces.cu`, `rates.cu`, `forces_rates.cu`): the
//! summation density, the density gradients, the rates and the forces, alone or fused.

use std::sync::Arc;

use cudarc::driver::{CudaStream, PushKernelArg};

use super::{cfg, grid::stamps, integrate::clear_red, scheme, NULL};
use crate::backend::cuda::body_buffers::BodyBuffers;
use crate::backend::cuda::buffers::Buffers;
use crate::backend::cuda::handover::{By, Mark};
use crate::backend::cuda::kernels::{Family, Kernels};
use crate::physics::params::SphParams;

pub fn density(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    bodies: Option<&BodyBuffers>,
) {
    wall_density(k, s, p, b, bodies);
    if b.n == 0 || b.handover.take(Mark::EosApplied, By::Density) {
        return;
    }
    let n = b.n as u32;
    let (kd, lanes) = (k.neighbour(Family::Density, scheme(p, b)), k.lanes);
    let c = &mut b.cur;
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
    // SAFETY: the arguments of `Family::Density` (kernels.rs); vel is written only in its w
    // slots; rho_dev null without solids, else n entries; art null without artificial stress
    // (then stress is not read), else both hold n_sym planes of n.
    kd.check(unsafe { l.launch(cfg(b.n * lanes)).map(|_| ()) });
}

/// mDBC walls (`MF_WALL_COUPLING_MDBC`): each wall particle's density, pressure and w slot
/// from its ghost node (`sph_wall_density`), first in the density stage, whether or not the
/// grid build applied the equation of state (it did so from the walls' old densities); the
/// normals of floating bodies (`bodies`) and turning walls turned to the clock's time.
/// Nothing under other wall couplings.
fn wall_density(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    bodies: Option<&BodyBuffers>,
) {
    if p.wall_coupling as u32 != crate::physics::params::MF_WALL_COUPLING_MDBC || b.n == 0 {
        return;
    }
    let n = b.n as u32;
    let surface = b
        .wall_surface
        .as_ref()
        .expect("mDBC walls hold Setup::wall_surface on the device (CudaSolver::new checks it)");
    let n_bodies = bodies.map_or(0, |bb| bb.n_bodies as u32);
    let c = &mut b.cur;
    let kw = k.get(Family::WallDensity);
    let mut l = s.launch_builder(&kw.f);
    l.arg(p)
        .arg(&n)
        .arg(&b.cell_start)
        .arg(&c.pos)
        .arg(&mut c.vel)
        .arg(&c.kind)
        .arg(&c.id)
        .arg(&c.group)
        .arg(surface)
        .arg(&b.time);
    match bodies {
        Some(bb) => l.arg(&bb.bodies),
        None => l.arg(&NULL),
    };
    l.arg(&n_bodies)
        .arg(&b.motion_series)
        .arg(&mut c.rho)
        .arg(&mut c.p);
    // SAFETY: the arguments of `Family::WallDensity`; surface holds 4 floats per boundary
    // particle, indexed by id - wall_first_id (every boundary id is in range:
    // `Setup::wall_surface_error`); the clock's first double is the time; bodies null where
    // n_bodies is 0, else n_bodies records; series the driven motions' knots; vel is written
    // only in the walls' w slots.
    kw.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
}

/// The fluid's pressure extrapolated to the bodies' particles (`Buffers::iface`), which the
/// forces pass (alone or fused) reads: the interface stage; nothing without solids or where
/// the bodies meet the fluid at their own pressure.
pub fn solid_interface(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    if !crate::physics::pairs::extrapolated(p) {
        return;
    }
    let Some(e) = b.iface.as_mut().filter(|_| b.n > 0) else {
        return;
    };
    let n = b.n as u32;
    let c = &b.cur;
    let ki = k.get(Family::SolidInterface);
    // SAFETY: the arguments of `Family::SolidInterface`; iface holds 2 floats per particle.
    ki.check(unsafe {
        s.launch_builder(&ki.f)
            .arg(p)
            .arg(&n)
            .arg(&b.cell_start)
            .arg(&c.pos)
            .arg(&c.rho)
            .arg(&c.p)
            .arg(&c.kind)
            .arg(e)
            .launch(cfg(b.n))
            .map(|_| ())
    });
}

/// The renormalised density gradients for the density diffusion in Antuono et al.'s form
/// (`Buffers::grad_rho`, held only where `needs_density_gradient`), which the rates pass
/// (alone or fused with the forces) reads: the density gradient stage.
pub fn grad_rho(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    let Some(g) = b.grad_rho.as_mut().filter(|_| b.n > 0) else {
        return;
    };
    let n = b.n as u32;
    let c = &b.cur;
    let kg = k.get(Family::GradRho);
    // SAFETY: the arguments of `Family::GradRho`; grad holds D floats per particle.
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
    let n = b.n as u32;
    let (kr, lanes) = (k.neighbour(Family::Rates, scheme(p, b)), k.lanes);
    let replay = b.handover.holds(Mark::PairsRecorded, By::Rates) && lanes == 1;
    let stamped = b.handover.holds(Mark::Stamped, By::Rates);
    let c = &b.cur;
    let mut l = s.launch_builder(&kr.f);
    l.arg(p).arg(&n).arg(&b.dt).arg(&b.cell_start);
    opt!(l, stamps(&b.stamp, stamped));
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
    // SAFETY: the arguments of `Family::Rates` (every scheme's; stamp as for the forces
    // pass); dt_dev holds 2 floats (the kick wrote this step's dt in its first); drho null
    // without the continuity density; stress and rate null without solids (the fluid-only
    // schemes read neither); grad_rho null unless `needs_density_gradient`; pair_a and
    // pair_b null, or the record of the forces pass at these positions
    // (`Mark::PairsRecorded`: alt's vel and pos, 4 and vstride words per particle),
    // which the kernel only reads.
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
    let n = b.n as u32;
    let family = if fused {
        Family::ForcesRates
    } else {
        Family::Forces
    };
    let (kf, lanes) = (k.neighbour(family, scheme(p, b)), k.lanes);
    let stamped = b.handover.holds(Mark::Stamped, By::Forces);
    let c = &b.cur;
    let mut l = s.launch_builder(&kf.f);
    l.arg(p).arg(&n).arg(&b.cell_start);
    opt!(l, stamps(&b.stamp, stamped));
    l.arg(&c.pos).arg(&c.vel).arg(&c.rho).arg(&c.p);
    l.arg(&c.kind).arg(&c.group);
    opt!(l, &c.stress);
    opt!(l, &b.art);
    opt!(
        l,
        b.iface
            .as_ref()
            .filter(|_| crate::physics::pairs::extrapolated(p))
    );
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
    // SAFETY: the arguments of `Family::Forces` or, fused, `Family::ForcesRates` (iface:
    // null, or 2 floats per particle from this step's interface stage; stamp:
    // null, or n_cells + 1 bytes from the grid build these positions were filed by): the same
    // followed by grad_rho, drho, xsph and rate (every scheme's); stress, art, surf may be
    // null (surf is read only under no_slip, when Buffers holds it: float4 per boundary
    // particle by id - wall_first_id); red holds 3 words; grad_rho, drho and rate may be
    // null, as for the rates kernel; unfused, pair_a and pair_b: alt's vel and pos, 4 and
    // vstride words per particle, which no stage reads between two grid builds (the
    // record of accepted candidates, `Mark::PairsRecorded`).
    kf.check(unsafe { l.launch(cfg(b.n * lanes)).map(|_| ()) });
    // At one lane the forces kernel records the accepted candidates of every particle with
    // rates, for a rates pass before anything moves the particles or writes alt.
    if !fused && lanes == 1 {
        b.handover.leave(Mark::PairsRecorded, true, By::Forces);
    }
}
