//! The optional artificial stress of elastic solids (Gray, Monaghan & Swift 2001), taken
//! in the density stage. Twin: `cuda/density.cu`; parity test `tests/cuda_parity/`.
// Index loops over tensor and vector components read like the equations they implement.
#![allow(clippy::needless_range_loop)]

use rayon::prelude::*;

use crate::consts::{MF_JACOBI_OFF_MIN, MF_JACOBI_PIVOT_MIN, MF_JACOBI_SWEEPS};
use crate::physics::dim::Dim;
use crate::physics::params::{SphParams, MF_KIND_SOLID};
use crate::physics::state::State;

/// The artificial stress R of every solid particle (zero elsewhere), from sigma = -P I + S,
/// eq. (11), at the current time level, or from S alone where the scene says so
/// (`artificial_stress_from`, `[solid] artificial_stress_from = "deviatoric"`). Does nothing
/// where it is switched off.
pub fn update_artificial_stress<D: Dim>(p: &SphParams, s: &mut State<D>) {
    let (kind, rho, pr) = (&s.kind, &s.rho, &s.p);
    let Some(solid) = s.solid.as_mut() else {
        return;
    };
    let stress = &solid.stress;
    if let Some(art) = solid.art_stress.as_mut() {
        art.par_iter_mut().enumerate().for_each(|(i, r)| {
            *r = if kind[i] as u32 == MF_KIND_SOLID {
                let sigma = stress[i] - D::identity() * art_pressure(p, pr[i]);
                artificial_stress::<D>(sigma, rho[i], p.artificial_stress)
            } else {
                D::zero()
            };
        });
    }
}

/// The pressure [M L^-d L^2 T^-2] that enters the artificial stress's sigma: P, or 0 where the
/// artificial stress is taken from the deviatoric stress alone. In the plate at H / dx = 32,
/// eps 0.3 of the whole stress drives a particle-scale (odd-even) pressure mode from the
/// start; from S alone R is smaller and the mode stays down, but the plate is softer at
/// 16 and 32 rows (docs/reference/accuracy.md, oscillating plate).
#[inline]
pub fn art_pressure(p: &SphParams, pr: f32) -> f32 {
    if p.artificial_stress_from != 0 {
        0.0
    } else {
        pr
    }
}

/// Artificial stress R^{ab} of Gray, Monaghan & Swift (2001): in the principal frame of
/// sigma, R'^{aa} = -eps sigma'^{aa} / rho^2 where sigma'^{aa} > 0 (tension), else 0;
/// rotated back. [L^2 T^-2 / (M L^-d)] like sigma / rho^2.
pub fn artificial_stress<D: Dim>(sigma: D::M, rho: f32, eps: f32) -> D::M {
    let d = D::D;
    let mut a = [[0.0f32; 3]; 3];
    for (r, row) in a.iter_mut().enumerate().take(d) {
        for (c, x) in row.iter_mut().enumerate().take(d) {
            *x = 0.5 * (D::entry(sigma, r, c) + D::entry(sigma, c, r));
        }
    }
    let (lambda, v) = jacobi_eigen(a, d);
    let mut out = D::zero();
    for k in 0..d {
        let rk = if lambda[k] > 0.0 {
            -eps * lambda[k] / (rho * rho)
        } else {
            0.0
        };
        if rk != 0.0 {
            let mut e = D::V::default();
            for r in 0..d {
                D::set_comp(&mut e, r, v[r][k]);
            }
            out += D::outer(e, e) * rk;
        }
    }
    out
}

/// Eigenvalues and eigenvectors (columns of the second result) of the symmetric upper-left
/// d x d block of `a`, by cyclic Jacobi rotations (one rotation is exact in 2D).
pub fn jacobi_eigen(mut a: [[f32; 3]; 3], d: usize) -> ([f32; 3], [[f32; 3]; 3]) {
    let mut v = [[0.0f32; 3]; 3];
    for (k, row) in v.iter_mut().enumerate() {
        row[k] = 1.0;
    }
    for _sweep in 0..MF_JACOBI_SWEEPS {
        let mut off = 0.0f32;
        for pp in 0..d {
            for qq in pp + 1..d {
                off += a[pp][qq].abs();
            }
        }
        if off <= MF_JACOBI_OFF_MIN as f32 {
            break;
        }
        for pp in 0..d {
            for qq in pp + 1..d {
                let apq = a[pp][qq];
                if apq.abs() <= MF_JACOBI_PIVOT_MIN as f32 {
                    continue;
                }
                let theta = (a[qq][qq] - a[pp][pp]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                // A <- J^T A J with the rotation J in the (pp, qq) plane.
                for k in 0..d {
                    let akp = a[k][pp];
                    let akq = a[k][qq];
                    a[k][pp] = c * akp - s * akq;
                    a[k][qq] = s * akp + c * akq;
                }
                for k in 0..d {
                    let apk = a[pp][k];
                    let aqk = a[qq][k];
                    a[pp][k] = c * apk - s * aqk;
                    a[qq][k] = s * apk + c * aqk;
                }
                for row in v.iter_mut().take(d) {
                    let vkp = row[pp];
                    let vkq = row[qq];
                    row[pp] = c * vkp - s * vkq;
                    row[qq] = s * vkp + c * vkq;
                }
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}
