//! Body-fitted particles (`pack = true` of a surface): the lattice points near a surface
//! relaxed against it, so that a curved surface is smooth at the particle scale instead of
//! stair-stepped. After Zhu, Zhang & Adams 2021 ("A CAD-compatible body-fitted particle
//! generator for arbitrarily complex geometry", J. Comput. Phys. 434, 110227; SPHinXsys'
//! relaxation), simplified: each particle within `REACH` spacings of the surface moves down
//! the gradient of the particles' kernel sum (the transport velocity's background pressure
//! force, which vanishes on a uniform arrangement), the surface's share taken from the
//! neighbours mirrored in its tangent plane (ghosts: a row at dx / 2 from a flat surface
//! feels no push across it), by a step capped at `MAX_STEP` spacings, and is then held on
//! its side of the surface at least half a spacing from it (and, in a wall's band, at most
//! its depth less half a spacing). Particles farther in stay on the lattice, as neighbours. On the CPU
//! (rayon), where the scene is generated. Lengths \[L\].

use rayon::prelude::*;

use super::surface::Surface;
use crate::scene::spatial::{Grid, P3};

/// \[spacings\] the particles that move: within this distance of the surface.
const REACH: f64 = 4.0;
/// \[spacings\] the kernel's smoothing length (its support is twice this).
const H: f64 = 1.3;
/// \[spacings\] the largest move in one iteration.
const MAX_STEP: f64 = 0.1;
/// The step per unit of the kernel-sum gradient, in spacings.
const GAIN: f64 = 0.05;
/// Iterations.
pub const ITERATIONS: usize = 120;

/// Where the particles of an object lie relative to its surface.
#[derive(Clone, Copy, Debug)]
pub struct Side {
    /// Inside the surface (a fluid region, a body, an obstacle's rows) or outside it (a
    /// tank's rows).
    pub inside: bool,
    /// \[L\] a wall's band depth: the particles stay within it. None: no limit.
    pub depth: Option<f64>,
}

/// The repulsion of a neighbour at `q` = r / h: -dW/dq of Wendland's C2 kernel, 5 q (1 -
/// q/2)^3 up to q = 2 (its normalisation is in `GAIN`).
fn push(q: f64) -> f64 {
    if q >= 2.0 {
        0.0
    } else {
        5.0 * q * (1.0 - 0.5 * q).powi(3)
    }
}

/// Relaxes `points` (an object's, on the lattice of spacing `dx`) against `surface` for
/// `ITERATIONS` steps; `fixed(p)`: a point that must not move (e.g. on a fluid block's own
/// box face). The points keep their number and order.
pub fn pack(
    surface: &Surface,
    points: &mut [P3],
    dx: f64,
    dim: usize,
    side: Side,
    fixed: impl Fn(&P3) -> bool + Sync,
) {
    let near: Vec<usize> = (0..points.len())
        .into_par_iter()
        .filter(|&i| surface.distance(&points[i]) < REACH * dx && !fixed(&points[i]))
        .collect();
    if near.is_empty() {
        return;
    }
    let h = H * dx;
    let support = 2.0 * h;
    // The points a mover can meet: within the movers' reach plus two supports.
    let active: Vec<usize> = (0..points.len())
        .into_par_iter()
        .filter(|&i| surface.distance(&points[i]) < REACH * dx + 2.0 * support)
        .collect();
    let mut slot = vec![usize::MAX; points.len()];
    for (k, &i) in active.iter().enumerate() {
        slot[i] = k;
    }
    for k in 0..ITERATIONS {
        // The step shrinks over the iterations to let the arrangement settle.
        let cap = MAX_STEP * dx * (1.0 - k as f64 / ITERATIONS as f64).max(0.1);
        let grid = Grid::new(support, active.iter().map(|&i| points[i]).collect());
        let moves: Vec<P3> = near
            .par_iter()
            .map(|&i| {
                let p = points[i];
                // The surface's share: the neighbours mirrored in its tangent plane at the
                // particle's closest point (ghosts, as a wall of the fluid's own arrangement
                // would push), so that a row at dx / 2 from it feels no net push across it.
                let c = surface.closest(&p);
                let to: P3 = std::array::from_fn(|a| c[a] - p[a]);
                let d = to.iter().map(|x| x * x).sum::<f64>().sqrt();
                let toward = (d > 0.0).then(|| to.map(|x| x / d));
                let mirror = toward.filter(|_| d < support);
                let mut f = [0.0; 3];
                let mut add = |q: &P3| {
                    let e: P3 = std::array::from_fn(|a| p[a] - q[a]);
                    let r = e.iter().map(|x| x * x).sum::<f64>().sqrt();
                    if r > 0.0 && r < support {
                        let w = push(r / h) / r;
                        for a in 0..dim {
                            f[a] += w * e[a];
                        }
                    }
                };
                let me = slot[i];
                grid.for_each_near(&p, support, |j| {
                    let q = *grid.point(j);
                    if j != me {
                        add(&q);
                    }
                    if let Some(u) = mirror {
                        // q reflected in the plane through c normal to u.
                        let s = 2.0 * (0..3).map(|a| (c[a] - q[a]) * u[a]).sum::<f64>();
                        add(&std::array::from_fn(|a| q[a] + s * u[a]));
                    }
                });
                let mut step: P3 = f.map(|x| GAIN * dx * x);
                let len = step.iter().map(|x| x * x).sum::<f64>().sqrt();
                if len > cap {
                    step = step.map(|x| x * cap / len);
                }
                let moved: P3 = std::array::from_fn(|a| p[a] + step[a]);
                match toward {
                    // Held against the tangent plane at c: a move of at most MAX_STEP
                    // spacings sees the surface's curvature to second order only.
                    Some(u) => {
                        let depth = (0..3).map(|a| (c[a] - moved[a]) * u[a]).sum::<f64>();
                        let hi = side
                            .depth
                            .map_or(f64::INFINITY, |t| (t - 0.5 * dx).max(0.5 * dx));
                        let shift = depth - depth.clamp(0.5 * dx, hi);
                        std::array::from_fn(|a| moved[a] + shift * u[a])
                    }
                    None => hold(surface, moved, dx, side),
                }
            })
            .collect();
        for (&i, p) in near.iter().zip(moves) {
            points[i] = p;
        }
    }
}

/// `p` held on its side of the surface, at least dx / 2 from it and, in a band, at most its
/// depth less dx / 2: moved along the line through its closest point.
/// A particle on the surface itself (no direction to it) is placed by the winding number.
fn hold(surface: &Surface, p: P3, dx: f64, side: Side) -> P3 {
    let c = surface.closest(&p);
    let v: P3 = std::array::from_fn(|a| p[a] - c[a]);
    let d = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let on_side = surface.inside(&p) == side.inside;
    let lo = 0.5 * dx;
    let hi = side.depth.map_or(f64::INFINITY, |t| (t - 0.5 * dx).max(lo));
    if on_side && d >= lo && d <= hi {
        return p;
    }
    if d == 0.0 {
        return p;
    }
    // The unit vector from the surface towards the particles' side.
    let u: P3 = v.map(|x| if on_side { x / d } else { -x / d });
    let target = if on_side { d.clamp(lo, hi) } else { lo };
    std::array::from_fn(|a| c[a] + target * u[a])
}
