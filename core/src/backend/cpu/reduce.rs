//! Reductions: the step size (eq. (19) with the force and viscous limits), diagnostics and
//! the health check. Twin: `cuda/reduce.cu`; parity test `tests/cuda_parity/`.
// Index loops over tensor and vector components read like the equations they implement.
#![allow(clippy::needless_range_loop)]

use rayon::prelude::*;

use crate::consts::{
    MF_DENSITY_SANE_HIGH, MF_DENSITY_SANE_LOW, MF_FAULT_DENSITY_RANGE, MF_FAULT_ESCAPED,
    MF_FAULT_NON_FINITE_DENSITY, MF_FAULT_NON_FINITE_POSITION, MF_FAULT_NON_FINITE_VELOCITY,
    MF_VISCOUS_DT,
};
use crate::physics::dim::Dim;
use crate::physics::params::{SphParams, MF_KIND_BOUNDARY, MF_KIND_FLUID};
use crate::physics::particle::Kind;
use crate::physics::state::State;
use crate::solver::Diagnostics;

/// The step size \[T\] from the largest speed \[L/T\], acceleration \[L/T^2\] and sound speed:
/// courant * min(h / (c + |v|max), sqrt(h / |a|max)), and `MF_VISCOUS_DT` h^2 / nu (0.125)
/// with laminar viscosity; eq. (19) is the first bound. A fixed dt overrides all.
pub fn step_size(p: &SphParams, c_max: f32, v_max: f32, a_max: f32) -> f32 {
    if p.dt > 0.0 {
        return p.dt;
    }
    let mut dt = p.h / (c_max + v_max); // eq. (19)
    if a_max > 0.0 {
        dt = dt.min((p.h / a_max).sqrt());
    }
    dt *= p.courant;
    if p.viscosity > 0.0 {
        dt = dt.min(MF_VISCOUS_DT as f32 * p.h * p.h / p.viscosity);
    }
    dt
}

/// Largest speed, acceleration and sound speed over the fluid and solid particles this
/// solver owns (all of them but in a subdomain of a decomposed run: `SphParams::owns`).
pub fn extremes<D: Dim>(p: &SphParams, s: &State<D>) -> (f32, f32, f32) {
    let axis = p.own_axis as usize;
    (0..s.len())
        .into_par_iter()
        .filter(|&i| s.kind[i] as u32 != MF_KIND_BOUNDARY && p.owns(D::comp(s.pos[i], axis)))
        .map(|i| {
            (
                D::length2(s.vel[i]).sqrt(),
                D::length2(s.acc[i]).sqrt(),
                p.sound_speed(s.kind[i]),
            )
        })
        .reduce(
            || (0.0, 0.0, 0.0),
            |a, b| (a.0.max(b.0), a.1.max(b.1), a.2.max(b.2)),
        )
}

pub fn diagnostics<D: Dim>(p: &SphParams, s: &State<D>) -> Diagnostics {
    let mut d = Diagnostics::default();
    for i in 0..s.len() {
        match Kind::from_code(s.kind[i]) {
            Some(Kind::Fluid) => d.fluid += 1,
            Some(Kind::Solid) => d.solid += 1,
            _ => {
                d.boundary += 1;
                continue;
            }
        }
        let v = D::to3(s.vel[i]);
        let m = s.mass[i] as f64;
        let v2 = v.iter().map(|c| (*c as f64).powi(2)).sum::<f64>();
        d.kinetic_energy += 0.5 * m * v2;
        d.max_speed = d.max_speed.max(v2.sqrt() as f32);
        for a in 0..3 {
            d.momentum[a] += m * v[a] as f64;
        }
        if s.kind[i] as u32 == MF_KIND_FLUID {
            d.density_error = d.density_error.max((s.rho[i] / p.rho0 - 1.0).abs());
        }
    }
    d
}

/// The first slot (in storage order) that is not healthy, with its fault code and value.
pub fn first_fault<D: Dim>(p: &SphParams, s: &State<D>) -> Option<(usize, u32, f32)> {
    (0..s.len()).into_par_iter().find_map_first(|i| {
        // A wall particle is checked for its place alone: a driven or floating one may move
        // out of the domain (a body that sinks through the floor); its density is a wall's.
        let wall = s.kind[i] as u32 == MF_KIND_BOUNDARY;
        let x = D::to3(s.pos[i]);
        let v = D::to3(s.vel[i]);
        if let Some(c) = x.iter().find(|c| !c.is_finite()) {
            return Some((i, MF_FAULT_NON_FINITE_POSITION, *c));
        }
        if !wall {
            if let Some(c) = v.iter().find(|c| !c.is_finite()) {
                return Some((i, MF_FAULT_NON_FINITE_VELOCITY, *c));
            }
            if !s.rho[i].is_finite() {
                return Some((i, MF_FAULT_NON_FINITE_DENSITY, s.rho[i]));
            }
            let rho0 = p.rest_density(s.kind[i]);
            if s.rho[i] < MF_DENSITY_SANE_LOW as f32 * rho0
                || s.rho[i] > MF_DENSITY_SANE_HIGH as f32 * rho0
            {
                return Some((i, MF_FAULT_DENSITY_RANGE, s.rho[i]));
            }
        }
        for a in 0..D::D {
            if p.periodic[a] == 0 && (x[a] < p.domain_min[a] || x[a] > p.domain_max[a]) {
                return Some((i, MF_FAULT_ESCAPED, x[a]));
            }
        }
        None
    })
}
