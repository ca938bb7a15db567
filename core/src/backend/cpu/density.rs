//! Density and pressure. Twin: `cuda/density.cu`; parity test `tests/cuda_parity/`.

use rayon::prelude::*;

use super::grid::Grid;
use crate::physics::dim::Dim;
use crate::physics::kernel;
use crate::physics::pairs::{couples, meets};
use crate::physics::params::{
    SphParams, MF_DENSITY_SUMMATION, MF_KIND_BOUNDARY, MF_KIND_FLUID, MF_KIND_SOLID,
};
use crate::physics::state::State;

/// Pressure from density: Tait eq. (9) plus the background pressure `background_pressure` for
/// fluid and dynamic wall particles, P = c_s^2 (rho - rho0_s) for solids (Gray & Monaghan
/// 2001), the latter from the departure `rho_dev` = rho - rho0_s [M L^-d]
/// (`SolidState::rho_dev`: rho itself rounds a stiff solid's compression away; unused for
/// other kinds). [M L^-d L^2 T^-2]
#[inline]
pub fn pressure(p: &SphParams, kind: u8, rho: f32, rho_dev: f32) -> f32 {
    match kind as u32 {
        MF_KIND_SOLID => p.solid_c0 * p.solid_c0 * rho_dev,
        MF_KIND_FLUID => {
            p.tait_b * ((rho / p.rho0).powf(p.tait_gamma) - 1.0) + p.background_pressure
        }
        _ if p.wall_coupling != 0 => {
            p.tait_b * ((rho / p.rho0).powf(p.tait_gamma) - 1.0) + p.background_pressure
        }
        _ => 0.0,
    }
}

/// Summation density eq. (8) where the scene uses it (and a solid's departure
/// rho_dev = rho - rho0_s from it), then the equation of state, then the artificial stress
/// of solids where it is on.
/// With unequal masses (solids of density 0.6 in fluid of 1.0) the sum is taken in the
/// number-density form rho_i = m_i sum_j W_ij (Hu & Adams 2006), which is eq. (8) exactly
/// when the masses are equal, and does not smear density across a material interface.
pub fn density<D: Dim>(p: &SphParams, grid: &Grid, s: &mut State<D>) {
    let summation = p.density_form as u32 == MF_DENSITY_SUMMATION;
    let (pos, kind, mass) = (&s.pos, &s.kind, &s.mass);
    // The density of slot i (summed, or as it is) and its pressure; `dev`: the solid's
    // departure from rest, where the scene has solids.
    let one = |i: usize, rho: &mut f32, pr: &mut f32, dev: Option<&mut f32>| {
        if kind[i] as u32 == MF_KIND_BOUNDARY && p.wall_coupling == 0 {
            return;
        }
        if summation {
            let mut sum_w = 0.0f32;
            grid.for_each_neighbor::<D>(p, pos, pos[i], |j, _r, r2| {
                if couples(p, kind[j]) && meets(p, kind[i], kind[j]) {
                    sum_w += kernel::w(p, r2.sqrt());
                }
            });
            *rho = mass[i] * sum_w; // eq. (8)
        }
        let mut d = 0.0;
        if let Some(dev) = dev {
            if summation && kind[i] as u32 == MF_KIND_SOLID {
                *dev = *rho - p.solid_rho0; // [M L^-d]
            }
            d = *dev;
        }
        *pr = pressure(p, kind[i], *rho, d); // eq. (9)
    };
    let rho_p = s.rho.par_iter_mut().zip(s.p.par_iter_mut()).enumerate();
    match s.solid.as_mut() {
        Some(so) => rho_p
            .zip(so.rho_dev.par_iter_mut())
            .for_each(|((i, (rho, pr)), dev)| one(i, rho, pr, Some(dev))),
        None => rho_p.for_each(|(i, (rho, pr))| one(i, rho, pr, None)),
    }
    super::stress::update_artificial_stress(p, s);
}
