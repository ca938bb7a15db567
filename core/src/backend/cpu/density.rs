//! Density and pressure. Twin: `cuda/density.cu`; parity test `tests/cuda_parity.rs`.

use rayon::prelude::*;

use super::grid::Grid;
use crate::dim::Dim;
use crate::kernel;
use crate::params::{
    SphParams, MF_DENSITY_SUMMATION, MF_KIND_BOUNDARY, MF_KIND_FLUID, MF_KIND_SOLID,
};
use crate::state::State;

/// Whether particle j of kind `kj` enters the SPH sums of another particle: boundary
/// particles only with dynamic walls (`wall_pressure`, Crespo et al. 2007: wall particles
/// carry density and pressure like fluid but do not move); with the paper's walls they act
/// through the Lennard-Jones force alone.
#[inline]
pub fn couples(p: &SphParams, kj: u8) -> bool {
    kj as u32 != MF_KIND_BOUNDARY || p.wall_pressure != 0
}

/// Whether particles of kinds `ki` and `kj` meet at all: a solid and a wall particle skip
/// each other, both ways, where the scene says so (`[solid] wall_contact = false`,
/// `solid_skips_walls`): no Lennard-Jones force, eq. (17), no wall pressure, and neither
/// enters the other's density (continuity or summation). A body that meets only the fluid
/// and other bodies: the free end of a gate standing on the tank floor, whose continuity
/// density read the foot leaving the floor's wall particles as a dilatation
/// (docs/accuracy.md, elastic gate). Twin: `meets` in `cuda/common.cuh`.
#[inline]
pub fn meets(p: &SphParams, ki: u8, kj: u8) -> bool {
    let (s, b) = (MF_KIND_SOLID, MF_KIND_BOUNDARY);
    let (ki, kj) = (ki as u32, kj as u32);
    p.solid_skips_walls == 0 || !((ki == s && kj == b) || (ki == b && kj == s))
}

/// Whether particles i (kind `ki`, scene group `gi`) and j count as one body for the terms
/// that act only within a body: XSPH, eq. (18), the velocity gradient of eq. (15) (so the
/// Jaumann stress rate, eq. (12)) and the artificial stress. All fluid is one body; a solid
/// is its own scene group; and a driven solid (a clamp: the `driven_group`, held by its
/// `motion`) is bonded to every solid particle it neighbours, so the held part takes up
/// strain and passes stress into the body it holds (a cantilever's root). Twin:
/// `same_body` in `cuda/common.cuh`.
#[inline]
pub fn same_body(p: &SphParams, ki: u8, kj: u8, gi: u32, gj: u32) -> bool {
    let clamp = |g: u32| p.driven != 0 && g == p.driven_group as u32;
    ki == kj
        && (ki as u32 == MF_KIND_FLUID
            || gi == gj
            || (ki as u32 == MF_KIND_SOLID && (clamp(gi) || clamp(gj))))
}

/// Pressure from density: Tait eq. (9) plus the background pressure `p_background` for
/// fluid and dynamic wall particles, P = c_s^2 (rho - rho0_s) for solids (Gray & Monaghan
/// 2001). [M L^-d L^2 T^-2]
#[inline]
pub fn pressure(p: &SphParams, kind: u8, rho: f32) -> f32 {
    match kind as u32 {
        MF_KIND_SOLID => p.solid_c0 * p.solid_c0 * (rho - p.solid_rho0),
        MF_KIND_FLUID => p.tait_b * ((rho / p.rho0).powf(p.tait_gamma) - 1.0) + p.p_background,
        _ if p.wall_pressure != 0 => {
            p.tait_b * ((rho / p.rho0).powf(p.tait_gamma) - 1.0) + p.p_background
        }
        _ => 0.0,
    }
}

/// Summation density eq. (8) where the scene uses it, then the equation of state, then the
/// artificial stress of solids where it is on.
/// With unequal masses (solids of density 0.6 in fluid of 1.0) the sum is taken in the
/// number-density form rho_i = m_i sum_j W_ij (Hu & Adams 2006), which is eq. (8) exactly
/// when the masses are equal, and does not smear density across a material interface.
pub fn density<D: Dim>(p: &SphParams, grid: &Grid, s: &mut State<D>) {
    let summation = p.density_mode as u32 == MF_DENSITY_SUMMATION;
    let (pos, kind, mass) = (&s.pos, &s.kind, &s.mass);
    s.rho
        .par_iter_mut()
        .zip(s.p.par_iter_mut())
        .enumerate()
        .for_each(|(i, (rho, pr))| {
            if kind[i] as u32 == MF_KIND_BOUNDARY && p.wall_pressure == 0 {
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
            *pr = pressure(p, kind[i], *rho); // eq. (9)
        });
    super::stress::update_artificial_stress(p, s);
}
