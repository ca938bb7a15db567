//! Smoothing kernels W(r, h), eqs. (1)-(4). The paper does not name its kernel; both
//! offered here have support radius 2h. Twin: `cuda/device/kernel.cuh` (`kernel_wf`, `kernel_w`).
//!
//! `w` is W [L^-d]; `f` is (dW/dr) / r [L^-(d+2)], so that grad_i W_ij = f(r) r_ij with
//! r_ij = r_i - r_j (no division by r, finite at r = 0).

use crate::physics::params::sph_params::{SphParams, MF_KERNEL_WENDLAND_C2};
use std::f32::consts::PI;

/// Normalisation sigma_d of the kernel in `dim` dimensions (W = sigma_d / h^d w(q)).
pub fn sigma(kernel: i32, dim: i32) -> f32 {
    match (kernel as u32 == MF_KERNEL_WENDLAND_C2, dim) {
        // Monaghan 1992 cubic spline.
        (false, 2) => 10.0 / (7.0 * PI),
        (false, _) => 1.0 / PI,
        // Wendland C2 with support 2h.
        (true, 2) => 7.0 / (4.0 * PI),
        (true, _) => 21.0 / (16.0 * PI),
    }
}

/// W(r, h) [L^-d].
#[inline]
pub fn w(p: &SphParams, r: f32) -> f32 {
    let q = r / p.h;
    p.kernel_norm * shape(p.kernel, q)
}

/// (dW/dr) / r [L^-(d+2)].
#[inline]
pub fn f(p: &SphParams, r: f32) -> f32 {
    let q = r / p.h;
    p.kernel_norm / (p.h * p.h) * shape_f(p.kernel, q)
}

/// The q = r / h at which |dW/dr| peaks: 2/3 for the cubic spline (dw/dq = -3 q + 9/4 q^2),
/// 1/2 for the Wendland C2 (dw/dq = -5 q (1 - q/2)^3) [-]. Closer than this (the kernel's
/// core) |grad W| falls as r falls. Twin: `kernel_gradient_peak_q` in cuda/device/kernel.cuh.
#[inline]
pub fn gradient_peak_q(kernel: i32) -> f32 {
    if kernel as u32 == MF_KERNEL_WENDLAND_C2 {
        0.5
    } else {
        2.0 / 3.0
    }
}

/// The dimensionless shape w(q), q = r / h.
#[inline]
pub fn shape(kernel: i32, q: f32) -> f32 {
    if kernel as u32 == MF_KERNEL_WENDLAND_C2 {
        if q < 2.0 {
            let t = 1.0 - 0.5 * q;
            t * t * t * t * (2.0 * q + 1.0)
        } else {
            0.0
        }
    } else if q < 1.0 {
        1.0 - 1.5 * q * q + 0.75 * q * q * q
    } else if q < 2.0 {
        let t = 2.0 - q;
        0.25 * t * t * t
    } else {
        0.0
    }
}

/// (dw/dq) / q, dimensionless.
#[inline]
pub fn shape_f(kernel: i32, q: f32) -> f32 {
    if kernel as u32 == MF_KERNEL_WENDLAND_C2 {
        if q < 2.0 {
            let t = 1.0 - 0.5 * q;
            -5.0 * t * t * t
        } else {
            0.0
        }
    } else if q < 1.0 {
        -3.0 + 2.25 * q
    } else if q < 2.0 {
        let t = 2.0 - q;
        -0.75 * t * t / q
    } else {
        0.0
    }
}
