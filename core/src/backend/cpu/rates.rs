//! Rates from the current velocities: d rho/dt (continuity form, with the density diffusion
//! of Molteni & Colagrossi 2009 where `density_diffusion` > 0), the XSPH velocity of
//! eq. (18) with the particle shifting velocity where `shifting` > 0 (`shift_velocity`), and
//! the Jaumann stress rate of solids, eqs. (12)-(15). Taken after the kick
//! in the symplectic integrator, so that density and stress see the new velocity (without
//! that, the elastic and acoustic modes grow like forward Euler on an oscillator).
//! Twin: `cuda/rates.cu`; parity test `tests/cuda_parity/`.

use rayon::prelude::*;

use super::grid::Grid;
use crate::consts::{MF_MOMENT_DET_MIN, MF_SHIFT_ANTI_CLUMP, MF_SHIFT_SURFACE_MARGIN};
use crate::physics::dim::Dim;
use crate::physics::kernel;
use crate::physics::pairs::{couples, extrapolated_pair, has_rates, meets, same_body};
use crate::physics::params::{
    needs_density_gradient, SphParams, MF_DIFFUSION_FOURTAKAS, MF_INTEGRATOR_LEAPFROG,
    MF_KIND_BOUNDARY, MF_KIND_FLUID, MF_KIND_SOLID,
};
use crate::physics::state::State;
use crate::physics::tlsph::total_lagrangian;

/// The particle shifting velocity [L/T] of a fluid particle, added to its XSPH velocity so
/// that the drift moves it by dt dv (Lind et al. 2012, J. Comput. Phys. 231, 1499; the
/// anti-clumping factor of Sun, Colagrossi, Marrone & Zhang 2017, the delta+-SPH):
/// dv_i = -C h c0 grad C_i with grad C_i = sum_j V_j (1 + R (W_ij / W(dx))^4) grad_i W_ij,
/// so that dt dv ~ C Courant h^2 grad C; `grad_c` is that sum and `div_r` the position
/// divergence; zero at a free surface, where the sum points out of the fluid (position
/// divergence below d - `MF_SHIFT_SURFACE_MARGIN`).
pub fn shift_velocity<D: Dim>(p: &SphParams, grad_c: D::V, div_r: f32) -> D::V {
    if div_r < D::D as f32 - MF_SHIFT_SURFACE_MARGIN as f32 {
        return D::V::default();
    }
    grad_c * (-p.shifting * p.h * p.c0)
}

/// rho^H_j - rho^H_i [M L^-d]: the density difference of water at rest under gravity between
/// j and i, r = r_i - r_j (Fourtakas, Dominguez, Vacondio & Rogers 2019, Comput. Fluids 190,
/// 346): the Tait density, eq. (9) inverted, of the hydrostatic pressure difference
/// p^H_j - p^H_i = rho0 g . (r_j - r_i), as rho0 expm1(ln(1 + p / B) / gamma) (the plain
/// power loses the difference to rounding in f32). Twin of `hydrostatic_rho_ji` in
/// cuda/rates.cuh.
fn hydrostatic_rho_ji<D: Dim>(p: &SphParams, r: D::V) -> f32 {
    let p_ji = -p.rho0 * D::dot(D::from3(p.gravity), r);
    p.rho0 * ((p_ji / p.tait_b).ln_1p() / p.tait_gamma).exp_m1()
}

/// The pair's separation r = x_i - x_j and |r|^2 moved by `half_dt` [T] of the relative
/// velocity `vij` [L/T]: the leapfrog's midpoint; the pair as given where `half_dt` is 0, and
/// where the pair is in the kernel's core (|r|^2 or the midpoint's below `core_r2` [L^2], the
/// square of `kernel::gradient_peak_q` h). In the core |grad W| falls as r falls, so the
/// midpoint lowers an approaching pair's compression rate below x^n's: with it a splash
/// blew up (the 2D dam break at dx = 0.01, Courant 0.4, t = 1.156), with x^n there it runs.
/// An ordered lattice at h = 1.3 dx has no pair in the core (nearest q = 0.77), so the step
/// stays second order where the particles are ordered.
/// Twin: `neighbour`'s `half_dt` in cuda/device/neighbours.cuh.
#[inline]
fn midpoint_pair<D: Dim>(r: D::V, r2: f32, vij: D::V, half_dt: f32, core_r2: f32) -> (D::V, f32) {
    if half_dt == 0.0 || r2 < core_r2 {
        return (r, r2);
    }
    let rm = r + vij * half_dt;
    let rm2 = D::dot(rm, rm);
    if rm2 < core_r2 {
        return (r, r2);
    }
    (rm, rm2)
}

#[derive(Clone, Copy)]
struct Rates<V, M> {
    drho: f32,
    xsph: V,
    stress_rate: M,
}

/// The renormalised density gradient of each particle within its material, for the density
/// diffusion in Antuono, Colagrossi, Marrone & Molteni 2010's form (Comput. Phys. Commun.
/// 181, 532): (sum_j V_j (x_j - x_i) (x) grad_i W_ij)^-T sum_j V_j (rho_j - rho_i) grad_i
/// W_ij over the neighbours of one body (solids, `[solid] density_diffusion`) or over the
/// fluid (`density_diffusion_form` = Antuono), V_j = m_j / rho_j, exact for a linear density; zero for
/// other particles and where the moment is singular. None unless `needs_density_gradient`.
/// Twin: `sph_grad_rho` in cuda/rates.cu. [M L^-d L^-1]
pub fn density_gradient<D: Dim>(p: &SphParams, grid: &Grid, s: &State<D>) -> Option<Vec<D::V>> {
    if !needs_density_gradient(p) {
        return None;
    }
    let (fluid, solid) = (
        p.fluid_density_gradient != 0,
        p.solid_density_diffusion > 0.0,
    );
    let (pos, rho, mass, kind, group) = (&s.pos, &s.rho, &s.mass, &s.kind, &s.group);
    let g = (0..s.len())
        .into_par_iter()
        .map(|i| {
            let on = match kind[i] as u32 {
                MF_KIND_FLUID => fluid,
                MF_KIND_SOLID => solid,
                _ => false,
            };
            if !on {
                return D::V::default();
            }
            let (mut g, mut m) = (D::V::default(), D::zero());
            grid.for_each_neighbor::<D>(p, pos, pos[i], |j, r, r2| {
                if j == i || !same_body(p, kind[i], kind[j], group[i], group[j]) {
                    return;
                }
                let gw = r * kernel::f(p, r2.sqrt());
                let vj = mass[j] / rho[j];
                g += gw * ((rho[j] - rho[i]) * vj);
                m += D::outer(-r, gw) * vj;
            });
            if D::determinant(m).abs() > MF_MOMENT_DET_MIN as f32 {
                D::mat_vec(D::inverse(D::transpose(m)), g)
            } else {
                D::V::default()
            }
        })
        .collect();
    Some(g)
}

/// The rates of every particle with the velocities just kicked (the symplectic Euler's
/// second pass). Under the leapfrog each pair is taken where the drift of step `dt` [T]
/// puts it halfway, r_ij + dt/2 (v_i - v_j) (`midpoint_pair`): the midpoint rule that makes
/// d rho/dt, XSPH and the stress rate second order in dt; a pair in the kernel's core stays
/// at x^n (`midpoint_pair` says why). The neighbours are those at x_i - x_j; a pair that the
/// half drift carries across the support's edge adds W ~ 0.
/// `grad_rho`: the density gradient stage's (`density_gradient`), where the scheme needs it.
pub fn rates<D: Dim>(
    p: &SphParams,
    dt: f32,
    grid: &Grid,
    grad_rho: Option<&[D::V]>,
    s: &mut State<D>,
) {
    let half_dt = if p.integrator == MF_INTEGRATOR_LEAPFROG as i32 {
        0.5 * dt
    } else {
        0.0
    };
    let core_r2 = (kernel::gradient_peak_q(p.kernel) * p.h).powi(2);
    let (pos, vel, rho, mass, kind, group) = (&s.pos, &s.vel, &s.rho, &s.mass, &s.kind, &s.group);
    let stress = s.solid.as_ref().map(|so| &so.stress);
    let out: Vec<Rates<D::V, D::M>> = (0..s.len())
        .into_par_iter()
        .map(|i| {
            let mut o = Rates {
                drho: 0.0,
                xsph: D::V::default(),
                stress_rate: D::zero(),
            };
            let ki = kind[i];
            if !has_rates(p, ki) {
                return o;
            }
            let (vi, rhoi) = (vel[i], rho[i]);
            let solid_i = ki as u32 == MF_KIND_SOLID;
            // A total-Lagrangian body takes its stress from F (`Solver::solid_stress`):
            // no Jaumann rate.
            let jaumann_i = solid_i && !total_lagrangian(p);
            let mut grad_v = D::zero();
            let mut moment = D::zero();
            // Density diffusion (delta-SPH) within one material: between fluid particles,
            // and between the particles of one body; walls and other materials have their
            // own rest densities, and diffusing across them would pull towards the wrong one.
            let (delta, c_i) = match ki as u32 {
                MF_KIND_FLUID => (p.density_diffusion, p.c0),
                MF_KIND_SOLID => (p.solid_density_diffusion, p.solid_c0),
                _ => (0.0, 0.0),
            };
            let diffuse = delta > 0.0;
            let mut diffusion = 0.0f32;
            let shift = p.shifting > 0.0 && ki as u32 == MF_KIND_FLUID;
            let (mut grad_c, mut div_r) = (D::V::default(), 0.0f32);
            grid.for_each_neighbor::<D>(p, pos, pos[i], |j, r, r2| {
                let kj = kind[j];
                if j == i || !couples(p, kj) || !meets(p, ki, kj) {
                    return;
                }
                // v = 0 on boundary particles.
                let vij = vi - vel[j];
                let (r, r2) = midpoint_pair::<D>(r, r2, vij, half_dt, core_r2);
                let rr = r2.sqrt();
                // grad_i W_ij
                let grad_w = r * kernel::f(p, rr);
                // Continuity: d rho_i/dt = rho_i sum_j m_j / rho_j v_ij . grad W, the
                // volume form (Colagrossi & Landrini 2003): a fluid neighbour of mass 1.0 dx^d
                // must not compress a solid of density 0.6 as if it were its own kind.
                // (The sum of m_j / rho_j v_ij . grad W here, times rho_i after the loop.)
                // A body meeting the fluid at its extrapolated pressure leaves the fluid
                // out of its own density (`pairs::extrapolated_pair`): the fluid's push
                // reaches it through the pair force, and the body's density is its own
                // deformation's.
                if !(solid_i && extrapolated_pair(p, ki, kj)) {
                    o.drho += mass[j] / rho[j] * D::dot(vij, grad_w);
                }
                if shift {
                    // Every neighbour that couples (fluid, solid, dynamic wall) fills the
                    // support, so a fluid particle is not shifted into a wall or a body.
                    let vj = mass[j] / rho[j];
                    let f = kernel::w(p, rr) * p.inv_w_dx;
                    let anti_clump = 1.0 + MF_SHIFT_ANTI_CLUMP as f32 * (f * f) * (f * f);
                    grad_c += grad_w * (vj * anti_clump);
                    div_r -= vj * D::dot(r, grad_w);
                }
                // One material: fluid with fluid; a solid's own body, or a clamp and the solid
                // it holds.
                let one_body = same_body(p, ki, kj, group[i], group[j]);
                if diffuse && r2 > 0.0 && one_body {
                    // Molteni & Colagrossi 2009 (Comput. Phys. Commun. 180, 861), the diffusive term
                    // sum_j psi_ij . grad_i W_ij V_j, psi_ij = 2 (rho_j - rho_i) r_ji / |r_ji|^2 with
                    // r_ji = r_j - r_i = -r (the sign that makes it a Laplacian of rho: with r_i - r_j
                    // it anti-diffuses and a tank blows up within 0.03 T), V_j = m_j / rho_j;
                    // psi_ij . grad W = 2 (rho_i - rho_j) r . grad W / r^2; [M L^-d L^-2], times delta h c0.
                    // Fourtakas et al. 2019: rho_i - rho_j less its hydrostatic part (fluid).
                    let mut drho_ij = rhoi - rho[j];
                    if p.density_diffusion_form == MF_DIFFUSION_FOURTAKAS as i32 && !solid_i {
                        drho_ij += hydrostatic_rho_ji::<D>(p, r);
                    }
                    let mut psi = 2.0 * drho_ij * D::dot(r, grad_w) / r2;
                    if let Some(g) = &grad_rho {
                        // Antuono et al. 2010's correction (in a body; in the fluid where
                        // `density_diffusion_form` says so, else both gradients are zero), which makes the
                        // term vanish for a linear density (a bending plate's pressure across
                        // its thickness, water at rest) where the support is cut too: less
                        // (grad rho_i + grad rho_j) . grad W.
                        psi -= D::dot(g[i] + g[j], grad_w);
                    }
                    diffusion += psi * (mass[j] / rho[j]);
                }
                if !one_body || ki as u32 == MF_KIND_BOUNDARY {
                    return;
                }
                let rho_bar = 0.5 * (rhoi + rho[j]);
                // XSPH, eq. (18), within one material (one body for solids).
                o.xsph -= vij * (p.xsph * mass[j] / rho_bar * kernel::w(p, rr));
                if jaumann_i {
                    // Velocity gradient, eq. (15):
                    // dv^a/dx^b = sum_j m_j / rho_bar_ij (v_j - v_i)^a dW_ij/dx_i^b
                    grad_v += D::outer(-vij, grad_w) * (mass[j] / rho_bar);
                    moment += D::outer(-r, grad_w) * (mass[j] / rho_bar);
                }
            });
            o.drho *= rhoi;
            if shift {
                o.xsph += shift_velocity::<D>(p, grad_c, div_r);
            }
            if diffuse {
                // + delta h c sum_j ... [M L^-d T^-1] (Molteni & Colagrossi 2009), with the
                // particle's material's delta and sound speed.
                o.drho += delta * p.h * c_i * diffusion;
            }
            if jaumann_i {
                // Kernel-gradient correction (Randles & Libersky 1996; Bonet & Lok 1999):
                // for v = G x the sum above gives G A with A = sum_j V_j (x_j - x_i) (x)
                // grad W, which is I inside a body but not at its surface, where rigid
                // rotation would otherwise read as strain. Skipped where A is singular.
                if D::determinant(moment).abs() > MF_MOMENT_DET_MIN as f32 {
                    grad_v = grad_v * D::inverse(moment);
                }
                let gt = D::transpose(grad_v);
                let eps_dot = (grad_v + gt) * 0.5; // eq. (13)
                let omega = (grad_v - gt) * 0.5; // eq. (14)
                let si = stress.map_or(D::zero(), |st| st[i]);
                // Jaumann rate, eq. (12): 2 mu (eps_dot^ab - delta^ab eps_dot^cc / 3)
                //   + S^ac Omega^bc + Omega^ac S^cb   (trace term as corrected in the notes)
                let dev = eps_dot - D::identity() * (D::trace(eps_dot) / 3.0);
                o.stress_rate =
                    dev * (2.0 * p.shear_modulus) + si * D::transpose(omega) + omega * si;
            }
            o
        })
        .collect();
    for (i, o) in out.into_iter().enumerate() {
        s.xsph[i] = o.xsph;
        if let Some(d) = s.drho.as_mut() {
            d[i] = o.drho;
        }
        if let Some(so) = s.solid.as_mut() {
            so.stress_rate[i] = o.stress_rate;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::midpoint_pair;
    use crate::physics::dim::D2;
    use glam::Vec2;

    /// The leapfrog's midpoint moves a pair by half_dt v_ij, except in the kernel's core
    /// (|r|^2 or the midpoint's below core_r2), where the pair stays at x^n; no move without
    /// half_dt.
    #[test]
    fn midpoint_skips_the_kernels_core() {
        let (h, half_dt) = (1.0f32, 0.1f32);
        let core_r2 = (2.0 / 3.0 * h) * (2.0 / 3.0 * h);
        let vij = Vec2::new(-1.0, 0.0); // i approaches j, which lies at -x
                                        // q = 1 -> 0.9: outside the core, moved.
        let r = Vec2::new(1.0, 0.0);
        let (m, m2) = midpoint_pair::<D2>(r, 1.0, vij, half_dt, core_r2);
        assert!((m.x - 0.9).abs() < 1e-6 && (m2 - 0.81).abs() < 1e-6);
        // q = 0.7 -> 0.6: the midpoint is in the core, so x^n.
        let r = Vec2::new(0.7, 0.0);
        assert_eq!(
            midpoint_pair::<D2>(r, 0.49, vij, half_dt, core_r2),
            (r, 0.49)
        );
        // q = 0.6 receding to 0.7: x^n in the core, so unmoved.
        let r = Vec2::new(0.6, 0.0);
        assert_eq!(
            midpoint_pair::<D2>(r, 0.36, -vij, half_dt, core_r2),
            (r, 0.36)
        );
        // No half step (the symplectic Euler): unmoved anywhere.
        let r = Vec2::new(1.0, 0.0);
        assert_eq!(midpoint_pair::<D2>(r, 1.0, vij, 0.0, core_r2), (r, 1.0));
    }
}
