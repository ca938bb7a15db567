//! Floating walls (`floating` of a `[[walls]]` entry, `format::Floating`): the rigid bodies
//! the solver starts with (`MfBody`, `physics::body`), their mass properties from the
//! wall's shape, and the checks serde cannot make.

use super::ctx::{fmt, Ctx, R};
use super::format::{Axis, Floating, Side, Wall};
use super::scheme::{NoSlip, SceneFile};
use crate::physics::body::{free_bits, matrix};
use crate::physics::params::MfBody;

/// The floating walls: (index in `[[walls]]`, the wall, its `floating`).
pub(crate) fn floating_walls(s: &SceneFile) -> impl Iterator<Item = (usize, &Wall, &Floating)> {
    (s.walls.iter().enumerate()).filter_map(|(i, w)| w.floating().map(|f| (i, w, f)))
}

/// The volume \[L^d\] (2D: area), centroid \[L\] and inertia tensor about it at unit density
/// \[L^(d+2)\] (row-major; 2D: zz alone) of a floating wall's solid: a box; a disc, or in 3D
/// a cylinder along z across the domain (the wall's rings span it); the inside of a mesh or
/// a polygon. None for a shape that encloses no solid.
fn solid(s: &SceneFile, w: &Wall) -> Option<(f64, [f64; 3], [f64; 9])> {
    let dim = s.dimension as usize;
    let mut t = [0.0; 9];
    match w {
        Wall::Box { min, max, .. } => {
            let e: Vec<f64> = (0..dim).map(|a| max[a] - min[a]).collect();
            let v: f64 = e.iter().product();
            let mut c = [0.0; 3];
            for a in 0..dim {
                c[a] = 0.5 * (min[a] + max[a]);
            }
            if dim == 2 {
                t[8] = v * (e[0] * e[0] + e[1] * e[1]) / 12.0;
            } else {
                t[0] = v * (e[1] * e[1] + e[2] * e[2]) / 12.0;
                t[4] = v * (e[0] * e[0] + e[2] * e[2]) / 12.0;
                t[8] = v * (e[0] * e[0] + e[1] * e[1]) / 12.0;
            }
            Some((v, c, t))
        }
        Wall::Cylinder { center, radius, .. } => {
            let r2 = radius * radius;
            if dim == 2 {
                let a = std::f64::consts::PI * r2;
                t[8] = 0.5 * a * r2;
                Some((a, [center[0], center[1], 0.0], t))
            } else {
                let (lo, hi) = (s.domain.min[2], s.domain.max[2]);
                let l = hi - lo;
                let v = std::f64::consts::PI * r2 * l;
                t[0] = v * (3.0 * r2 + l * l) / 12.0;
                t[4] = t[0];
                t[8] = 0.5 * v * r2;
                Some((v, [center[0], center[1], 0.5 * (lo + hi)], t))
            }
        }
        Wall::Mesh {
            mesh: o,
            solid: Side::Inside,
            ..
        }
        | Wall::Polygon {
            polygon: o,
            solid: Side::Inside,
            ..
        } => Some(o.surface().solid_properties()),
        _ => None,
    }
}

/// The rigid bodies of a checked scene at t = 0, in the order of their walls.
pub(crate) fn bodies(s: &SceneFile, wall_group: impl Fn(usize) -> u32) -> Vec<MfBody> {
    let dim = s.dimension as usize;
    floating_walls(s)
        .map(|(i, w, f)| {
            let (volume, centre, unit) = solid(s, w).expect("a checked floating wall's shape");
            let mass = f.mass.unwrap_or_else(|| f.density.unwrap_or(0.0) * volume);
            let axes = |list: &Option<Vec<Axis>>, all: [bool; 3]| match list {
                None => all,
                Some(l) => [0, 1, 2].map(|a| l.iter().any(|x| x.index() == a)),
            };
            let moves = axes(&f.moves, [true; 3]);
            let turns = axes(&f.turns, [true; 3]);
            let mut b = MfBody {
                group: wall_group(i) as i32,
                free: free_bits(dim, moves, turns),
                mass,
                inertia: unit.map(|x| x * mass / volume),
                centre,
                orientation: [1.0, 0.0, 0.0, 0.0],
                turn: matrix(&[1.0, 0.0, 0.0, 0.0]),
                ..Default::default()
            };
            if let Some(v) = &f.velocity {
                for (a, v) in v.iter().enumerate() {
                    if b.free & (1 << a) != 0 {
                        b.velocity[a] = *v;
                    }
                }
            }
            b
        })
        .collect()
}

/// The checks of the floating walls: a shape that encloses a solid, `density` or `mass`
/// (one, positive), axes of the scene's dimension, no `motion` or `remove_at` beside it, an
/// integrator that kicks before it drifts, and a mass and inertia about each free axis.
pub(super) fn check(c: &Ctx, s: &SceneFile, euler: bool) -> R {
    let dim = c.dim;
    for (i, w, f) in floating_walls(s) {
        let field = format!("walls[{i}].floating");
        if euler {
            return Err(c.err(
                field,
                "a floating body needs an integrator that kicks before it drifts: \
                 [time] integrator = \"leapfrog\" (the default) or \"symplectic-euler\"",
            ));
        }
        if w.motion().is_some() {
            return Err(c.err(
                field,
                "a wall either floats or follows a motion; give floating or motion, not both",
            ));
        }
        if w.remove_at().is_some() {
            return Err(c.err(field, "a floating body cannot be a gate (remove_at)"));
        }
        if s.boundary
            .as_ref()
            .is_some_and(|b| b.no_slip == NoSlip::Morris)
        {
            return Err(c.err(
                field,
                "a floating body turns, and Morris's no-slip walls take each wall particle's \
                 normal at t = 0: use [boundary] no_slip = \"wall-velocity\" (the default) \
                 with floating bodies",
            ));
        }
        if (0..dim).any(|a| s.domain.periodic.as_ref().is_some_and(|p| p[a])) {
            return Err(c.err(
                field,
                "floating bodies need a domain without periodic axes (a body is not carried \
                 across one)",
            ));
        }
        let Some((volume, _, unit)) = solid(s, w) else {
            return Err(c.err(
                field,
                "only a wall around a solid floats: a box, a cylinder, or a mesh or polygon \
                 with solid = \"inside\"",
            ));
        };
        match (f.density, f.mass) {
            (Some(_), Some(_)) => {
                return Err(c.err(field, "give density or mass, not both"));
            }
            (None, None) => {
                return Err(c.err(
                    field,
                    "give the body's density (its mass from its shape's volume) or its mass",
                ));
            }
            (Some(d), None) => c.positive(&format!("{field}.density"), d)?,
            (None, Some(m)) => c.positive(&format!("{field}.mass"), m)?,
        }
        c.opt_vec(&format!("{field}.velocity"), &f.velocity)?;
        for (key, list) in [("moves", &f.moves), ("turns", &f.turns)] {
            for a in list.iter().flatten() {
                let ok = if key == "moves" {
                    a.index() < dim
                } else {
                    dim == 3 || *a == Axis::Z
                };
                if !ok {
                    return Err(c.err(
                        format!("{field}.{key}"),
                        if dim == 2 && key == "turns" {
                            "a 2D body turns about z only".to_string()
                        } else {
                            format!("a {dim}D scene has no z axis to move along")
                        },
                    ));
                }
            }
        }
        if volume <= 0.0 {
            return Err(c.err(field, "the body's shape encloses no volume"));
        }
        // A free turn needs an inertia about its axis.
        let turns_about = |a: usize| match &f.turns {
            None => dim == 3 || a == 2,
            Some(l) => l.iter().any(|x| x.index() == a),
        };
        if let Some(a) = (0..3).find(|&a| turns_about(a) && unit[4 * a] <= 0.0) {
            return Err(c.err(
                format!("{field}.turns"),
                format!(
                    "the body has no inertia about {} ({}): hold that axis",
                    ["x", "y", "z"][a],
                    fmt(unit[4 * a])
                ),
            ));
        }
    }
    Ok(())
}
