//! Checks on a parsed scene that serde cannot express: array lengths against `dimension`,
//! ordering of corners, positive sizes, objects inside the domain, materials present, and
//! enough neighbour-grid cells on periodic axes, numbers single precision holds
//! (`scheme::single_precision`), sizes the solver can index (`estimate`); the keys of the scheme's tables are checked
//! as `crate::scene::scheme` declares them. The first failure is returned.

use super::ctx::{fmt, Ctx};
use super::format::*;
use super::motion;
use super::wave;
use super::zones;
use super::SceneError;
use crate::physics::params::MF_MAX_DRIVEN;
use crate::scene::scheme::*;

use super::ctx::R;

/// [bytes] the longest scene `name` (a directory name on every file system).
const MAX_NAME: usize = 100;

/// Validate everything that does not need the particles.
pub(crate) fn validate(s: &SceneFile, origin: &str) -> R {
    if s.dimension != 2 && s.dimension != 3 {
        return Err(SceneError::Invalid {
            origin: origin.into(),
            field: "dimension".into(),
            reason: format!("must be 2 or 3, found {}", s.dimension),
        });
    }
    let c = Ctx::new(origin, s.dimension as usize);
    let dim = c.dim;
    let euler = s.time.integrator == IntegratorChoice::Euler;
    if s.name.trim().is_empty() || s.name.contains(['/', '\\']) || s.name == "." || s.name == ".." {
        return Err(c.err("name", "must be a non-empty name without path separators"));
    }
    // It names the default output directory and files: no control characters (NUL, line
    // breaks), no leading or trailing space, a length every file system takes.
    if s.name.chars().any(char::is_control) || s.name.trim() != s.name || s.name.len() > MAX_NAME {
        return Err(c.err(
            "name",
            format!(
                "must be at most {MAX_NAME} bytes without control characters (NUL, line breaks) \
                 or surrounding spaces: it names the output directory"
            ),
        ));
    }

    // Domain.
    c.corners("domain", &s.domain.min, &s.domain.max)?;
    if let Some(p) = &s.domain.periodic {
        if p.len() != dim {
            return Err(c.err(
                "domain.periodic",
                format!(
                    "expected {dim} booleans (dimension = {dim}), found {}",
                    p.len()
                ),
            ));
        }
    }

    // Every key of the scheme's tables (crate::scene::scheme): ranges, and the checks of a key
    // against the rest of the scene.
    crate::scene::scheme::validate(s).map_err(|(field, reason)| c.err(field, reason))?;

    let d = &s.discretisation;
    let h = d.h();
    if let Some(p) = &s.domain.periodic {
        for (a, &on) in p.iter().enumerate() {
            let len = s.domain.max[a] - s.domain.min[a];
            let cells = (len / (2.0 * h)).floor();
            if on && cells < 3.0 {
                return Err(c.err(
                    format!("domain.periodic[{a}]"),
                    format!(
                        "a periodic axis needs at least 3 neighbour cells of size 2h = {}, but the \
                         domain is {len} long ({cells} cells)",
                        fmt(2.0 * h)
                    ),
                ));
            }
        }
    }
    for a in 0..dim {
        let len = s.domain.max[a] - s.domain.min[a];
        if len < d.spacing {
            return Err(c.err(
                "domain.max",
                format!(
                    "the domain is {len} long on axis {a}, shorter than one spacing {}",
                    d.spacing
                ),
            ));
        }
    }

    c.opt_vec("gravity", &s.gravity)?;

    // Objects.
    let dom = &s.domain;
    for (i, b) in s.fluid_blocks.iter().enumerate() {
        let field = format!("fluid_blocks[{i}]");
        c.corners(&field, &b.min, &b.max)?;
        c.opt_vec(&format!("{field}.velocity"), &b.velocity)?;
        c.inside(&field, "the block", &b.min, &b.max, dom)?;
    }
    if !s.solids.is_empty() && s.solid.is_none() {
        return Err(c.err(
            "solid",
            format!(
                "the scene has {} solid object(s) but no [solid] material table (density, \
                 sound_speed, shear_modulus)",
                s.solids.len()
            ),
        ));
    }
    for (i, o) in s.solids.iter().enumerate() {
        let field = format!("solids[{i}]");
        c.opt_vec(&format!("{field}.velocity"), &o.velocity().cloned())?;
        if let Some(m) = o.motion() {
            motion::check(&c, &format!("{field}.motion"), m, euler, s.time.end)?;
            if let Motion::Law(MotionLaw { wave: Some(_), .. }) = m {
                return Err(c.err(
                    format!("{field}.motion.wave"),
                    "a wave maker's paddle is a box wall ([[walls]] shape = \"box\")",
                ));
            }
        }
        if o.velocity().is_some() && o.motion().is_some() {
            return Err(c.err(
                format!("{field}.velocity"),
                "a driven body (motion) moves at its motion; give motion or velocity, not both",
            ));
        }
        match o {
            SolidObject::Box { min, max, .. } => {
                c.corners(&field, min, max)?;
                c.inside(&field, "the box", min, max, dom)?;
            }
            SolidObject::Disc { center, radius, .. }
            | SolidObject::Sphere { center, radius, .. } => {
                let is_disc = matches!(o, SolidObject::Disc { .. });
                if is_disc && dim != 2 {
                    return Err(c.err(
                        format!("{field}.shape"),
                        "a \"disc\" is a 2D shape; use \"sphere\" in a 3D scene",
                    ));
                }
                if !is_disc && dim != 3 {
                    return Err(c.err(
                        format!("{field}.shape"),
                        "a \"sphere\" is a 3D shape; use \"disc\" in a 2D scene",
                    ));
                }
                c.vec(&format!("{field}.center"), center)?;
                c.positive(&format!("{field}.radius"), *radius)?;
                let lo: Vec<f64> = center.iter().map(|x| x - radius).collect();
                let hi: Vec<f64> = center.iter().map(|x| x + radius).collect();
                c.inside(&field, "the shape", &lo, &hi, dom)?;
            }
            // Read, placed and checked with the scene's other surfaces (`geometry::check`).
            SolidObject::Mesh { .. } | SolidObject::Polygon { .. } => {}
        }
    }
    if !s.walls.is_empty() && s.boundary.is_none() {
        return Err(c.err(
            "boundary",
            format!(
                "the scene has {} wall(s) but no [boundary] table (strength = C0 of eq. 17)",
                s.walls.len()
            ),
        ));
    }
    for (i, w) in s.walls.iter().enumerate() {
        let field = format!("walls[{i}]");
        if let Some(m) = w.motion() {
            motion::check(&c, &format!("{field}.motion"), m, euler, s.time.end)?;
            if let Motion::Law(MotionLaw {
                wave: Some(wave), ..
            }) = m
            {
                let f = format!("{field}.motion.wave");
                match w {
                    Wall::Box { min, max, .. } => {
                        c.corners(&field, min, max)?;
                        wave::check(&c, &f, wave, s, min, max)?
                    }
                    _ => {
                        return Err(
                            c.err(f, "a wave maker's paddle is a box wall (shape = \"box\")")
                        )
                    }
                }
            }
        }
        if let Some(t) = w.remove_at() {
            c.non_negative(&format!("{field}.remove_at"), t)?;
        }
        match w {
            Wall::BoxContainer {
                min,
                max,
                layers,
                open_top,
                ..
            } => {
                c.corners(&field, min, max)?;
                if *layers == 0 {
                    return Err(c.err(format!("{field}.layers"), "must be at least 1"));
                }
                let t = *layers as f64 * d.spacing;
                let lo: Vec<f64> = min.iter().map(|x| x - t).collect();
                let mut hi: Vec<f64> = max.iter().map(|x| x + t).collect();
                if *open_top {
                    hi[1] = max[1];
                }
                c.inside(&field, "the container with its wall layers", &lo, &hi, dom)?;
            }
            Wall::Box { min, max, .. } => {
                c.corners(&field, min, max)?;
                c.inside(&field, "the box", min, max, dom)?;
            }
            Wall::Segment {
                from, to, layers, ..
            } => {
                if dim != 2 {
                    return Err(c.err(format!("{field}.shape"), "a \"segment\" wall is 2D only"));
                }
                c.vec(&format!("{field}.from"), from)?;
                c.vec(&format!("{field}.to"), to)?;
                let len = (to[0] - from[0]).hypot(to[1] - from[1]);
                if len < d.spacing {
                    return Err(c.err(
                        format!("{field}.to"),
                        format!("the segment is {} long, shorter than one spacing", fmt(len)),
                    ));
                }
                if *layers == 0 {
                    return Err(c.err(format!("{field}.layers"), "must be at least 1"));
                }
                // The rows reach `layers` dx to the left of the segment.
                let t = *layers as f64 * d.spacing / len;
                let n = [-(to[1] - from[1]) * t, (to[0] - from[0]) * t];
                let xs = [from[0], to[0], from[0] + n[0], to[0] + n[0]];
                let ys = [from[1], to[1], from[1] + n[1], to[1] + n[1]];
                let lo = [xs, ys].map(|v| v.iter().cloned().fold(f64::MAX, f64::min));
                let hi = [xs, ys].map(|v| v.iter().cloned().fold(f64::MIN, f64::max));
                c.inside(&field, "the segment with its wall layers", &lo, &hi, dom)?;
            }
            Wall::Cylinder {
                center,
                radius,
                layers,
                ..
            } => {
                c.vec(&format!("{field}.center"), center)?;
                c.positive(&format!("{field}.radius"), *radius)?;
                if *layers == 0 {
                    return Err(c.err(format!("{field}.layers"), "must be at least 1"));
                }
                let mut lo = center.clone();
                let mut hi = center.clone();
                for a in 0..2 {
                    lo[a] -= radius;
                    hi[a] += radius;
                }
                c.inside(&field, "the cylinder", &lo, &hi, dom)?;
            }
            Wall::Mesh { layers, .. } | Wall::Polygon { layers, .. } => {
                if *layers == 0 {
                    return Err(c.err(format!("{field}.layers"), "must be at least 1"));
                }
            }
        }
    }
    super::geometry::check(&c, s)?;
    super::bodies::check(&c, s, euler)?;
    let driven: Vec<String> = (s.solids.iter().enumerate())
        .filter(|(_, o)| o.motion().is_some())
        .map(|(i, _)| format!("solids[{i}].motion"))
        .chain(
            (s.walls.iter().enumerate())
                .filter(|(_, w)| w.motion().is_some())
                .map(|(i, _)| format!("walls[{i}].motion")),
        )
        .chain(super::bodies::floating_walls(s).map(|(i, _, _)| format!("walls[{i}].floating")))
        .collect();
    let most = MF_MAX_DRIVEN as usize;
    if driven.len() > most {
        return Err(c.err(
            driven[most].clone(),
            format!(
                "at most {most} driven or floating objects (motion, floating) per scene; \
                 found {} ({})",
                driven.len(),
                driven.join(", ")
            ),
        ));
    }
    clamp_lattice(&c, s)?;
    zones::check(&c, s)?;
    super::open::check(&c, s)?;
    let mut names = std::collections::HashSet::new();
    for (i, m) in s.monitors.iter().enumerate() {
        let field = format!("monitors[{i}]");
        // It names the monitor's file in the output directory (`run_files::monitor_file`).
        if let Some(why) = crate::run_files::stem_problem(&m.name) {
            return Err(c.err(format!("{field}.name"), why));
        }
        // Unique without case: `Drag.csv` is `drag.csv` on a case-insensitive file system.
        if !names.insert(m.name.to_ascii_lowercase()) {
            return Err(c.err(
                format!("{field}.name"),
                format!(
                    "{:?} names an earlier monitor too (compared without case)",
                    m.name
                ),
            ));
        }
        if m.wall >= s.walls.len() {
            return Err(c.err(
                format!("{field}.wall"),
                format!(
                    "wall {} does not exist: the scene has {} wall(s) (indices from 0)",
                    m.wall,
                    s.walls.len()
                ),
            ));
        }
        c.positive(&format!("{field}.interval"), m.interval)?;
        match (m.reference_velocity, m.reference_length) {
            (Some(u), Some(d)) => {
                c.positive(&format!("{field}.reference_velocity"), u)?;
                c.positive(&format!("{field}.reference_length"), d)?;
            }
            (None, None) => {}
            (u, _) => {
                let (given, missing) = match u {
                    Some(_) => ("reference_velocity", "reference_length"),
                    None => ("reference_length", "reference_velocity"),
                };
                return Err(c.err(
                    format!("{field}.{missing}"),
                    format!(
                        "a bluff body's coefficients need both scales: {given} is given, \
                         {missing} is not (give both, or neither for the peak force and \
                         impulse alone)"
                    ),
                ));
            }
        }
    }
    if let Some(fields) = &s.output.fields {
        if fields.contains(&crate::solver::frame::Field::Stress) && s.solids.is_empty() {
            return Err(c.err(
                "output.fields",
                "`stress` is a field of solid particles and the scene has no [[solids]]",
            ));
        }
    }
    if let Some(t) = s.output.checkpoint_interval {
        c.positive("output.checkpoint_interval", t)?;
    }
    probes_and_gauges(&c, s)?;
    if s.fluid_blocks.is_empty() && s.solids.is_empty() && s.walls.is_empty() {
        return Err(c.err(
            "fluid_blocks",
            "the scene has no objects (fluid_blocks, solids or walls)",
        ));
    }
    // Sizes first: a tiny h_factor is a grid too large before it is a step too short.
    sizes(&c, s)?;
    time_step(&c, s)
}

/// What the solver can index, from the estimate (no allocation): the grid's cells in an
/// i32, the particles' ids in a u32.
fn sizes(c: &Ctx, s: &SceneFile) -> R {
    let e = super::estimate::estimate(s);
    let d = &s.discretisation;
    if e.particles > super::estimate::MAX_PARTICLES {
        return Err(c.err(
            "discretisation.spacing",
            format!(
                "the objects would hold up to {:.3e} particles at this spacing, more than the \
                 {:.3e} that particle ids number",
                e.particles,
                super::estimate::MAX_PARTICLES
            ),
        ));
    }
    if e.cells > super::estimate::MAX_CELLS {
        // The field to blame: an unusual h_factor, else the domain's size.
        let field = if d.h_factor < 0.5 {
            "discretisation.h_factor"
        } else {
            "domain.max"
        };
        return Err(c.err(
            field,
            format!(
                "the neighbour grid would have {:.3e} cells (the domain over h = h_factor x \
                 spacing = {} on each axis), more than the {:.3e} it can index: a larger \
                 spacing or h_factor, or a smaller domain",
                e.cells,
                fmt(d.h()),
                super::estimate::MAX_CELLS
            ),
        ));
    }
    if e.cells > super::estimate::SPARSE_GRID_CELLS
        && e.cells > super::estimate::MAX_CELLS_PER_PARTICLE * e.particles
    {
        return Err(c.err(
            "domain.max",
            format!(
                "the neighbour grid spans the whole domain: {:.3e} cells (about {:.1} GB, \
                 cleared at every step) for at most {:.3e} particles, over {} cells each: a \
                 domain closer to where the particles can go, or a larger spacing",
                e.cells,
                e.grid_host_bytes() / 1e9,
                e.particles,
                super::estimate::MAX_CELLS_PER_PARTICLE
            ),
        ));
    }
    Ok(())
}

/// The shortest step a run may take, as a fraction of its end time: a step shorter than
/// this would take over 1e9 steps; it is a unit error (a modulus in MPa given in Pa, a
/// sound speed in mm/s, a fixed dt in the wrong unit), not a run to start. (A step that
/// collapses during the run stops it at `step::DT_FLOOR`.)
pub const MIN_STEP_FRACTION: f64 = 1e-9;

/// The step at rest must be at least `MIN_STEP_FRACTION` of `time.end`: the scene's fixed
/// `time.dt`, or eq. (19)'s acoustic limit dt = courant h / c with the fluid's c0 and, with
/// `[[solids]]`, the solid's longitudinal speed sqrt(c_s^2 + 4 G / (3 rho0_s))
/// (`SphParams::sound_speed`). The error names the field that sets the step (the fixed dt,
/// the fluid's sound speed, or the larger of the solid's two terms), the step and the
/// number of steps.
fn time_step(c: &Ctx, s: &SceneFile) -> R {
    let end = s.time.end;
    let h = s.discretisation.h(); // [L]
    let (dt, field, what) = if let Some(dt) = s.time.dt {
        (dt, "time.dt", format!("the fixed time step {dt}"))
    } else {
        let fluid = s.fluid.sound_speed; // [L/T]
        let mut speed = (
            fluid,
            "fluid.sound_speed",
            format!("the fluid's sound speed {fluid}"),
        );
        if let (Some(m), false) = (&s.solid, s.solids.is_empty()) {
            let bulk = m.sound_speed * m.sound_speed; // [L^2 T^-2]
            let shear = 4.0 / 3.0 * m.shear_modulus / m.density; // [L^2 T^-2]
            let solid = (bulk + shear).sqrt(); // [L/T]
            if solid > speed.0 {
                speed = if bulk >= shear {
                    (
                        solid,
                        "solid.sound_speed",
                        format!("the solid's sound speed {}", m.sound_speed),
                    )
                } else {
                    (
                        solid,
                        "solid.shear_modulus",
                        format!(
                            "the shear modulus {} (with density {})",
                            m.shear_modulus, m.density
                        ),
                    )
                };
                speed.2 = format!("{} (a longitudinal wave speed of {solid:.3e})", speed.2);
            }
        }
        let courant = s.time.courant_number();
        let dt = courant * h / speed.0; // [T], eq. (19) at rest
        let how = format!(
            "{}: the time step (eq. 19: courant {courant} x h {h:.3e} / {:.3e})",
            speed.2, speed.0
        );
        (dt, speed.1, how)
    };
    if dt.is_finite() && dt >= MIN_STEP_FRACTION * end {
        return Ok(());
    }
    Err(c.err(
        field,
        format!(
            "{what} would be {dt:.3e}, below {MIN_STEP_FRACTION:e} of the end time {end}: \
             {:.3e} steps. Check the units",
            (end / dt).ceil()
        ),
    ))
}

/// `[[probes]]` and `[[gauges]]`: names (plain, unique within each table), points inside
/// the domain, positive intervals and steps, known and distinct fields, and walls in the
/// interpolation only where they carry density and pressure (dynamic walls).
fn probes_and_gauges(c: &Ctx, s: &SceneFile) -> R {
    let name_ok = |field: &str, name: &str, seen: &mut std::collections::HashSet<String>| {
        let plain = !name.is_empty()
            && name
                .chars()
                .all(|ch| ch.is_ascii_alphanumeric() || ch == '-' || ch == '_');
        if !plain {
            return Err(c.err(
                format!("{field}.name"),
                format!(
                    "must be a non-empty name of letters, digits, '-' and '_' (it is a CSV \
                     value), found {name:?}"
                ),
            ));
        }
        if !seen.insert(name.to_string()) {
            return Err(c.err(
                format!("{field}.name"),
                format!("{name:?} names an earlier entry of the same table too"),
            ));
        }
        Ok(())
    };
    let point = |field: &str, x: &[f64]| -> R {
        c.vec(field, x)?;
        let d = &s.domain;
        for a in 0..c.dim {
            let tol = 1e-9 * (d.max[a] - d.min[a]);
            if x[a] < d.min[a] - tol || x[a] > d.max[a] + tol {
                return Err(c.err(
                    field,
                    format!(
                        "the point {x:?} is outside the domain: x[{a}] = {} is not within \
                         [domain.min[{a}], domain.max[{a}]] = [{}, {}]",
                        fmt(x[a]),
                        d.min[a],
                        d.max[a]
                    ),
                ));
            }
        }
        Ok(())
    };
    let lj_walls = s
        .boundary
        .as_ref()
        .is_some_and(|b| b.wall_coupling == WallCoupling::LennardJonesOnly);
    let mut names = std::collections::HashSet::new();
    for (i, pr) in s.probes.iter().enumerate() {
        let field = format!("probes[{i}]");
        name_ok(&field, &pr.name, &mut names)?;
        if pr.points.is_empty() {
            return Err(c.err(format!("{field}.points"), "needs at least one point"));
        }
        for (k, x) in pr.points.iter().enumerate() {
            point(&format!("{field}.points[{k}]"), x)?;
        }
        c.positive(&format!("{field}.interval"), pr.interval)?;
        if pr.fields.is_empty() {
            return Err(c.err(
                format!("{field}.fields"),
                "needs at least one of \"pressure\", \"velocity\", \"density\"",
            ));
        }
        for (k, f) in pr.fields.iter().enumerate() {
            if pr.fields[..k].contains(f) {
                return Err(c.err(
                    format!("{field}.fields[{k}]"),
                    format!("{:?} is listed twice", f.name()),
                ));
            }
        }
        if pr.walls && lj_walls {
            return Err(c.err(
                format!("{field}.walls"),
                "wall particles carry no density or pressure with [boundary] wall_coupling = \
                 \"lennard-jones-only\"; interpolate over the fluid alone (walls = false)",
            ));
        }
    }
    let mut names = std::collections::HashSet::new();
    for (i, g) in s.gauges.iter().enumerate() {
        let field = format!("gauges[{i}]");
        name_ok(&field, &g.name, &mut names)?;
        point(&format!("{field}.start"), &g.start)?;
        point(&format!("{field}.end"), &g.end)?;
        let len = (0..c.dim)
            .map(|a| (g.end[a] - g.start[a]).powi(2))
            .sum::<f64>()
            .sqrt();
        if len <= 0.0 {
            return Err(c.err(
                format!("{field}.end"),
                "the line has no length: end = start",
            ));
        }
        c.positive(&format!("{field}.interval"), g.interval)?;
        if let Some(step) = g.step {
            c.positive(&format!("{field}.step"), step)?;
        }
        let step = g.step.unwrap_or(0.5 * s.discretisation.spacing);
        if len / step > MAX_GAUGE_POINTS as f64 {
            return Err(c.err(
                format!("{field}.step"),
                format!(
                    "the line is {} long: {} steps of {} is more than {MAX_GAUGE_POINTS} points",
                    fmt(len),
                    (len / step).ceil(),
                    fmt(step)
                ),
            ));
        }
    }
    Ok(())
}

/// A clamp (a driven solid box) bonded to a solid box it touches must share that box's
/// particle lattice (`min + (i + 0.5) dx`): off it, the rows at the joint are dropped or
/// crowded (`generate.rs` keeps particles 0.5 dx apart) and the bond has a gap or a seam.
fn clamp_lattice(c: &Ctx, s: &SceneFile) -> R {
    let dx = s.discretisation.spacing;
    let boxes = |driven: bool| {
        (s.solids.iter().enumerate()).filter_map(move |(i, o)| match o {
            SolidObject::Box { min, max, .. } if o.motion().is_some() == driven => {
                Some((i, min, max))
            }
            _ => None,
        })
    };
    for (ci, cmin, cmax) in boxes(true) {
        for (oi, omin, omax) in boxes(false) {
            // Touching: the boxes overlap or meet within one spacing on every axis.
            let touch = (0..c.dim).all(|a| cmin[a] <= omax[a] + dx && omin[a] <= cmax[a] + dx);
            if !touch {
                continue;
            }
            for a in 0..c.dim {
                let k = (cmin[a] - omin[a]) / dx;
                if (k - k.round()).abs() > 1e-6 {
                    return Err(c.err(
                        format!("solids[{ci}].min"),
                        format!(
                            "a clamp (a solid with motion) is bonded to the solid it touches, \
                             solids[{oi}], and must sit on its particle lattice: min[{a}] differs \
                             by {}, not a whole number of spacings ({}), so the joint would have \
                             a gap or a seam",
                            fmt(cmin[a] - omin[a]),
                            fmt(dx)
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}
