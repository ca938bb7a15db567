//! Reading a surface (`load`): the file or points, the placement (scale, turns, move), the
//! checks (no triangle, open beyond `MAX_HOLE`, no volume, not finite) and the outward
//! orientation, then the trees that answer its queries.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use super::base::{Base, ASSETS};
use super::read::{self, Format, Raw};
use super::surface::{From, Info, Shape, Surface, MAX_HOLE};
use super::topology::Topology;
use super::winding;
use crate::scene::ctx::{fmt, Ctx, R};
use crate::scene::format::Outline;
use crate::scene::spatial::P3;

/// The outline's transform applied to `v`: scale, then the turns (3D: about x, then y, then
/// z; 2D: one about z) \[deg\], then the translation.
fn place(o: &Outline, dim: usize, v: [f64; 3]) -> [f64; 3] {
    let mut p = DVec3::from_array(v) * o.scale;
    if let Some(r) = &o.rotate {
        let turns: Vec<(DVec3, f64)> = if dim == 3 {
            vec![(DVec3::X, r[0]), (DVec3::Y, r[1]), (DVec3::Z, r[2])]
        } else {
            vec![(DVec3::Z, r[0])]
        };
        for (axis, deg) in turns {
            p = glam::DQuat::from_axis_angle(axis, deg.to_radians()) * p;
        }
    }
    if let Some(t) = &o.translate {
        for (a, x) in t.iter().enumerate() {
            p[a] += x;
        }
    }
    if dim == 2 {
        p.z = 0.0;
    }
    p.to_array()
}

/// Reads, places, checks and orients the surface of outline `o` (at `field`), for a scene of
/// `dim` dimensions whose files are at `base`. A closed surface (a fluid block's `inside`, a
/// solid, a wall around a volume) must enclose one: open beyond `MAX_HOLE`, it is refused.
/// An `open` one (a wall's sheet or line, `Side::open`) keeps the file's orientation and
/// need enclose nothing; a 2D line's points are not closed into a loop.
pub(in crate::scene) fn load(
    c: &Ctx,
    field: &str,
    o: &Outline,
    open: bool,
    base: &Base,
) -> Result<Surface, crate::scene::SceneError> {
    let dim = c.dim;
    let started = std::time::Instant::now();
    check_keys(c, field, o)?;
    if open && o.slice.is_some() {
        return Err(c.err(
            format!("{field}.slice"),
            "the cut of a mesh is a closed polygon (solid = \"inside\" or \"outside\"); an open line is given by its points, or a file of x y points",
        ));
    }
    let (raw, source, from) = match (&o.file, &o.points) {
        (Some(file), None) => {
            let f = format!("{field}.file");
            let format = Format::of(file).ok_or_else(|| {
                c.err(
                    &f,
                    format!(
                        "{file:?}: the format is not known from its extension (.stl, .obj, .ply{})",
                        if dim == 2 {
                            ", or .csv/.txt/.dat of x y points"
                        } else {
                            ""
                        }
                    ),
                )
            })?;
            // 2D reads points, or a 3D mesh with `slice`; 3D reads a mesh.
            let points_file = format == Format::Points;
            if dim == 3 && points_file {
                return Err(c.err(
                    &f,
                    format!("{file:?}: a 3D surface is an STL, OBJ or PLY file"),
                ));
            }
            if dim == 2 && points_file == o.slice.is_some() {
                return Err(c.err(&f, if points_file {
                    format!("{file:?}: a file of points is a polygon already: slice cuts a 3D mesh (STL, OBJ, PLY)")
                } else {
                    format!("{file:?}: a 3D mesh in a 2D scene needs slice (the plane z = slice that cuts it); or give a text file of x y points")
                }));
            }
            let (bytes, from) = match base {
                Base::Builtin => ASSETS
                    .iter()
                    .find(|(n, _)| *n == file)
                    .map(|(_, b)| (b.to_vec(), From::Asset(b)))
                    .ok_or_else(|| {
                        c.err(&f, format!("{file:?}: no asset of that name is built in"))
                    })?,
                Base::Dir(dir) => {
                    let path = dir.join(file);
                    let bytes = read::bytes_of(&path)
                        .map_err(|why| c.err(&f, format!("{}: {why}", path.display())))?;
                    (bytes, From::Path(path))
                }
            };
            let raw =
                read::parse(&bytes, format).map_err(|why| c.err(&f, format!("{file:?}: {why}")))?;
            (raw, file.clone(), from)
        }
        (None, Some(points)) => {
            let mut raw = Raw::default();
            for (k, p) in points.iter().enumerate() {
                c.vec(&format!("{field}.points[{k}]"), p)?;
                raw.vertices.push([p[0], p[1], 0.0]);
            }
            (raw, "points".to_string(), From::Points)
        }
        _ => unreachable!("check_keys"),
    };
    let mut raw = raw;
    if let Some(z) = o.slice {
        raw = slice(c, field, &raw, z / o.scale, &source)?;
    }
    for v in raw.vertices.iter_mut() {
        *v = place(o, dim, *v);
    }
    if let Some(k) = raw
        .vertices
        .iter()
        .position(|v| v.iter().any(|x| !x.is_finite()))
    {
        return Err(c.err(
            field,
            format!("{source}: vertex {k} is not finite ({:?})", raw.vertices[k]),
        ));
    }
    let mut surface = if dim == 3 {
        mesh_surface(c, field, raw, source, open)
    } else {
        polygon_surface(c, field, raw, source, open)
    }?;
    surface.from = from;
    surface.info.read_seconds = started.elapsed().as_secs_f64();
    Ok(surface)
}

/// The cut of `raw`'s triangles by the plane z = `z` (the file's unit): its segments as a
/// soup (vertices in pairs), each oriented with the inside on its left where the triangles
/// are wound outward (an outward normal n gives the direction (-n_y, n_x)). A vertex on the
/// plane counts as above it.
fn slice(
    c: &Ctx,
    field: &str,
    raw: &Raw,
    z: f64,
    source: &str,
) -> Result<Raw, crate::scene::SceneError> {
    let mut out = Raw::default();
    for t in &raw.triangles {
        let p = t.map(|i| DVec3::from_array(raw.vertices[i as usize]));
        let above = p.map(|q| q.z >= z);
        let cut: Vec<DVec3> = (0..3)
            .filter(|&k| above[k] != above[(k + 1) % 3])
            .map(|k| {
                let (a, b) = (p[k], p[(k + 1) % 3]);
                a + (b - a) * ((z - a.z) / (b.z - a.z))
            })
            .collect();
        if cut.len() != 2 {
            continue;
        }
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let (mut a, mut b) = (cut[0], cut[1]);
        if (b - a).dot(DVec3::new(-n.y, n.x, 0.0)) < 0.0 {
            std::mem::swap(&mut a, &mut b);
        }
        let k = out.vertices.len() as u32;
        out.vertices.extend([[a.x, a.y, 0.0], [b.x, b.y, 0.0]]);
        out.triangles.push([k, k + 1, k + 1]);
    }
    if out.vertices.is_empty() {
        let (lo, hi) = bounds(&raw.vertices);
        return Err(c.err(format!("{field}.slice"), format!(
            "{source}: the plane z = {} cuts no triangle (the mesh's z runs from {} to {} in the file's unit)",
            fmt(z), fmt(lo[2]), fmt(hi[2]))));
    }
    Ok(out)
}

fn check_keys(c: &Ctx, field: &str, o: &Outline) -> R {
    match (&o.file, &o.points) {
        (Some(_), Some(_)) => {
            return Err(c.err(format!("{field}.points"), "give file or points, not both"))
        }
        (None, None) => {
            return Err(c.err(
                field,
                if c.dim == 2 {
                    "needs file (x y points) or points"
                } else {
                    "needs file (STL, OBJ or PLY)"
                },
            ))
        }
        (None, Some(_)) if c.dim == 3 => {
            return Err(c.err(
                format!("{field}.points"),
                "points make a 2D polygon; a 3D surface is a file (STL, OBJ or PLY)",
            ))
        }
        _ => {}
    }
    if let Some(z) = o.slice {
        let why = if c.dim == 3 {
            Some("slice cuts a 3D mesh into a 2D scene's polygon; a 3D scene takes the mesh whole")
        } else if o.file.is_none() {
            Some("slice cuts a mesh file; points are a polygon already")
        } else if !z.is_finite() {
            Some("must be a finite number")
        } else {
            None
        };
        if let Some(why) = why {
            return Err(c.err(format!("{field}.slice"), why));
        }
    }
    if !(o.scale.is_finite() && o.scale > 0.0) {
        return Err(c.err(
            format!("{field}.scale"),
            format!("must be a positive number, found {}", o.scale),
        ));
    }
    if let Some(r) = &o.rotate {
        let n = if c.dim == 3 { 3 } else { 1 };
        if r.len() != n || r.iter().any(|x| !x.is_finite()) {
            return Err(c.err(
                format!("{field}.rotate"),
                format!(
                    "expected {n} finite angle(s) in degrees ({}), found {r:?}",
                    if n == 3 {
                        "about x, then y, then z"
                    } else {
                        "about z"
                    }
                ),
            ));
        }
    }
    c.opt_vec(&format!("{field}.translate"), &o.translate)
}

fn mesh_surface(
    c: &Ctx,
    field: &str,
    raw: Raw,
    source: String,
    open: bool,
) -> Result<Surface, crate::scene::SceneError> {
    if raw.triangles.is_empty() {
        return Err(c.err(
            format!("{field}.file"),
            format!("{source}: the file holds no triangle"),
        ));
    }
    let mut tris = raw.triangles;
    let v = &raw.vertices;
    let (lo, hi) = bounds(v);
    let diag = (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum::<f64>().sqrt();
    // Signed volume, sum of a . (b x c) / 6: negative for inward normals.
    let p = |i: u32| DVec3::from_array(v[i as usize]);
    let volume: f64 = tris
        .par_iter()
        .map(|t| p(t[0]).dot(p(t[1]).cross(p(t[2]))) / 6.0)
        .sum();
    // An open surface keeps its faces as given: they say which side is which.
    let turned = volume < 0.0 && !open;
    if turned {
        for t in tris.iter_mut() {
            t.swap(1, 2);
        }
    }
    // The edges, parry's tree (distances) and the winding tree (inside), each on its own
    // threads: about a second each for a million triangles. An open surface's side is
    // parry's instead: the sign against the pseudo-normal (angle-weighted at a vertex,
    // Baerentzen & Aanaes 2005) of the closest point's feature, which its tree then holds;
    // it needs no winding number.
    let tree_vertices: Vec<parry3d_f64::math::Vector> = v
        .iter()
        .map(|q| parry3d_f64::math::Vector::new(q[0], q[1], q[2]))
        .collect();
    let (topology, (tree, winding)) = rayon::join(
        || Topology::of(v, &tris),
        || {
            rayon::join(
                || {
                    let flags = if open {
                        parry3d_f64::shape::TriMeshFlags::ORIENTED
                    } else {
                        parry3d_f64::shape::TriMeshFlags::empty()
                    };
                    parry3d_f64::shape::TriMesh::with_flags(tree_vertices, tris.clone(), flags)
                },
                || {
                    winding::Winding::new(if open {
                        Vec::new()
                    } else {
                        tris.iter().map(|t| [p(t[0]), p(t[1]), p(t[2])]).collect()
                    })
                },
            )
        },
    );
    if topology.largest_hole > MAX_HOLE * diag && !open {
        return Err(c.err(format!("{field}.file"), format!(
            "{source} is open: {} open edges in {} hole(s), the largest {} across around ({}, {}, {}); a volume needs a closed surface (holes up to {} % of its size, {}, are bridged); a wall of an open surface, a terrain or a sheet, takes solid = \"back\" or \"front\" of its faces",
            topology.open_edges, topology.holes, fmt(topology.largest_hole),
            fmt(topology.hole_at[0]), fmt(topology.hole_at[1]), fmt(topology.hole_at[2]),
            MAX_HOLE * 100.0, fmt(MAX_HOLE * diag))));
    }
    let area: f64 = tris
        .par_iter()
        .map(|t| 0.5 * (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length())
        .sum();
    let box_volume = (0..3).map(|a| hi[a] - lo[a]).product::<f64>();
    if volume.abs() <= 1e-9 * box_volume.max(f64::MIN_POSITIVE) && !open {
        return Err(c.err(format!("{field}.file"), format!("{source} encloses no volume (flat, or its triangles cancel): a volume needs a closed surface")));
    }
    let tree = tree.map_err(|e| c.err(format!("{field}.file"), format!("{source}: {e}")))?;
    Ok(Surface {
        from: From::Points,
        info: Info {
            source,
            elements: tris.len(),
            lo,
            hi,
            volume: if open { 0.0 } else { volume.abs() },
            area,
            topology,
            turned,
            open,
            read_seconds: 0.0,
        },
        shape: Shape::Mesh {
            tree,
            winding,
            open,
        },
    })
}

fn polygon_surface(
    c: &Ctx,
    field: &str,
    raw: Raw,
    source: String,
    open: bool,
) -> Result<Surface, crate::scene::SceneError> {
    if open {
        return line_surface(c, field, raw, source);
    }
    let at = |i: u32| {
        let v = raw.vertices[i as usize];
        DVec2::new(v[0], v[1])
    };
    let key = if source == "points" { "points" } else { "file" };
    // A cut mesh is a soup of segments (its `triangles` hold each as [a, b, b]); points are
    // one closed loop of corners (a closing corner equal to the first is the same).
    let mut segments: Vec<[DVec2; 2]> = if raw.triangles.is_empty() {
        let mut corners: Vec<DVec2> = (0..raw.vertices.len() as u32).map(at).collect();
        if corners.len() > 1 && corners.first() == corners.last() {
            corners.pop();
        }
        if corners.len() < 3 {
            return Err(c.err(
                format!("{field}.{key}"),
                format!(
                    "{source}: a polygon needs at least 3 corners, found {}",
                    corners.len()
                ),
            ));
        }
        let n = corners.len();
        (0..n).map(|k| [corners[k], corners[(k + 1) % n]]).collect()
    } else {
        raw.triangles.iter().map(|t| [at(t[0]), at(t[1])]).collect()
    };
    let area: f64 = segments.iter().map(|s| s[0].perp_dot(s[1])).sum::<f64>() / 2.0;
    let (lo, hi) = bounds(&raw.vertices);
    if area.abs() <= 1e-9 * ((hi[0] - lo[0]) * (hi[1] - lo[1])).max(f64::MIN_POSITIVE) {
        return Err(c.err(
            format!("{field}.{key}"),
            format!("{source}: the polygon encloses no area"),
        ));
    }
    let turned = area < 0.0;
    if turned {
        for s in segments.iter_mut() {
            s.swap(0, 1);
        }
    }
    let n = segments.len() as u32;
    let line = parry2d_f64::shape::Polyline::new(
        (segments.iter().flatten())
            .map(|q| parry2d_f64::math::Vector::new(q.x, q.y))
            .collect(),
        Some((0..n).map(|k| [2 * k, 2 * k + 1]).collect()),
    );
    Ok(Surface {
        from: From::Points,
        info: Info {
            source,
            elements: segments.len(),
            lo,
            hi,
            volume: area.abs(),
            area: segments.iter().map(|[a, b]| a.distance(*b)).sum(),
            topology: Topology::default(),
            turned,
            open: false,
            read_seconds: 0.0,
        },
        shape: Shape::Polygon {
            line,
            segments,
            open: false,
        },
    })
}

/// An open 2D line through `raw`'s points in their order (a wall's `solid` = "left" or
/// "right"): parry's polyline with its pseudo-normals (`ORIENTED`: a point on the left of
/// the walk is "inside", the bisector deciding at a corner).
fn line_surface(
    c: &Ctx,
    field: &str,
    raw: Raw,
    source: String,
) -> Result<Surface, crate::scene::SceneError> {
    let key = if source == "points" { "points" } else { "file" };
    let mut corners: Vec<DVec2> = raw
        .vertices
        .iter()
        .map(|v| DVec2::new(v[0], v[1]))
        .collect();
    corners.dedup();
    if corners.len() < 2 {
        return Err(c.err(
            format!("{field}.{key}"),
            format!(
                "{source}: a line needs at least 2 distinct points, found {}",
                corners.len()
            ),
        ));
    }
    let n = corners.len();
    let segments: Vec<[DVec2; 2]> = (1..n).map(|k| [corners[k - 1], corners[k]]).collect();
    let line = parry2d_f64::shape::Polyline::with_flags(
        (corners.iter())
            .map(|q| parry2d_f64::math::Vector::new(q.x, q.y))
            .collect(),
        Some((1..n as u32).map(|k| [k - 1, k]).collect()),
        parry2d_f64::shape::PolylineFlags::ORIENTED,
    );
    let (lo, hi) = bounds(&raw.vertices);
    Ok(Surface {
        from: From::Points,
        info: Info {
            source,
            elements: segments.len(),
            lo,
            hi,
            volume: 0.0,
            area: segments.iter().map(|[a, b]| a.distance(*b)).sum(),
            topology: Topology::default(),
            turned: false,
            open: true,
            read_seconds: 0.0,
        },
        shape: Shape::Polygon {
            line,
            segments,
            open: true,
        },
    })
}

fn bounds(v: &[[f64; 3]]) -> (P3, P3) {
    let mut lo = [f64::MAX; 3];
    let mut hi = [f64::MIN; 3];
    for p in v {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}
