//! Force monitors (`[[monitors]]` in a scene): the force the fluid and solids exert on one
//! wall object, its drag and lift coefficients, and the Strouhal number of the lift.
//!
//! A run samples the force with `Readback::wall_forces`, on the solver's own state (the CPU
//! backend: `src/backend/cpu/monitor.rs`; the CUDA backend: `cuda/monitor.cu`, summed on the
//! device). `wall_force` here is the same sum from a particle read-back (`Readback::particles`,
//! either backend), the CPU and parity tests' reference: for every wall
//! particle j of the object and every fluid or solid neighbour i, the acceleration that j
//! contributes to i in the CPU force stage's own pair sum (`ForceSum` in
//! `src/backend/cpu/forces.rs`: Lennard-Jones eq. (17); with dynamic walls also the pressure
//! term of eqs. (7)/(16) with the wall cut-off, the artificial viscosity eq. (10) and the
//! laminar viscosity of Morris, Fox & Zhu 1997). By Newton's third law the wall feels
//! F = - sum_i m_i a_i(from wall). [M L T^-2] (per unit depth in 2D: [M T^-2]). Pressures are
//! the Tait / solid EOS of the read-back density, as the next force stage would take them.

use crate::backend::cpu::{self, Grid};
use crate::physics::dim::{Dim, D2, D3};
use crate::physics::params::SphParams;
use crate::physics::particle::{Kind, Particle};
use crate::physics::state::State;

/// The force [M L T^-2] that fluid and solid particles exert on the boundary particles of
/// scene group `group`, as three numbers (z = 0 in 2D), from `particles` (any order).
/// `surface`: the solver's `Setup::wall_surface` (`Readback::wall_surface`; empty unless
/// `no_slip`).
pub fn wall_force(
    p: &SphParams,
    particles: &[Particle],
    surface: &[[f32; 4]],
    group: u32,
) -> [f64; 3] {
    let near = near_wall(p, particles, group);
    let particles = near.as_deref().unwrap_or(particles);
    if p.dim == 2 {
        wall_force_d::<D2>(p, particles, surface, group)
    } else {
        wall_force_d::<D3>(p, particles, surface, group)
    }
}

/// The particles within one support radius of the wall group's bounding box: the only
/// ones that interact with it (the force is the same, the grid and sums far smaller in a
/// large domain). None (take all) when the widened box crosses a periodic boundary.
fn near_wall(p: &SphParams, particles: &[Particle], group: u32) -> Option<Vec<Particle>> {
    let d = p.dim as usize;
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for q in particles
        .iter()
        .filter(|q| q.kind == Kind::Boundary && q.group == group)
    {
        for a in 0..d {
            lo[a] = lo[a].min(q.position[a]);
            hi[a] = hi[a].max(q.position[a]);
        }
    }
    for a in 0..d {
        lo[a] -= p.support;
        hi[a] += p.support;
        if lo[a] > hi[a]
            || (p.periodic[a] != 0 && (lo[a] < p.domain_min[a] || hi[a] > p.domain_max[a]))
        {
            return None;
        }
    }
    Some(
        particles
            .iter()
            .filter(|q| (0..d).all(|a| q.position[a] >= lo[a] && q.position[a] <= hi[a]))
            .copied()
            .collect(),
    )
}

/// The particles as a state, its pressures from the equation of state, eq. (9), its grid,
/// then the CPU backend's sum over the pairs (`cpu::wall_force`).
fn wall_force_d<D: Dim>(
    p: &SphParams,
    particles: &[Particle],
    surface: &[[f32; 4]],
    group: u32,
) -> [f64; 3] {
    let mut s = State::<D>::from_particles(particles, false, false, p.solid_rho0);
    cpu::refresh_pressure(p, &mut s); // eq. (9)
    let mut grid = Grid::default();
    grid.build(p, &mut s);
    cpu::wall_force(p, &s, &grid, surface, group)
}

/// One sample of a monitor.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ForceSample {
    /// \[T\]
    pub t: f64,
    /// [M L T^-2]
    pub force: [f64; 3],
    /// Drag coefficient Fx / (0.5 rho0 U^2 D^(d-1)); 0 where the monitor declares no
    /// reference scales (`BluffBody`).
    pub cd: f64,
    /// Lift coefficient Fy / (0.5 rho0 U^2 D^(d-1)); 0 likewise.
    pub cl: f64,
}

/// The frequency [1/T] of the largest peak of the Hann-windowed discrete Fourier transform
/// of `x(t)` (mean removed), evaluated directly on the sample times (they need not be
/// evenly spaced): a scan in steps of 1 / (4 T) between 1.5 / T (at least one and a half
/// periods in the record of length T) and the Nyquist frequency of the mean spacing, then
/// a scan in steps of 1 / (256 T) around the best coarse frequency. None with fewer than 8
/// samples or a constant signal.
pub fn dominant_frequency(t: &[f64], x: &[f64]) -> Option<f64> {
    let n = t.len().min(x.len());
    if n < 8 {
        return None;
    }
    let (t0, span) = (t[0], t[n - 1] - t[0]);
    if span <= 0.0 {
        return None;
    }
    let mean = x[..n].iter().sum::<f64>() / n as f64;
    let tau = 2.0 * std::f64::consts::PI;
    let w: Vec<f64> = (0..n)
        .map(|k| (0.5 - 0.5 * (tau * (t[k] - t0) / span).cos()) * (x[k] - mean))
        .collect();
    if w.iter().all(|v| v.abs() < 1e-300) {
        return None;
    }
    let power = |f: f64| {
        let (mut re, mut im) = (0.0, 0.0);
        for k in 0..n {
            let ph = tau * f * (t[k] - t0);
            re += w[k] * ph.cos();
            im -= w[k] * ph.sin();
        }
        re * re + im * im
    };
    let best_on = |lo: f64, hi: f64, df: f64| {
        let steps = ((hi - lo) / df).floor().max(0.0) as usize;
        (0..=steps)
            .map(|k| lo + k as f64 * df)
            .map(|f| (f, power(f)))
            .fold(None, |b: Option<(f64, f64)>, c| match b {
                Some(b) if b.1 >= c.1 => Some(b),
                _ => Some(c),
            })
    };
    let (f_lo, nyquist) = (1.5 / span, 0.5 * (n - 1) as f64 / span);
    if nyquist <= f_lo {
        return None;
    }
    let coarse = best_on(f_lo, nyquist, 0.25 / span)?.0;
    let lo = (coarse - 0.25 / span).max(f_lo);
    let hi = (coarse + 0.25 / span).min(nyquist);
    best_on(lo, hi, 1.0 / (256.0 * span)).map(|b| b.0)
}

/// The rms [x's units] of the part of `x` within the band |f / f0 - 1| <= `rel` around the
/// frequency `f0` [1/T], `x` sampled at the evenly spaced times `t`: by Parseval's theorem
/// over the discrete Fourier transform X_k = sum_j (x_j - mean) exp(-2 pi i k j / n) of the
/// record (n samples, bin k at the frequency k / (n dt)),
/// rms^2 = (2 / n^2) sum_{0 < k < n/2, |k / (n dt) / f0 - 1| <= rel} |X_k|^2.
/// A narrow-band amplitude: broadband noise adds only its share of the band, and the
/// signal in the band is not attenuated (a moving average would be, by its gain
/// sin(N pi f dt) / (N sin(pi f dt)) at f). 0 with fewer than 2 samples or f0 <= 0.
pub fn band_rms(t: &[f64], x: &[f64], f0: f64, rel: f64) -> f64 {
    let n = t.len().min(x.len());
    if n < 2 || f0 <= 0.0 {
        return 0.0;
    }
    let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
    let mean = x[..n].iter().sum::<f64>() / n as f64;
    let tau = 2.0 * std::f64::consts::PI;
    let mut sum = 0.0;
    for k in 1..n.div_ceil(2) {
        let f = k as f64 / (n as f64 * dt);
        if (f / f0 - 1.0).abs() > rel {
            continue;
        }
        let (mut re, mut im) = (0.0, 0.0);
        for (j, xj) in x[..n].iter().enumerate() {
            let ph = tau * (k * j % n) as f64 / n as f64;
            re += (xj - mean) * ph.cos();
            im -= (xj - mean) * ph.sin();
        }
        sum += re * re + im * im;
    }
    (2.0 * sum).sqrt() / n as f64
}

/// The half-width of the band around the shedding frequency f_s whose part of the lift is
/// its rms (`MonitorSummary::rms_cl`, `band_rms`): [0.5, 1.5] f_s holds the fundamental and
/// its spread (a record of ~10 periods resolves 0.1 f_s) and leaves out the mean's drift
/// below and the odd harmonic at 3 f_s (a few per cent of the amplitude at Re 100, under
/// 0.1 % of the rms squared).
pub const BAND_REL: f64 = 0.5;

/// A bluff body's reference scales (`[[monitors]] reference_velocity`, `reference_length`),
/// which make a force a coefficient and a frequency a Strouhal number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BluffBody {
    /// [L/T] U.
    pub velocity: f64,
    /// \[L\] D.
    pub length: f64,
    /// D / H, H the domain's extent along y (the lift axis).
    pub blockage_ratio: f64,
}

/// What a monitor reports at the end of a run (summary.json, end-of-run line): the peak
/// force, its time and the impulse of any force record, and, for a bluff body in a stream
/// (`BluffBody`), the coefficients and the Strouhal number. A dam-break obstacle's monitor
/// declares no reference scales and reports no coefficient (issue #51).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MonitorSummary {
    pub name: String,
    /// Index of the wall in `[[walls]]`.
    pub wall: usize,
    pub samples: usize,
    /// [M L T^-2] (per unit depth in 2D) the largest |F| over the record.
    #[serde(default)]
    pub peak_force: f64,
    /// \[T\] when it came.
    #[serde(default)]
    pub peak_time: f64,
    /// [M L T^-1] (per unit depth in 2D) the integral of F over the record (trapezoids).
    #[serde(default)]
    pub impulse: [f64; 3],
    /// Where the monitor declares a bluff body's scales.
    #[serde(flatten, default)]
    pub coefficients: Option<Coefficients>,
}

/// A bluff body's coefficients, Cd = Fx / (0.5 rho0 U^2 D^(d-1)) and Cl likewise with Fy.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Coefficients {
    /// \[T\] the statistics below are over t >= window_start: the second half of the record.
    pub window_start: f64,
    /// f D / U from the lift's dominant frequency (`dominant_frequency`); None when the
    /// window holds too few samples or the lift is constant.
    pub strouhal: Option<f64>,
    pub mean_cd: f64,
    pub mean_cl: f64,
    /// Root mean square of Cl: of its part within `BAND_REL` of the dominant frequency
    /// (`band_rms`: the shedding's, without the broadband SPH force noise, which doubles
    /// the record's rms in a wake at D / dx = 20; issue #23), or about its mean when there
    /// is no dominant frequency.
    pub rms_cl: f64,
    /// D / H, H the domain's extent along y (the lift axis).
    pub blockage_ratio: f64,
}

impl MonitorSummary {
    /// The peak, its time and the impulse of `samples`; with `body`, the coefficients'
    /// statistics over the second half (in time) of the record, taken at even intervals
    /// (`band_rms`).
    pub fn of(
        name: &str,
        wall: usize,
        samples: &[ForceSample],
        body: Option<BluffBody>,
    ) -> MonitorSummary {
        let norm = |f: &[f64; 3]| (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        let peak = (samples.iter()).max_by(|a, b| norm(&a.force).total_cmp(&norm(&b.force)));
        let mut impulse = [0.0; 3];
        for w in samples.windows(2) {
            for (k, i) in impulse.iter_mut().enumerate() {
                *i += 0.5 * (w[0].force[k] + w[1].force[k]) * (w[1].t - w[0].t);
            }
        }
        MonitorSummary {
            name: name.to_string(),
            wall,
            samples: samples.len(),
            peak_force: peak.map_or(0.0, |p| norm(&p.force)),
            peak_time: peak.map_or(0.0, |p| p.t),
            impulse,
            coefficients: body.map(|b| Coefficients::of(samples, b)),
        }
    }
}

impl Coefficients {
    /// The statistics of `samples` over the second half (in time) of the record, taken at
    /// even intervals (`band_rms`), as coefficients of `body`'s scales.
    pub fn of(samples: &[ForceSample], body: BluffBody) -> Coefficients {
        let (first, last) = match (samples.first(), samples.last()) {
            (Some(a), Some(b)) => (a.t, b.t),
            _ => (0.0, 0.0),
        };
        let window_start = 0.5 * (first + last);
        let win: Vec<&ForceSample> = samples.iter().filter(|s| s.t >= window_start).collect();
        let m = win.len().max(1) as f64;
        let mean_cd = win.iter().map(|s| s.cd).sum::<f64>() / m;
        let mean_cl = win.iter().map(|s| s.cl).sum::<f64>() / m;
        let t: Vec<f64> = win.iter().map(|s| s.t).collect();
        let cl: Vec<f64> = win.iter().map(|s| s.cl).collect();
        let frequency = dominant_frequency(&t, &cl);
        let rms_cl = match frequency {
            Some(f) => band_rms(&t, &cl, f, BAND_REL),
            None => (win.iter().map(|s| (s.cl - mean_cl).powi(2)).sum::<f64>() / m).sqrt(),
        };
        Coefficients {
            window_start,
            strouhal: frequency.map(|f| f * body.length / body.velocity),
            mean_cd,
            mean_cl,
            rms_cl,
            blockage_ratio: body.blockage_ratio,
        }
    }
}

impl std::fmt::Display for MonitorSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "monitor {} (wall {}): {} samples; peak |F| {:.4e} at t = {:.4}, impulse ({:.4e}, {:.4e}, {:.4e})",
            self.name,
            self.wall,
            self.samples,
            self.peak_force,
            self.peak_time,
            self.impulse[0],
            self.impulse[1],
            self.impulse[2],
        )?;
        match &self.coefficients {
            Some(c) => write!(f, "; {c}"),
            None => Ok(()),
        }
    }
}

impl std::fmt::Display for Coefficients {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let st = (self.strouhal)
            .map_or("n/a (too few samples or no oscillation)".to_string(), |s| {
                format!("{s:.4}")
            });
        write!(
            f,
            "over t >= {:.3}: Strouhal {st} (lift DFT peak), mean Cd {:.4}, rms Cl {:.4}, \
             mean Cl {:.4}, blockage D/H {:.3}",
            self.window_start, self.mean_cd, self.rms_cl, self.mean_cl, self.blockage_ratio
        )
    }
}
