//! Density and pressure. Twin: `cuda/density.cu`; parity test `tests/cuda_parity/`.

use rayon::prelude::*;

use super::grid::Grid;
use super::interface::tait_density;
use crate::physics::dim::Dim;
use crate::physics::kernel;
use crate::physics::mdbc::{cloned_pressure, normal_now, GhostSums};
use crate::physics::pairs::{couples, meets};
use crate::physics::params::{
    MfBody, SphParams, MF_DENSITY_SUMMATION, MF_KIND_BOUNDARY, MF_KIND_FLUID, MF_KIND_SOLID,
    MF_WALL_COUPLING_MDBC,
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
    let mdbc = p.wall_coupling as u32 == MF_WALL_COUPLING_MDBC;
    let one = |i: usize, rho: &mut f32, pr: &mut f32, dev: Option<&mut f32>| {
        let wall = kind[i] as u32 == MF_KIND_BOUNDARY;
        if wall && p.wall_coupling == 0 {
            return;
        }
        // mDBC walls took theirs from their ghost nodes (`wall_density`).
        if summation && !(wall && mdbc) {
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

/// Modified dynamic walls (`MF_WALL_COUPLING_MDBC`; English et al. 2022, `physics::mdbc`):
/// each wall particle a's density [M L^-d] from its ghost node x_g = x_a + 2 d_B n in the
/// fluid (`surface`: `Setup::wall_surface`, (n, d_B) at id - `wall_first_id`, n turned as
/// its wall has turned by time `t` \[T\], `mdbc::normal_now`: a floating body of `bodies`,
/// a turning driven wall), by the
/// first-order corrected interpolation of the fluid particles around x_g (`GhostSums`),
/// its pressure cloned back to x_a with the hydrostatic term (`mdbc::cloned_pressure`) and
/// the Tait density of that; rho0 where no fluid is near the ghost node, held at rho0 or more
/// under `wall_density_floor`. A particle whose surface has no normal (a wall with no wet face)
/// keeps its density. Before `density`, which takes the pressures from these densities.
/// Nothing under other wall couplings. Twin: `sph_wall_density` in `cuda/density.cu`.
pub fn wall_density<D: Dim>(
    p: &SphParams,
    grid: &Grid,
    s: &mut State<D>,
    surface: &[[f32; 4]],
    bodies: &[MfBody],
    series: &[f64],
    t: f64,
) {
    if p.wall_coupling as u32 != MF_WALL_COUPLING_MDBC {
        return;
    }
    let (pos, kind, mass, id, rho, group) = (&s.pos, &s.kind, &s.mass, &s.id, &s.rho, &s.group);
    let new: Vec<Option<f32>> = (0..s.len())
        .into_par_iter()
        .map(|i| {
            if kind[i] as u32 != MF_KIND_BOUNDARY {
                return None;
            }
            let [nx, ny, nz, d_b] = surface[(id[i] - p.wall_first_id) as usize];
            if nx == 0.0 && ny == 0.0 && nz == 0.0 {
                return None;
            }
            let mut n = [nx as f64, ny as f64, nz as f64];
            normal_now::<D>(p, bodies, series, t, group[i], &mut n);
            let two_dn = n.map(|c| 2.0 * d_b * c as f32);
            let mut xg = pos[i];
            for (a, t) in two_dn.iter().enumerate().take(D::D) {
                let x = D::comp(xg, a) + t;
                D::set_comp(&mut xg, a, x);
            }
            let mut g = GhostSums::default();
            grid.for_each_neighbor::<D>(p, pos, xg, |j, r, r2| {
                if kind[j] as u32 == MF_KIND_FLUID {
                    let len = r2.sqrt();
                    let (w, f) = (kernel::w(p, len), kernel::f(p, len));
                    g.add(D::D, &D::to3(r), w, f, mass[j], rho[j]);
                }
            });
            let out = match g.density(D::D, p.rho0, p.dx) {
                // The ghost node's pressure, eq. (9), cloned back to the wall particle.
                Some(rho_g) => {
                    let pr_g = pressure(p, MF_KIND_BOUNDARY as u8, rho_g, 0.0);
                    tait_density(p, cloned_pressure(p, pr_g, &n, d_b))
                }
                None => p.rho0,
            };
            Some(if p.wall_density_floor != 0 {
                out.max(p.rho0)
            } else {
                out
            })
        })
        .collect();
    for (r, n) in s.rho.iter_mut().zip(new) {
        if let Some(n) = n {
            *r = n;
        }
    }
}
