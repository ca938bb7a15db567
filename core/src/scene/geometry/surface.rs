//! A surface in place (`Surface`): its queries (inside by the winding number, the closest
//! point and distance by parry's trees, the lattice points it selects) and its report
//! (`Info`); `Loaded`, the slot of an `Outline` that holds it. Lengths \[L\].

use std::path::PathBuf;
use std::sync::Arc;

use glam::{DVec2, DVec3};
use parry2d_f64::query::PointQuery as _;
use parry3d_f64::query::PointQuery as _;
use rayon::prelude::*;

use super::topology::Topology;
use super::winding;
use crate::scene::spatial::P3;

/// A surface in place: its queries and what `meshfree check` reports of it.
pub struct Surface {
    pub(super) shape: Shape,
    /// Where its file is (a run copies it into its directory: `copies.rs`).
    pub(super) from: From,
    /// What was read: the file (or "points"), its triangles or segments, its box, the
    /// volume (3D) or area (2D) it encloses, and its edges.
    pub info: Info,
}

/// A surface's report.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Info {
    /// The file as the scene names it, or "points".
    pub source: String,
    /// Triangles (3D) or edges (2D).
    pub elements: usize,
    /// \[L\] the box of the surface in place.
    pub lo: P3,
    pub hi: P3,
    /// \[L^d\] the volume (3D) or area (2D) it encloses.
    pub volume: f64,
    /// \[L^(d-1)\] its own area (3D) or length (2D).
    pub area: f64,
    /// Its edges: open ones, holes, the largest hole.
    pub topology: Topology,
    /// Whether it was wound inward (its normals pointing in) and was turned outward.
    pub turned: bool,
    /// An open surface (a wall's sheet or line: `format::Side::open`), taken as given: its
    /// `volume` is 0.
    pub open: bool,
    /// \[s\] reading, placing, checking it and building its trees.
    pub read_seconds: f64,
}

/// The file a surface was read from.
pub(super) enum From {
    Path(PathBuf),
    Asset(&'static [u8]),
    /// The scene's own `points`.
    Points,
}

pub(super) enum Shape {
    Mesh {
        /// With its pseudo-normals where `open`.
        tree: parry3d_f64::shape::TriMesh,
        /// Empty where `open`.
        winding: winding::Winding,
        open: bool,
    },
    Polygon {
        /// With its pseudo-normals where `open`.
        line: parry2d_f64::shape::Polyline,
        /// (from, to), the inside on the left.
        segments: Vec<[DVec2; 2]>,
        open: bool,
    },
}

/// The loaded surface of an `Outline` (set once by `load_all`, when the scene is read).
/// Equal whatever it holds and not serialised: the scene's text is the outline's identity.
#[derive(Clone, Default)]
pub struct Loaded(std::sync::OnceLock<Arc<Surface>>);

impl Loaded {
    /// The surface, once read.
    pub fn get(&self) -> Option<&Surface> {
        self.0.get().map(|s| &**s)
    }

    /// Holds `surface` (the first set stays: a second reader of the same outline reads its
    /// own copy).
    pub(super) fn set(&self, surface: Surface) {
        let _ = self.0.set(Arc::new(surface));
    }
}

impl PartialEq for Loaded {
    fn eq(&self, _: &Loaded) -> bool {
        true
    }
}

impl std::fmt::Debug for Loaded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.get() {
            Some(s) => write!(f, "Loaded({}, {} elements)", s.info.source, s.info.elements),
            None => write!(f, "Loaded(none)"),
        }
    }
}

/// A hole may span this share of the surface's box diagonal and the surface still be a
/// volume: the winding number bridges it (Barill et al. 2018's soups). Larger, and which
/// side is inside is a guess: refused.
pub const MAX_HOLE: f64 = 0.1;

impl Surface {
    /// Whether `p` is inside: a closed surface's winding number above 1/2; for an open one,
    /// behind its faces (3D) or left of its line (2D) as seen from its closest point, against
    /// the pseudo-normal there (the face's, or the angle-weighted mean of the faces at an
    /// edge or a corner: Baerentzen & Aanaes 2005), so that a point near a fold is on the
    /// right side of it.
    pub fn inside(&self, p: &P3) -> bool {
        match &self.shape {
            Shape::Mesh {
                tree, open: true, ..
            } => {
                let q = parry3d_f64::math::Vector::new(p[0], p[1], p[2]);
                tree.project_local_point(q, false).is_inside
            }
            Shape::Mesh { winding, .. } => winding.at(DVec3::from_array(*p)) > 0.5,
            Shape::Polygon {
                line, open: true, ..
            } => {
                let q = parry2d_f64::math::Vector::new(p[0], p[1]);
                line.project_local_point(q, false).is_inside
            }
            Shape::Polygon { segments, .. } => {
                polygon_winding(segments, DVec2::new(p[0], p[1])) > 0.5
            }
        }
    }

    /// The closest point of the surface to `p` (in 2D, z = p's).
    pub fn closest(&self, p: &P3) -> P3 {
        match &self.shape {
            Shape::Mesh { tree, .. } => {
                let q = parry3d_f64::math::Vector::new(p[0], p[1], p[2]);
                let c = tree.project_local_point(q, false).point;
                [c.x, c.y, c.z]
            }
            Shape::Polygon { line, .. } => {
                let q = parry2d_f64::math::Vector::new(p[0], p[1]);
                let c = line.project_local_point(q, false).point;
                [c.x, c.y, p[2]]
            }
        }
    }

    /// The distance from `p` to the surface \[L\].
    pub fn distance(&self, p: &P3) -> f64 {
        let c = self.closest(p);
        (0..3).map(|a| (c[a] - p[a]).powi(2)).sum::<f64>().sqrt()
    }

    /// The volume (3D) or area (2D) it encloses \[L^d\], its centroid \[L\] and the inertia
    /// tensor of that solid about the centroid at unit density \[L^(d+2)\] (row-major; 2D:
    /// the zz entry alone, per unit depth): a floating body's mass properties. 3D through
    /// parry's `MassProperties::from_trimesh` (tetrahedra from the centroid); 2D from Green's
    /// theorem over the segments (inside on their left).
    pub fn solid_properties(&self) -> (f64, [f64; 3], [f64; 9]) {
        match &self.shape {
            Shape::Mesh { tree, .. } => {
                let m = parry3d_f64::mass_properties::MassProperties::from_trimesh(
                    1.0,
                    tree.vertices(),
                    tree.indices(),
                );
                let i = m.reconstruct_inertia_matrix();
                let c = m.local_com;
                let cols = [i.x_axis, i.y_axis, i.z_axis];
                let mut t = [0.0; 9];
                for (r, row) in t.chunks_mut(3).enumerate() {
                    for (k, v) in row.iter_mut().enumerate() {
                        *v = cols[k][r];
                    }
                }
                (m.mass(), [c.x, c.y, c.z], t)
            }
            Shape::Polygon { segments, .. } => {
                let (mut a, mut cx, mut cy, mut i0) = (0.0, 0.0, 0.0, 0.0);
                for [p, q] in segments {
                    let k = p.x * q.y - q.x * p.y;
                    a += 0.5 * k;
                    cx += (p.x + q.x) * k / 6.0;
                    cy += (p.y + q.y) * k / 6.0;
                    i0 += (p.x * p.x + p.x * q.x + q.x * q.x + p.y * p.y + p.y * q.y + q.y * q.y)
                        * k
                        / 12.0;
                }
                let c = [cx / a, cy / a, 0.0];
                let mut t = [0.0; 9];
                // About the centroid (parallel axes), and the same sign as the area.
                t[8] = (i0 - a * (c[0] * c[0] + c[1] * c[1])) * a.signum();
                (a.abs(), c, t)
            }
        }
    }

    /// A 3D surface's edges (from, to) \[L\] to draw it by: every edge where it has at most
    /// `max`, else its feature edges alone (open, or between triangles whose normals differ
    /// by more than 30 degrees); none for a polygon.
    pub fn edges(&self, max: usize) -> Vec<[[f64; 3]; 2]> {
        let Shape::Mesh { tree, .. } = &self.shape else {
            return Vec::new();
        };
        let (v, tris) = (tree.vertices(), tree.indices());
        let mut keys: Vec<(u64, u32)> = (tris.iter().enumerate())
            .flat_map(|(i, t)| {
                (0..3).map(move |k| {
                    let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
                    ((u64::from(a) << 32) | u64::from(b), i as u32)
                })
            })
            .collect();
        keys.par_sort_unstable();
        let runs: Vec<&[(u64, u32)]> = keys.chunk_by(|a, b| a.0 == b.0).collect();
        let normal = |i: u32| {
            let t = tris[i as usize].map(|k| v[k as usize]);
            (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero()
        };
        let all = runs.len() <= max;
        let cos30 = 30f64.to_radians().cos();
        runs.iter()
            .filter(|run| all || run.len() != 2 || normal(run[0].1).dot(normal(run[1].1)) < cos30)
            .map(|run| {
                let (a, b) = ((run[0].0 >> 32) as usize, (run[0].0 & 0xffff_ffff) as usize);
                [[v[a].x, v[a].y, v[a].z], [v[b].x, v[b].y, v[b].z]]
            })
            .collect()
    }

    /// The points of the lattice `origin + (i + 0.5) dx` (first `dim` axes; z = 0 in 2D)
    /// inside the box [lo, hi] that `pick` selects: inside the surface, or in the band of
    /// `width` behind it on one side. The lattice is walked in blocks of `BLOCK` points a
    /// side: a block whose centre is farther from the surface than its half diagonal (plus
    /// the band) is all on one side, decided by one winding number; the others point by
    /// point. In lattice order (x fastest), in parallel.
    pub fn lattice(
        &self,
        origin: &P3,
        dx: f64,
        lo: &P3,
        hi: &P3,
        dim: usize,
        pick: Pick,
    ) -> Vec<P3> {
        const BLOCK: i64 = 8;
        let range = |a: usize| -> (i64, i64) {
            if a >= dim {
                return (0, 1);
            }
            let first = ((lo[a] - origin[a]) / dx - 0.5).ceil() as i64;
            let last = ((hi[a] - origin[a]) / dx - 0.5).floor() as i64;
            (first, (last + 1).max(first))
        };
        let r = [range(0), range(1), range(2)];
        let blocks = |a: usize| ((r[a].1 - r[a].0) + BLOCK - 1) / BLOCK;
        let nb = [blocks(0), blocks(1), blocks(2)];
        let coord = |a: usize, i: i64| {
            if a < dim {
                origin[a] + (i as f64 + 0.5) * dx
            } else {
                0.0
            }
        };
        let band = match pick {
            Pick::Inside => 0.0,
            Pick::Band { width, .. } => width,
        };
        let take = |inside: bool, dist: f64| match pick {
            Pick::Inside => inside,
            Pick::Band {
                inside: side,
                width,
            } => inside == side && dist <= width,
        };
        let half_diag = 0.5 * (BLOCK as f64) * dx * (dim as f64).sqrt();
        let n_blocks = (nb[0] * nb[1] * nb[2]).max(0) as usize;
        let per_block: Vec<Vec<(i64, P3)>> = (0..n_blocks)
            .into_par_iter()
            .map(|b| {
                let b = b as i64;
                let bi = [b % nb[0], (b / nb[0]) % nb[1], b / (nb[0] * nb[1])];
                let span = |a: usize| {
                    let s = r[a].0 + bi[a] * BLOCK;
                    let e = if a < dim { (s + BLOCK).min(r[a].1) } else { 1 };
                    (s, e)
                };
                let (sx, sy, sz) = (span(0), span(1), span(2));
                let center: P3 = std::array::from_fn(|a| {
                    let (s, e) = [sx, sy, sz][a];
                    0.5 * (coord(a, s) + coord(a, e - 1))
                });
                let mut out = Vec::new();
                // A block far from the surface is all on the side of its centre, and (a
                // wall's band) none of it within the band.
                let far = self.distance(&center) > half_diag + band;
                let whole = match pick {
                    _ if !far => false,
                    Pick::Inside if self.inside(&center) => true,
                    _ => return out,
                };
                for k in sz.0..sz.1 {
                    for j in sy.0..sy.1 {
                        for i in sx.0..sx.1 {
                            let p = [coord(0, i), coord(1, j), coord(2, k)];
                            let keep = whole || {
                                let dist = if band > 0.0 { self.distance(&p) } else { 0.0 };
                                (band == 0.0 || dist <= band) && take(self.inside(&p), dist)
                            };
                            if keep {
                                let key = ((k - r[2].0) * (r[1].1 - r[1].0) + (j - r[1].0))
                                    * (r[0].1 - r[0].0)
                                    + (i - r[0].0);
                                out.push((key, p));
                            }
                        }
                    }
                }
                out
            })
            .collect();
        let mut all: Vec<(i64, P3)> = per_block.into_iter().flatten().collect();
        all.par_sort_unstable_by_key(|(k, _)| *k);
        all.into_iter().map(|(_, p)| p).collect()
    }
}

/// What `Surface::lattice` keeps.
#[derive(Clone, Copy, Debug)]
pub enum Pick {
    /// The points inside the surface.
    Inside,
    /// The points on the `inside` side (or outside) within `width` of the surface: a wall's
    /// layers.
    Band { inside: bool, width: f64 },
}

/// The winding number of closed loops of `segments` at `p` (the sum of the signed angles
/// they subtend, / 2 pi): 1 inside an anticlockwise loop, 0 outside.
fn polygon_winding(segments: &[[DVec2; 2]], p: DVec2) -> f64 {
    let sum: f64 = (segments.iter())
        .map(|[a, b]| {
            let (a, b) = (*a - p, *b - p);
            a.perp_dot(b).atan2(a.dot(b))
        })
        .sum();
    sum / (2.0 * std::f64::consts::PI)
}
