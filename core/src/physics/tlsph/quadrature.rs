//! The quadrature of the total-Lagrangian body's strain energy: the weight omega_a with which
//! each particle's energy density enters E = sum_a omega_a psi(F_a) (`crate::physics::tlsph`).
//!
//! With omega_a = V0_a, the particle's volume, the sum is the midpoint rule over the
//! particles' cells, which misses (dx^2 / 24) lap psi per unit volume (the integral of the
//! second-order term of psi over a cube of side dx: int (X - X_a)_i^2 dV = V0 dx^2 / 12). A
//! bent beam's energy density is quadratic across its thickness, and the rule reads its
//! second moment of area short by the factor 1 - (dx / t)^2 (the rows' sum of y^2 dx against
//! t^3 / 12): a cantilever of 9 particles across 1.2 % too soft, 5 across 4 %. The midpoint
//! rule with that term, E = sum_a V0_a (psi_a + (dx_a^2 / 24) lap psi_a), is exact for a
//! quadratic psi over the union of the cells (in the interior lap psi is summed where the
//! midpoint rule needed no help: the Euler-Maclaurin correction of a uniform lattice's rule
//! sits at its ends, which is where the sum below puts it). With the fit's Laplacian
//! (`gradient::laplacian`, lap psi_a = sum_b L_ab (psi_b - psi_a)) it is a sum of the psi_b
//! again, so a weight per particle, set up once:
//!
//! omega_c = V0_c + sum_{a: c in N(a)} V0_a (dx_a^2 / 24) L_ac - V0_c (dx_c^2 / 24) sum_b L_cb,
//!
//! dx_a = V0_a^(1/d) (the cell's side). In the interior of a lattice L is symmetric and
//! omega = V0; it moves weight outwards at the faces (on a lattice block omega / V0 stays
//! within 0.751 ... 1.162 in 2D, test `energy_quadrature_is_exact_for_a_quadratic_density`). The force
//! is the derivative of that energy: P_a enters the internal force as (omega_a / V0_a) P_a
//! (`Reference::quad`).
//!
//! Where the fits are poor the weights are not: a sphere 5 particles across with jittered
//! positions (`tests/cuda_parity/`, the clamped block) gave omega / V0 from -3.9 to 7.4, an
//! energy that is no longer positive, and blew up. A quadrature with a weight below half the
//! particle's volume or above one and a half (an energy not positive with a margin, a wave
//! speed more than 1.22 times the one the time step allows for) is not used: its body (the
//! particles of one group) keeps the midpoint rule, omega = V0.

use crate::physics::dim::Dim;
use crate::physics::params::SphParams;
use crate::physics::tlsph::gradient;

/// The bounds of omega / V0 within which a body's quadrature is used (see above) [-].
pub const QUAD_RANGE: (f32, f32) = (0.5, 1.5);

/// omega_a / V0_a per particle [-] from the reference positions, volumes, neighbours (the
/// CSR of `Reference`: the neighbours of a are `nbr[start[a] .. start[a + 1]]`) and groups
/// (a body: one group). A particle whose fit is linear (fewer than three rows across,
/// `gradient::laplacian`) adds no term; a body with a weight outside `QUAD_RANGE` takes 1.
pub fn weights<D: Dim>(
    p: &SphParams,
    x0: &[D::V],
    vol: &[f32],
    start: &[u32],
    nbr: &[u32],
    group: &[u32],
) -> Vec<f32> {
    let n = x0.len();
    let mut omega: Vec<f64> = vol.iter().map(|&v| v as f64).collect();
    let cell2 = |v: f32| (v as f64).powf(2.0 / D::D as f64); // [L^2] dx^2
    for a in 0..n {
        let list = &nbr[start[a] as usize..start[a + 1] as usize];
        let nbrs: Vec<(D::V, f32)> = list
            .iter()
            .map(|&b| (x0[b as usize], vol[b as usize]))
            .collect();
        let Some(l) = gradient::laplacian::<D>(p, x0[a], &nbrs) else {
            continue;
        };
        let k = vol[a] as f64 * cell2(vol[a]) / 24.0; // [L^d L^2]
        for &b in list {
            let b = b as usize;
            let (w, s) = gradient::pair::<D>(p, x0[a], x0[b]);
            let pb = gradient::basis::<D>(s);
            let lab: f64 = l
                .iter()
                .zip(pb)
                .map(|(&x, y)| x as f64 * y as f64)
                .sum::<f64>()
                * vol[b] as f64
                * w as f64;
            omega[b] += k * lab;
            omega[a] -= k * lab;
        }
    }
    let mut quad: Vec<f32> = omega
        .iter()
        .zip(vol)
        .map(|(&o, &v)| if v > 0.0 { (o / v as f64) as f32 } else { 1.0 })
        .collect();
    let poor: std::collections::HashSet<u32> = (0..n)
        .filter(|&a| !(QUAD_RANGE.0..=QUAD_RANGE.1).contains(&quad[a]))
        .map(|a| group[a])
        .collect();
    for (q, g) in quad.iter_mut().zip(group) {
        if poor.contains(g) {
            *q = 1.0;
        }
    }
    quad
}
