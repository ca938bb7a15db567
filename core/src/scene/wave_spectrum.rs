//! An irregular sea at a wave maker's paddle (`wave.spectrum`): the paddle's motion as a
//! sum of linear components drawn from a JONSWAP spectrum (Hasselmann et al. 1973; gamma =
//! 1 is Pierson-Moskowitz), made into a time series of knots (`MfMotion::series_*`, cubic
//! between them) that the solver follows as it follows a recorded one.
//!
//! Spectrum, f \[1/T\], f_p = 1 / T_p:
//! S(f) ~ f^-5 exp(-5/4 (f_p / f)^4) gamma^exp(-(f / f_p - 1)^2 / (2 sigma^2)), sigma = 0.07
//! below f_p, 0.09 above, scaled so that the components' 4 sqrt(m0) is H_m0.
//! Components: N bins over [f_p / 2, 3 f_p], one frequency drawn at random within each (no
//! repeat period), amplitude a_i = sqrt(2 S(f_i) df), phase drawn at random (the seed's
//! SplitMix64 stream: the same seed makes the same sea on every machine and version); or, for
//! a focused group (NewWave, Tromans, Anaturk & Hagemeijer 1991), a_i = A S(f_i) / sum S,
//! A the crest's elevation, and phases pi/2 - omega_i t_f + k_i x_f, so that every
//! component crests at the distance x_f from the paddle at t_f;
//! components shorter than 10 particle spacings are left out (the flume cannot carry them).
//! Paddle: each component's stroke from Biesel's transfer function (`wave::height_per_stroke`):
//! the piston's displacement x(t) = r(t) sum (a_i / (H/S)_i) sin(omega_i t + phi_i), a flap's
//! turn theta(t) = -atan(x(t) / depth) (its face at the still-water level moves by x(t)), r
//! the motion's ramp. The surface it makes at the paddle, to first order:
//! eta(t) = r(t) sum a_i sin(omega_i t + phi_i).

use super::format::{Paddle, SpectrumShape, WaveMaker};
use super::wave::{height_per_stroke, wave_number};
use crate::physics::params::MF_SERIES_STRIDE;

/// The spectrum's band, in units of the peak frequency.
pub const BAND: (f64, f64) = (0.5, 3.0);

/// Samples of the paddle's motion a shortest kept component's period.
const SAMPLES_PER_PERIOD: f64 = 40.0;

/// One linear component of the sea: frequency \[1/T\], amplitude \[L\], phase \[rad\] and
/// the paddle's displacement amplitude at the still-water level \[L\].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Component {
    pub f: f64,
    pub a: f64,
    pub phase: f64,
    pub stroke: f64,
}

/// SplitMix64 (Steele, Lea & Flood 2014): a uniform draw in [0, 1) from `state`.
fn uniform(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// The spectrum's shape at `f` \[1/T\] for peak frequency `fp`, unscaled.
fn shape(kind: SpectrumShape, gamma: f64, f: f64, fp: f64) -> f64 {
    let pm = f.powi(-5) * (-1.25 * (fp / f).powi(4)).exp();
    let gamma = match kind {
        SpectrumShape::Jonswap => gamma,
        SpectrumShape::PiersonMoskowitz => 1.0,
    };
    let sigma = if f <= fp { 0.07 } else { 0.09 };
    pm * gamma.powf((-(f / fp - 1.0).powi(2) / (2.0 * sigma * sigma)).exp())
}

impl WaveMaker {
    /// The sea's components under gravity `g` \[L/T^2\], those at least `min_wavelength`
    /// \[L\] long; empty for a regular wave.
    pub fn components(&self, g: f64, min_wavelength: f64) -> Vec<Component> {
        let Some(sp) = &self.spectrum else {
            return Vec::new();
        };
        let fp = 1.0 / self.period;
        let n = sp.components as usize;
        let (lo, hi) = (BAND.0 * fp, BAND.1 * fp);
        let df = (hi - lo) / n as f64;
        let mut state = sp.seed;
        let mut out = Vec::with_capacity(n);
        let tau = 2.0 * std::f64::consts::PI;
        for i in 0..n {
            let f = lo + (i as f64 + uniform(&mut state)) * df;
            let random = tau * uniform(&mut state);
            let k = wave_number(g, 1.0 / f, self.depth);
            if tau / k < min_wavelength {
                continue;
            }
            let s = shape(sp.shape, sp.gamma, f, fp);
            let (a, phase) = match &sp.focus {
                // In phase at the focus: sin(omega t_f - k x_f + phase) = 1.
                Some(fo) => (
                    s,
                    (0.25 * tau - tau * f * fo.time + k * fo.distance).rem_euclid(tau),
                ),
                None => ((2.0 * s * df).sqrt(), random),
            };
            out.push(Component {
                f,
                a,
                phase,
                stroke: a / height_per_stroke(self.paddle, k * self.depth),
            });
        }
        // Scaled so that 4 sqrt(m0) = H_m0, m0 = sum a^2 / 2; a focused group's crest,
        // sum a, to `height`.
        let total = match sp.focus {
            Some(_) => out.iter().map(|c| c.a).sum::<f64>(),
            None => 4.0 * out.iter().map(|c| 0.5 * c.a * c.a).sum::<f64>().sqrt(),
        };
        if total > 0.0 {
            let scale = self.height / total;
            for c in &mut out {
                c.a *= scale;
                c.stroke *= scale;
            }
        }
        out
    }

    /// The paddle's knots (`MF_SERIES_STRIDE` numbers a knot: t, s_x, s_y, s_z, theta) from
    /// before t = 0 to past `end` \[T\], for `components` and the motion's `ramp` \[T\]: a
    /// piston's displacement in s_x, a flap's turn in theta.
    pub fn knots(&self, components: &[Component], ramp: f64, end: f64) -> Vec<f64> {
        let f_max = components.iter().map(|c| c.f).fold(0.0, f64::max);
        if f_max <= 0.0 {
            return Vec::new();
        }
        let h = 1.0 / (SAMPLES_PER_PERIOD * f_max);
        let n = (end / h).ceil() as usize + 2;
        let mut k = Vec::with_capacity((n + 1) * MF_SERIES_STRIDE as usize);
        for j in 0..=n {
            let t = (j as f64 - 1.0) * h;
            let x = ramp_at(ramp, t) * stroke_at(components, t);
            let (sx, theta) = match self.paddle {
                Paddle::Piston => (x, 0.0),
                Paddle::Flap => (0.0, -(x / self.depth).atan()),
            };
            k.extend([t, sx, 0.0, 0.0, theta]);
        }
        k
    }
}

/// The paddle's displacement at the still-water level without the ramp \[L\].
pub fn stroke_at(components: &[Component], t: f64) -> f64 {
    let w = 2.0 * std::f64::consts::PI;
    components
        .iter()
        .map(|c| c.stroke * (w * c.f * t + c.phase).sin())
        .sum()
}

/// The surface elevation the components make at the paddle, to first order, without the
/// ramp \[L\].
pub fn elevation_at(components: &[Component], t: f64) -> f64 {
    let w = 2.0 * std::f64::consts::PI;
    components
        .iter()
        .map(|c| c.a * (w * c.f * t + c.phase).sin())
        .sum()
}

/// The motion's smooth start r(t) over `ramp` \[T\] (`MfMotion`'s: (1 - cos(pi t / ramp)) / 2
/// up to it, 0 before 0, 1 after it and without one).
fn ramp_at(ramp: f64, t: f64) -> f64 {
    if ramp <= 0.0 {
        1.0
    } else if t <= 0.0 {
        0.0
    } else if t >= ramp {
        1.0
    } else {
        0.5 * (1.0 - (std::f64::consts::PI * t / ramp).cos())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::format::{Focus, Spectrum};

    fn sea(shape: SpectrumShape, seed: u64) -> WaveMaker {
        WaveMaker {
            paddle: Paddle::Piston,
            height: 0.1,
            period: 1.5,
            depth: 0.6,
            phase: 0.0,
            hinge: None,
            spectrum: Some(Spectrum {
                shape,
                gamma: 3.3,
                seed,
                components: 256,
                focus: None,
            }),
            made: Default::default(),
        }
    }

    #[test]
    fn the_components_carry_the_significant_height_and_peak_where_asked() {
        for shape in [SpectrumShape::Jonswap, SpectrumShape::PiersonMoskowitz] {
            let c = sea(shape, 7).components(9.81, 0.0);
            assert_eq!(c.len(), 256);
            let m0: f64 = c.iter().map(|c| 0.5 * c.a * c.a).sum();
            assert!((4.0 * m0.sqrt() - 0.1).abs() < 1e-12);
            // The bin of the largest density a^2 / (2 df) holds f_p = 1 / 1.5.
            let df = (BAND.1 - BAND.0) / 1.5 / 256.0;
            let peak = c.iter().max_by(|a, b| a.a.total_cmp(&b.a)).unwrap();
            assert!(
                (peak.f - 1.0 / 1.5).abs() < 2.0 * df,
                "{shape:?}: {}",
                peak.f
            );
        }
        // JONSWAP's peak is sharper: more of m0 within 10 % of f_p.
        let share = |s| {
            let c = sea(s, 7).components(9.81, 0.0);
            let near: f64 = c
                .iter()
                .filter(|c| (c.f * 1.5 - 1.0).abs() < 0.1)
                .map(|c| c.a * c.a)
                .sum();
            near / c.iter().map(|c| c.a * c.a).sum::<f64>()
        };
        let (j, pm) = (
            share(SpectrumShape::Jonswap),
            share(SpectrumShape::PiersonMoskowitz),
        );
        assert!(j > 1.3 * pm, "{j} vs {pm}");
    }

    #[test]
    fn a_record_of_the_sea_has_its_significant_height() {
        // Over 200 peak periods the record's 4 std(eta) is H_m0 within a few per cent (the
        // components' phases are random: the estimate's own scatter).
        let w = sea(SpectrumShape::Jonswap, 11);
        let c = w.components(9.81, 0.0);
        let (n, t_end) = (60_000, 300.0);
        let eta: Vec<f64> = (0..n)
            .map(|j| elevation_at(&c, t_end * j as f64 / n as f64))
            .collect();
        let mean = eta.iter().sum::<f64>() / n as f64;
        let var = eta.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / n as f64;
        let hs = 4.0 * var.sqrt();
        assert!((hs / 0.1 - 1.0).abs() < 0.03, "H_m0 {hs}");
        // Another seed, another sea of the same height.
        let d = w.components(9.81, 0.0);
        let e = sea(SpectrumShape::Jonswap, 12).components(9.81, 0.0);
        assert_eq!(c, d);
        assert_ne!(c[0].phase, e[0].phase);
    }

    #[test]
    fn the_knots_follow_the_paddle_and_its_ramp() {
        let w = sea(SpectrumShape::Jonswap, 3);
        let c = w.components(9.81, 0.5);
        // Components shorter than 0.5 m (above 1.77 Hz, of a band up to 2 Hz) were left out.
        assert!(c.len() < 236 && c.len() > 200, "{}", c.len());
        assert!(c.iter().all(|c| c.f < 1.8));
        let k = w.knots(&c, 3.0, 20.0);
        let stride = MF_SERIES_STRIDE as usize;
        assert!(k[0] < 0.0 && k[k.len() - stride] > 20.0);
        for row in k.chunks_exact(stride) {
            let t = row[0];
            let want = ramp_at(3.0, t) * stroke_at(&c, t);
            assert!((row[1] - want).abs() < 1e-15 && row[4] == 0.0);
        }
        let flap = WaveMaker {
            paddle: Paddle::Flap,
            hinge: Some(vec![0.0, 0.0]),
            ..w
        };
        let cf = flap.components(9.81, 0.5);
        let kf = flap.knots(&cf, 3.0, 20.0);
        assert!(kf.chunks_exact(stride).all(|r| r[1] == 0.0));
        assert!(kf.chunks_exact(stride).any(|r| r[4].abs() > 1e-3));
        // A flap needs a larger stroke than a piston for the same sea.
        assert!(cf[0].stroke > c[0].stroke);
    }

    #[test]
    fn a_focused_group_crests_where_and_when_it_is_asked() {
        // Every component crests 3 m down the flume at t = 12: the surface there, carried by
        // linear dispersion, reaches `height` then and nowhere near it a few periods before.
        let mut w = sea(SpectrumShape::Jonswap, 3);
        w.height = 0.06;
        w.spectrum.as_mut().unwrap().focus = Some(Focus {
            distance: 3.0,
            time: 12.0,
        });
        let c = w.components(9.81, 0.0);
        assert!((c.iter().map(|c| c.a).sum::<f64>() - 0.06).abs() < 1e-12);
        let tau = 2.0 * std::f64::consts::PI;
        let eta = |x: f64, t: f64| -> f64 {
            c.iter()
                .map(|c| {
                    let k = wave_number(9.81, 1.0 / c.f, w.depth);
                    c.a * (tau * c.f * t - k * x + c.phase).sin()
                })
                .sum()
        };
        assert!((eta(3.0, 12.0) - 0.06).abs() < 1e-12, "{}", eta(3.0, 12.0));
        let before = (0..200)
            .map(|j| eta(3.0, 4.0 + 0.02 * j as f64).abs())
            .fold(0.0, f64::max);
        assert!(before < 0.3 * 0.06, "{before}");
        // At the paddle the group is still spread out (it focuses on its way): its highest
        // crest there is lower, and earlier by about the group's travel time.
        let (mut peak, mut when) = (0.0, 0.0);
        for j in 0..600 {
            let e = elevation_at(&c, 0.02 * j as f64);
            if e > peak {
                (peak, when) = (e, 0.02 * j as f64);
            }
        }
        eprintln!("paddle crest {peak} at {when}");
        assert!(peak < 0.9 * 0.06 && when < 11.0, "{peak} at {when}");
    }
}
