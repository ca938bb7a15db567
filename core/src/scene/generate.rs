//! Particles from a validated scene.
//!
//! * Every shape is filled on the lattice `min + (i + 0.5) dx` (a box holds
//!   `floor(len / dx)` particles per axis); discs and spheres take the lattice points
//!   `center + (i + 0.5) dx` strictly inside the radius.
//! * `box-container` walls: `layers` rows just outside the box, at `min - (k + 0.5) dx` and
//!   `max + (k + 0.5) dx`, none above `max[1]` when `open_top` (y is up). Fluid at spacing dx
//!   inside the box then sits dx from the first row.
//! * `segment` walls (2D): `layers` rows on the segment's left at (k + 0.5) dx, about dx
//!   apart along it; fluid and solids behind it (its left, within its length) are dropped.
//! * `cylinder` walls: rings at radius `r - (k + 0.5) dx`, about dx apart along the ring;
//!   in 3D repeated along z on the domain's lattice.
//! * `mesh` (3D) and `polygon` (2D) walls: the domain's lattice points `domain.min + (i +
//!   0.5) dx` within `layers` dx of the closed surface on its `solid` side; solids of those
//!   shapes the domain's lattice points inside it; a fluid block's `inside` keeps the
//!   block's lattice points inside its surface (`geometry::Surface::lattice`).
//! * Overlaps: walls take precedence over solids, solids over fluid; within a kind an
//!   earlier object over a later one. A particle is dropped when it lies within 0.5 dx of
//!   a particle kept from a preceding object, or (fluid, solid) inside the region of a
//!   wall or (fluid) of a solid.
//! * `group` = the object's index in the sequence fluid_blocks, solids, walls; the final
//!   list is ordered by group, then generation order; `id` = index in that list.
//! * Mass = reference density * dx^dim (boundary particles take the fluid's rho0).
//! * A driven object (`motion`) starts at its motion's velocity (`Motion::start_velocity`).
//! * Under a ramped start (`[inflow] ramp` > 0) the fluid starts at its block's velocity
//!   less the inflow's `velocity` (at rest where the block moves with the mean flow); the
//!   kick adds the mean flow back over the ramp.
//! * A `hydrostatic` fluid block starts at p = rho0 g depth (eq. (9) gives its density), and,
//!   with `[boundary] hydrostatic_walls`, so does every dynamic wall particle within a kernel
//!   support (2h) of one of its fluid particles, at the wall particle's own depth below the
//!   block's top (`wall_hydrostatic`).

use rayon::prelude::*;

use super::format::*;
use super::geometry::pack::Side as PackSide;
use super::geometry::{Pick, Surface};
use super::spatial::{BoxIndex, Grid, Tiles, P3, PARALLEL_FROM};
use crate::physics::particle::{Kind, Particle};
use crate::scene::scheme::*;

/// [spacings] the tile of `Tiles` and the bin of `BoxIndex`: a few spacings, so that a
/// one-particle object reads a few dozen candidates.
const TILE: f64 = 4.0;

/// One object's candidate particles and region test.
struct Object<'a> {
    group: u32,
    kind: Kind,
    points: Vec<P3>,
    region: Region<'a>,
}

enum Region<'a> {
    Box(&'a [f64], &'a [f64]),
    /// Extended box minus the interior box.
    Band {
        lo: Vec<f64>,
        hi: Vec<f64>,
        min: &'a [f64],
        max: &'a [f64],
    },
    Ball {
        center: &'a [f64],
        radius: f64,
    },
    /// In-plane (x, y) disc: a cylinder along z.
    Column {
        center: &'a [f64],
        radius: f64,
    },
    /// Behind a 2D segment: on its left (looking from `from` to `to`), within its length.
    Behind {
        from: &'a [f64],
        to: &'a [f64],
    },
    /// Inside a closed surface (`inside`), or outside it.
    Surface {
        surface: &'a Surface,
        inside: bool,
    },
}

impl Region<'_> {
    /// A box [lo, hi] over the first `dim` axes (0 past them) holding the region, None
    /// where it is unbounded: behind a segment, and a cylinder's column in 3D.
    fn bounds(&self, dim: usize) -> Option<(P3, P3)> {
        let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
        match self {
            Region::Box(a, b) => {
                lo[..dim].copy_from_slice(&a[..dim]);
                hi[..dim].copy_from_slice(&b[..dim]);
            }
            Region::Band { lo: a, hi: b, .. } => {
                lo[..dim].copy_from_slice(&a[..dim]);
                hi[..dim].copy_from_slice(&b[..dim]);
            }
            Region::Ball { center, radius } => {
                for k in 0..dim {
                    (lo[k], hi[k]) = (center[k] - radius, center[k] + radius);
                }
            }
            Region::Column { center, radius } if dim == 2 => {
                for k in 0..2 {
                    (lo[k], hi[k]) = (center[k] - radius, center[k] + radius);
                }
            }
            // Behind an open surface is a half-space, not its box.
            Region::Surface {
                surface,
                inside: true,
            } if !surface.info.open => {
                lo[..dim].copy_from_slice(&surface.info.lo[..dim]);
                hi[..dim].copy_from_slice(&surface.info.hi[..dim]);
            }
            Region::Column { .. } | Region::Behind { .. } | Region::Surface { .. } => return None,
        }
        Some((lo, hi))
    }

    fn contains(&self, p: &P3, dim: usize) -> bool {
        let in_box = |lo: &[f64], hi: &[f64]| (0..dim).all(|a| p[a] > lo[a] && p[a] < hi[a]);
        match self {
            Region::Box(lo, hi) => in_box(lo, hi),
            Region::Band { lo, hi, min, max } => in_box(lo, hi) && !in_box(min, max),
            Region::Ball { center, radius } => {
                (0..dim).map(|a| (p[a] - center[a]).powi(2)).sum::<f64>() < radius * radius
            }
            Region::Column { center, radius } => {
                (0..2).map(|a| (p[a] - center[a]).powi(2)).sum::<f64>() < radius * radius
            }
            Region::Behind { from, to } => {
                let d = [to[0] - from[0], to[1] - from[1]];
                let q = [p[0] - from[0], p[1] - from[1]];
                let along = (q[0] * d[0] + q[1] * d[1]) / (d[0] * d[0] + d[1] * d[1]);
                let left = d[0] * q[1] - d[1] * q[0];
                (0.0..=1.0).contains(&along) && left > 0.0
            }
            Region::Surface { surface, inside } => surface.inside(p) == *inside,
        }
    }
}

/// Lattice coordinates min + (i + 0.5) dx, i in 0..floor(len / dx).
fn axis(min: f64, max: f64, dx: f64) -> Vec<f64> {
    let n = ((max - min) / dx + 1e-6).floor().max(0.0) as usize;
    (0..n).map(|i| min + (i as f64 + 0.5) * dx).collect()
}

/// Every point of the tensor product of per-axis coordinate lists (x fastest).
fn product(axes: &[Vec<f64>], dim: usize, mut keep: impl FnMut(&P3) -> bool) -> Vec<P3> {
    let mut out = Vec::new();
    let zs: Vec<f64> = if dim == 3 { axes[2].clone() } else { vec![0.0] };
    for &z in &zs {
        for &y in &axes[1] {
            for &x in &axes[0] {
                let p = [x, y, z];
                if keep(&p) {
                    out.push(p);
                }
            }
        }
    }
    out
}

fn box_points(min: &[f64], max: &[f64], dx: f64, dim: usize) -> Vec<P3> {
    let axes: Vec<Vec<f64>> = (0..dim).map(|a| axis(min[a], max[a], dx)).collect();
    product(&axes, dim, |_| true)
}

fn ball_points(center: &[f64], radius: f64, dx: f64, dim: usize) -> Vec<P3> {
    let n = (radius / dx).ceil() as i64 + 1;
    let axes: Vec<Vec<f64>> = (0..dim)
        .map(|a| (-n..n).map(|i| center[a] + (i as f64 + 0.5) * dx).collect())
        .collect();
    product(&axes, dim, |p| {
        (0..dim).map(|a| (p[a] - center[a]).powi(2)).sum::<f64>() < radius * radius
    })
}

/// Rows outside the box: a point is a wall point when any coordinate is a layer coordinate.
fn container_points(
    min: &[f64],
    max: &[f64],
    layers: u32,
    open_top: bool,
    dx: f64,
    dim: usize,
) -> Vec<P3> {
    // Per axis: (coordinate, is_layer).
    let axes: Vec<Vec<(f64, bool)>> = (0..dim)
        .map(|a| {
            let mut v: Vec<(f64, bool)> = (0..layers)
                .rev()
                .map(|k| (min[a] - (k as f64 + 0.5) * dx, true))
                .collect();
            v.extend(axis(min[a], max[a], dx).into_iter().map(|x| (x, false)));
            if !(open_top && a == 1) {
                v.extend((0..layers).map(|k| (max[a] + (k as f64 + 0.5) * dx, true)));
            }
            v
        })
        .collect();
    let zs: Vec<(f64, bool)> = if dim == 3 {
        axes[2].clone()
    } else {
        vec![(0.0, false)]
    };
    let mut out = Vec::new();
    for &(z, lz) in &zs {
        for &(y, ly) in &axes[1] {
            for &(x, lx) in &axes[0] {
                if lx || ly || lz {
                    out.push([x, y, z]);
                }
            }
        }
    }
    out
}

fn cylinder_points(
    center: &[f64],
    radius: f64,
    layers: u32,
    dx: f64,
    dim: usize,
    domain: &Domain,
) -> Vec<P3> {
    let zs: Vec<f64> = if dim == 3 {
        axis(domain.min[2], domain.max[2], dx)
    } else {
        vec![0.0]
    };
    let mut out = Vec::new();
    for &z in &zs {
        for k in 0..layers {
            let r = radius - (k as f64 + 0.5) * dx;
            if r <= 0.0 {
                if r > -0.5 * dx {
                    out.push([center[0], center[1], z]);
                }
                break;
            }
            let n = ((2.0 * std::f64::consts::PI * r / dx).round() as usize).max(1);
            // Alternate rings are offset by half a step so the layers interlock.
            let offset = if k % 2 == 1 { 0.5 } else { 0.0 };
            for j in 0..n {
                let t = 2.0 * std::f64::consts::PI * (j as f64 + offset) / n as f64;
                out.push([center[0] + r * t.cos(), center[1] + r * t.sin(), z]);
            }
        }
    }
    out
}

/// `layers` rows along the 2D segment from -> to, on its left, at (k + 0.5) dx from it;
/// round(len / dx) particles per row at the midpoints of equal pieces.
fn segment_points(from: &[f64], to: &[f64], layers: u32, dx: f64) -> Vec<P3> {
    let d = [to[0] - from[0], to[1] - from[1]];
    let len = d[0].hypot(d[1]);
    let n_left = [-d[1] / len, d[0] / len];
    let n = ((len / dx).round() as usize).max(1);
    let mut out = Vec::new();
    for k in 0..layers {
        let off = (k as f64 + 0.5) * dx;
        for i in 0..n {
            let t = (i as f64 + 0.5) / n as f64;
            out.push([
                from[0] + t * d[0] + off * n_left[0],
                from[1] + t * d[1] + off * n_left[1],
                0.0,
            ]);
        }
    }
    out
}

/// The points of `all` that may lie within `r` of one of `points`: those inside the
/// bounding box of `points` grown by 2 r (a margin that no rounding can cross).
fn near_box(all: &Tiles, points: &[P3], r: f64) -> Vec<P3> {
    let Some(first) = points.first() else {
        return Vec::new();
    };
    let grow = |(mut lo, mut hi): (P3, P3), p: &P3| {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
        (lo, hi)
    };
    let (lo, hi) = if points.len() < PARALLEL_FROM {
        points.iter().fold((*first, *first), grow)
    } else {
        points
            .par_iter()
            .fold(|| (*first, *first), grow)
            .reduce(|| (*first, *first), |acc, (l, h)| grow(grow(acc, &l), &h))
    };
    all.within(&lo.map(|x| x - 2.0 * r), &hi.map(|x| x + 2.0 * r))
}

/// The hydrostatic pressure of eq. (9)'s set-up: p = rho0 g . (x - x_top), with x_top the
/// block corner furthest against gravity.
fn hydrostatic_pressure(block: &FluidBlock, g: &P3, rho0: f64, p: &P3, dim: usize) -> f64 {
    // min over corners of g . c = sum over axes of min(g_a min_a, g_a max_a).
    let top: f64 = (0..dim)
        .map(|a| (g[a] * block.min[a]).min(g[a] * block.max[a]))
        .sum();
    let here: f64 = (0..dim).map(|a| g[a] * p[a]).sum();
    rho0 * (here - top)
}

/// The hydrostatic fluid blocks and their kept particles (hashed at the kernel support,
/// each tagged with its block's place in `blocks`), for the initial pressure of the
/// dynamic walls that hold them.
struct Columns<'a> {
    blocks: Vec<&'a FluidBlock>,
    near: Grid,
    tags: Vec<u32>,
    support: f64,
    g: P3,
    rho0: f64,
    dim: usize,
}

/// The initial pressure [M L^-d L^2 T^-2] of a dynamic wall particle at `p`: the
/// hydrostatic pressure rho0 g depth at its own depth below the top of the first
/// hydrostatic block with a fluid particle within a kernel support (2h) of it, not below
/// zero; None where no such block is near. A dynamic wall's pressure is its fluid
/// neighbours' pressure extrapolated along gravity (Adami, Hu & Adams 2012, eq. (27), at
/// rest); a wall left at p = 0 under a column pulls the fluid onto it at the start (the
/// column falls until the continuity density of the wall has risen: an acoustic transient).
fn wall_hydrostatic(c: &Columns, p: &P3) -> Option<f64> {
    let first = c.near.min_tag_near(p, c.support, &c.tags)?;
    let block = c.blocks[first as usize];
    Some(hydrostatic_pressure(block, &c.g, c.rho0, p, c.dim).max(0.0))
}

/// A point whose first `dim` coordinates are `f(axis)` (0 past them).
fn in_plane(dim: usize, f: impl Fn(usize) -> f64) -> P3 {
    std::array::from_fn(|a| if a < dim { f(a) } else { 0.0 })
}

/// `points` relaxed against `surface` where the outline asks (`pack`).
fn packed(
    o: &Outline,
    surface: &Surface,
    points: &mut [P3],
    dx: f64,
    dim: usize,
    side: PackSide,
    fixed: impl Fn(&P3) -> bool + Sync,
) {
    if o.pack {
        super::geometry::pack::pack(surface, points, dx, dim, side, fixed);
    }
}

/// The box of `surface` grown by `grow` on every side, within the domain.
fn clipped(surface: &Surface, grow: f64, domain: &Domain, dim: usize) -> (P3, P3) {
    let lo = in_plane(dim, |a| (surface.info.lo[a] - grow).max(domain.min[a]));
    let hi = in_plane(dim, |a| (surface.info.hi[a] + grow).min(domain.max[a]));
    (lo, hi)
}

fn vec3(v: Option<&Vec<f64>>) -> P3 {
    let mut out = [0.0; 3];
    if let Some(v) = v {
        for (o, x) in out.iter_mut().zip(v) {
            *o = *x;
        }
    }
    out
}

/// All particles of a validated scene, ordered by group; ids assigned.
pub(crate) fn generate(s: &SceneFile) -> Vec<Particle> {
    let dim = s.dimension as usize;
    let dx = s.discretisation.spacing;
    let n_fluid = s.fluid_blocks.len() as u32;
    let n_solid = s.solids.len() as u32;

    let mut objects: Vec<Object> = Vec::new();
    for (i, b) in s.fluid_blocks.iter().enumerate() {
        let points = match b.inside.as_ref() {
            // The block's own lattice, inside the surface.
            Some(o) => {
                let surface = o.surface();
                let lo = in_plane(dim, |a| b.min[a].max(surface.info.lo[a]));
                let hi = in_plane(dim, |a| b.max[a].min(surface.info.hi[a]));
                let origin = vec3(Some(&b.min));
                // The block's lattice points in [lo, hi] that the block itself holds.
                let mut p = surface.lattice(&origin, dx, &lo, &hi, dim, Pick::Inside);
                p.retain(|q| (0..dim).all(|a| q[a] < b.max[a] - 0.49 * dx));
                // Packed against the surface; the block's own faces (a free surface, say)
                // hold their rows.
                let on_face = |q: &P3| {
                    (0..dim).any(|a| q[a] < b.min[a] + 2.0 * dx || q[a] > b.max[a] - 2.0 * dx)
                };
                let inside = PackSide {
                    inside: true,
                    depth: None,
                };
                packed(o, surface, &mut p, dx, dim, inside, on_face);
                p
            }
            None => box_points(&b.min, &b.max, dx, dim),
        };
        objects.push(Object {
            group: i as u32,
            kind: Kind::Fluid,
            points,
            region: Region::Box(&b.min, &b.max),
        });
    }
    let origin = vec3(Some(&s.domain.min));
    for (i, o) in s.solids.iter().enumerate() {
        let (points, region) = match o {
            SolidObject::Box { min, max, .. } => {
                (box_points(min, max, dx, dim), Region::Box(min, max))
            }
            SolidObject::Disc { center, radius, .. }
            | SolidObject::Sphere { center, radius, .. } => (
                ball_points(center, *radius, dx, dim),
                Region::Ball {
                    center,
                    radius: *radius,
                },
            ),
            SolidObject::Mesh { mesh: o, .. } | SolidObject::Polygon { polygon: o, .. } => {
                let surface = o.surface();
                let (lo, hi) = clipped(surface, 0.0, &s.domain, dim);
                let mut p = surface.lattice(&origin, dx, &lo, &hi, dim, Pick::Inside);
                let inside = PackSide {
                    inside: true,
                    depth: None,
                };
                packed(o, surface, &mut p, dx, dim, inside, |_| false);
                (
                    p,
                    Region::Surface {
                        surface,
                        inside: true,
                    },
                )
            }
        };
        objects.push(Object {
            group: n_fluid + i as u32,
            kind: Kind::Solid,
            points,
            region,
        });
    }
    for (i, w) in s.walls.iter().enumerate() {
        let (points, region) = match w {
            Wall::BoxContainer {
                min,
                max,
                layers,
                open_top,
                ..
            } => {
                let t = *layers as f64 * dx;
                let lo: Vec<f64> = min.iter().map(|x| x - t).collect();
                let mut hi: Vec<f64> = max.iter().map(|x| x + t).collect();
                if *open_top {
                    hi[1] = max[1];
                }
                (
                    container_points(min, max, *layers, *open_top, dx, dim),
                    Region::Band { lo, hi, min, max },
                )
            }
            Wall::Box { min, max, .. } => (box_points(min, max, dx, dim), Region::Box(min, max)),
            Wall::Segment {
                from, to, layers, ..
            } => (
                segment_points(from, to, *layers, dx),
                Region::Behind { from, to },
            ),
            Wall::Cylinder {
                center,
                radius,
                layers,
                ..
            } => (
                cylinder_points(center, *radius, *layers, dx, dim, &s.domain),
                Region::Column {
                    center,
                    radius: *radius,
                },
            ),
            Wall::Mesh {
                mesh: o,
                solid,
                layers,
                ..
            }
            | Wall::Polygon {
                polygon: o,
                solid,
                layers,
                ..
            } => {
                let surface = o.surface();
                let inside = solid.inside();
                let width = *layers as f64 * dx;
                let (lo, hi) = clipped(surface, width, &s.domain, dim);
                let pick = Pick::Band { inside, width };
                let mut p = surface.lattice(&origin, dx, &lo, &hi, dim, pick);
                let side = PackSide {
                    inside,
                    depth: Some(width),
                };
                packed(o, surface, &mut p, dx, dim, side, |_| false);
                (p, Region::Surface { surface, inside })
            }
        };
        objects.push(Object {
            group: n_fluid + n_solid + i as u32,
            kind: Kind::Boundary,
            points,
            region,
        });
    }

    // The inlets' buffers (`[[open_boundaries]]`): fluid on the box's lattice, of the
    // buffer's group. An outlet's buffer starts empty.
    let n_objects = objects.len();
    let inlets: Vec<usize> = (0..s.open_boundaries.len())
        .filter(|&b| s.open_boundaries[b].kind == OpenKind::Inlet)
        .collect();
    for &b in &inlets {
        let o = &s.open_boundaries[b];
        objects.push(Object {
            group: super::open::buffer_group(s, b),
            kind: Kind::Fluid,
            points: box_points(&o.min, &o.max, dx, dim),
            region: Region::Box(&o.min, &o.max),
        });
    }

    // Precedence: walls, then solids, then the inlets' buffers, then fluid; within a kind,
    // scene order.
    let rank = |i: usize| match objects[i].kind {
        Kind::Boundary => 0,
        Kind::Solid => 1,
        Kind::Fluid if i >= n_objects => 2,
        Kind::Fluid => 3,
    };
    let mut order: Vec<usize> = (0..objects.len()).collect();
    order.sort_by_key(|&i| (rank(i), objects[i].group));

    // The objects in precedence order, each against the ones before it: a grid of the points
    // kept so far near the object, then its points tested in parallel (each test reads only
    // what earlier objects kept), in their order.
    // The regions that block others (of walls and solids) are found through their
    // bounding boxes, the points kept so far through their tiles: the work grows with the
    // particles, not with particles times objects (issue #52).
    let r = 0.5 * dx;
    let blocking: Vec<usize> = (0..objects.len())
        .filter(|&j| objects[j].kind != Kind::Fluid)
        .collect();
    let bounds: Vec<Option<(P3, P3)>> = blocking
        .iter()
        .map(|&j| objects[j].region.bounds(dim))
        .collect();
    let regions = BoxIndex::new(TILE * dx, dim, &bounds);
    let mut all = Tiles::new(TILE * dx);
    let mut kept: Vec<Vec<P3>> = vec![Vec::new(); objects.len()];
    for (n, &i) in order.iter().enumerate() {
        let obj = &objects[i];
        // Every object of a kind that blocks this one's precedes it in `order`.
        let blocks = |other: &Object| match obj.kind {
            Kind::Fluid => other.kind != Kind::Fluid,
            Kind::Solid => other.kind == Kind::Boundary,
            Kind::Boundary => false,
        };
        let blocked = |p: &P3| {
            obj.kind != Kind::Boundary
                && regions.any(p, |j| {
                    let other = &objects[blocking[j as usize]];
                    blocks(other) && other.region.contains(p, dim)
                })
        };
        let grid = Grid::new(dx, near_box(&all, &obj.points, r));
        let keep = |p: &&P3| !grid.near(p, r) && !blocked(p);
        let mine: Vec<P3> = if obj.points.len() < PARALLEL_FROM {
            obj.points.iter().filter(keep).copied().collect()
        } else {
            obj.points.par_iter().filter(keep).copied().collect()
        };
        // No object comes after the last.
        if n + 1 < order.len() {
            all.extend(&mine);
        }
        kept[i] = mine;
    }

    let g = vec3(s.gravity.as_ref());
    let f = &s.fluid;
    // The hydrostatic blocks' kept particles, for the dynamic walls that hold them.
    let hydrostatic_walls = s
        .boundary
        .as_ref()
        .is_some_and(|b| b.wall_coupling != WallCoupling::LennardJonesOnly && b.hydrostatic_walls);
    let support = 2.0 * s.discretisation.h();
    let hydrostatic: Vec<usize> = (0..n_fluid as usize)
        .filter(|&i| hydrostatic_walls && s.fluid_blocks[i].hydrostatic)
        .collect();
    let columns = Columns {
        blocks: hydrostatic.iter().map(|&i| &s.fluid_blocks[i]).collect(),
        near: Grid::new(
            support,
            hydrostatic
                .iter()
                .flat_map(|&i| kept[i].iter().copied())
                .collect(),
        ),
        tags: (hydrostatic.iter().enumerate())
            .flat_map(|(t, &i)| std::iter::repeat_n(t as u32, kept[i].len()))
            .collect(),
        support,
        g,
        rho0: f.density,
        dim,
    };
    let tait_b = f.density * f.sound_speed * f.sound_speed / f.gamma;
    let dxd = dx.powi(dim as i32);
    let mut out: Vec<Particle> = Vec::with_capacity(kept.iter().map(Vec::len).sum());
    for (i, obj) in objects.iter().enumerate() {
        // A driven object starts at its motion's velocity there (`Motion::start_velocity`).
        let (rho_ref, velocity, motion) = match obj.kind {
            // An inlet's buffer: at its velocity at t = 0 (none under a ramp).
            Kind::Fluid if i >= n_objects => {
                let o = &s.open_boundaries[inlets[i - n_objects]];
                // Its series' scale at t = 0 (`MfOpen::scale`; knots from t <= 0).
                let scale = o
                    .series
                    .as_deref()
                    .and_then(|r| r.loaded.get())
                    .map_or(1.0, |k| {
                        crate::physics::motion::knots_at(
                            &k.knots,
                            0,
                            k.count() as i32,
                            o.series.as_deref().unwrap().interpolation
                                == super::format::Interpolation::Cubic,
                            0.0,
                        )
                        .s[0]
                    });
                let r = if o.ramp > 0.0 { 0.0 } else { scale };
                (f.density, vec3(o.velocity.as_ref()).map(|u| r * u), None)
            }
            Kind::Fluid => {
                let mut v = vec3(s.fluid_blocks[i].velocity.as_ref());
                if let Some(b) = s.inflow.as_ref().filter(|b| b.ramp > 0.0) {
                    // A ramped start: the mean flow comes from the kick (`integrate::kick`).
                    for (x, u) in v.iter_mut().zip(&b.velocity) {
                        *x -= u;
                    }
                }
                (f.density, v, None)
            }
            Kind::Solid => {
                let o = &s.solids[i - n_fluid as usize];
                (
                    s.solid.as_ref().map(|m| m.density).unwrap_or(f.density),
                    vec3(o.velocity()),
                    o.motion(),
                )
            }
            Kind::Boundary => (
                f.density,
                [0.0; 3],
                s.walls[i - (n_fluid + n_solid) as usize].motion(),
            ),
        };
        let first = out.len() as u32;
        let particle = |(j, p): (usize, &P3)| {
            let (mut density, mut pressure) = (rho_ref, 0.0);
            if obj.kind == Kind::Fluid && i < n_objects && s.fluid_blocks[i].hydrostatic {
                pressure = hydrostatic_pressure(&s.fluid_blocks[i], &g, f.density, p, dim);
                density = f.density * (1.0 + pressure / tait_b).powf(1.0 / f.gamma);
            }
            if obj.kind == Kind::Boundary {
                if let Some(ph) = wall_hydrostatic(&columns, p) {
                    // Tait eq. (9) inverted: rho = rho0 (1 + p / B)^(1/gamma) [M L^-d].
                    pressure = ph;
                    density = f.density * (1.0 + pressure / tait_b).powf(1.0 / f.gamma);
                }
            }
            Particle {
                id: first + j as u32,
                kind: obj.kind,
                group: obj.group,
                position: p.map(|x| x as f32),
                velocity: motion
                    .map_or(velocity, |m| {
                        m.start_velocity(*p, dim, super::wave::gravity(s))
                    })
                    .map(|x| x as f32),
                density: density as f32,
                pressure: pressure as f32,
                mass: (rho_ref * dxd) as f32,
                stress: [0.0; 6],
            }
        };
        if kept[i].len() < PARALLEL_FROM {
            out.extend(kept[i].iter().enumerate().map(particle));
        } else {
            out.par_extend(kept[i].par_iter().enumerate().map(particle));
        }
    }
    out
}
