//! Regular waves at a row of gauges (`meshfree waves`, issue #57): each gauge's first
//! harmonic over whole periods, and the incident and reflected waves separated by the
//! least-squares method of Mansard & Funke (1980, "The measurement of incident and reflected
//! spectra using a least squares method", Proc. 17th ICCE, pp. 154-172), which with two
//! gauges is Goda & Suzuki's (1976).
//!
//! Each gauge p at x_p (along the waves' direction, +x) reads eta_p(t); over a window of
//! whole periods T its first harmonic is fitted by least squares, eta_p = c_p + a_p cos(wt) +
//! b_p sin(wt), w = 2 pi / T, as the complex amplitude B_p = a_p - i b_p (eta's harmonic is
//! Re{B_p e^{iwt}}). An incident wave travelling towards +x and a reflected one towards -x
//! give B_p = Z_I e^{-ik x_p} + Z_R e^{ik x_p}, k from the linear dispersion relation
//! (`scene::wave::wave_number`); Z_I and Z_R minimise sum_p |B_p - Z_I e^{-ikx_p} - Z_R
//! e^{ikx_p}|^2. The system is singular where every spacing k (x_p - x_q) is a multiple of pi
//! (gauges half a wavelength apart see the two waves alike): `conditioning` reports how far
//! from that the gauges are. Heights \[L\] are crest to trough, 2 |Z|.

use num_complex::Complex64 as C;

/// A gauge's first harmonic over the window.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Harmonic {
    /// \[L\] the mean level c.
    pub mean: f64,
    /// \[L\] the first harmonic's height 2 |B|.
    pub height: f64,
    /// \[L\] the record's crest-to-trough range over the window (max - min).
    pub range: f64,
    /// B = a - i b \[L\].
    #[serde(skip)]
    pub amplitude: C,
}

/// The least-squares first harmonic of `eta` \[L\] sampled at `times` \[T\] at angular
/// frequency `omega` \[1/T\]; None with fewer than 3 samples or a singular fit.
pub fn harmonic(times: &[f64], eta: &[f64], omega: f64) -> Option<Harmonic> {
    if times.len() < 3 || times.len() != eta.len() {
        return None;
    }
    // The normal equations of eta = c + a cos + b sin, solved by Cramer's rule.
    let mut m = [[0.0f64; 3]; 3];
    let mut r = [0.0f64; 3];
    for (&t, &e) in times.iter().zip(eta) {
        let f = [1.0, (omega * t).cos(), (omega * t).sin()];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += f[i] * f[j];
            }
            r[i] += f[i] * e;
        }
    }
    let det3 = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det3(&m);
    if d.abs() <= 1e-12 * (times.len() as f64).powi(3) {
        return None;
    }
    let solve = |k: usize| {
        let mut mk = m;
        for i in 0..3 {
            mk[i][k] = r[i];
        }
        det3(&mk) / d
    };
    let (c, a, b) = (solve(0), solve(1), solve(2));
    let amplitude = C::new(a, -b);
    let (lo, hi) = eta
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &e| (lo.min(e), hi.max(e)));
    Some(Harmonic {
        mean: c,
        height: 2.0 * amplitude.norm(),
        range: hi - lo,
        amplitude,
    })
}

/// The incident and reflected waves at a row of gauges.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Separation {
    /// \[L\] the incident wave's height 2 |Z_I|.
    pub incident: f64,
    /// \[L\] the reflected wave's height 2 |Z_R|.
    pub reflected: f64,
    /// |Z_R| / |Z_I| \[-\].
    pub coefficient: f64,
    /// 1 - |sum_p e^{2ikx_p}| / N in [0, 1]: 0 where the gauges cannot tell the waves apart
    /// (every spacing a multiple of half a wavelength), 1 at best. Mansard & Funke advise
    /// spacings that keep it well above 0 (k dx away from multiples of pi).
    pub conditioning: f64,
    /// \[L\] the rms of the fit's residual over the gauges, |B_p - model| (0 for two gauges).
    pub residual: f64,
}

/// The separation of the gauges' complex amplitudes `b` at positions `x` \[L\] for wave
/// number `k` \[1/L\]; None with fewer than two gauges or where the gauges cannot tell the
/// two waves apart (`conditioning` below 1e-6).
pub fn separate(x: &[f64], b: &[C], k: f64) -> Option<Separation> {
    let n = x.len();
    if n < 2 || b.len() != n {
        return None;
    }
    // v_p = e^{ikx_p}; u_p = conj(v_p) = e^{-ikx_p}.
    let v: Vec<C> = x.iter().map(|&x| C::from_polar(1.0, k * x)).collect();
    let nf = n as f64;
    let s: C = v.iter().map(|v| v * v).sum();
    let p: C = v.iter().zip(b).map(|(v, b)| v * b).sum();
    let q: C = v.iter().zip(b).map(|(v, b)| v.conj() * b).sum();
    let conditioning = 1.0 - s.norm() / nf;
    if conditioning < 1e-6 {
        return None;
    }
    let det = nf * nf - s.norm_sqr();
    let zi = (p * nf - s * q) / det;
    let zr = (q * nf - s.conj() * p) / det;
    let residual = (v.iter().zip(b))
        .map(|(v, b)| (b - zi * v.conj() - zr * v).norm_sqr())
        .sum::<f64>()
        / nf;
    Some(Separation {
        incident: 2.0 * zi.norm(),
        reflected: 2.0 * zr.norm(),
        coefficient: zr.norm() / zi.norm(),
        conditioning,
        residual: residual.sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Incident and reflected waves of known heights and phases, a mean level and a second
    /// harmonic, sampled as a run's gauges are: the fit finds the first harmonic and the
    /// separation the two waves, to rounding.
    #[test]
    fn known_waves_are_separated() {
        let (period, k) = (1.2, 3.55);
        let w = 2.0 * std::f64::consts::PI / period;
        let (zi, zr) = (C::from_polar(0.025, 0.3), C::from_polar(0.005, 1.1));
        let xs = [1.0, 1.3, 1.75];
        let times: Vec<f64> = (0..600).map(|i| 2.0 + 0.02 * i as f64).collect();
        let b: Vec<C> = xs
            .iter()
            .map(|&x| {
                let model = zi * C::from_polar(1.0, -k * x) + zr * C::from_polar(1.0, k * x);
                let eta: Vec<f64> = (times.iter())
                    .map(|&t| {
                        0.3 + (model * C::from_polar(1.0, w * t)).re
                            + 0.002 * (2.0 * w * t + x).cos()
                    })
                    .collect();
                let h = harmonic(&times, &eta, w).unwrap();
                assert!((h.mean - 0.3).abs() < 1e-12, "{h:?}");
                assert!((h.amplitude - model).norm() < 1e-12, "{h:?}");
                h.amplitude
            })
            .collect();
        let s = separate(&xs, &b, k).unwrap();
        assert!((s.incident - 0.05).abs() < 1e-12, "{s:?}");
        assert!((s.reflected - 0.01).abs() < 1e-12, "{s:?}");
        assert!((s.coefficient - 0.2).abs() < 1e-10, "{s:?}");
        assert!(s.residual < 1e-12 && s.conditioning > 0.3, "{s:?}");
        // Two gauges (Goda & Suzuki) agree; gauges half a wavelength apart cannot.
        let two = separate(&xs[..2], &b[..2], k).unwrap();
        assert!((two.coefficient - 0.2).abs() < 1e-10, "{two:?}");
        let half = std::f64::consts::PI / k;
        assert!(separate(&[1.0, 1.0 + half], &b[..2], k).is_none());
    }
}
