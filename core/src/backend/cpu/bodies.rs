//! Floating rigid bodies (`physics::body`): the fluid's load on each, summed at the kick
//! from the state the force stage saw; the bodies' kick, which sets their particles'
//! velocities; and their drift, which moves the particles rigidly before the drift of the
//! rest. Twin: `cuda/bodies.cu`; parity test `tests/cuda_parity/`.

use rayon::prelude::*;

use super::grid::Grid;
use super::monitor::wall_load;
use crate::physics::body::Load;
use crate::physics::dim::Dim;
use crate::physics::params::{MfBody, SphParams, MF_KIND_BOUNDARY};
use crate::physics::state::State;

/// The body whose particles a boundary particle of `group` is, if any.
#[inline]
pub fn body_of(bodies: &[MfBody], kind: u8, group: u32) -> Option<&MfBody> {
    if kind as u32 != MF_KIND_BOUNDARY {
        return None;
    }
    bodies.iter().find(|b| b.group as u32 == group)
}

/// The fluid's force \[M L T^-2\] and torque \[M L^2 T^-2\] on each body's particles
/// (`wall_load`, the force monitors' sum) and the contacts' from walls and other bodies, from
/// the state the force stage saw: before the kick, whose new velocities the force stage did
/// not take.
pub fn loads<D: Dim>(
    p: &SphParams,
    grid: &Grid,
    surface: &[[f32; 4]],
    bodies: &[MfBody],
    s: &State<D>,
) -> Vec<Load> {
    (bodies.iter())
        .map(|b| wall_load(p, s, grid, surface, b.group as u32, Some(b.centre)))
        .collect()
}

/// The kick of every body over `span` \[T\] under its load (`loads`) and gravity, then its
/// particles' velocities V + omega x (x - c).
pub fn kick<D: Dim>(
    p: &SphParams,
    span: f32,
    loads: &[Load],
    bodies: &mut [MfBody],
    s: &mut State<D>,
) {
    for (b, load) in bodies.iter_mut().zip(loads) {
        b.kick(load, p.gravity, span);
    }
    let (kind, group, pos) = (&s.kind, &s.group, &s.pos);
    s.vel.par_iter_mut().enumerate().for_each(|(i, v)| {
        if let Some(b) = body_of(bodies, kind[i], group[i]) {
            *v = b.velocity_at::<D>(pos[i]);
        }
    });
}

/// The drift of every body over `dt` \[T\] and of its particles with it.
pub fn drift<D: Dim>(dt: f32, bodies: &mut [MfBody], s: &mut State<D>) {
    for b in bodies.iter_mut() {
        b.drift(dt);
    }
    let (kind, group) = (&s.kind, &s.group);
    s.pos.par_iter_mut().enumerate().for_each(|(i, x)| {
        if let Some(b) = body_of(bodies, kind[i], group[i]) {
            *x = b.moved::<D>(*x);
        }
    });
}
