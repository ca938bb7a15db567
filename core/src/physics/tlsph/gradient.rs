//! The total-Lagrangian solid's reference gradient, consistent to second order: exact for
//! any field that is quadratic in the reference position, the body's faces included.
//!
//! Bonet & Lok's correction (L_a = M_a^-T) makes the kernel gradient exact for linear
//! fields only. A bending beam's displacement is quadratic (u_x = -kappa x y): at a face,
//! where the support is cut in half, the linear correction reads the bending strain of the
//! outermost row short by about the kernel's reach (16 % at 5 particles across with
//! h = 1.3 dx), and the row that carries most of the strain energy comes out soft: a
//! cantilever of 9 particles across bent 16 % too far. A weighted least-squares fit of a
//! quadratic about each particle (the moving-least-squares / finite-particle form of
//! Liu, Liu & Lam 2003 and Zhang & Batra 2004, in the reference configuration) removes it:
//!
//! u_b - u_a = sum_m c_m p_m(s_ab),  s_ab = (X0_b - X0_a) / h (the minimum image on a
//! periodic axis, `pairs::separation`),
//! p(s) = [s_1 .. s_d, the d (d + 1) / 2 products s_i s_j (i <= j)] (Q = 5 in 2D, 9 in 3D),
//! A_a = sum_b V0_b w_ab p(s_ab) p(s_ab)^T,  w_ab = -(dW/dr) / r at |X0_ab| (>= 0),
//! grad u_a = (1 / h) [A_a^-1]_{1..d} sum_b V0_b w_ab p(s_ab) (u_b - u_a),
//!
//! so that the pair weight is g_ab = V0_b w_ab C_a p(s_ab) with the d x Q matrix
//! C_a = (1 / h) [A_a^-1]_{1..d} [L^-1 after V0 w]. Where the neighbourhood is symmetric the
//! odd moments vanish and C_a p(s) = L_a (X0_b - X0_a): the interior is Bonet & Lok's.
//! Where A_a is singular (fewer than three rows across, a lone particle) C_a falls back to
//! [h L_a | 0], and to [h I | 0] where M_a is singular too.
//!
//! C_a is set up once, on the host, in double precision; the stages read it as Q columns of
//! d floats per solid particle (`Corr`).

use crate::consts::MF_MOMENT_DET_MIN;
use crate::physics::dim::Dim;
use crate::physics::kernel;
use crate::physics::pairs::separation;
use crate::physics::params::SphParams;

/// The most basis functions (3D: 3 linear + 6 quadratic).
pub const Q_MAX: usize = 9;

/// The basis size in `d` dimensions: d + d (d + 1) / 2.
#[inline]
pub const fn basis_len(d: usize) -> usize {
    d + d * (d + 1) / 2
}

/// The quadratic basis p(s) (the first `basis_len(D)` entries; the rest zero) [-].
#[inline]
pub fn basis<D: Dim>(s: D::V) -> [f32; Q_MAX] {
    let mut p = [0.0f32; Q_MAX];
    let mut k = D::D;
    for i in 0..D::D {
        p[i] = D::comp(s, i);
        for j in i..D::D {
            p[k] = D::comp(s, i) * D::comp(s, j);
            k += 1;
        }
    }
    p
}

/// C_a of one solid particle: its Q columns of d components, \[L\].
pub type Corr<D> = [<D as Dim>::V; Q_MAX];

/// C p: the sum of column m times p_m.
#[inline]
pub fn apply<D: Dim>(c: &Corr<D>, p: &[f32; Q_MAX]) -> D::V {
    let mut out = D::V::default();
    for m in 0..basis_len(D::D) {
        out += c[m] * p[m];
    }
    out
}

/// The pair's kernel weight w_ab = -(dW/dr) / r at the reference distance [L^-d-2] and its
/// scaled separation s_ab = (X0_b - X0_a) / h [-], X0_b - X0_a the minimum image.
#[inline]
pub fn pair<D: Dim>(p: &SphParams, x0a: D::V, x0b: D::V) -> (f32, D::V) {
    let d = separation::<D>(p, x0b, x0a);
    (-kernel::f(p, D::length2(d).sqrt()), d * (1.0 / p.h))
}

/// The gradient weight g_ab = V0_b w_ab C_a p(s_ab) [L^-1]: grad u_a = sum_b (u_b - u_a) (x) g_ab.
#[inline]
pub fn weight<D: Dim>(p: &SphParams, c: &Corr<D>, vol_b: f32, x0a: D::V, x0b: D::V) -> D::V {
    let (w, s) = pair::<D>(p, x0a, x0b);
    apply::<D>(c, &basis::<D>(s)) * (vol_b * w)
}

/// A_a = sum_b V0_b w_ab p(s_ab) p(s_ab)^T over the reference neighbours `nbrs` (positions,
/// volumes) of the particle at `x0a` [L^-2] (f64: set up once, on the host).
fn moments<D: Dim>(p: &SphParams, x0a: D::V, nbrs: &[(D::V, f32)]) -> [[f64; Q_MAX]; Q_MAX] {
    let q = basis_len(D::D);
    let mut a = [[0.0f64; Q_MAX]; Q_MAX];
    for &(x0b, vol) in nbrs {
        let (w, s) = pair::<D>(p, x0a, x0b);
        let pb = basis::<D>(s);
        let vw = vol as f64 * w as f64;
        for i in 0..q {
            for j in 0..q {
                a[i][j] += vw * pb[i] as f64 * pb[j] as f64;
            }
        }
    }
    a
}

/// C_a of the particle at `x0a` with the reference neighbours `nbrs` (positions, volumes).
pub fn correction<D: Dim>(p: &SphParams, x0a: D::V, nbrs: &[(D::V, f32)]) -> Corr<D> {
    let q = basis_len(D::D);
    let h = p.h as f64;
    let mut c = [D::V::default(); Q_MAX];
    if let Some(inv) = invert(&moments::<D>(p, x0a, nbrs), q) {
        for (m, col) in c.iter_mut().enumerate().take(q) {
            for (k, row) in inv.iter().enumerate().take(D::D) {
                D::set_comp(col, k, (row[m] / h) as f32);
            }
        }
        return c;
    }
    // Linear only: C p(s) = L (X0_b - X0_a) = h L s, L = M^-T, M = sum_b V0_b w s s^T h^2
    // (Bonet & Lok; the identity where M is singular too).
    let mut m = D::zero();
    for &(x0b, vol) in nbrs {
        let (w, s) = pair::<D>(p, x0a, x0b);
        m += D::outer(s, s) * (vol * w * p.h * p.h);
    }
    let l = if D::determinant(m).abs() > MF_MOMENT_DET_MIN as f32 {
        D::inverse(D::transpose(m))
    } else {
        D::identity()
    };
    for (k, col) in c.iter_mut().enumerate().take(D::D) {
        for i in 0..D::D {
            D::set_comp(col, i, D::entry(l, i, k) * p.h);
        }
    }
    c
}

/// The fit's value at the point `x`: the weights r with which the quadratic that a's fit
/// makes of the field f (`correction`, the same `nbrs`, and `c` = its C_a) predicts
/// f(x) - f_a = sum_m r_m B_m, where B = sum_b V0_b w_ab p(s_ab) (f_b - f_a) is the sum the
/// fit reads (the clamp's face adds (f_clamp - f_a) F_a to it) [-]:
/// r = A_a^-1 p(s), s = (x - X0_a) / h (A_a symmetric; x - X0_a the minimum image), exact
/// for a quadratic field; where A_a is singular, the linear fit's r_m = C_a column m .
/// (x - X0_a) (zero on the quadratic terms), f_a + grad f_a (x - X0_a). The hourglass control
/// of the clamp's face pairs predicts the face points' displacement with it
/// (`TlBodies::forces`).
pub fn value_weights<D: Dim>(
    p: &SphParams,
    c: &Corr<D>,
    x0a: D::V,
    nbrs: &[(D::V, f32)],
    x: D::V,
) -> [f32; Q_MAX] {
    let q = basis_len(D::D);
    let dx = separation::<D>(p, x, x0a);
    let s = dx * (1.0 / p.h);
    let mut r = [0.0f32; Q_MAX];
    if let Some(inv) = invert(&moments::<D>(p, x0a, nbrs), q) {
        let ps = basis::<D>(s);
        for (m, rm) in r.iter_mut().enumerate().take(q) {
            *rm = (0..q).map(|k| inv[m][k] * ps[k] as f64).sum::<f64>() as f32;
        }
    } else {
        for (m, rm) in r.iter_mut().enumerate().take(D::D) {
            *rm = D::dot(c[m], dx);
        }
    }
    r
}

/// The fit's Laplacian: the weights l_a with which the quadratic that the fit about `x0a`
/// (neighbours `nbrs`) makes of a field f gives its Laplacian,
/// lap f_a = sum_b V0_b w_ab l_a . p(s_ab) (f_b - f_a) [L^-2], exact for a quadratic f;
/// None where A_a is singular (the fit is linear). The quadratic term s_i^2 of the fit's
/// coefficients c = A_a^-1 sum_b V0_b w_ab p(s_ab) (f_b - f_a) is c_ii X_i^2 / h^2, so
/// lap f = (2 / h^2) sum_i c_ii: l_a = (2 / h^2) the sum of the rows ii of A_a^-1.
pub fn laplacian<D: Dim>(p: &SphParams, x0a: D::V, nbrs: &[(D::V, f32)]) -> Option<[f32; Q_MAX]> {
    let q = basis_len(D::D);
    let inv = invert(&moments::<D>(p, x0a, nbrs), q)?;
    let scale = 2.0 / (p.h as f64 * p.h as f64);
    let mut l = [0.0f32; Q_MAX];
    // The index of s_i^2 in the basis: after the d linear terms, the products s_i s_j (j >= i).
    let mut k = D::D;
    for i in 0..D::D {
        for (m, lm) in l.iter_mut().enumerate().take(q) {
            *lm += (scale * inv[k][m]) as f32;
        }
        k += D::D - i;
    }
    Some(l)
}

/// The inverse of the symmetric positive semi-definite q x q matrix `a`, or None where it is
/// singular: scaled to a unit diagonal, Gauss-Jordan with partial pivoting, refused where a
/// pivot falls below 1e-9 (exact on a lattice where the basis is degenerate: fewer than three
/// rows across a direction make s_i^2 a multiple of s_i).
fn invert(a: &[[f64; Q_MAX]; Q_MAX], q: usize) -> Option<[[f64; Q_MAX]; Q_MAX]> {
    let mut d = [0.0f64; Q_MAX];
    for i in 0..q {
        if a[i][i] <= 0.0 {
            return None;
        }
        d[i] = a[i][i].sqrt();
    }
    let mut m = [[0.0f64; Q_MAX]; Q_MAX];
    let mut inv = [[0.0f64; Q_MAX]; Q_MAX];
    for i in 0..q {
        for j in 0..q {
            m[i][j] = a[i][j] / (d[i] * d[j]);
        }
        inv[i][i] = 1.0;
    }
    for col in 0..q {
        let piv = (col..q).max_by(|&x, &y| m[x][col].abs().total_cmp(&m[y][col].abs()))?;
        if m[piv][col].abs() < 1e-9 {
            return None;
        }
        m.swap(col, piv);
        inv.swap(col, piv);
        let pv = m[col][col];
        for j in 0..q {
            m[col][j] /= pv;
            inv[col][j] /= pv;
        }
        for r in 0..q {
            if r != col {
                let f = m[r][col];
                if f != 0.0 {
                    for j in 0..q {
                        m[r][j] -= f * m[col][j];
                        inv[r][j] -= f * inv[col][j];
                    }
                }
            }
        }
    }
    for i in 0..q {
        for j in 0..q {
            inv[i][j] /= d[i] * d[j];
        }
    }
    Some(inv)
}
