//! A driven object's `motion` (`format::Motion`): what the solver makes of it (`MfMotion`,
//! `physics::motion`) and the checks serde cannot make (lengths against `dimension`,
//! positive periods, an axis in 3D, a law that moves something, a series that covers the run,
//! and a kick before the drift for anything but a steady velocity).

use glam::Vec3A;

use super::ctx::Ctx;
use super::format::{Interpolation, Motion, MotionLaw, Paddle};
use super::SceneError;
use crate::physics::dim::D3;
use crate::physics::params::MfMotion;

impl Motion {
    /// The solver's form of this motion for scene group `group` in a `dim`-D scene (a 2D
    /// scene turns about z) under gravity `g` \[L/T^2\] (its magnitude: a wave maker's
    /// stroke, `scene::wave`); a series' knots first in the table (`series_first` 0: the
    /// scene's parameters offset it). Assumes `check` passed.
    pub fn params(&self, group: u32, dim: usize, g: f64) -> MfMotion {
        let v3 = |v: &[f64]| {
            let mut a = [0.0f32; 3];
            for (o, x) in a.iter_mut().zip(v) {
                *o = *x as f32;
            }
            a
        };
        let mut m = MfMotion {
            group: group as i32,
            axis: [0.0, 0.0, 1.0],
            ..Default::default()
        };
        match self {
            Motion::Velocity(v) => m.velocity = v3(v),
            Motion::Law(l) => {
                if let Some(v) = &l.velocity {
                    m.velocity = v3(v);
                }
                if let Some(o) = &l.oscillation {
                    m.amplitude = v3(&o.amplitude);
                    (m.period, m.phase) = (o.period as f32, o.phase as f32);
                }
                if let Some(r) = &l.rotation {
                    m.pivot = v3(&r.pivot);
                    if let (3, Some(a)) = (dim, &r.axis) {
                        let len = a.iter().map(|x| x * x).sum::<f64>().sqrt();
                        m.axis = v3(&a.iter().map(|x| x / len).collect::<Vec<_>>());
                    }
                    m.rate = r.rate as f32;
                    m.angle = r.amplitude as f32;
                    (m.angle_period, m.angle_phase) = (r.period as f32, r.phase as f32);
                }
                if let Some(w) = l.wave.as_ref().filter(|w| w.spectrum.is_some()) {
                    // An irregular sea: the paddle follows its record (`wave_spectrum`).
                    if let Some(k) = w.made.get() {
                        m.series_count = k.count() as i32;
                    }
                    m.series_cubic = 1;
                    if let Some(h) = &w.hinge {
                        m.pivot = v3(h);
                    }
                } else if let Some(w) = &l.wave {
                    // A piston moves S / 2 along x; a flap turns about its hinge so that its
                    // face at the still-water level moves as much (clockwise about z: the
                    // top towards +x first).
                    let s = w.paddling(g).stroke;
                    match (w.paddle, &w.hinge) {
                        (Paddle::Flap, Some(h)) => {
                            m.pivot = v3(h);
                            m.angle = -(0.5 * s / w.depth).atan() as f32;
                            (m.angle_period, m.angle_phase) = (w.period as f32, w.phase as f32);
                        }
                        _ => {
                            m.amplitude = [(0.5 * s) as f32, 0.0, 0.0];
                            (m.period, m.phase) = (w.period as f32, w.phase as f32);
                        }
                    }
                }
                if let Some(r) = &l.series {
                    if let Some(k) = r.loaded.get() {
                        m.series_count = k.count() as i32;
                    }
                    m.series_cubic = (r.interpolation == Interpolation::Cubic) as i32;
                    if let Some(p) = &r.pivot {
                        m.pivot = v3(p);
                    }
                    if let (3, Some(a)) = (dim, &r.axis) {
                        let len = a.iter().map(|x| x * x).sum::<f64>().sqrt();
                        m.axis = v3(&a.iter().map(|x| x / len).collect::<Vec<_>>());
                    }
                }
                m.ramp = l.ramp as f32;
            }
        }
        m
    }

    /// The knots it follows besides its laws (`motion_series::knots_of`: a series file's,
    /// an irregular sea's), empty where it has none.
    pub fn series_knots(&self) -> &[f64] {
        super::motion_series::knots_of(self).map_or(&[], |k| &k.knots)
    }

    /// [L/T] The velocity at t = 0 of the object's particle at `x` (a ramped motion starts
    /// from rest): what generation gives it, and what the first kick would.
    pub fn start_velocity(&self, x: [f64; 3], dim: usize, g: f64) -> [f64; 3] {
        let m = self.params(0, dim, g);
        let x = Vec3A::new(x[0] as f32, x[1] as f32, x[2] as f32);
        let v = m.velocity_at::<D3>(self.series_knots(), x, 0.0, 0.0);
        [v.x as f64, v.y as f64, v.z as f64]
    }
}

/// The checks of the `motion` at `field` (`walls[2].motion`); `euler`: the scene integrates
/// with the paper's forward Euler, which has no kick before the drift (a driven object
/// moves steadily only, see `sph_drift_kick`); `end` \[T\]: the run's end, which a series
/// must reach.
pub(super) fn check(
    c: &Ctx,
    field: &str,
    m: &Motion,
    euler: bool,
    end: f64,
) -> Result<(), SceneError> {
    let err = |f: String, why: &str| Err(c.err(f, why));
    let finite = |f: String, x: f64| {
        if x.is_finite() {
            Ok(())
        } else {
            err(f, "must be a finite number")
        }
    };
    let l: &MotionLaw = match m {
        Motion::Velocity(v) => return c.vec(field, v),
        Motion::Law(l) => l,
    };
    if l.velocity.is_none()
        && l.oscillation.is_none()
        && l.rotation.is_none()
        && l.wave.is_none()
        && l.series.is_none()
    {
        return err(
            field.to_string(),
            "the table gives no velocity, oscillation, rotation, wave or series: nothing moves \
             (a clamp is motion = [0, 0])",
        );
    }
    if l.wave.is_some()
        && (l.velocity.is_some()
            || l.oscillation.is_some()
            || l.rotation.is_some()
            || l.series.is_some())
    {
        return err(
            format!("{field}.wave"),
            "a wave maker's paddle follows its wave alone: leave out velocity, oscillation, \
             rotation and series",
        );
    }
    if let Some(r) = &l.series {
        check_series(c, &format!("{field}.series"), r, l.rotation.is_some(), end)?;
    }
    if let Some(v) = &l.velocity {
        c.vec(&format!("{field}.velocity"), v)?;
    }
    if let Some(o) = &l.oscillation {
        let f = format!("{field}.oscillation");
        c.vec(&format!("{f}.amplitude"), &o.amplitude)?;
        if !(o.period > 0.0 && o.period.is_finite()) {
            return err(format!("{f}.period"), "must be a positive number [T]");
        }
        finite(format!("{f}.phase"), o.phase)?;
    }
    if let Some(r) = &l.rotation {
        let f = format!("{field}.rotation");
        c.vec(&format!("{f}.pivot"), &r.pivot)?;
        check_axis(c, &f, r.axis.as_deref())?;
        finite(format!("{f}.rate"), r.rate)?;
        finite(format!("{f}.amplitude"), r.amplitude)?;
        finite(format!("{f}.phase"), r.phase)?;
        if r.rate == 0.0 && r.amplitude == 0.0 {
            return err(
                f,
                "the rotation turns nothing: give rate [rad/T] or amplitude [rad] with period",
            );
        }
        if r.amplitude != 0.0 && !(r.period > 0.0 && r.period.is_finite()) {
            return err(
                format!("{f}.period"),
                "an oscillating angle (amplitude) needs a positive period [T]",
            );
        }
    }
    if !(l.ramp >= 0.0 && l.ramp.is_finite()) {
        return err(format!("{field}.ramp"), "must be a number >= 0 [T]");
    }
    // (Any gravity: the wave's stroke is checked in `wave::check`.)
    // (An irregular sea's record is made after the checks: a wave is never steady.)
    let steady = m.params(0, c.dim, 9.81).steady() && l.wave.is_none();
    if euler && !steady {
        return err(
            field.to_string(),
            "an oscillation, a rotation or a ramp needs a kick before the drift \
             (time.integrator \"symplectic-euler\" or \"leapfrog\"): under the forward Euler \
             a driven object moves at a steady velocity only",
        );
    }
    Ok(())
}

/// A turn's `axis` at `f` (a rotation's, a series'): none in 2D (about z), three finite
/// numbers with a direction in 3D.
fn check_axis(c: &Ctx, f: &str, axis: Option<&[f64]>) -> Result<(), SceneError> {
    let err = |why: &str| Err(c.err(format!("{f}.axis"), why));
    match (c.dim, axis) {
        (2, Some(_)) => err("a 2D scene turns about z: leave out axis"),
        (3, None) => err("a 3D rotation needs its axis, e.g. axis = [0, 0, 1]"),
        (3, Some(a)) => {
            if a.len() != 3 {
                return err("expected 3 numbers");
            }
            if let Some(i) = a.iter().position(|x| !x.is_finite()) {
                return Err(c.err(format!("{f}.axis[{i}]"), "must be a finite number"));
            }
            if a.iter().all(|&x| x == 0.0) {
                return err("the axis has no direction");
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

/// A `series` at `f`: read (`motion_series::load_all`), reaching the run's `end` \[T\];
/// with an `angle` column, its pivot (and in 3D its axis), and no `rotation` beside it
/// (`rotated`: the object turns about one pivot); without one, neither pivot nor axis.
fn check_series(
    c: &Ctx,
    f: &str,
    r: &super::format::Series,
    rotated: bool,
    end: f64,
) -> Result<(), SceneError> {
    let k = super::motion_series::covering(c, f, r, end)?;
    if !k.turns {
        if r.pivot.is_some() || r.axis.is_some() {
            return Err(c.err(
                f,
                "pivot and axis are the angle column's: the file has none (leave them out, or \
                 add an angle column)",
            ));
        }
        return Ok(());
    }
    if rotated {
        return Err(c.err(
            f,
            "the series' angle column and rotation both turn the object, about one pivot: \
             put the turn in one of them",
        ));
    }
    match &r.pivot {
        None => Err(c.err(
            format!("{f}.pivot"),
            "the angle column turns the object about a pivot: give it (the centre of the turn \
             at t = 0)",
        )),
        Some(p) => c.vec(&format!("{f}.pivot"), p),
    }?;
    check_axis(c, f, r.axis.as_deref())
}
