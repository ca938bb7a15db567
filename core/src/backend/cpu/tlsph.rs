//! The total-Lagrangian solid's stages (`crate::physics::tlsph`): the slot map after each grid
//! build, the stress from the deformation gradient (`Solver::solid_stress`), the internal
//! force with the hourglass control (`Solver::solid_forces`) and the displacement's drift.
//! Twin: `cuda/tlsph.cu`; parity test `tests/cuda_parity/`. A pair's reference separation is
//! the minimum image on periodic axes (`pairs::separation`, in `gradient::pair` too), its
//! current one X0_ab + u_a - u_b (face pairs) or the minimum image of the positions.

use rayon::prelude::*;

use super::integrate::driven_moved;
use crate::physics::dim::Dim;
use crate::physics::pairs::separation;
use crate::physics::params::{SphParams, MF_KIND_SOLID};
use crate::physics::particle::Particle;
use crate::physics::state::State;
use crate::physics::tlsph::gradient::{apply, basis, pair, Q_MAX};
use crate::physics::tlsph::{hourglass, pair_error, svk, Corr, Material, Reference, NONE};

/// The bodies' reference configuration and what the stages keep per solid particle, in
/// solid space (`crate::physics::tlsph`).
#[derive(Clone, Debug)]
pub struct TlBodies<D: Dim> {
    pub reference: Reference<D>,
    /// Solid index -> storage slot, rebuilt after every reorder (`NONE`: removed).
    pub slot: Vec<u32>,
    /// \[L\] u = x - X0, advanced with the position in the drift.
    pub disp: Vec<D::V>,
    /// [-] H = F - I of the last stress stage.
    pub grad_u: Vec<D::M>,
    /// [M L^-d L^2 T^-2 L] (omega / V0) P C of the last stress stage, column by column (the
    /// internal force's factor; `tlsph::quadrature`).
    pub pk1_corr: Vec<Corr<D>>,
}

impl<D: Dim> TlBodies<D> {
    /// The reference configuration of `particles` as they are: zero displacement.
    pub fn new(p: &SphParams, particles: &[Particle]) -> Self {
        let reference = Reference::<D>::new(p, particles);
        let n = reference.len();
        TlBodies {
            reference,
            slot: vec![NONE; n],
            disp: vec![D::V::default(); n],
            grad_u: vec![D::zero(); n],
            pk1_corr: vec![[D::V::default(); Q_MAX]; n],
        }
    }

    /// `slot[a]` = the storage slot of solid a (`NONE` where it is gone), from the ids.
    pub fn map_slots(&mut self, s: &State<D>) {
        self.slot.fill(NONE);
        let index = &self.reference.index_of_id;
        for (i, (&id, &k)) in s.id.iter().zip(&s.kind).enumerate() {
            if k as u32 == MF_KIND_SOLID {
                let a = index[id as usize];
                if a != NONE {
                    self.slot[a as usize] = i as u32;
                }
            }
        }
    }

    /// The stress stage: per solid particle H = F - I from the displacements, the
    /// Saint Venant-Kirchhoff stress (`svk`), P C kept for the force stage, and the
    /// deviator of the Cauchy stress written into the stress array, where the rest of the
    /// scheme reads it. The particle's density and pressure stay the continuity density's
    /// and its equation of state's, as a dynamic wall particle's: they are what the fluid
    /// meets at the interface (with the solid's own -p I in them, the fluid ran into the gate
    /// and squeezed the impinging bodies until their density doubled).
    pub fn stress(&mut self, p: &SphParams, s: &mut State<D>) {
        let m = Material::of(p);
        let (r, slot, disp) = (&self.reference, &self.slot, &self.disp);
        // Per solid particle: H, P L, and the Cauchy stress's deviator (`SolidStress`).
        let out: Vec<(D::M, Corr<D>, D::M)> = (0..r.len())
            .into_par_iter()
            .map(|a| {
                if slot[a] == NONE {
                    return (D::zero(), [D::V::default(); Q_MAX], D::zero());
                }
                let h =
                    r.displacement_gradient(p, a, disp[a], |b| (slot[b] != NONE).then(|| disp[b]));
                let st = svk::<D>(&m, p.solid_rho0, h);
                // The energy's quadrature weight omega_a = quad_a V0_a (`tlsph::quadrature`).
                let pk1 = st.pk1 * r.quad[a];
                (h, r.corr[a].map(|c| D::mat_vec(pk1, c)), st.deviator)
            })
            .collect();
        let mut stress = s.solid.as_mut().map(|so| &mut so.stress);
        for (a, (h, pl, dev)) in out.into_iter().enumerate() {
            self.grad_u[a] = h;
            self.pk1_corr[a] = pl;
            let i = slot[a];
            if i == NONE {
                continue;
            }
            let i = i as usize;
            if let Some(st) = stress.as_mut() {
                st[i] = dev;
            }
        }
    }

    /// The internal force: acc_a += (1 / rho0_s) (sum_b V0_b w_ab [P_a C_a p(s_ab) -
    /// P_b C_b p(-s_ab)] + P_a C_a F_a) (F_a: the clamp's face, `tlsph::faces`;
    /// `crate::physics::tlsph`: m_a dv_a/dt = sum_b V0_a V0_b w_ab [...], V0_a / m_a = 1 / rho0_s) plus
    /// the hourglass control (`hourglass`) over the neighbours and the face points, added to
    /// the force stage's sum (which skipped the pairs of one body: `ForceSum`). [L/T^2]
    pub fn forces(&self, p: &SphParams, s: &mut State<D>) {
        let young = Material::of(p).young;
        let (r, slot) = (&self.reference, &self.slot);
        let pos = &s.pos;
        let add: Vec<D::V> = (0..r.len())
            .into_par_iter()
            .map(|a| {
                let i = slot[a];
                if i == NONE {
                    return D::V::default();
                }
                let (pla, ha, ua) = (&self.pk1_corr[a], self.grad_u[a], self.disp[a]);
                // The clamp's face (`tlsph::faces`): P_a C_a F_a, the derivative of a's strain
                // energy through its face term.
                let mut acc = D::V::default();
                if let Some(c) = r.clamp_of(a).filter(|&c| slot[c] != NONE) {
                    acc += apply::<D>(pla, &r.face[a]) * (1.0 / p.solid_rho0);
                    // The face pairs' hourglass control (`hourglass`): a face point m moves with
                    // the clamp (x_m = X0_m + u_c); the error of the pair is that of a's fit at
                    // X0_m, eps = 2 (u_c - u_fit(X0_m)), u_fit(X0_m) = u_a + sum_k r_k B_k
                    // (`FacePair::fit`, B the sum a's fit reads: `gradient::value_weights`),
                    // zero for a quadratic field that takes the clamp's value on the face
                    // (with H_a X0_ma for u_fit - u_a, the bent beam's root came out soft at
                    // first order). Without it the root of a thin gate slid along the face
                    // (0.3 dx in 0.05 s at 2 across, docs/journal/2026-11-27-clamp-face.md).
                    if p.hourglass > 0.0 {
                        let uc = self.disp[c];
                        let fit_sum = self.fit_sum(p, a, uc);
                        for m in r.faces_of(a) {
                            let x0_am = separation::<D>(p, r.x0[a], m.x0);
                            let u_fit = ua + apply::<D>(&fit_sum, &m.fit);
                            let eps = (uc - u_fit) * 2.0;
                            acc += hourglass::<D>(p, young, m.vol, x0_am, x0_am + (ua - uc), eps);
                        }
                    }
                }
                for &b in r.neighbours(a) {
                    let b = b as usize;
                    let j = slot[b];
                    if j == NONE {
                        continue;
                    }
                    let (w, sab) = pair::<D>(p, r.x0[a], r.x0[b]);
                    let (pab, pba) = (basis::<D>(sab), basis::<D>(-sab));
                    let f = apply::<D>(pla, &pab) - apply::<D>(&self.pk1_corr[b], &pba);
                    acc += f * (r.vol[b] * w / p.solid_rho0);
                    if p.hourglass > 0.0 {
                        let x_ab = separation::<D>(p, pos[i as usize], pos[j as usize]);
                        let x0_ab = separation::<D>(p, r.x0[a], r.x0[b]);
                        let eps = pair_error::<D>(x0_ab, ua - self.disp[b], ha, self.grad_u[b]);
                        acc += hourglass::<D>(p, young, r.vol[b], x0_ab, x_ab, eps);
                    }
                }
                acc
            })
            .collect();
        for (a, da) in add.into_iter().enumerate() {
            if slot[a] != NONE {
                s.acc[slot[a] as usize] += da;
            }
        }
    }

    /// B_a = sum_b V0_b w_ab p(s_ab) (u_b - u_a) + F_a (u_c - u_a) [L^-d L], the sum a's fit
    /// reads (`gradient`; the face term with the clamp's displacement `uc`), as Q columns:
    /// grad u_a = C_a B_a, the fit's value at a point `gradient::value_weights`.
    fn fit_sum(&self, p: &SphParams, a: usize, uc: D::V) -> Corr<D> {
        let r = &self.reference;
        let ua = self.disp[a];
        let mut sum = [D::V::default(); Q_MAX];
        let mut add = |weights: &[f32; Q_MAX], du: D::V| {
            for (s, &wk) in sum.iter_mut().zip(weights) {
                *s += du * wk;
            }
        };
        for &b in r.neighbours(a) {
            let b = b as usize;
            if self.slot[b] != NONE {
                let (w, sab) = pair::<D>(p, r.x0[a], r.x0[b]);
                add(
                    &basis::<D>(sab).map(|v| v * r.vol[b] * w),
                    self.disp[b] - ua,
                );
            }
        }
        add(&r.face[a], uc - ua);
        sum
    }

    /// u += dt (v + xsph), or a driven object's move over the step from `t0`
    /// (`integrate::driven_moved`): what the drift adds to the position
    /// (`integrate::drift`), with the velocity the drift takes (the new one in the
    /// symplectic Euler, the old one in the forward Euler). \[L\]
    pub fn drift(&mut self, p: &SphParams, series: &[f64], dt: f32, t0: f64, s: &State<D>) {
        let slot = &self.slot;
        self.disp.par_iter_mut().enumerate().for_each(|(a, u)| {
            let i = slot[a];
            if i == NONE {
                return;
            }
            let i = i as usize;
            let x = s.pos[i];
            *u += match driven_moved::<D>(p, series, s.group[i], x, dt, t0) {
                Some(y) => y - x,
                None => (s.vel[i] + s.xsph[i]) * dt,
            };
        });
    }
}
