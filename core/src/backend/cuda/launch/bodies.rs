//! The floating rigid bodies' launches (`cuda/bodies.cu`, and `cuda/monitor.cu`'s
//! `sph_body_load_*`): the loads before the particles' kick, the bodies' kick and their
//! particles' velocities after it, and the bodies' drift and their particles' move before
//! the particles' drift. All on the device, inside the step's graph.

use std::sync::Arc;

use cudarc::driver::{CudaStream, LaunchConfig, PushKernelArg};

use super::{cfg, reduce::sum_partials, settle_step_size, NULL};
use crate::backend::cuda::body_buffers::BodyBuffers;
use crate::backend::cuda::buffers::Buffers;
use crate::backend::cuda::kernels::{Family, Kernels};
use crate::consts::{MF_BLOCK, MF_LANES_MAX};
use crate::physics::params::SphParams;

use super::reduce::WALL_FORCE_BLOCKS;

/// The fluid's force and torque on every body's particles and the contacts' (one
/// `sph_body_load_*` pass per body, block partial sums, then `sph_sum_partials`), from the
/// state the force stage saw: its grid, pressures and velocities (launched before the
/// particles' kick).
pub fn body_loads(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &Buffers,
    bb: &mut BodyBuffers,
) {
    let n = b.n as u32;
    let blocks = (b.n * MF_LANES_MAX as usize)
        .div_ceil(MF_BLOCK as usize)
        .clamp(1, WALL_FORCE_BLOCKS);
    let family = if b.cur.stress.is_some() {
        Family::BodyLoad
    } else {
        Family::BodyLoadFluid
    };
    let kl = k.get(family);
    let c = &b.cur;
    for body in 0..bb.n_bodies as u32 {
        let mut l = s.launch_builder(&kl.f);
        l.arg(p)
            .arg(&n)
            .arg(&bb.bodies)
            .arg(&body)
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
        l.arg(&mut bb.partial);
        // SAFETY: the arguments of `Family::BodyLoad` or `Family::BodyLoadFluid` (one
        // signature); body < n_bodies; stress null without solids; surf null unless
        // no_slip; partial holds 4 n_bodies x WALL_FORCE_BLOCKS x 3 doubles
        // (`BodyBuffers::new`); grid of at most WALL_FORCE_BLOCKS blocks.
        kl.check(unsafe {
            l.launch(LaunchConfig {
                grid_dim: (blocks as u32, 1, 1),
                block_dim: (MF_BLOCK, 1, 1),
                shared_mem_bytes: 0,
            })
            .map(|_| ())
        });
    }
    sum_partials(
        k,
        s,
        blocks as u32,
        4 * bb.n_bodies as u32,
        &bb.partial,
        &mut bb.load,
    );
}

/// The bodies' kick under their loads (after the particles' kick, which settled dt), then
/// their particles' velocities.
pub fn body_kick(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    bb: &mut BodyBuffers,
) {
    let nb = bb.n_bodies as u32;
    let kk = k.get(Family::BodyKick);
    // SAFETY: the arguments of `Family::BodyKick`; dt_dev holds 2 floats, load 12 doubles
    // per body.
    kk.check(unsafe {
        s.launch_builder(&kk.f)
            .arg(p)
            .arg(&nb)
            .arg(&b.dt)
            .arg(&bb.load)
            .arg(&mut bb.bodies)
            .launch(cfg(bb.n_bodies))
            .map(|_| ())
    });
    if b.n == 0 {
        return;
    }
    let n = b.n as u32;
    let kv = k.get(Family::BodyVelocity);
    let c = &mut b.cur;
    // SAFETY: the arguments of `Family::BodyVelocity`; the state's arrays hold n particles.
    kv.check(unsafe {
        s.launch_builder(&kv.f)
            .arg(&n)
            .arg(&nb)
            .arg(&bb.bodies)
            .arg(&c.kind)
            .arg(&c.group)
            .arg(&c.pos)
            .arg(&mut c.vel)
            .launch(cfg(b.n))
            .map(|_| ())
    });
}

/// The bodies' drift over the step's dt (settled first) and their particles' move, before
/// the particles' drift files every particle in its cell.
pub fn body_drift(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    bb: &mut BodyBuffers,
) {
    settle_step_size(k, s, p, b);
    let nb = bb.n_bodies as u32;
    let kd = k.get(Family::BodyDrift);
    // SAFETY: the arguments of `Family::BodyDrift`; dt_dev holds 2 floats.
    kd.check(unsafe {
        s.launch_builder(&kd.f)
            .arg(&nb)
            .arg(&b.dt)
            .arg(&mut bb.bodies)
            .launch(cfg(bb.n_bodies))
            .map(|_| ())
    });
    if b.n == 0 {
        return;
    }
    let n = b.n as u32;
    let km = k.get(Family::BodyMove);
    let c = &mut b.cur;
    // SAFETY: the arguments of `Family::BodyMove`; the state's arrays hold n particles.
    km.check(unsafe {
        s.launch_builder(&km.f)
            .arg(&n)
            .arg(&nb)
            .arg(&bb.bodies)
            .arg(&c.kind)
            .arg(&c.group)
            .arg(&mut c.pos)
            .launch(cfg(b.n))
            .map(|_| ())
    });
}
