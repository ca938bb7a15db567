//! A driven object's `motion` (`format::Motion`): what the solver makes of it (`MfMotion`,
//! `physics::motion`) and the checks serde cannot make (lengths against `dimension`,
//! positive periods, an axis in 3D, a law that moves something, and a kick before the drift
//! for anything but a steady velocity).

use glam::Vec3A;

use super::ctx::Ctx;
use super::format::{Motion, MotionLaw, Paddle};
use super::SceneError;
use crate::physics::dim::D3;
use crate::physics::params::MfMotion;

impl Motion {
    /// The solver's form of this motion for scene group `group` in a `dim`-D scene (a 2D
    /// scene turns about z) under gravity `g` \[L/T^2\] (its magnitude: a wave maker's
    /// stroke, `scene::wave`). Assumes `check` passed.
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
                if let Some(w) = &l.wave {
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
                m.ramp = l.ramp as f32;
            }
        }
        m
    }

    /// [L/T] The velocity at t = 0 of the object's particle at `x` (a ramped motion starts
    /// from rest): what generation gives it, and what the first kick would.
    pub fn start_velocity(&self, x: [f64; 3], dim: usize, g: f64) -> [f64; 3] {
        let m = self.params(0, dim, g);
        let x = Vec3A::new(x[0] as f32, x[1] as f32, x[2] as f32);
        let v = m.velocity_at::<D3>(x, 0.0, 0.0);
        [v.x as f64, v.y as f64, v.z as f64]
    }
}

/// The checks of the `motion` at `field` (`walls[2].motion`); `euler`: the scene integrates
/// with the paper's forward Euler, which has no kick before the drift (a driven object
/// moves steadily only, see `sph_drift_kick`).
pub(super) fn check(c: &Ctx, field: &str, m: &Motion, euler: bool) -> Result<(), SceneError> {
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
    if l.velocity.is_none() && l.oscillation.is_none() && l.rotation.is_none() && l.wave.is_none() {
        return err(
            field.to_string(),
            "the table gives no velocity, oscillation, rotation or wave: nothing moves (a \
             clamp is motion = [0, 0])",
        );
    }
    if l.wave.is_some() && (l.velocity.is_some() || l.oscillation.is_some() || l.rotation.is_some())
    {
        return err(
            format!("{field}.wave"),
            "a wave maker's paddle follows its wave alone: leave out velocity, oscillation and \
             rotation",
        );
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
        match (c.dim, &r.axis) {
            (2, Some(_)) => {
                return err(
                    format!("{f}.axis"),
                    "a 2D scene turns about z: leave out axis",
                )
            }
            (3, None) => {
                return err(
                    format!("{f}.axis"),
                    "a 3D rotation needs its axis, e.g. axis = [0, 0, 1]",
                )
            }
            (3, Some(a)) => {
                if a.len() != 3 {
                    return err(format!("{f}.axis"), "expected 3 numbers");
                }
                for (i, &x) in a.iter().enumerate() {
                    finite(format!("{f}.axis[{i}]"), x)?;
                }
                if a.iter().all(|&x| x == 0.0) {
                    return err(format!("{f}.axis"), "the axis has no direction");
                }
            }
            _ => {}
        }
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
    let steady = m.params(0, c.dim, 9.81).steady();
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
