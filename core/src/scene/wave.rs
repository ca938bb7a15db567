//! A wave maker's paddle (`MotionLaw::wave`): linear wave-maker theory for the stroke of a
//! regular wave, and the checks that refuse a wave the flume cannot make.
//!
//! Dispersion (Airy): omega^2 = g k tanh(k d), omega = 2 pi / T. Transfer functions of
//! Biesel (1951), in Dean & Dalrymple 1991, "Water Wave Mechanics for Engineers and
//! Scientists", sec. 6.2, eqs. (6.23) and (6.26), H wave height, S stroke:
//!
//! piston: H / S = 2 (cosh 2kd - 1) / (sinh 2kd + 2kd),
//! flap hinged at the floor: H / S = 4 (sinh kd / kd) (kd sinh kd - cosh kd + 1) / (sinh 2kd + 2kd).
//!
//! Breaking: Miche's limit H / L <= 0.142 tanh(kd).

use super::ctx::Ctx;
use super::format::{Paddle, WaveMaker};
use super::SceneError;
use super::SceneFile;

/// \[1/L\] The wave number of a wave of `period` \[T\] in water of `depth` \[L\] under gravity
/// `g` \[L/T^2\]: the root of omega^2 = g k tanh(k d) by Newton's method from the
/// deep-water guess (converges for any depth: the function is increasing and concave).
pub fn wave_number(g: f64, period: f64, depth: f64) -> f64 {
    let w2 = (2.0 * std::f64::consts::PI / period).powi(2);
    // Eckart's approximation as the start: within 5 % everywhere.
    let k0 = w2 / g;
    let mut k = k0 / (k0 * depth).tanh().sqrt();
    for _ in 0..50 {
        let t = (k * depth).tanh();
        let f = g * k * t - w2;
        let df = g * t + g * k * depth * (1.0 - t * t);
        let dk = f / df;
        k -= dk;
        if dk.abs() < 1e-14 * k {
            break;
        }
    }
    k
}

/// H / S of a paddle at relative depth kd (Biesel; the module's equations).
pub fn height_per_stroke(paddle: Paddle, kd: f64) -> f64 {
    let den = (2.0 * kd).sinh() + 2.0 * kd;
    match paddle {
        Paddle::Piston => 2.0 * ((2.0 * kd).cosh() - 1.0) / den,
        Paddle::Flap => 4.0 * (kd.sinh() / kd) * (kd * kd.sinh() - kd.cosh() + 1.0) / den,
    }
}

/// A wave maker's numbers: wave number k \[1/L\], wavelength \[L\] and stroke S \[L\] (the
/// paddle's travel at the still-water level, crest of its motion to trough).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Paddling {
    pub k: f64,
    pub wavelength: f64,
    pub stroke: f64,
}

impl WaveMaker {
    /// The paddling for gravity `g` \[L/T^2\] (its magnitude).
    pub fn paddling(&self, g: f64) -> Paddling {
        let k = wave_number(g, self.period, self.depth);
        Paddling {
            k,
            wavelength: 2.0 * std::f64::consts::PI / k,
            stroke: self.height / height_per_stroke(self.paddle, k * self.depth),
        }
    }
}

/// The magnitude of the scene's gravity \[L/T^2\].
pub fn gravity(s: &SceneFile) -> f64 {
    s.gravity
        .iter()
        .flatten()
        .map(|x| x * x)
        .sum::<f64>()
        .sqrt()
}

/// The checks of the wave maker at `field` (`walls[1].motion.wave`) of the box wall
/// `lo`..`hi` (the paddle): its numbers, gravity along -y, a wave that does not break at
/// the paddle (Miche), a wavelength of at least 10 spacings and at most the domain's length
/// along x, and a paddle that stays inside the domain.
pub(super) fn check(
    c: &Ctx,
    field: &str,
    w: &WaveMaker,
    s: &SceneFile,
    lo: &[f64],
    hi: &[f64],
) -> Result<(), SceneError> {
    let err = |f: String, why: String| Err(c.err(f, why));
    c.positive(&format!("{field}.height"), w.height)?;
    c.positive(&format!("{field}.period"), w.period)?;
    c.positive(&format!("{field}.depth"), w.depth)?;
    if !w.phase.is_finite() {
        return err(format!("{field}.phase"), "must be a finite number".into());
    }
    let g = s.gravity.clone().unwrap_or_default();
    if !(g.len() >= 2 && g[1] < 0.0 && g.iter().enumerate().all(|(a, &x)| a == 1 || x == 0.0)) {
        return err(
            field.to_string(),
            format!("a wave maker makes waves along +x with y up: gravity must point along -y, found {g:?}"),
        );
    }
    match (w.paddle, &w.hinge) {
        (Paddle::Flap, None) => {
            return err(
                format!("{field}.hinge"),
                "a flap needs its hinge, the point on the floor it turns about".into(),
            )
        }
        (Paddle::Piston, Some(_)) => {
            return err(
                format!("{field}.hinge"),
                "a piston has no hinge: leave it out (or paddle = \"flap\")".into(),
            )
        }
        (_, Some(h)) => c.vec(&format!("{field}.hinge"), h)?,
        _ => {}
    }
    if let Some(sp) = &w.spectrum {
        let f = format!("{field}.spectrum");
        if !(1.0..=10.0).contains(&sp.gamma) {
            return err(format!("{f}.gamma"), "must be a number from 1 to 10".into());
        }
        if !(16..=4096).contains(&sp.components) {
            return err(format!("{f}.components"), "must be from 16 to 4096".into());
        }
        if let Some(fo) = &sp.focus {
            c.positive(&format!("{f}.focus.distance"), fo.distance)?;
            c.positive(&format!("{f}.focus.time"), fo.time)?;
            let room = s.domain.max[0] - hi[0];
            if fo.distance > room {
                return err(
                    format!("{f}.focus.distance"),
                    format!(
                        "the focus is {} from the paddle, beyond the domain's end {room} past it",
                        fo.distance
                    ),
                );
            }
        }
    }
    let p = w.paddling(gravity(s));
    let (l, kd) = (p.wavelength, p.k * w.depth);
    let miche = 0.142 * l * kd.tanh();
    // An irregular sea: its significant height at its peak period.
    if w.height > miche {
        return err(
            format!("{field}.height"),
            format!(
                "a wave {} high breaks at the paddle: Miche's limit at this period and depth \
                 (wavelength {l:.4}, kd {kd:.3}) is H <= 0.142 L tanh(kd) = {miche:.4}",
                w.height
            ),
        );
    }
    let dx = s.discretisation.spacing;
    if l < 10.0 * dx {
        return err(
            format!("{field}.period"),
            format!(
                "the wavelength {l:.4} is under 10 particle spacings ({}): lengthen the \
                 period or refine the spacing",
                10.0 * dx
            ),
        );
    }
    let length = s.domain.max[0] - s.domain.min[0];
    if l > length {
        return err(
            format!("{field}.period"),
            format!("the wavelength {l:.4} is longer than the domain along x ({length})"),
        );
    }
    // The paddle's travel either way: S / 2 at the still-water level, for a flap (S / 2)
    // (y - hinge) / depth at the paddle's top. An irregular sea's, from its record once it is
    // made (`motion_series::make_all`).
    if w.spectrum.is_some() {
        return Ok(());
    }
    let reach = match (&w.paddle, &w.hinge) {
        (Paddle::Flap, Some(h)) => 0.5 * p.stroke * ((hi[1] - h[1]) / w.depth).max(1.0),
        _ => 0.5 * p.stroke,
    };
    if lo[0] - reach < s.domain.min[0] || hi[0] + reach > s.domain.max[0] {
        return err(
            field.to_string(),
            format!(
                "the paddle moves {reach:.4} either way (stroke {:.4}): from x in [{}, {}] it \
                 leaves the domain [{}, {}]",
                p.stroke, lo[0], hi[0], s.domain.min[0], s.domain.max[0]
            ),
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dispersion_meets_its_limits_and_itself() {
        let g = 9.81;
        // Deep water: L = g T^2 / (2 pi).
        let k = wave_number(g, 1.0, 100.0);
        assert!((2.0 * std::f64::consts::PI / k - g / (2.0 * std::f64::consts::PI)).abs() < 1e-9);
        // Shallow water: omega = k sqrt(g d) to O((kd)^2).
        let (t, d) = (20.0, 0.1);
        let k = wave_number(g, t, d);
        let c = 2.0 * std::f64::consts::PI / t / k;
        assert!((c / (g * d).sqrt() - 1.0).abs() < 1e-3, "{c}");
        // Intermediate: the relation holds to rounding (T = 1.2, d = 0.3).
        let k = wave_number(g, 1.2, 0.3);
        let w = 2.0 * std::f64::consts::PI / 1.2;
        assert!((g * k * (k * 0.3).tanh() - w * w).abs() < 1e-10 * w * w);
    }

    #[test]
    fn transfer_functions_meet_shallow_and_deep_limits() {
        // Shallow: piston H/S = kd, flap kd / 2 (Dean & Dalrymple 6.2); deep: both 2.
        for (paddle, shallow) in [(Paddle::Piston, 1.0), (Paddle::Flap, 0.5)] {
            let kd = 1e-3;
            let r = height_per_stroke(paddle, kd) / kd;
            assert!((r - shallow).abs() < 1e-3, "{paddle:?}: {r}");
            assert!(
                (height_per_stroke(paddle, 20.0) - 2.0).abs() < 0.11,
                "{paddle:?}"
            );
        }
        // A flap makes a smaller wave than a piston of the same stroke at any depth.
        for kd in [0.3, 1.0, 2.0] {
            assert!(height_per_stroke(Paddle::Flap, kd) < height_per_stroke(Paddle::Piston, kd));
        }
    }
}
