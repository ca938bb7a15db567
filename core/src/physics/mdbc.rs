//! Modified dynamic boundary conditions (mDBC; English, Domínguez, Vacondio, Crespo,
//! Stansby, Lind, Chiapponi & Gómez-Gesteira 2022, Comput. Part. Mech. 9, 1-15): a wall
//! particle's density from a ghost node mirrored into the fluid. The ghost node's density
//! comes from a first-order (kernel- and gradient-) corrected interpolation of the fluid
//! around it, a (d+1) x (d+1) linear system; the wall particle takes its pressure cloned
//! back across the wall with the hydrostatic term, and the density of that pressure. Twin: `cuda/device/mdbc.cuh`; the wall pass:
//! `backend/cpu/density.rs` (`wall_density`), `cuda/density.cu` (`sph_wall_density`).
// Index loops, line for line as the CUDA twin's, so that both sum and eliminate alike.
#![allow(clippy::needless_range_loop)]

use crate::consts::{MF_MDBC_COND_MAX, MF_MDBC_DET_MIN, MF_MDBC_SUM_MIN};
use crate::physics::body::matrix;
use crate::physics::dim::Dim;
use crate::physics::params::{MfBody, SphParams};

/// A wall particle's unit normal now, at time `t` \[T\]: its normal at t = 0, `n`
/// (`Setup::wall_surface`), turned as its `group` has turned since: a floating body's by its
/// orientation (`MfBody::orientation`, the identity at t = 0), a driven wall's by its
/// motion's turn theta(t) (`MfMotion::turn_vector`); any other group's as it was. Twin:
/// `wall_normal_now` in `cuda/device/mdbc.cuh`. `series`: `Setup::motion_series`.
pub fn normal_now<D: Dim>(
    p: &SphParams,
    bodies: &[MfBody],
    series: &[f64],
    t: f64,
    group: u32,
    n: &mut [f64; 3],
) {
    let Some(m) = p.driven_motion[..p.driven as usize]
        .iter()
        .find(|m| m.group as u32 == group)
    else {
        return;
    };
    if m.floating != 0 {
        if let Some(b) = bodies.iter().find(|b| b.group as u32 == group) {
            let r = matrix(&b.orientation);
            let u = *n;
            for (a, c) in n.iter_mut().enumerate() {
                *c = r[3 * a] * u[0] + r[3 * a + 1] * u[1] + r[3 * a + 2] * u[2];
            }
        }
    } else if m.rate != 0.0 || m.angle != 0.0 || m.series_count > 0 {
        m.turn_vector::<D>(series, t, n);
    }
}

/// The sums over the fluid particles b around a ghost node x_g, with r = x_g - x_b \[L\],
/// V_b = m_b / rho_b [L^d], W = W(|r|), grad W = f(|r|) r (`physics::kernel`):
/// `a` = [[sum V W, sum V W r^T], [sum V grad W, sum V grad W r^T]] (the first `d + 1` rows
/// and columns; dimensionless up to the rows' and columns' length units), `b` = [sum m W,
/// sum m grad W] [M L^-d, M L^-d L^-1]. Accumulated in f32 in the neighbour order (both
/// backends alike).
#[derive(Clone, Copy, Debug, Default)]
pub struct GhostSums {
    pub a: [[f32; 4]; 4],
    pub b: [f32; 4],
}

impl GhostSums {
    /// Adds fluid particle b: separation `r` (d components), kernel `w` and `f`, mass `m`,
    /// density `rho`.
    #[inline]
    pub fn add(&mut self, d: usize, r: &[f32; 3], w: f32, f: f32, m: f32, rho: f32) {
        let v = m / rho;
        let vw = w * v;
        self.b[0] += m * w;
        self.a[0][0] += vw;
        for k in 0..d {
            self.a[0][1 + k] += r[k] * vw;
        }
        for a in 0..d {
            let g = f * r[a];
            self.b[1 + a] += m * g;
            let vg = g * v;
            self.a[1 + a][0] += vg;
            for k in 0..d {
                self.a[1 + a][1 + k] += r[k] * vg;
            }
        }
    }

    /// The ghost node's density [M L^-d]: the first-order solution rho_g of A x = b where the
    /// system is regular (|det A| >= `MF_MDBC_DET_MIN`, `cuda/sph_consts.h`) and well
    /// conditioned (dx^2 |A| |A^-1| <= `MF_MDBC_COND_MAX`, spacing `dx` \[L\]) and the kernel
    /// sum well filled (sum V W >= `MF_MDBC_SUM_MIN`), else the Shepard sum sum m W / sum V W
    /// (held at `rho0` or more where the kernel sum is thin: a ghost node by a free surface
    /// pulls no water to the wall); `None` where no fluid is near the ghost node.
    pub fn density(&self, d: usize, rho0: f32, dx: f32) -> Option<f32> {
        if self.a[0][0] <= 0.0 {
            return None;
        }
        let shepard = self.b[0] / self.a[0][0];
        if (self.a[0][0] as f64) < MF_MDBC_SUM_MIN {
            return Some(shepard.max(rho0));
        }
        // [A | b | I]: the solution and the inverse by one elimination.
        let m = d + 1;
        let w = 2 * m + 1;
        let mut a = [[0.0f64; 9]; 4];
        let mut norm_a = 0.0f64;
        for r in 0..m {
            let mut row = 0.0;
            for c in 0..m {
                a[r][c] = self.a[r][c] as f64;
                row += a[r][c].abs();
            }
            norm_a = norm_a.max(row);
            a[r][m] = self.b[r] as f64;
            a[r][m + 1 + r] = 1.0;
        }
        // Gaussian elimination with partial pivoting; det A is the pivots' product.
        let mut det = 1.0f64;
        for c in 0..m {
            let mut piv = c;
            for r in c + 1..m {
                if a[r][c].abs() > a[piv][c].abs() {
                    piv = r;
                }
            }
            if piv != c {
                a.swap(piv, c);
                det = -det;
            }
            det *= a[c][c];
            if a[c][c] == 0.0 {
                break;
            }
            for r in c + 1..m {
                let k = a[r][c] / a[c][c];
                for cc in c..w {
                    a[r][cc] -= k * a[c][cc];
                }
            }
        }
        if det.abs() < MF_MDBC_DET_MIN {
            return Some(shepard);
        }
        // Back substitution, every right-hand side: x[.][m] solves A x = b, x[.][m + 1 + j]
        // is column j of A^-1.
        let mut x = [[0.0f64; 9]; 4];
        for k in m..w {
            for r in (0..m).rev() {
                let mut s = a[r][k];
                for c in r + 1..m {
                    s -= a[r][c] * x[c][k];
                }
                x[r][k] = s / a[r][r];
            }
        }
        let mut norm_inv = 0.0f64;
        for r in 0..m {
            let mut row = 0.0;
            for j in 0..m {
                row += x[r][m + 1 + j].abs();
            }
            norm_inv = norm_inv.max(row);
        }
        // The scaled condition number dx^2 |A| |A^-1| (infinity norms): an ill-conditioned
        // system (a ghost node between a wall and a free surface) takes the Shepard sum.
        if (dx as f64) * (dx as f64) * norm_a * norm_inv > MF_MDBC_COND_MAX {
            return Some(shepard);
        }
        // x = [rho_g, -grad rho]: the density at the ghost node.
        Some(x[0][m] as f32)
    }
}

/// The wall particle's pressure [M L^-d L^2 T^-2] from its ghost node's, P_g (eq. (9) of
/// the ghost density), cloned back across the wall along the unit normal `n` into the fluid
/// with the hydrostatic term (English et al. 2022; DualSPHysics 5.2's mDBC):
/// P_a = P_g + rho0 (g . n) (n . (x_a - x_g)), x_a - x_g = -2 d_B n, so
/// P_a = P_g - 2 d_B rho0 (g . n). A wall that moves adds its acceleration a_w as
/// g - a_w; not here: walls are taken at rest or at a steady velocity. Twin: `mdbc_clone` in
/// `cuda/device/mdbc.cuh`.
#[inline]
pub fn cloned_pressure(p: &SphParams, pr_ghost: f32, n: &[f64; 3], d_b: f32) -> f32 {
    let g_n: f32 = (0..p.dim as usize)
        .map(|a| p.gravity[a] * n[a] as f32)
        .sum();
    pr_ghost - 2.0 * d_b * p.rho0 * g_n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::kernel;
    use crate::physics::params::{SphParams, MF_KERNEL_CUBIC_SPLINE};

    /// 2D cubic spline, dx = 0.01, h = 1.3 dx.
    fn params() -> SphParams {
        let mut p = SphParams {
            dim: 2,
            kernel: MF_KERNEL_CUBIC_SPLINE as i32,
            h: 0.013,
            ..SphParams::default()
        };
        p.kernel_norm = kernel::sigma(p.kernel, p.dim) / (p.h * p.h);
        p
    }

    /// The ghost sums at `xg` of a lattice of fluid particles of spacing dx filling y > 0
    /// (rows at (k + 1/2) dx), density `rho(x, y)`, mass rho0 dx^2.
    fn sums(p: &SphParams, xg: [f32; 2], rows: i32, rho: impl Fn(f32, f32) -> f32) -> GhostSums {
        let dx = 0.01f32;
        let mut g = GhostSums::default();
        for j in 0..rows {
            for i in -8..8 {
                let x = [(i as f32 + 0.5) * dx, (j as f32 + 0.5) * dx];
                let r = [xg[0] - x[0], xg[1] - x[1], 0.0];
                let len = (r[0] * r[0] + r[1] * r[1]).sqrt();
                if len < 2.0 * p.h {
                    let f = kernel::f(p, len);
                    g.add(
                        2,
                        &r,
                        kernel::w(p, len),
                        f,
                        1000.0 * dx * dx,
                        rho(x[0], x[1]),
                    );
                }
            }
        }
        g
    }

    #[test]
    fn a_linear_density_is_read_exactly_at_the_ghost_node() {
        // Water over a floor at y = 0, its density steeply linear in y: rho = 1000 (1 + 5
        // (0.1 - y)); the ghost node 1.5 dx over the floor. The first-order interpolation is
        // exact for a linear field (1425 at y = 0.015), where the plain Shepard sum (zeroth
        // order, its kernel truncated by the floor) is off by about 1.
        let p = params();
        let field = |_x: f32, y: f32| 1000.0 * (1.0 + 5.0 * (0.1 - y));
        let g = sums(&p, [0.001, 0.015], 10, field);
        let rho = g.density(2, 1000.0, 0.01).unwrap();
        assert!((rho - field(0.0, 0.015)).abs() < 0.01, "{rho}");
        let shepard = g.b[0] / g.a[0][0];
        assert!((shepard - field(0.0, 0.015)).abs() > 0.5, "{shepard}");
    }

    #[test]
    fn the_pressure_is_cloned_with_the_hydrostatic_term() {
        // A floor particle 1.5 dx under the floor (its ghost 1.5 dx over it) under g = 9.81
        // down: it carries the ghost's pressure plus rho0 g over the 3 dx between them.
        let mut p = params();
        (p.rho0, p.gravity) = (1000.0, [0.0, -9.81, 0.0]);
        let pr = cloned_pressure(&p, 500.0, &[0.0, 1.0, 0.0], 0.015);
        assert!((pr - (500.0 + 1000.0 * 9.81 * 0.03)).abs() < 1e-3, "{pr}");
        // A lid (normal down) reads less than the water under it.
        let pr = cloned_pressure(&p, 500.0, &[0.0, -1.0, 0.0], 0.015);
        assert!((pr - (500.0 - 1000.0 * 9.81 * 0.03)).abs() < 1e-3, "{pr}");
    }

    #[test]
    fn too_few_neighbours_fall_back_to_shepard_and_none_to_nothing() {
        let p = params();
        // A ghost node whose support holds one row of water: the first-order system is
        // singular along y (every neighbour at one height), the Shepard sum remains.
        let g = sums(&p, [0.0, 0.01], 1, |_, _| 1010.0);
        assert!(g.a[0][0] as f64 >= MF_MDBC_SUM_MIN, "{}", g.a[0][0]);
        let rho = g.density(2, 1000.0, 0.01).unwrap();
        assert!((rho - 1010.0).abs() < 0.01, "{rho}");
        // Barely in the water (a thin kernel sum): Shepard, at least rho0.
        let g = sums(&p, [0.0, 0.02], 1, |_, _| 990.0);
        assert!((g.a[0][0] as f64) < MF_MDBC_SUM_MIN, "{}", g.a[0][0]);
        assert_eq!(g.density(2, 1000.0, 0.01), Some(1000.0));
        assert_eq!(GhostSums::default().density(2, 1000.0, 0.01), None);
    }
}
