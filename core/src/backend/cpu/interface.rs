//! The pressure an elastic body's particles present to the fluid (`[solid] fluid_pressure =
//! "extrapolated"`, `Solver::solid_interface`): the fluid's, extrapolated to them as to a
//! wall's particles (Adami, Hu & Adams 2012, J. Comput. Phys. 231, 7057, eq. (27)), with
//! its Tait density. The force stage then pairs a fluid particle and a body's particle as
//! two fluid particles, the body's of its own volume (`ForceSum`).
//! Twin: `sph_solid_interface` in `cuda/density.cu`; parity test `tests/cuda_parity/`.

use rayon::prelude::*;

use super::grid::Grid;
use crate::physics::dim::Dim;
use crate::physics::kernel;
use crate::physics::params::{SphParams, MF_KIND_FLUID, MF_KIND_SOLID};
use crate::physics::state::State;

/// The Tait density of pressure `pr` [M L^-d L^2 T^-2], eq. (9) inverted (less the background
/// pressure), held at 0.1 rho0 or more (the health check's floor): a pressure below the
/// equation of state's -B has no density. [M L^-d]
#[inline]
pub fn tait_density(p: &SphParams, pr: f32) -> f32 {
    let base = (1.0 + (pr - p.background_pressure) / p.tait_b).max(0.1f32.powf(p.tait_gamma));
    p.rho0 * base.powf(1.0 / p.tait_gamma)
}

/// Per slot (P', rho') [M L^-d L^2 T^-2, M L^-d]: for a body's particle b with fluid
/// neighbours, P'_b = (sum_f P_f W_bf + rho_f g . (x_b - x_f) W_bf) / sum_f W_bf (Adami et
/// al. 2012, eq. (27), without the body's acceleration a_b: it enters as rho_f a_b . r_bf,
/// under 1 % of the hydrostatic part for a body accelerating at g / 3 a support from the
/// fluid; and no state outside the checkpoint is needed) and rho'_b = `tait_density`;
/// (background pressure, rho0) elsewhere (no pair reads it).
pub fn solid_interface<D: Dim>(p: &SphParams, grid: &Grid, s: &State<D>) -> Vec<[f32; 2]> {
    let g = D::from3(p.gravity);
    let (pos, kind, rho, pr) = (&s.pos, &s.kind, &s.rho, &s.p);
    (0..s.len())
        .into_par_iter()
        .map(|b| {
            if kind[b] as u32 != MF_KIND_SOLID {
                return [p.background_pressure, p.rho0];
            }
            let (mut sum_w, mut sum_pw) = (0.0f32, 0.0f32);
            grid.for_each_neighbor::<D>(p, pos, pos[b], |f, r, r2| {
                if kind[f] as u32 != MF_KIND_FLUID {
                    return;
                }
                // r = x_b - x_f
                let w = kernel::w(p, r2.sqrt());
                sum_w += w;
                sum_pw += (pr[f] + rho[f] * D::dot(g, r)) * w;
            });
            if sum_w <= 0.0 {
                return [p.background_pressure, p.rho0];
            }
            let pb = sum_pw / sum_w;
            [pb, tait_density(p, pb)]
        })
        .collect()
}
