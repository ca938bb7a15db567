//! `[[open_boundaries]]`: the file's table (`OpenBoundary`, `OpenKind`: `format` re-exports
//! them), their checks, their scene groups and their `MfOpen` parameters (`physics::open`
//! for what they do).

use super::ctx::{fmt, Ctx, R};
use serde::{Deserialize, Serialize};

use super::format::is_zero;
use super::scheme::{IntegratorChoice, SceneFile, SolidFormulation, WallCoupling};
use crate::physics::params::{MfOpen, SphParams, MF_MAX_OPEN, MF_OPEN_INLET, MF_OPEN_OUTLET};

/// What an open boundary is (`kind` of `[[open_boundaries]]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OpenKind {
    /// Fluid enters at a prescribed velocity: its buffer's particles join the fluid as they
    /// cross the plane, and new ones take their place behind.
    Inlet,
    /// Fluid leaves: what enters its buffer coasts on at the velocity it came with and is
    /// removed at the buffer's far side.
    Outlet,
}

/// An inlet's velocity across its face (`profile` of `[[open_boundaries]]`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OpenProfile {
    /// The same velocity everywhere on the face.
    #[default]
    Uniform,
    /// Plane Poiseuille flow's parabola, 6 eta (1 - eta) across each side of the face that is
    /// not periodic (eta from 0 to 1 across the buffer box), zero at the box's sides and 1.5
    /// times `velocity` at its middle: `velocity` is the mean, the flux `velocity` times the
    /// face's area. Across two sides (a 3D duct) the product of the two parabolas, not the
    /// duct's series solution (its mean is still `velocity`).
    Parabolic,
}

/// An inlet or outlet (`[[open_boundaries]]`, `physics::open`): a buffer box whose face on
/// the fluid's side is the boundary, normal to an axis. The box is `min`..`max`; `normal`
/// (a unit vector along an axis) points from the buffer into the fluid, and the box's
/// extent along it is the buffer's depth (at least the kernel's support, 2h).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OpenBoundary {
    pub kind: OpenKind,
    /// \[L\] the buffer box's corners, `dimension` numbers each.
    pub min: Vec<f64>,
    pub max: Vec<f64>,
    /// \[-\] the inward unit normal, along an axis: `[1.0, 0.0]` for fluid that flows in
    /// the +x direction out of an inlet at the box's +x face (or into an outlet at its -x
    /// face, `[-1.0, 0.0]` there).
    pub normal: Vec<f64>,
    /// \[L/T\] an inlet's velocity, `dimension` numbers, pointing into the fluid (along
    /// `normal`, or at an angle to it); not for an outlet.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<Vec<f64>>,
    /// \[T\] an inlet's smooth start: its velocity r(t) `velocity`, r = (1 - cos(pi t /
    /// ramp)) / 2 up to `ramp`, then 1; 0 (the default): at full velocity from the start.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub ramp: f64,
    /// An inlet's velocity across its face: `"uniform"` (the default) or `"parabolic"`
    /// (`OpenProfile`); not for an outlet.
    #[serde(default, skip_serializing_if = "is_uniform")]
    pub profile: OpenProfile,
    /// An inlet's velocity over time: `velocity` times the `scale` column of a CSV file
    /// (`t,scale` rows, `motion_series`; a pulsing or a tidal inflow), as well as the ramp.
    /// Default none: scale 1. Its `pivot` and `axis` are a motion's: not for an inlet.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub series: Option<Box<super::format::Series>>,
}

fn is_uniform(p: &OpenProfile) -> bool {
    *p == OpenProfile::Uniform
}

/// The axes across open boundary `o`'s face that its profile spans, as `MfOpen::profile_axes`'
/// bits: every axis of the scene's `dim` but the normal's and the periodic ones, under a
/// parabolic profile; none under a uniform one.
fn profile_axes(s: &SceneFile, o: &OpenBoundary) -> i32 {
    if o.profile == OpenProfile::Uniform {
        return 0;
    }
    let (axis, _) = o.axis_sign().expect("validated");
    let periodic = |a: usize| s.domain.periodic.as_ref().is_some_and(|p| p[a]);
    (0..s.dimension as usize)
        .filter(|&a| a != axis && !periodic(a))
        .fold(0, |m, a| m | 1 << a)
}

impl OpenBoundary {
    /// The normal's axis and sign, where it is a unit vector along an axis.
    pub fn axis_sign(&self) -> Option<(usize, f64)> {
        let nonzero: Vec<usize> = (0..self.normal.len())
            .filter(|&a| self.normal[a] != 0.0)
            .collect();
        match nonzero[..] {
            [a] if self.normal[a].abs() == 1.0 => Some((a, self.normal[a])),
            _ => None,
        }
    }
}

/// The scene group of open boundary `b`'s buffer; its `through` group is the next one.
/// After every object's (fluid blocks, solids, walls: `generate`'s numbering).
pub(crate) fn buffer_group(s: &SceneFile, b: usize) -> u32 {
    (s.fluid_blocks.len() + s.solids.len() + s.walls.len() + 2 * b) as u32
}

/// The inward normal's axis and sign, the plane's coordinate on it and the depth \[L\].
fn plane(o: &OpenBoundary) -> (usize, f64, f64, f64) {
    let (a, sign) = o.axis_sign().expect("validated");
    let plane = if sign > 0.0 { o.max[a] } else { o.min[a] };
    (a, sign, plane, o.max[a] - o.min[a])
}

pub(super) fn check(c: &Ctx, s: &SceneFile) -> R {
    let dim = c.dim;
    let n = s.open_boundaries.len();
    if n > MF_MAX_OPEN as usize {
        return Err(c.err(
            "open_boundaries",
            format!("{n} open boundaries: at most {MF_MAX_OPEN} per scene"),
        ));
    }
    if n == 0 {
        return Ok(());
    }
    if s.time.integrator == IntegratorChoice::Euler {
        return Err(c.err(
            "open_boundaries",
            "open boundaries need a kick before the drift (time.integrator \"leapfrog\" or \
             \"symplectic-euler\"), not the forward Euler",
        ));
    }
    if s.walls.iter().any(|w| w.floating().is_some()) {
        return Err(c.err(
            "open_boundaries",
            "open boundaries and floating bodies in one scene are not supported yet",
        ));
    }
    if !s.solids.is_empty()
        && s.solid.as_ref().map(|m| m.formulation) == Some(SolidFormulation::TotalLagrangian)
    {
        return Err(c.err(
            "open_boundaries",
            "open boundaries and total-Lagrangian solids in one scene are not supported yet",
        ));
    }
    // Dynamic walls beside an inlet's buffer see its particles move off its back face:
    // their continuity density drains (the open nozzle's blew up at t = 0.29) unless held.
    if s.boundary
        .as_ref()
        .is_some_and(|m| m.wall_coupling == WallCoupling::Dynamic && !m.wall_density_floor)
        && !s.walls.is_empty()
    {
        return Err(c.err(
            "boundary.wall_density_floor",
            "open boundaries with dynamic walls need wall_density_floor = true: the walls \
             beside an inlet's buffer see its particles move off its back face, and their \
             density drains until the fluid next to them tears",
        ));
    }
    let support = 2.0 * s.discretisation.h();
    for (b, o) in s.open_boundaries.iter().enumerate() {
        let f = |k: &str| format!("open_boundaries[{b}].{k}");
        c.corners(&f("max"), &o.min, &o.max)?;
        c.inside(&f("min"), "the buffer box", &o.min, &o.max, &s.domain)?;
        c.vec(&f("normal"), &o.normal)?;
        let Some((a, sign)) = o.axis_sign() else {
            return Err(c.err(
                f("normal"),
                format!(
                    "must be a unit vector along an axis ([1, 0], [0, -1], ...), found {:?}: \
                     planes at an angle are not supported yet",
                    o.normal
                ),
            ));
        };
        if s.domain.periodic.as_ref().is_some_and(|p| p[a]) {
            return Err(c.err(
                f("normal"),
                format!("axis {a} is periodic: an open boundary needs a closed one"),
            ));
        }
        let depth = o.max[a] - o.min[a];
        if depth < support * (1.0 - 1e-9) {
            return Err(c.err(
                f("max"),
                format!(
                    "the buffer is {} deep along the normal, less than the kernel's support \
                     2h = {}: the fluid next to it would miss neighbours",
                    fmt(depth),
                    fmt(support)
                ),
            ));
        }
        // An outlet's particles are removed a step after they pass its far face: the
        // domain reaches on beyond it, so that none is outside the domain meanwhile.
        let far = if sign > 0.0 { o.min[a] } else { o.max[a] };
        let room = if sign > 0.0 {
            far - s.domain.min[a]
        } else {
            s.domain.max[a] - far
        };
        if o.kind == OpenKind::Outlet && room < support * (1.0 - 1e-9) {
            return Err(c.err(
                f(if sign > 0.0 { "min" } else { "max" }),
                format!(
                    "the outlet's far face at {} is {} from the domain's edge: the domain must \
                     reach at least 2h = {} beyond it, where the particles that leave are \
                     removed",
                    fmt(far),
                    fmt(room),
                    fmt(support)
                ),
            ));
        }
        match (o.kind, &o.velocity) {
            (OpenKind::Inlet, None) => {
                return Err(c.err(f("velocity"), "an inlet needs its velocity"));
            }
            (OpenKind::Inlet, Some(v)) => {
                c.vec(&f("velocity"), v)?;
                if sign * v[a] <= 0.0 {
                    return Err(c.err(
                        f("velocity"),
                        format!(
                            "{v:?} does not point into the fluid (along the normal {:?})",
                            o.normal
                        ),
                    ));
                }
                c.non_negative(&f("ramp"), o.ramp)?;
                if let Some(r) = o.series.as_deref() {
                    check_series(c, &f("series"), r, s.time.end)?;
                }
                if o.profile == OpenProfile::Parabolic && profile_axes(s, o) == 0 {
                    return Err(c.err(
                        f("profile"),
                        "a parabolic profile spans the face's sides that are not periodic, \
                         and every side of this one is periodic: give \"uniform\"",
                    ));
                }
            }
            (OpenKind::Outlet, Some(_)) => {
                return Err(c.err(
                    f("velocity"),
                    "an outlet takes the velocity the fluid brings: give none",
                ));
            }
            (OpenKind::Outlet, None) if o.ramp != 0.0 => {
                return Err(c.err(f("ramp"), "only an inlet has a ramp"));
            }
            (OpenKind::Outlet, None) if o.series.is_some() => {
                return Err(c.err(
                    f("series"),
                    "only an inlet has a series (of its velocity's scale)",
                ));
            }
            (OpenKind::Outlet, None) if o.profile != OpenProfile::Uniform => {
                return Err(c.err(
                    f("profile"),
                    "only an inlet has a velocity profile: an outlet takes the fluid's",
                ));
            }
            (OpenKind::Outlet, None) => {}
        }
        for (e, q) in s.open_boundaries[..b].iter().enumerate() {
            let overlap = (0..dim).all(|k| o.min[k] < q.max[k] && q.min[k] < o.max[k]);
            if overlap {
                return Err(c.err(
                    f("min"),
                    format!("the buffer box overlaps open_boundaries[{e}]'s"),
                ));
            }
        }
    }
    Ok(())
}

/// An inlet's `series` at `f`: read, reaching the run's `end` \[T\], without a motion's
/// `pivot` and `axis`.
fn check_series(c: &Ctx, f: &str, r: &super::format::Series, end: f64) -> R {
    if r.pivot.is_some() || r.axis.is_some() {
        return Err(c.err(
            f,
            "pivot and axis turn a driven object: an inlet's series scales its velocity",
        ));
    }
    super::motion_series::covering(c, f, r, end).map(|_| ())
}

/// `open_count` and `open` from the scene; an inlet's series' knots after the motions'
/// in `Setup::motion_series` (`motion_series::table`).
pub(super) fn write_params(s: &SceneFile, p: &mut SphParams) {
    p.open_count = s.open_boundaries.len().min(MF_MAX_OPEN as usize) as i32;
    let mut first = super::motion_series::motion_knots(s) as i32;
    for (b, o) in s
        .open_boundaries
        .iter()
        .take(MF_MAX_OPEN as usize)
        .enumerate()
    {
        let (axis, sign, plane, depth) = plane(o);
        let group = buffer_group(s, b) as i32;
        let mut m = MfOpen {
            kind: match o.kind {
                OpenKind::Inlet => MF_OPEN_INLET,
                OpenKind::Outlet => MF_OPEN_OUTLET,
            } as i32,
            group,
            through: group + 1,
            axis: axis as i32,
            sign: sign as f32,
            plane: plane as f32,
            depth: depth as f32,
            ramp: o.ramp as f32,
            profile_axes: profile_axes(s, o),
            ..Default::default()
        };
        if let Some(r) = o.series.as_deref() {
            m.series_count = r.loaded.get().map_or(0, |k| k.count() as i32);
            m.series_cubic = (r.interpolation == super::format::Interpolation::Cubic) as i32;
            m.series_first = first;
            first += m.series_count;
        }
        for k in 0..s.dimension as usize {
            m.lo[k] = o.min[k] as f32;
            m.hi[k] = o.max[k] as f32;
            m.velocity[k] = o.velocity.as_ref().map_or(0.0, |v| v[k] as f32);
        }
        p.open[b] = m;
    }
}
