//! Accelerations: eqs. (7), (10), (16), (17), laminar viscosity, artificial stress,
//! fluid cohesion (Akinci et al. 2013), gravity. Twin: `cuda/forces.cu`; parity test `tests/cuda_parity/`.

use rayon::prelude::*;

use super::grid::Grid;
use crate::consts::MF_MOMENT_DET_MIN;
use crate::physics::dim::Dim;
use crate::physics::kernel;
use crate::physics::pairs::{couples, extrapolated_pair, meets, same_body};
use crate::physics::params::{
    SphParams, MF_KIND_BOUNDARY, MF_KIND_FLUID, MF_KIND_SOLID, MF_NO_SLIP_MORRIS,
};
use crate::physics::state::State;
use crate::physics::tlsph::total_lagrangian;

/// Lennard-Jones boundary force per unit mass, eq. (17): C0 [(r0/r)^p1 - (r0/r)^p2] r_ij/r,
/// acting for r < r0 (repulsive), or within the support where the scene asks for the
/// attractive branch (`lj_range`). [L/T^2]
#[inline]
pub fn lennard_jones<D: Dim>(p: &SphParams, r: D::V, rr: f32) -> D::V {
    if rr <= 0.0 || rr >= p.lj_range {
        return D::V::default();
    }
    let q = p.lj_r0 / rr;
    let mag = p.lj_c0 * (q.powi(p.lj_p1) - q.powi(p.lj_p2));
    r * (mag / rr)
}

/// Monaghan artificial viscosity Pi_ij, eq. (10), for approaching pairs (v_ij . r_ij < 0),
/// with c the mean sound speed and rho_bar the mean density. [L^2 T^-2 / (M L^-d)]
#[inline]
pub fn artificial_viscosity(p: &SphParams, vr: f32, r2: f32, c_bar: f32, rho_bar: f32) -> f32 {
    if vr >= 0.0 {
        return 0.0;
    }
    let mu = p.h * vr / (r2 + p.av_eta2);
    (-p.alpha * c_bar * mu + p.beta * mu * mu) / rho_bar
}

/// Laminar viscosity factor of Morris, Fox & Zhu (1997): the pair term is
/// m_j (mu_i + mu_j) / (rho_i rho_j) (r_ij . grad W) / (r^2 + 0.01 h^2) v_ij with mu = rho nu.
#[inline]
pub fn laminar(p: &SphParams, r2: f32, f: f32, rho_i: f32, rho_j: f32) -> f32 {
    p.viscosity * (rho_i + rho_j) / (rho_i * rho_j) * (r2 * f) / (r2 + p.visc_eta2)
}

/// The no-slip factor beta of Morris, Fox & Zhu 1997 (J. Comput. Phys. 136, 214, boundary
/// conditions) for the laminar term between fluid particle A and wall particle B at
/// r = x_A - x_B [L] (`no_slip = MF_NO_SLIP_MORRIS`): B takes the artificial velocity
/// v_w - (d_B / d_A) (v_A - v_w) for the viscous term, so v_AB = beta (v_A - v_w) with
/// beta = min(beta_max, 1 + d_B / d_A) [-]. `surf` = (n, d_B), B's entry of
/// `Setup::wall_surface`: n the unit normal of the wall surface into the fluid, d_B [L] B's
/// distance behind it; d_A = r . n - d_B [L] is A's distance from the same (locally flat)
/// surface. A at or behind the surface (d_A <= 0) takes beta_max.
#[inline]
pub fn no_slip_factor<D: Dim>(p: &SphParams, r: D::V, surf: [f32; 4]) -> f32 {
    let n = D::from3([surf[0], surf[1], surf[2]]);
    let d_b = surf[3];
    let d_a = D::dot(r, n) - d_b;
    if d_a > 0.0 {
        (1.0 + d_b / d_a).min(p.no_slip_beta_max)
    } else {
        p.no_slip_beta_max
    }
}

/// The velocity difference the laminar term of a fluid particle takes across a pair with
/// neighbour j of kind kj and id `id_j` (r = x_i - x_j, vij = v_i - v_j) [L/T]: vij, or
/// beta vij from a wall particle under `no_slip = MF_NO_SLIP_MORRIS` (`no_slip_factor`).
#[inline]
pub fn laminar_velocity<D: Dim>(
    p: &SphParams,
    surface: &[[f32; 4]],
    kj: u8,
    id_j: u32,
    r: D::V,
    vij: D::V,
) -> D::V {
    if p.no_slip as u32 == MF_NO_SLIP_MORRIS && kj as u32 == MF_KIND_BOUNDARY {
        vij * no_slip_factor::<D>(p, r, surface[(id_j - p.wall_first_id) as usize])
    } else {
        vij
    }
}

/// Cohesion spline of Akinci, Akinci & Teschner 2013 ("Versatile surface tension and
/// adhesion for SPH fluids", eq. (2)) over the support s = 2h, divided by r:
/// C(r) / r with C(r) = 32 / (pi s^9) * { (s - r)^3 r^3 for s/2 < r <= s;
/// 2 (s - r)^3 r^3 - s^6 / 64 for 0 < r <= s/2 }, 0 beyond s, written with x = r / s as
/// 32 / (pi s^3) (1 - x)^3 x^3 (f32 range). The 3D normalisation in 2D as well (gamma is a
/// tuning constant either way). C < 0 (repulsive) for r < 0.27 s, > 0 (attractive) beyond.
/// [L^-d-1]; the pair acceleration is -gamma m_j C(r) r_ij / r.
#[inline]
pub fn cohesion_over_r(support: f32, rr: f32) -> f32 {
    if rr <= 0.0 || rr > support {
        return 0.0;
    }
    let x = rr / support;
    let y = 1.0 - x;
    let poly = y * y * y * x * x * x;
    let c = if x > 0.5 {
        poly
    } else {
        2.0 * poly - 1.0 / 64.0
    };
    32.0 / (std::f32::consts::PI * support * support * support) * c / rr
}

/// Whether a pair exchanges the whole stress sigma = -P I + S of eq. (16), or only its
/// pressure part -P I (`[solid] interface`, `interface`). By default only two
/// particles of one body (or two fluid particles) do: an inviscid fluid carries no shear
/// traction, so across a fluid-solid interface the fluid and the body meet through pressure
/// alone (Antoci, Gallati & Sibilla 2007, Comput. Struct. 85, 879: the interface term is a
/// surface integral of the fluid's pressure), and so do two bodies in contact or a body and
/// a wall. Passing a body's deviatoric stress to the fluid (the paper's eq. (16) across
/// every pair, `interface = "stress"`, kept by `--paper-exact`) tore an 8 x 8-particle
/// square apart within 0.3 time units of the water's impact (docs/reference/paper-scenes.md).
#[inline]
pub fn whole_stress_pair(p: &SphParams, same_body: bool) -> bool {
    same_body || p.interface != 0
}

/// sigma_i / rho_i^2 + sigma_j / rho_j^2 of eqs. (7), (16) across a pair with a wall
/// particle j. A wall pushes and never pulls: negative pressures (the tension of a thinning
/// layer) are cut to zero across a fluid-wall pair, or water clings to the walls (a dam
/// break's column stayed at the wall's top). [L^2 T^-2 / (M L^-d)]
#[inline]
pub fn wall_pair_stress<D: Dim>(
    sig_i: D::M,
    sig_j: D::M,
    p_i: f32,
    p_j: f32,
    rho_i: f32,
    rho_j: f32,
) -> D::M {
    let neg_i = (-p_i).max(0.0) / (rho_i * rho_i);
    let neg_j = (-p_j).max(0.0) / (rho_j * rho_j);
    sig_i + sig_j - D::identity() * (neg_i + neg_j)
}

/// The acceleration of particle i summed over its neighbours, as the force stage takes it:
/// `new`, then `add` for every neighbour j != i in the neighbour loop's order; `acc` is the
/// sum. The force monitors (`crate::measure::monitor`) take the wall pairs from it one by one. Twin:
/// `ForceSum` in `cuda/forces.cuh`.
pub struct ForceSum<'a, D: Dim> {
    s: &'a State<D>,
    /// `Setup::wall_surface` (empty unless `no_slip`).
    surface: &'a [[f32; 4]],
    /// (P', rho') per slot, the fluid's pressure at the bodies' particles and its Tait
    /// density (`interface::solid_interface`), where the bodies meet the fluid at it.
    iface: Option<&'a [[f32; 2]]>,
    /// The deviatoric stress and the artificial stress, where the state holds them.
    stress: Option<&'a Vec<D::M>>,
    art: Option<&'a Vec<D::M>>,
    i: usize,
    ki: u8,
    vi: D::V,
    rhoi: f32,
    pi: f32,
    ci: f32,
    /// sigma_i / rho_i^2 with sigma = -P I + S, eq. (11); S = 0 for fluid.
    sig_i: D::M,
    /// Its pressure part alone, for pairs across two objects (`whole_stress_pair`).
    sig_i_p: D::M,
    /// The acceleration so far [L/T^2].
    pub acc: D::V,
    /// `gradient_correction`'s matrices, where `[fluid] gradient_correction` is on.
    corr: Option<&'a [D::M]>,
}

impl<'a, D: Dim> ForceSum<'a, D> {
    /// Particle i (no wall particle) of state `s`, its sum started at `acc` (gravity in the
    /// force stage). Pressures are those of `s.p`.
    /// `iface`: `interface::solid_interface`'s (P', rho') where the bodies meet the fluid at
    /// its extrapolated pressure (`pairs::extrapolated_pair`), else None.
    pub fn new(
        p: &SphParams,
        s: &'a State<D>,
        surface: &'a [[f32; 4]],
        iface: Option<&'a [[f32; 2]]>,
        i: usize,
        acc: D::V,
    ) -> Self {
        let ki = s.kind[i];
        let (vi, rhoi, pi) = (s.vel[i], s.rho[i], s.p[i]);
        let stress = s.solid.as_ref().map(|so| &so.stress);
        let si = stress.map_or(D::zero(), |st| st[i]);
        ForceSum {
            s,
            surface,
            iface,
            stress,
            art: s.solid.as_ref().and_then(|so| so.art_stress.as_ref()),
            i,
            ki,
            vi,
            rhoi,
            pi,
            ci: p.sound_speed(ki),
            sig_i: (si - D::identity() * pi) * (1.0 / (rhoi * rhoi)),
            sig_i_p: (D::zero() - D::identity() * pi) * (1.0 / (rhoi * rhoi)),
            acc,
            corr: None,
        }
    }

    /// Adds what neighbour j (j != i, r = x_i - x_j, r2 = |r|^2 within the support) exerts on
    /// particle i.
    #[inline]
    pub fn add(&mut self, p: &SphParams, j: usize, r: D::V, r2: f32) {
        let s = self.s;
        let (vel, rho, pr, mass, kind, group, id) =
            (&s.vel, &s.rho, &s.p, &s.mass, &s.kind, &s.group, &s.id);
        let (stress, art) = (self.stress, self.art);
        let (i, ki, vi, rhoi, pi, ci) = (self.i, self.ki, self.vi, self.rhoi, self.pi, self.ci);
        let kj = kind[j];
        let rr = r2.sqrt();
        let fw = kernel::f(p, rr);
        let grad_w = r * fw; // grad_i W_ij
        if kj as u32 == MF_KIND_BOUNDARY {
            // A body that skips walls (`meets`) feels nothing of them.
            if !meets(p, ki, kj) {
                return;
            }
            self.acc += lennard_jones::<D>(p, r, rr); // eq. (17)
            if !couples(p, kj) {
                return;
            }
        }
        if let Some(iface) = self.iface.filter(|_| extrapolated_pair(p, ki, kj)) {
            let a = self.fluid_body(p, iface, j, r, r2, fw);
            self.acc += a;
            return;
        }
        let acc = &mut self.acc;
        let (vj, rhoj, kj32) = (vel[j], rho[j], kj as u32);
        let vij = vi - vj;
        let vr = D::dot(vij, r);
        let bonded = same_body(p, ki, kj, group[i], group[j]);
        // Stress term, eq. (16) (eq. (7) when both are fluid: sigma = -P I); across
        // two objects the pressure part only (`whole_stress_pair`). Within a
        // total-Lagrangian body the internal force replaces it (`Solver::solid_forces`).
        let whole = whole_stress_pair(p, bonded);
        let tl_internal = bonded && ki as u32 == MF_KIND_SOLID && total_lagrangian(p);
        if !tl_internal {
            let sj = match stress {
                Some(st) if whole => st[j],
                _ => D::zero(),
            };
            let sig_i = if whole { self.sig_i } else { self.sig_i_p };
            let sig_j = (sj - D::identity() * pr[j]) * (1.0 / (rhoj * rhoj));
            if kj as u32 == MF_KIND_BOUNDARY {
                let sig = wall_pair_stress::<D>(sig_i, sig_j, pi, pr[j], rhoi, rhoj);
                *acc += D::mat_vec(sig, grad_w) * mass[j];
            } else if let Some(l) = self.corr.filter(|_| both_fluid(ki, kj)) {
                // The renormalised gradient, (L_i + L_j) / 2 grad_i W_ij: antisymmetric in
                // the pair, so momentum stays conserved.
                let grad_l = D::mat_vec((l[i] + l[j]) * 0.5, grad_w);
                *acc += D::mat_vec(sig_i + sig_j, grad_l) * mass[j];
            } else {
                *acc += D::mat_vec(sig_i + sig_j, grad_w) * mass[j];
            }
        }
        // Artificial viscosity, eq. (10).
        let c_bar = 0.5 * (ci + p.sound_speed(kj));
        let rho_bar = 0.5 * (rhoi + rhoj);
        let pi_ij = artificial_viscosity(p, vr, r2, c_bar, rho_bar);
        *acc -= grad_w * (mass[j] * pi_ij);
        // Laminar viscosity wherever fluid meets fluid, a solid or a wall (no-slip; a
        // wall's velocity extrapolated under `no_slip`, Morris et al. 1997).
        if p.viscosity > 0.0 && (ki as u32 == MF_KIND_FLUID || kj32 == MF_KIND_FLUID) {
            let v_visc = laminar_velocity::<D>(p, self.surface, kj, id[j], r, vij);
            *acc += v_visc * (mass[j] * laminar(p, r2, fw, rhoi, rhoj));
        }
        // Cohesion between fluid particles, Akinci et al. 2013, eq. (2) (no curvature
        // term): -gamma m_j C(r) r_ij / r. A uniform branch: nothing when gamma = 0.
        if p.cohesion != 0.0 && ki as u32 == MF_KIND_FLUID && kj32 == MF_KIND_FLUID {
            *acc -= r * (p.cohesion * mass[j] * cohesion_over_r(p.support, rr));
        }
        if let Some(r_art) = art {
            if bonded && ki as u32 == MF_KIND_SOLID {
                // Gray, Monaghan & Swift 2001: f_ij^n (R_i + R_j) . grad W.
                let fij = (kernel::w(p, rr) * p.inv_w_dx).powf(p.artificial_stress_exponent);
                *acc += D::mat_vec(r_art[i] + r_art[j], grad_w) * (mass[j] * fij);
            }
        }
    }

    /// What j exerts on i where one is a fluid particle and the other a body's particle that
    /// meet at the fluid's extrapolated pressure (`pairs::extrapolated_pair`; r = x_i - x_j,
    /// fw = `kernel::f`): the body's particle b as fluid of its own volume
    /// V_b = m_b / rho_b, mass rho'_b V_b, at (P'_b, rho'_b) (`interface::solid_interface`),
    /// in eq. (7), eq. (10) (with the fluid's c0: b stands for fluid) and the laminar term.
    /// On b the same pair force, reversed, over its own mass: its acceleration is the fluid
    /// form's times rho'_b / rho_b (a body lighter than water rises). Momentum is conserved.
    #[inline]
    fn fluid_body(
        &self,
        p: &SphParams,
        iface: &[[f32; 2]],
        j: usize,
        r: D::V,
        r2: f32,
        fw: f32,
    ) -> D::V {
        let grad_w = r * fw; // grad_i W_ij
        let s = self.s;
        let i = self.i;
        let body_i = self.ki as u32 == MF_KIND_SOLID;
        // (P, rho, mass) as the pair sees each.
        let seen = |k: usize| {
            if s.kind[k] as u32 == MF_KIND_SOLID {
                let [pk, rk] = iface[k];
                (pk, rk, rk * s.mass[k] / s.rho[k])
            } else {
                (s.p[k], s.rho[k], s.mass[k])
            }
        };
        let (pi, rhoi, _) = seen(i);
        let (pj, rhoj, mj) = seen(j);
        // m_i' / m_i: 1 for fluid, rho'_b / rho_b for a body's particle.
        let scale = if body_i { rhoi / s.rho[i] } else { 1.0 };
        let vij = self.vi - s.vel[j];
        // eq. (7): -m_j (P_i / rho_i^2 + P_j / rho_j^2) grad_i W_ij
        let mut a = grad_w * (-mj * (pi / (rhoi * rhoi) + pj / (rhoj * rhoj)));
        // eq. (10)
        let pi_ij = artificial_viscosity(p, D::dot(vij, r), r2, p.c0, 0.5 * (rhoi + rhoj));
        a -= grad_w * (mj * pi_ij);
        if p.viscosity > 0.0 {
            a += vij * (mj * laminar(p, r2, fw, rhoi, rhoj));
        }
        a * scale
    }
}

/// `surface`: `Setup::wall_surface` (empty unless `no_slip`).
/// `iface`: `interface::solid_interface`'s, where the bodies meet the fluid at its
/// extrapolated pressure.
pub fn forces<D: Dim>(
    p: &SphParams,
    grid: &Grid,
    surface: &[[f32; 4]],
    iface: Option<&[[f32; 2]]>,
    s: &mut State<D>,
) {
    let g = D::from3(p.gravity);
    let st: &State<D> = s;
    let corr = gradient_correction(p, grid, st);
    let acc: Vec<D::V> = (0..st.len())
        .into_par_iter()
        .map(|i| {
            if st.kind[i] as u32 == MF_KIND_BOUNDARY {
                return D::V::default();
            }
            let mut f = ForceSum::new(p, st, surface, iface, i, g);
            f.corr = corr.as_deref();
            grid.for_each_neighbor::<D>(p, &st.pos, st.pos[i], |j, r, r2| {
                if j != i {
                    f.add(p, j, r, r2);
                }
            });
            f.acc
        })
        .collect();
    s.acc = acc;
}

fn both_fluid(ki: u8, kj: u8) -> bool {
    ki as u32 == MF_KIND_FLUID && kj as u32 == MF_KIND_FLUID
}

/// \[-\] Below this kernel sum sum_j V_j W_ij a fluid particle takes the plain gradient
/// (`gradient_correction`): a free surface's top row (about 0.5 to 0.6) and spray.
const CORRECTION_FROM: f32 = 0.7;
/// \[-\] From this kernel sum on it takes the whole correction (the bulk: about 1).
const CORRECTION_FULL: f32 = 0.95;

/// The kernel gradient renormalisation of each fluid particle for `[fluid]
/// gradient_correction` (Bonet & Lok 1999, Comput. Methods Appl. Mech. Engrg. 180, 97;
/// Oger et al. 2007, J. Comput. Phys. 225, 1472): L_i = (sum_j V_j (x_j - x_i) (x)
/// grad_i W_ij)^-T over every neighbour (walls and bodies stand in for the fluid they hold
/// back), V_j = m_j / rho_j, so that sum_j V_j (f_j - f_i) L_i grad_i W_ij is exact for a
/// linear f. Blended to the identity as the kernel sum gamma_i = sum_j V_j W_ij (itself
/// included) falls from `CORRECTION_FULL` to `CORRECTION_FROM`, where the moment matrix
/// is near singular and the plain gradient's pull towards the fluid is what holds a free
/// surface at p = 0; the identity where the matrix is singular and for other particles.
/// None unless the switch is on. \[-\]
pub fn gradient_correction<D: Dim>(p: &SphParams, grid: &Grid, s: &State<D>) -> Option<Vec<D::M>> {
    if p.gradient_correction == 0 {
        return None;
    }
    let (pos, rho, mass, kind) = (&s.pos, &s.rho, &s.mass, &s.kind);
    let l = (0..s.len())
        .into_par_iter()
        .map(|i| {
            if kind[i] as u32 != MF_KIND_FLUID {
                return D::identity();
            }
            let (mut m, mut gamma) = (D::zero(), 0.0f32);
            grid.for_each_neighbor::<D>(p, pos, pos[i], |j, r, r2| {
                let (rr, vj) = (r2.sqrt(), mass[j] / rho[j]);
                gamma += kernel::w(p, rr) * vj;
                if j != i {
                    m += D::outer(-r, r * kernel::f(p, rr)) * vj;
                }
            });
            let w =
                ((gamma - CORRECTION_FROM) / (CORRECTION_FULL - CORRECTION_FROM)).clamp(0.0, 1.0);
            if w == 0.0 || D::determinant(m).abs() <= MF_MOMENT_DET_MIN as f32 {
                return D::identity();
            }
            D::inverse(D::transpose(m)) * w + D::identity() * (1.0 - w)
        })
        .collect();
    Some(l)
}
