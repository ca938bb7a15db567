//! The sea state of an irregular record of the free surface (a gauge's elevation eta(t), `meshfree
//! waves` on a run with `wave.spectrum`): the significant height from the variance, and the
//! periods from its spectrum.
//!
//! H_m0 = 4 sqrt(m0), m0 the record's variance \[L^2\]. The one-sided spectrum S(f) \[L^2 T\]
//! is the periodogram 2 |X(f_k)|^2 dt / N at f_k = k / (N dt) (X the discrete Fourier sum of
//! the record less its mean), averaged over `BAND_BINS` neighbouring bins (a band-averaged
//! estimate, ~2 x `BAND_BINS` degrees of freedom). The peak period is Read's (1989) T_p5:
//! 1 / f_p, f_p = sum f S^5 / sum S^5, far steadier than the largest bin's; the mean period
//! T_m01 = m0 / m1 over the same spectrum.

/// Bins averaged into one band of the spectrum.
pub const BAND_BINS: usize = 8;

/// A record's sea state.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SeaState {
    /// \[L\] 4 sqrt(m0).
    pub hm0: f64,
    /// \[T\] Read's peak period.
    pub tp: f64,
    /// \[T\] m0 / m1.
    pub tm01: f64,
    /// \[L\] the record's mean level.
    pub mean: f64,
    /// \[T\] the record's length.
    pub duration: f64,
}

/// The sea state of `eta` \[L\] sampled at `times` \[T\], evenly (a gauge's interval; a row
/// off by more than 1 % of it, a dry gap, is refused), over frequencies up to `f_max`
/// \[1/T\]. None where the record is uneven or too short for a spectrum (under
/// 4 x `BAND_BINS` samples).
pub fn sea_state(times: &[f64], eta: &[f64], f_max: f64) -> Option<SeaState> {
    let n = times.len();
    if n < 4 * BAND_BINS || eta.len() != n {
        return None;
    }
    let dt = (times[n - 1] - times[0]) / (n - 1) as f64;
    if dt.is_nan()
        || dt <= 0.0
        || times
            .windows(2)
            .any(|w| ((w[1] - w[0]) - dt).abs() > 0.01 * dt)
    {
        return None;
    }
    let mean = eta.iter().sum::<f64>() / n as f64;
    let d: Vec<f64> = eta.iter().map(|e| e - mean).collect();
    let m0_time = d.iter().map(|e| e * e).sum::<f64>() / n as f64;
    let span = n as f64 * dt;
    let k_max = ((f_max * span).floor() as usize).min(n / 2);
    // The periodogram by direct sums (k_max x n: a few million terms for a long record),
    // each bin's phase advanced by a rotation rather than a sine a sample.
    let mut bins = Vec::with_capacity(k_max);
    for k in 1..=k_max {
        let w = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        let (step_c, step_s) = (w.cos(), w.sin());
        let (mut c, mut s) = (1.0f64, 0.0f64);
        let (mut re, mut im) = (0.0, 0.0);
        for (j, e) in d.iter().enumerate() {
            re += e * c;
            im -= e * s;
            // Renormalised now and then: the rotation's round-off grows with its steps.
            let (c1, s1) = (c * step_c - s * step_s, s * step_c + c * step_s);
            (c, s) = if j % 1024 == 1023 {
                let r = (c1 * c1 + s1 * s1).sqrt();
                (c1 / r, s1 / r)
            } else {
                (c1, s1)
            };
        }
        bins.push((k as f64 / span, 2.0 * (re * re + im * im) * dt / n as f64));
    }
    let bands: Vec<(f64, f64)> = bins
        .chunks(BAND_BINS)
        .filter(|c| c.len() == BAND_BINS)
        .map(|c| {
            let f = c.iter().map(|b| b.0).sum::<f64>() / BAND_BINS as f64;
            (f, c.iter().map(|b| b.1).sum::<f64>() / BAND_BINS as f64)
        })
        .collect();
    let df = BAND_BINS as f64 / span;
    let (m0, m1) = bands
        .iter()
        .fold((0.0, 0.0), |(a, b), (f, s)| (a + s * df, b + f * s * df));
    let (s5, fs5) = bands.iter().fold((0.0, 0.0), |(a, b), (f, s)| {
        (a + s.powi(5), b + f * s.powi(5))
    });
    if m1 <= 0.0 || s5 <= 0.0 || m1.is_nan() || s5.is_nan() {
        return None;
    }
    Some(SeaState {
        hm0: 4.0 * m0_time.sqrt(),
        tp: s5 / fs5,
        tm01: m0 / m1,
        mean,
        duration: span,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::format::{Paddle, Spectrum, SpectrumShape, WaveMaker};
    use crate::scene::wave_spectrum::elevation_at;

    #[test]
    fn a_jonswap_record_gives_back_its_height_and_peak() {
        // 200 peak periods of the sea the wave maker makes (its first-order surface),
        // sampled every 0.02 as a gauge is: H_m0 and T_p within 5 % (the tolerance
        // for a run), a mean period below the peak's as a JONSWAP sea's is (~0.8 T_p).
        for (seed, tp) in [(1, 1.5), (2, 1.2), (9, 2.0)] {
            let w = WaveMaker {
                paddle: Paddle::Piston,
                height: 0.08,
                period: tp,
                depth: 0.5,
                phase: 0.0,
                hinge: None,
                spectrum: Some(Spectrum {
                    shape: SpectrumShape::Jonswap,
                    gamma: 3.3,
                    seed,
                    components: 512,
                    focus: None,
                }),
                made: Default::default(),
            };
            let c = w.components(9.81, 0.0);
            let n = (200.0 * tp / 0.02) as usize;
            let times: Vec<f64> = (0..n).map(|j| 0.02 * j as f64).collect();
            let eta: Vec<f64> = times.iter().map(|&t| 0.3 + elevation_at(&c, t)).collect();
            let s = sea_state(&times, &eta, 4.0 / tp).unwrap();
            assert!((s.hm0 / 0.08 - 1.0).abs() < 0.05, "{tp}: {s:?}");
            assert!((s.tp / tp - 1.0).abs() < 0.05, "{tp}: {s:?}");
            assert!(s.tm01 < 0.9 * tp && s.tm01 > 0.7 * tp, "{tp}: {s:?}");
            assert!((s.mean - 0.3).abs() < 1e-3);
        }
    }

    #[test]
    fn a_sine_is_its_own_peak_and_uneven_records_are_refused() {
        let times: Vec<f64> = (0..5000).map(|j| 0.01 * j as f64).collect();
        // Period 2.5: 20 whole periods in the record.
        let period = 2.5;
        let w = 2.0 * std::f64::consts::PI / period;
        let eta: Vec<f64> = times.iter().map(|t| 0.02 * (w * t).sin()).collect();
        let s = sea_state(&times, &eta, 5.0).unwrap();
        // Within the band's width (8 bins of 1/50 s^-1: 0.16 s^-1 about 0.4 s^-1).
        assert!((s.tp / period - 1.0).abs() < 0.05, "{s:?}");
        // H_m0 of a sine of amplitude a is 4 a / sqrt 2.
        assert!((s.hm0 - 4.0 * 0.02 / 2f64.sqrt()).abs() < 1e-9, "{s:?}");
        let mut gap = times.clone();
        gap[2000] += 0.005;
        assert!(sea_state(&gap, &eta, 5.0).is_none());
        assert!(sea_state(&times[..20], &eta[..20], 5.0).is_none());
    }
}
