//! Each wall particle's surface (`Setup::wall_surface`): its unit normal into the fluid and
//! its distance behind the surface, from its wall's own shape, for the no-slip walls of
//! Morris, Fox & Zhu 1997.

use super::format::*;
use super::spatial::P3;
use crate::physics::particle::{Kind, Particle};
use crate::scene::scheme::SceneFile;

/// The wall surface seen from boundary point `x` of wall `w`: the unit normal into the
/// fluid \[-\] and the distance d_B >= 0 of `x` behind the surface \[L\], from the wall's own
/// shape (Morris, Fox & Zhu 1997's no-slip walls need both, `Setup::wall_surface`).
/// * box-container: the nearest point of the box [min, max] (the fluid's side; at a corner
///   the corner itself, so the normal is diagonal there);
/// * box: the nearest of its faces that the fluid touches (`wet`, per axis the min and the
///   max face; all faces where none is); a plate's back face is no surface;
/// * segment: the segment's right side (its left holds the rows), d_B = distance from the
///   segment's line;
/// * cylinder: the circle of `radius` (in-plane), normal radial outward; zero at the centre;
/// * mesh and polygon: toward the surface's closest point (the rows lie on the solid side),
///   d_B the distance to it.
fn surface_at(w: &Wall, x: &P3, dim: usize, wet: &[[bool; 2]; 3]) -> ([f64; 3], f64) {
    let unit = |v: [f64; 3]| {
        let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if len > 0.0 {
            (v.map(|c| c / len), len)
        } else {
            ([0.0; 3], 0.0)
        }
    };
    match w {
        Wall::BoxContainer { min, max, .. } => {
            let mut v = [0.0; 3];
            for a in 0..dim {
                v[a] = x[a].clamp(min[a], max[a]) - x[a];
            }
            unit(v)
        }
        Wall::Box { min, max, .. } => {
            let any_wet = wet[..dim].iter().flatten().any(|&b| b);
            let mut best: Option<([f64; 3], f64)> = None;
            for a in 0..dim {
                for (k, (face, sign)) in [(min[a], -1.0), (max[a], 1.0)].into_iter().enumerate() {
                    if any_wet && !wet[a][k] {
                        continue;
                    }
                    let d = (face - x[a]).abs();
                    if best.is_none_or(|b| d < b.1) {
                        let mut n = [0.0; 3];
                        n[a] = sign;
                        best = Some((n, d));
                    }
                }
            }
            best.unwrap_or(([0.0; 3], 0.0))
        }
        Wall::Segment { from, to, .. } => {
            let d = [to[0] - from[0], to[1] - from[1]];
            let len = d[0].hypot(d[1]);
            let left = [-d[1] / len, d[0] / len];
            let behind = (x[0] - from[0]) * left[0] + (x[1] - from[1]) * left[1];
            ([-left[0], -left[1], 0.0], behind)
        }
        Wall::Cylinder { center, radius, .. } => {
            let (n, r) = unit([x[0] - center[0], x[1] - center[1], 0.0]);
            (n, radius - r)
        }
        Wall::Mesh { mesh: o, .. } | Wall::Polygon { polygon: o, .. } => {
            let c = o.surface().closest(x);
            unit([c[0] - x[0], c[1] - x[1], c[2] - x[2]])
        }
    }
}

/// Which faces of box [min, max] the fluid or a solid touches: per axis (min face, max
/// face), true where a non-boundary particle lies within one spacing outside the face and
/// within the box's extent along the other axes (no periodic images: a face on a periodic
/// cut is no surface).
fn wet_faces(
    min: &[f64],
    max: &[f64],
    dim: usize,
    dx: f64,
    particles: &[Particle],
) -> [[bool; 2]; 3] {
    let mut wet = [[false; 2]; 3];
    for q in particles.iter().filter(|q| q.kind != Kind::Boundary) {
        let x = q.position.map(|c| c as f64);
        for a in 0..dim {
            let across = (0..dim)
                .filter(|&b| b != a)
                .all(|b| x[b] >= min[b] && x[b] <= max[b]);
            if !across {
                continue;
            }
            if x[a] < min[a] && x[a] >= min[a] - dx {
                wet[a][0] = true;
            }
            if x[a] > max[a] && x[a] <= max[a] + dx {
                wet[a][1] = true;
            }
        }
    }
    wet
}

/// `Setup::wall_surface` for the particles of `generate(s)`: the smallest boundary id and,
/// per boundary particle from it on, (normal into the fluid, d_B) of its wall
/// (`surface_at`); (0, empty) without boundary particles. `generate` numbers walls last, so
/// their ids are contiguous; an id of another kind in between gets a zero entry.
pub(crate) fn wall_surface(s: &SceneFile, particles: &[Particle]) -> (u32, Vec<[f32; 4]>) {
    let dim = s.dimension as usize;
    let dx = s.discretisation.spacing;
    let first_wall_group = (s.fluid_blocks.len() + s.solids.len()) as u32;
    let walls = || particles.iter().filter(|q| q.kind == Kind::Boundary);
    let Some(first) = walls().map(|q| q.id).min() else {
        return (0, Vec::new());
    };
    let last = walls().map(|q| q.id).max().unwrap_or(first);
    let wet: Vec<[[bool; 2]; 3]> = s
        .walls
        .iter()
        .map(|w| match w {
            Wall::Box { min, max, .. } => wet_faces(min, max, dim, dx, particles),
            _ => [[false; 2]; 3],
        })
        .collect();
    let mut out = vec![[0.0f32; 4]; (last - first) as usize + 1];
    for q in walls() {
        let k = (q.group - first_wall_group) as usize;
        let x = q.position.map(|c| c as f64);
        let (n, d) = surface_at(&s.walls[k], &x, dim, &wet[k]);
        out[(q.id - first) as usize] = [n[0] as f32, n[1] as f32, n[2] as f32, d as f32];
    }
    (first, out)
}
