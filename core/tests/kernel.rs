//! Kernel properties in 2D and 3D: normalisation, compact support, gradient consistency,
//! zero gradient sum on a lattice.
mod common;

use meshfree_core::physics::kernel;
use meshfree_core::physics::params::{MF_KERNEL_CUBIC_SPLINE, MF_KERNEL_WENDLAND_C2};

fn each_kernel(mut f: impl FnMut(i32, i32)) {
    for k in [MF_KERNEL_CUBIC_SPLINE as i32, MF_KERNEL_WENDLAND_C2 as i32] {
        for dim in [2, 3] {
            f(k, dim);
        }
    }
}

fn params_for(kernel: i32, dim: i32) -> meshfree_core::physics::params::SphParams {
    let mut p = common::params(dim, 0.1, [0.0; 3], [1.0; 3], [0; 3]);
    p.kernel = kernel;
    meshfree_core::physics::params::derive(&mut p);
    p
}

#[test]
fn kernel_integrates_to_one() {
    each_kernel(|k, dim| {
        let p = params_for(k, dim);
        // Midpoint quadrature of W over the support on a fine lattice.
        let n = 120;
        let step = 2.0 * p.support / n as f32;
        let mut sum = 0.0f64;
        let nz = if dim == 3 { n } else { 1 };
        for iz in 0..nz {
            for iy in 0..n {
                for ix in 0..n {
                    let c = |i: usize| -p.support + (i as f32 + 0.5) * step;
                    let z = if dim == 3 { c(iz) } else { 0.0 };
                    let r = (c(ix).powi(2) + c(iy).powi(2) + z * z).sqrt();
                    sum += kernel::w(&p, r) as f64 * (step as f64).powi(dim);
                }
            }
        }
        assert!(
            (sum - 1.0).abs() < 2e-3,
            "kernel {k}, {dim}D: integral of W = {sum}, want 1 within 2e-3"
        );
    });
}

#[test]
fn kernel_has_compact_support_and_is_positive_inside() {
    each_kernel(|k, dim| {
        let p = params_for(k, dim);
        assert_eq!(kernel::w(&p, p.support), 0.0, "W(2h) must vanish");
        assert_eq!(kernel::w(&p, 1.5 * p.support), 0.0);
        assert_eq!(kernel::f(&p, p.support), 0.0);
        for i in 0..50 {
            let r = p.support * i as f32 / 50.0;
            assert!(
                kernel::w(&p, r) > 0.0,
                "W({r}) must be positive inside the support"
            );
            assert!(
                kernel::f(&p, r) <= 0.0,
                "W must not increase with r (r = {r})"
            );
        }
    });
}

#[test]
fn gradient_factor_matches_numerical_derivative() {
    each_kernel(|k, dim| {
        let p = params_for(k, dim);
        for i in 1..40 {
            let r = p.support * i as f32 / 40.0;
            let e = 1e-4 * p.h;
            let numeric = (kernel::w(&p, r + e) - kernel::w(&p, r - e)) / (2.0 * e);
            let analytic = kernel::f(&p, r) * r;
            let scale = kernel::w(&p, 0.0) / p.h;
            assert!(
                (numeric - analytic).abs() < 2e-3 * scale,
                "kernel {k}, {dim}D, r = {r}: dW/dr numeric {numeric} vs analytic {analytic}"
            );
        }
    });
}

#[test]
fn gradient_sums_to_zero_and_lattice_sums_to_one() {
    each_kernel(|k, dim| {
        let p = params_for(k, dim);
        let d = dim as usize;
        // A particle at the origin inside a full lattice of spacing dx.
        let m = 4;
        let mut grad = [0.0f32; 3];
        let mut sum_w = 0.0f32;
        let range = |a: usize| if a < d { -m..=m } else { 0..=0 };
        for iz in range(2) {
            for iy in range(1) {
                for ix in range(0) {
                    let r = [ix as f32 * p.dx, iy as f32 * p.dx, iz as f32 * p.dx];
                    let rr = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
                    let f = kernel::f(&p, rr);
                    for a in 0..3 {
                        grad[a] += -r[a] * f; // grad_i W_ij with r_ij = -r
                    }
                    sum_w += kernel::w(&p, rr) * p.dx.powi(dim);
                }
            }
        }
        for (a, g) in grad.iter().enumerate() {
            assert!(
                g.abs() < 1e-3 * kernel::w(&p, 0.0) / p.h,
                "axis {a}: gradient sum {g}"
            );
        }
        assert!(
            (sum_w - 1.0).abs() < 0.02,
            "kernel {k}, {dim}D: lattice sum of W dV = {sum_w}"
        );
    });
}
