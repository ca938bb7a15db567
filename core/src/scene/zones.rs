//! The scene's zones along an axis (`[inflow]`, `[damping_zone]`): the checks that their axis
//! exists, that they lie in the domain and have a length, and that the integrator has the
//! kick they act in.

use super::ctx::Ctx;
use super::scheme::{IntegratorChoice, SceneFile};
use super::SceneError;

/// The inflow band's and the damping zone's checks.
pub(super) fn check(c: &Ctx, s: &SceneFile) -> Result<(), SceneError> {
    let (dim, dom) = (c.dim, &s.domain);
    let euler = s.time.integrator == IntegratorChoice::Euler;
    if let Some(b) = &s.inflow {
        let a = b.axis.index();
        if a >= dim {
            return Err(c.err(
                "inflow.axis",
                format!("axis {a} does not exist in a {dim}D scene"),
            ));
        }
        if !(b.min.is_finite() && b.max.is_finite() && b.min < b.max) {
            return Err(c.err(
                "inflow.max",
                format!(
                    "the band needs min < max, found min = {}, max = {}",
                    b.min, b.max
                ),
            ));
        }
        if b.min < dom.min[a] || b.max > dom.max[a] {
            return Err(c.err(
                "inflow",
                format!(
                    "the band [{}, {}] reaches outside the domain [{}, {}] on axis {a}",
                    b.min, b.max, dom.min[a], dom.max[a]
                ),
            ));
        }
        c.vec("inflow.velocity", &b.velocity)?;
        c.non_negative("inflow.ramp", b.ramp)?;
        if b.ramp > 0.0 && s.time.integrator == IntegratorChoice::Euler {
            return Err(c.err(
                "inflow.ramp",
                "a ramped start needs a kick before the drift (time.integrator \
                 \"symplectic-euler\" or \"leapfrog\"): the ramp's velocity is set at the \
                 kick's time, which the forward Euler's fused drift-kick advances in the same \
                 pass on the GPU",
            ));
        }
    }
    if let Some(z) = &s.damping_zone {
        let a = z.axis.index();
        if a >= dim {
            return Err(c.err(
                "damping_zone.axis",
                format!("axis {a} does not exist in a {dim}D scene"),
            ));
        }
        for (key, x) in [("start", z.start), ("end", z.end)] {
            if !(x.is_finite() && x >= dom.min[a] && x <= dom.max[a]) {
                return Err(c.err(
                    format!("damping_zone.{key}"),
                    format!(
                        "{x} is outside the domain [{}, {}] on axis {a}",
                        dom.min[a], dom.max[a]
                    ),
                ));
            }
        }
        if z.start == z.end {
            return Err(c.err(
                "damping_zone.end",
                "the zone needs a length: end != start (the damping rises from start to end)",
            ));
        }
        c.positive("damping_zone.strength", z.strength)?;
        if euler {
            return Err(c.err(
                "damping_zone",
                "the damping acts in the kick: it needs time.integrator \"symplectic-euler\" \
                 or \"leapfrog\" (the forward Euler's fused drift-kick on the GPU has no \
                 kick of its own)",
            ));
        }
    }
    Ok(())
}
