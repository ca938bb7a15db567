//! The total-Lagrangian elastic solid (`[solid] formulation = "total-lagrangian"`): the
//! reference configuration, set up once at start on the host (both backends take it from
//! here), and the per-particle material law. O'Connor & Rogers 2021 ("A fluid-structure
//! interaction model for free-surface flows and flexible structures using smoothed particle
//! hydrodynamics on a GPU", J. Fluids Struct. 104, 103312; equation numbers not checked
//! against the paper, so none are cited here); the hourglass
//! control of Ganzenmueller 2015 (Comput. Methods Appl. Mech. Engrg. 286, 87).
//!
//! The solid particles live in a fixed *solid space*: index a = their rank by id, whatever
//! the storage order (which the grid re-sorts every step). Per solid particle: the reference
//! position X0_a \[L\], the reference volume V0_a = m_a / rho0_s \[L^d\], the correction C_a of
//! its reference gradient (`gradient`: consistent to second order, so that the gradient
//! sum_b (f_b - f_a) (x) g_ab with g_ab = V0_b w_ab C_a p(s_ab) is exact for a quadratic
//! field f, the body's faces included; Bonet & Lok's L_a = M_a^-T in the interior), and its
//! reference neighbours: the solid particles of the same body (`same_body`: a clamp is bonded
//! to the body it holds) within the support at the start, ascending, as a CSR list.
//!
//! Periodic axes (`[domain] periodic`): a body or a clamp may cross the seam, so every
//! reference separation X0_b - X0_a, here and in the stages, is the minimum image
//! (`pairs::separation`, as the fluid's neighbour search takes it), and the candidates come
//! from cells that wrap round the period (`cells`). X0 stays where the particle started,
//! inside the domain; u = x - X0 is integrated, not wrapped, so the current separation
//! X0_b - X0_a + u_b - u_a needs nothing more.
//!
//! The stages (CPU: `backend/cpu/tlsph.rs`; CUDA: `cuda/tlsph.cu`) integrate a displacement
//! u = x - X0 per solid particle (f32 positions near 1 m resolve strains of about 1e-7 / dx
//! only, an aluminium plate strains 1e-5), form the displacement gradient H = F - I from it,
//! the Saint Venant-Kirchhoff stress (`svk`), and the internal force, the derivative of the
//! discrete strain energy sum_a V0_a psi(F_a) with respect to u_a (so momentum-conserving):
//! m_a dv_a/dt = V0_a P_a sum_b g_ab - sum_b V0_b P_b g_ba
//!             = sum_b V0_a V0_b w_ab [P_a C_a p(s_ab) - P_b C_b p(-s_ab)]
//! (O'Connor & Rogers 2021's sum_b V0_a V0_b (P_a L_a + P_b L_b) grad_a W0_ab where C is
//! linear).

pub mod cells;
pub mod gradient;
pub mod quadrature;

use crate::physics::dim::Dim;
use crate::physics::kernel;
use crate::physics::pairs::{same_body, separation};
use crate::physics::params::{SphParams, MF_KIND_SOLID, MF_SOLID_TOTAL_LAGRANGIAN};
use crate::physics::particle::{Kind, Particle};
pub use gradient::Corr;
use gradient::Q_MAX;

/// No solid index (an id that is not a solid particle's), no storage slot (a solid particle
/// removed with its group).
pub const NONE: u32 = u32::MAX;

/// Whether the scene's bodies are total Lagrangian.
#[inline]
pub fn total_lagrangian(p: &SphParams) -> bool {
    p.solid_formulation as u32 == MF_SOLID_TOTAL_LAGRANGIAN
}

/// The reference configuration of every solid particle, in solid space (rank by id).
#[derive(Clone, Debug, Default)]
pub struct Reference<D: Dim> {
    /// Solid index -> particle id, ascending.
    pub id: Vec<u32>,
    /// Particle id -> solid index (`NONE` for other particles); as long as the largest id + 1.
    pub index_of_id: Vec<u32>,
    /// \[L\] X0.
    pub x0: Vec<D::V>,
    /// [L^d] V0 = m / rho0_s.
    pub vol: Vec<f32>,
    /// \[L\] C_a, the second-order correction of the reference gradient (`gradient`).
    pub corr: Vec<Corr<D>>,
    /// [-] omega_a / V0_a, the weight of a's strain energy over its volume (`quadrature`).
    pub quad: Vec<f32>,
    /// CSR: the neighbours of a are `nbr[start[a] .. start[a + 1]]` (solid indices).
    pub start: Vec<u32>,
    pub nbr: Vec<u32>,
    /// [L^-d] F_a = sum_m V_m w_am p(s_am) over the clamp's face points m within a's support
    /// (`faces`): the face's share of the gradient, g_face = C_a F_a [L^-1]; zero away from a
    /// clamp.
    pub face: Vec<[f32; Q_MAX]>,
    /// The solid index of a clamp particle whose displacement the face takes (the clamp is
    /// rigid), `NONE` where a has no face term.
    pub face_clamp: Vec<u32>,
    /// CSR: the face points within a's support are `face_pts[face_start[a] .. face_start[a + 1]]`
    /// (the hourglass control's face pairs).
    pub face_start: Vec<u32>,
    pub face_pts: Vec<FacePair<D>>,
}

impl<D: Dim> Reference<D> {
    /// The reference configuration of the solid particles of `particles` (any order, any
    /// kinds) as they are now.
    pub fn new(p: &SphParams, particles: &[Particle]) -> Self {
        let mut solids: Vec<&Particle> =
            particles.iter().filter(|q| q.kind == Kind::Solid).collect();
        solids.sort_by_key(|q| q.id);
        let n = solids.len();
        let max_id = particles
            .iter()
            .map(|q| q.id as usize + 1)
            .max()
            .unwrap_or(0);
        let mut index_of_id = vec![NONE; max_id];
        for (a, q) in solids.iter().enumerate() {
            index_of_id[q.id as usize] = a as u32;
        }
        let x0: Vec<D::V> = solids.iter().map(|q| D::from3(q.position)).collect();
        let vol: Vec<f32> = solids.iter().map(|q| q.mass / p.solid_rho0).collect();
        // Candidates from cells one support wide (3^d cells around each particle).
        let cells = cells::Cells::<D>::new(p, x0.iter().copied());
        let clamp = |a: usize| p.is_driven(solids[a].group);
        let faces = faces::<D>(p, &x0, &vol, &clamp, |x| cells.around(x));
        let face_cells = cells::Cells::<D>::new(p, faces.iter().map(|f| f.x));
        let mut start = Vec::with_capacity(n + 1);
        let mut nbr = Vec::new();
        start.push(0u32);
        let solid = MF_KIND_SOLID as u8;
        for a in 0..n {
            let mut list: Vec<u32> = cells
                .around(x0[a])
                .into_iter()
                .filter(|&b| {
                    let b_us = b as usize;
                    b_us != a
                        && D::length2(separation::<D>(p, x0[a], x0[b_us])) < p.support2
                        && same_body(p, solid, solid, solids[a].group, solids[b_us].group)
                        && (faces.is_empty() || clamp(a) == clamp(b_us))
                })
                .collect();
            list.sort_unstable();
            nbr.extend_from_slice(&list);
            start.push(nbr.len() as u32);
        }
        let mut face = vec![[0.0f32; Q_MAX]; n];
        let mut face_clamp = vec![NONE; n];
        let mut face_near: Vec<Vec<FacePair<D>>> = vec![Vec::new(); n];
        let corr = (0..n)
            .map(|a| {
                let mut nbrs: Vec<(D::V, f32)> = nbr[start[a] as usize..start[a + 1] as usize]
                    .iter()
                    .map(|&b| (x0[b as usize], vol[b as usize]))
                    .collect();
                let near: Vec<&Face<D>> = if clamp(a) {
                    Vec::new()
                } else {
                    face_cells
                        .around(x0[a])
                        .into_iter()
                        .map(|m| &faces[m as usize])
                        .filter(|f| D::length2(separation::<D>(p, f.x, x0[a])) < p.support2)
                        .collect()
                };
                nbrs.extend(near.iter().map(|f| (f.x, f.vol)));
                let c = gradient::correction::<D>(p, x0[a], &nbrs);
                for f in &near {
                    let (w, s) = gradient::pair::<D>(p, x0[a], f.x);
                    let pm = gradient::basis::<D>(s);
                    for (acc, v) in face[a].iter_mut().zip(pm) {
                        *acc += f.vol * w * v;
                    }
                    face_clamp[a] = f.clamp;
                    face_near[a].push(FacePair {
                        x0: f.x,
                        vol: f.vol,
                        fit: gradient::value_weights::<D>(p, &c, x0[a], &nbrs, f.x),
                    });
                }
                c
            })
            .collect();
        let group: Vec<u32> = solids.iter().map(|q| q.group).collect();
        let quad = quadrature::weights::<D>(p, &x0, &vol, &start, &nbr, &group);
        Reference {
            id: solids.iter().map(|q| q.id).collect(),
            index_of_id,
            x0,
            vol,
            corr,
            quad,
            start,
            nbr,
            face,
            face_clamp,
            face_start: std::iter::once(0)
                .chain(face_near.iter().scan(0u32, |k, l| {
                    *k += l.len() as u32;
                    Some(*k)
                }))
                .collect(),
            face_pts: face_near.concat(),
        }
    }

    /// Solid particles.
    pub fn len(&self) -> usize {
        self.id.len()
    }

    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// The reference neighbours of solid index a.
    #[inline]
    pub fn neighbours(&self, a: usize) -> &[u32] {
        &self.nbr[self.start[a] as usize..self.start[a + 1] as usize]
    }

    /// The displacement gradient H_a = F_a - I = sum_b (u_b - u_a) (x) g_ab plus the clamp's
    /// face term (u_clamp - u_a) (x) C_a F_a (`faces`) [-] (`gradient`;
    /// O'Connor & Rogers 2021's F less I, from the displacement rather than the position so
    /// that small strains survive f32), over the neighbours b for which `disp(b)` answers (a
    /// removed particle does not).
    pub fn displacement_gradient(
        &self,
        p: &SphParams,
        a: usize,
        ua: D::V,
        disp: impl Fn(usize) -> Option<D::V>,
    ) -> D::M {
        let mut g = D::zero();
        for &b in self.neighbours(a) {
            let b = b as usize;
            if let Some(ub) = disp(b) {
                let gw =
                    gradient::weight::<D>(p, &self.corr[a], self.vol[b], self.x0[a], self.x0[b]);
                g += D::outer(ub - ua, gw);
            }
        }
        if let Some(uc) = self.clamp_of(a).and_then(&disp) {
            g += D::outer(uc - ua, gradient::apply::<D>(&self.corr[a], &self.face[a]));
        }
        g
    }

    /// The face points within a's support.
    #[inline]
    pub fn faces_of(&self, a: usize) -> &[FacePair<D>] {
        &self.face_pts[self.face_start[a] as usize..self.face_start[a + 1] as usize]
    }

    /// The clamp particle whose displacement a's face term takes, if a has one.
    #[inline]
    pub fn clamp_of(&self, a: usize) -> Option<usize> {
        let c = self.face_clamp[a];
        (c != NONE).then_some(c as usize)
    }
}

/// A point of a clamp's face: where the clamp holds the body at the clamp's displacement.
#[derive(Clone, Copy, Debug)]
pub struct Face<D: Dim> {
    /// \[L\] its reference position: the midpoint of a clamp particle and a body particle that
    /// face each other (across a periodic seam: on the body particle's side, maybe just
    /// outside the domain).
    pub x: D::V,
    /// [L^d] the weight it takes in the fit: the clamp particle's V0.
    pub vol: f32,
    /// The clamp particle's solid index.
    pub clamp: u32,
}

/// A face point m as one body particle a sees it, for the hourglass control of the pair
/// (a, m) (`TlBodies::forces`).
#[derive(Clone, Copy, Debug)]
pub struct FacePair<D: Dim> {
    /// \[L\] X0_m.
    pub x0: D::V,
    /// [L^d] V_m, its weight in a's fit (`Face::vol`).
    pub vol: f32,
    /// [-] r_am, the weights with which a's fit predicts the displacement at X0_m from the
    /// sum it reads (`gradient::value_weights`): u_a + sum_k r_k B_k, exact for a quadratic
    /// field.
    pub fit: [f32; Q_MAX],
}

/// The faces of the clamps (`[[solids]]` held by a driven group): for every body particle b,
/// its nearest clamp particles g (within 1 % of the nearest, and no further than 1.5 dx: the
/// clamp's first row across the face) give a face point at (X0_g + X0_b) / 2, X0_g - X0_b the
/// minimum image. `candidates(x)` lists the solid indices within one support of x.
///
/// Why: the body's displacement is smooth up to the face, but the clamp's is zero behind it.
/// A fit that reads the clamp's particles as neighbours averages the two across the face, and
/// the clamped end of a bent beam, where the curvature is largest, comes out soft (the root
/// rotates: a cantilever of 9 particles across bent 7 % too far, its deflection near the root
/// 2-3 times the theory's at 5). Where faces exist, the body and the clamp are not each other's
/// neighbours; the body's fit takes the face points instead, with the clamp's displacement as
/// their value: a Dirichlet condition on the face, exact for a quadratic field that takes the
/// clamp's value there (a clamped beam's, u = 0 at the root). Where none are found (a clamp
/// that does not sit on the body's lattice), the clamp stays a bonded neighbour.
fn faces<D: Dim>(
    p: &SphParams,
    x0: &[D::V],
    vol: &[f32],
    clamp: &impl Fn(usize) -> bool,
    candidates: impl Fn(D::V) -> Vec<u32>,
) -> Vec<Face<D>> {
    let reach2 = (1.5 * p.dx) * (1.5 * p.dx); // [L^2]
    let mut out = Vec::new();
    for b in (0..x0.len()).filter(|&b| !clamp(b)) {
        let near: Vec<(f32, usize)> = candidates(x0[b])
            .into_iter()
            .map(|g| g as usize)
            .filter(|&g| clamp(g))
            .map(|g| (D::length2(separation::<D>(p, x0[g], x0[b])), g))
            .filter(|&(r2, _)| r2 <= reach2)
            .collect();
        let Some(r2_min) = near.iter().map(|n| n.0).min_by(f32::total_cmp) else {
            continue;
        };
        for &(r2, g) in &near {
            if r2 <= 1.0201 * r2_min {
                // The image of g nearest b: X0_g itself unless the pair crosses a periodic
                // seam (so that elsewhere the face point is the plain midpoint, bit for bit).
                let xg = x0[g] - ((x0[g] - x0[b]) - separation::<D>(p, x0[g], x0[b]));
                out.push(Face {
                    x: (xg + x0[b]) * 0.5,
                    vol: vol[g],
                    clamp: g as u32,
                });
            }
        }
    }
    out
}

/// The elastic constants of the Saint Venant-Kirchhoff law from the scene's solid: mu = G
/// (`shear_modulus`), lambda = K - 2 G / 3 with the bulk modulus K = rho0_s c_s^2 (`[solid]
/// sound_speed` is the bulk sound speed), and Young's modulus E = 9 K G / (3 K + G) for the
/// hourglass control. [M L^-d L^2 T^-2]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub lambda: f32,
    pub mu: f32,
    pub young: f32,
}

impl Material {
    pub fn of(p: &SphParams) -> Self {
        let k = p.solid_rho0 * p.solid_c0 * p.solid_c0;
        let g = p.shear_modulus;
        Material {
            lambda: k - 2.0 * g / 3.0,
            mu: g,
            young: if 3.0 * k + g > 0.0 {
                9.0 * k * g / (3.0 * k + g)
            } else {
                0.0
            },
        }
    }
}

/// What the stress stage makes of one particle's displacement gradient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolidStress<M> {
    /// The first Piola-Kirchhoff stress P = F S [M L^-d L^2 T^-2].
    pub pk1: M,
    /// The Cauchy stress's pressure p = -tr(sigma) / 3, sigma = J^-1 P F^T (in 2D plane
    /// strain with sigma_zz = J^-1 S_zz) [M L^-d L^2 T^-2].
    pub pressure: f32,
    /// Its deviator sigma + p I (the D x D block), which the existing stress array carries:
    /// sigma = -p I + S as eq. (11) [M L^-d L^2 T^-2].
    pub deviator: M,
    /// rho0_s / J, J = det F [M L^-d].
    pub density: f32,
}

/// Saint Venant-Kirchhoff (as O'Connor & Rogers 2021): the Green strain
/// E = (F^T F - I) / 2 = (H + H^T + H^T H) / 2 (written in H = F - I so that a strain of 1e-6
/// is not lost to rounding against I), the second Piola-Kirchhoff stress
/// S = lambda tr(E) I + 2 mu E, P = F S; objective (a rigid rotation gives E = 0). 2D is
/// plane strain: F_zz = 1, E_zz = 0, S_zz = lambda tr(E).
pub fn svk<D: Dim>(m: &Material, rho0: f32, h: D::M) -> SolidStress<D::M> {
    let ht = D::transpose(h);
    let e = (h + ht + ht * h) * 0.5;
    let tr_e = D::trace(e);
    let s = D::identity() * (m.lambda * tr_e) + e * (2.0 * m.mu);
    let f = D::identity() + h;
    let pk1 = f * s;
    let j = D::determinant(f);
    let inv_j = 1.0 / j;
    let sigma = pk1 * D::transpose(f) * inv_j;
    let zz = if D::D == 2 {
        m.lambda * tr_e * inv_j
    } else {
        0.0
    };
    let pressure = -(D::trace(sigma) + zz) / 3.0;
    SolidStress {
        pk1,
        pressure,
        deviator: sigma + D::identity() * pressure,
        density: rho0 * inv_j,
    }
}

/// Ganzenmueller 2015's hourglass control, eq. (10) as TrixiParticles writes it: the
/// acceleration [L/T^2] of a from the pair (a, b) that pushes the pair's separation towards
/// the one the deformation gradients predict. `x0_ab` = X0_a - X0_b, `x_ab` = x_a - x_b
/// (current), `eps` the error of the separation \[L\] (`pair_error`; for a face pair,
/// `TlBodies::forces`): delta = eps . x_ab / |x_ab|,
/// a_a = (alpha / 2) (V0_b / rho0) W0_ab / |X0_ab|^2 E delta x_ab / |x_ab|.
#[inline]
pub fn hourglass<D: Dim>(
    p: &SphParams,
    young: f32,
    vol_b: f32,
    x0_ab: D::V,
    x_ab: D::V,
    eps: D::V,
) -> D::V {
    let r0_2 = D::length2(x0_ab);
    let r2 = D::length2(x_ab);
    if r0_2 <= 0.0 || r2 <= 0.0 {
        return D::V::default();
    }
    let w0 = kernel::w(p, r0_2.sqrt());
    // delta x_ab / |x_ab| = (eps . x_ab) x_ab / |x_ab|^2.
    let k = 0.5 * p.hourglass * vol_b / p.solid_rho0 * w0 / r0_2 * young * D::dot(eps, x_ab) / r2;
    x_ab * k
}

/// The error of a body pair's separation, Ganzenmueller 2015's
/// eps = (F_a + F_b) X0_ab - 2 x_ab = (H_a + H_b) X0_ab - 2 u_ab \[L\] (in displacements for
/// f32; `u_ab` = u_a - u_b, `h_a`, `h_b` the displacement gradients): zero for a quadratic
/// field under gradients exact for it (the trapezoidal rule).
#[inline]
pub fn pair_error<D: Dim>(x0_ab: D::V, u_ab: D::V, h_a: D::M, h_b: D::M) -> D::V {
    D::mat_vec(h_a + h_b, x0_ab) - u_ab * 2.0
}
