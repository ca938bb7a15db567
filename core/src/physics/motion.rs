//! Prescribed rigid motion of a driven object (a piston, a flap, a rotating tank, a clamp):
//! `MfMotion` of `sph_params.h`, one per driven object (`SphParams::driven_motion`). Its
//! particles move with a pivot c(t) = pivot + s(t) and turn about it by theta(t) about the
//! unit `axis` (z in 2D):
//!
//! x(t) = c(t) + R(axis, theta(t)) (x(0) - pivot),
//! s(t) = velocity I(t) + r(t) amplitude (sin(2 pi t / period + phase) - sin phase) \[L\],
//! theta(t) = rate I(t) + r(t) angle (sin(2 pi t / angle_period + angle_phase) - sin angle_phase) \[rad\],
//!
//! r(t) the smooth start over `ramp` ((1 - cos(pi t / ramp)) / 2 up to `ramp`, then 1; 1
//! without a ramp) and I(t) its integral over [0, t] (t without a ramp). A time series from a
//! file (`series_*`) adds its own displacement and turn, interpolated between its knots
//! (`series_at`), to s(t) and theta(t). Evaluated in double
//! precision from the simulated time, so a step's move is the difference of two exact poses:
//! a rotating tank keeps its radius over any number of steps. Twin:
//! `cuda/device/motion.cuh`; parity test `tests/cuda_parity/`.

use std::f64::consts::PI;

use super::dim::Dim;
use super::params::{MfMotion, MF_SERIES_STRIDE};

/// The smooth start at a time: r, dr/dt \[1/T\] and the integral of r over [0, t] \[T\].
#[derive(Clone, Copy, Debug)]
struct Ramp {
    r: f64,
    dr: f64,
    integral: f64,
}

/// An oscillation's shape, sin(2 pi t / T + phase) - sin(phase), and its rate \[1/T\].
#[derive(Clone, Copy, Debug)]
struct Wave {
    f: f64,
    df: f64,
}

fn wave(period: f32, phase: f32, t: f64) -> Wave {
    if period <= 0.0 {
        return Wave { f: 0.0, df: 0.0 };
    }
    let w = 2.0 * PI / period as f64;
    let phase = phase as f64;
    Wave {
        f: (w * t + phase).sin() - phase.sin(),
        df: w * (w * t + phase).cos(),
    }
}

/// The pivot's displacement s(t) \[L\] and turn theta(t) \[rad\] at a time, and their rates
/// \[L/T\], \[rad/T\].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct At {
    pub s: [f64; 3],
    pub q: f64,
    pub ds: [f64; 3],
    pub dq: f64,
}

/// A series' interpolation between knots i and i + 1 at u = (t - t_i) / h in [0, 1), h =
/// t_{i+1} - t_i: value and rate of component `c` (1..=4 of a knot: s_x, s_y, s_z, theta).
/// Linear: the chord. Cubic: Hermite with Catmull-Rom tangents (the central difference of the
/// neighbouring knots; one-sided at the ends), so the velocity is continuous at the knots.
fn series_segment(knots: &[f64], n: usize, cubic: bool, i: usize, t: f64) -> [[f64; 2]; 4] {
    let k = |j: usize, c: usize| knots[j * MF_SERIES_STRIDE as usize + c];
    let (t0, t1) = (k(i, 0), k(i + 1, 0));
    let h = t1 - t0;
    let u = (t - t0) / h;
    let mut out = [[0.0; 2]; 4];
    for (c, o) in (1..=4).zip(out.iter_mut()) {
        let (f0, f1) = (k(i, c), k(i + 1, c));
        if !cubic {
            *o = [f0 + (f1 - f0) * u, (f1 - f0) / h];
            continue;
        }
        let tangent = |j: usize| {
            let (a, b) = (j.saturating_sub(1), (j + 1).min(n - 1));
            (k(b, c) - k(a, c)) / (k(b, 0) - k(a, 0))
        };
        let (m0, m1) = (tangent(i) * h, tangent(i + 1) * h);
        let (u2, u3) = (u * u, u * u * u);
        let f = (2.0 * u3 - 3.0 * u2 + 1.0) * f0
            + (u3 - 2.0 * u2 + u) * m0
            + (-2.0 * u3 + 3.0 * u2) * f1
            + (u3 - u2) * m1;
        let df = (6.0 * u2 - 6.0 * u) * f0
            + (3.0 * u2 - 4.0 * u + 1.0) * m0
            + (-6.0 * u2 + 6.0 * u) * f1
            + (3.0 * u2 - 2.0 * u) * m1;
        *o = [f, df / h];
    }
    out
}

/// The `count` knots of `series` from knot `first` (`Setup::motion_series`, `MF_SERIES_STRIDE`
/// numbers a knot) at time `t` \[T\]: their values (s_x, s_y, s_z in `s`, theta in `q`) and
/// rates, linear or (`cubic`) cubic Hermite between knots (`series_segment`); held at the
/// first knot before it and at the last after it (rates 0 there: the scene's checks ask a
/// series to cover the run); zero without knots. Twin: `series_knots_at`.
pub fn knots_at(series: &[f64], first: i32, count: i32, cubic: bool, t: f64) -> At {
    let n = count.max(0) as usize;
    let mut at = At::default();
    if n == 0 {
        return at;
    }
    let first = first as usize * MF_SERIES_STRIDE as usize;
    let knots = &series[first..first + n * MF_SERIES_STRIDE as usize];
    let time = |j: usize| knots[j * MF_SERIES_STRIDE as usize];
    let hold = |j: usize, at: &mut At| {
        let k = &knots[j * MF_SERIES_STRIDE as usize..];
        at.s = [k[1], k[2], k[3]];
        at.q = k[4];
    };
    if n == 1 || t < time(0) {
        hold(0, &mut at);
        return at;
    }
    if t >= time(n - 1) {
        hold(n - 1, &mut at);
        return at;
    }
    // The last knot at or before t: time(lo) <= t < time(hi).
    let (mut lo, mut hi) = (0, n - 1);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if time(mid) <= t {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let v = series_segment(knots, n, cubic, lo, t);
    at.s = [v[0][0], v[1][0], v[2][0]];
    at.ds = [v[0][1], v[1][1], v[2][1]];
    (at.q, at.dq) = (v[3][0], v[3][1]);
    at
}

impl MfMotion {
    /// Velocity only, no ramp and no series: the particles take x += velocity dt in float
    /// and v = velocity, as a constant-velocity piston always did. Twin: `motion_steady`.
    pub fn steady(&self) -> bool {
        self.amplitude == [0.0; 3]
            && self.rate == 0.0
            && self.angle == 0.0
            && self.ramp <= 0.0
            && self.series_count == 0
    }

    fn ramp_at(&self, t: f64) -> Ramp {
        let tr = self.ramp as f64;
        if tr <= 0.0 {
            Ramp {
                r: 1.0,
                dr: 0.0,
                integral: t,
            }
        } else if t <= 0.0 {
            Ramp {
                r: 0.0,
                dr: 0.0,
                integral: 0.0,
            }
        } else if t >= tr {
            Ramp {
                r: 1.0,
                dr: 0.0,
                integral: t - 0.5 * tr,
            }
        } else {
            let w = PI / tr;
            Ramp {
                r: 0.5 * (1.0 - (w * t).cos()),
                dr: 0.5 * w * (w * t).sin(),
                integral: 0.5 * (t - (w * t).sin() / w),
            }
        }
    }

    /// The series' displacement and turn at time `t` \[T\] and their rates, from the knots'
    /// table `series` (`Setup::motion_series`; `knots_at`). Twin: `motion_series_at`.
    pub fn series_at(&self, series: &[f64], t: f64) -> At {
        knots_at(
            series,
            self.series_first,
            self.series_count,
            self.series_cubic != 0,
            t,
        )
    }

    /// The pivot's displacement s(t) from its place at t = 0 \[L\], the turn theta(t)
    /// \[rad\] and their rates at time `t` \[T\]: the laws' plus the series' (`series_at`).
    /// Twin: `motion_at`.
    pub fn at(&self, series: &[f64], t: f64) -> At {
        let r = self.ramp_at(t);
        let w = wave(self.period, self.phase, t);
        let a = wave(self.angle_period, self.angle_phase, t);
        let mut at = self.series_at(series, t);
        for d in 0..3 {
            let (v, amp) = (self.velocity[d] as f64, self.amplitude[d] as f64);
            at.s[d] += v * r.integral + r.r * amp * w.f;
            at.ds[d] += v * r.r + amp * (r.dr * w.f + r.r * w.df);
        }
        let (rate, angle) = (self.rate as f64, self.angle as f64);
        at.q += rate * r.integral + r.r * angle * a.f;
        at.dq += rate * r.r + angle * (r.dr * a.f + r.r * a.df);
        at
    }

    /// The pivot's displacement s(t) from its place at t = 0 \[L\] and the turn theta(t)
    /// \[rad\] at time t \[T\].
    pub fn pose(&self, series: &[f64], t: f64) -> ([f64; 3], f64) {
        let at = self.at(series, t);
        (at.s, at.q)
    }

    /// `u` turned as the object has turned by time `t` \[T\]: by theta(t) about its axis
    /// (`pose`, `rotate`). Twin: `motion_at` and `motion_rotate` in `cuda/device/motion.cuh`.
    pub fn turn_vector<D: Dim>(&self, series: &[f64], t: f64, u: &mut [f64; 3]) {
        let q = self.at(series, t).q;
        self.rotate::<D>(q, u);
    }

    /// `u` turned by `q` \[rad\] about the unit axis (Rodrigues; about z in 2D).
    fn rotate<D: Dim>(&self, q: f64, u: &mut [f64; 3]) {
        let (c, s) = (q.cos(), q.sin());
        if D::D == 2 {
            let [x, y, _] = *u;
            u[0] = c * x - s * y;
            u[1] = s * x + c * y;
        } else {
            let a = self.axis.map(f64::from);
            let x = *u;
            let ax = a[0] * x[0] + a[1] * x[1] + a[2] * x[2];
            let cr = [
                a[1] * x[2] - a[2] * x[1],
                a[2] * x[0] - a[0] * x[2],
                a[0] * x[1] - a[1] * x[0],
            ];
            for d in 0..3 {
                u[d] = x[d] * c + cr[d] * s + a[d] * ax * (1.0 - c);
            }
        }
    }

    /// The arm of a particle at `x` from the pivot at a time when it was displaced by `s0`,
    /// x - (pivot + s0) \[L\].
    fn arm<D: Dim>(&self, x: D::V, s0: [f64; 3]) -> [f64; 3] {
        let x = D::to3(x);
        let mut u = [0.0; 3];
        for (d, u) in u.iter_mut().enumerate().take(D::D) {
            *u = x[d] as f64 - (self.pivot[d] as f64 + s0[d]);
        }
        u
    }

    /// Where the object's particle at `x` at time `t0` is at `t1` \[L\]:
    /// c(t1) + R(theta(t1) - theta(t0)) (x - c(t0)), rounded to float once. Twin:
    /// `motion_moved`.
    pub fn moved<D: Dim>(&self, series: &[f64], x: D::V, t0: f64, t1: f64) -> D::V {
        let (a0, a1) = (self.at(series, t0), self.at(series, t1));
        let mut u = self.arm::<D>(x, a0.s);
        self.rotate::<D>(a1.q - a0.q, &mut u);
        let mut y = [0.0f32; 3];
        for (d, y) in y.iter_mut().enumerate().take(D::D) {
            *y = (self.pivot[d] as f64 + a1.s[d] + u[d]) as f32;
        }
        D::from3(y)
    }

    /// The velocity at time `t` of the object's particle at `x`, its pivot where it was at
    /// `t0` \[L/T\]: ds/dt + dtheta/dt axis x (x - c(t0)). Twin: `motion_velocity`.
    pub fn velocity_at<D: Dim>(&self, series: &[f64], x: D::V, t0: f64, t: f64) -> D::V {
        let at = self.at(series, t);
        let om = at.dq;
        let u = self.arm::<D>(x, self.at(series, t0).s);
        let w = if D::D == 2 {
            [-om * u[1], om * u[0], 0.0]
        } else {
            let a = self.axis.map(f64::from);
            [
                om * (a[1] * u[2] - a[2] * u[1]),
                om * (a[2] * u[0] - a[0] * u[2]),
                om * (a[0] * u[1] - a[1] * u[0]),
            ]
        };
        let mut v = [0.0f32; 3];
        for (d, v) in v.iter_mut().enumerate().take(D::D) {
            *v = (at.ds[d] + w[d]) as f32;
        }
        D::from3(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::dim::{D2, D3};
    use glam::{Vec2, Vec3A};

    fn spin(rate: f32, ramp: f32) -> MfMotion {
        MfMotion {
            pivot: [1.0, 0.5, 0.0],
            axis: [0.0, 0.0, 1.0],
            rate,
            ramp,
            ..Default::default()
        }
    }

    #[test]
    fn a_spinning_object_keeps_its_radius_and_reaches_its_angle() {
        // 10,000 steps of a turn at 2 rad/s from (2, 0.5): the radius stays 1 to float
        // round-off and the angle is 2 t, where an explicit x += v dt would grow the radius
        // by (1 + (w dt)^2)^(n/2) - 1 = 2e-4 at dt = 1e-3.
        let m = spin(2.0, 0.0);
        let (dt, n) = (1.0e-3, 10_000);
        let mut x = Vec2::new(2.0, 0.5);
        for k in 0..n {
            x = m.moved::<D2>(&[], x, k as f64 * dt, (k + 1) as f64 * dt);
        }
        let u = x - Vec2::new(1.0, 0.5);
        let t = n as f64 * dt;
        assert!((u.length() - 1.0).abs() < 2e-6, "radius {}", u.length());
        let want = (2.0 * t).rem_euclid(2.0 * PI);
        let got = (u.y as f64).atan2(u.x as f64).rem_euclid(2.0 * PI);
        assert!((got - want).abs() < 1e-4, "angle {got} vs {want}");
    }

    #[test]
    fn the_ramp_starts_from_rest_and_its_turn_is_the_integral_of_its_rate() {
        let m = spin(3.0, 0.5);
        assert_eq!(m.pose(&[], 0.0).1, 0.0);
        let v0 = m.velocity_at::<D2>(&[], Vec2::new(2.0, 0.5), 0.0, 0.0);
        assert_eq!(v0, Vec2::ZERO);
        // theta(t) against the trapezoidal integral of its rate, through and past the ramp.
        let (mut sum, h) = (0.0, 1.0e-4);
        let rate = |t: f64| {
            let v = m.velocity_at::<D2>(&[], Vec2::new(2.0, 0.5), t, t);
            v.y as f64 // the arm is (1, 0): v = omega x arm = (0, omega)
        };
        for k in 0..10_000 {
            let t = k as f64 * h;
            sum += 0.5 * h * (rate(t) + rate(t + h));
        }
        let theta = m.pose(&[], 1.0).1;
        assert!((theta - sum).abs() < 1e-5, "{theta} vs {sum}");
        assert!((theta - 3.0 * (1.0 - 0.25)).abs() < 1e-12, "{theta}");
    }

    #[test]
    fn an_oscillation_returns_to_its_start_after_a_period_with_the_velocity_it_began() {
        let m = MfMotion {
            amplitude: [0.1, 0.0, 0.02],
            period: 0.8,
            phase: 0.3,
            ..Default::default()
        };
        let x = Vec3A::new(0.5, 0.2, 0.1);
        let back = m.moved::<D3>(&[], x, 0.0, 0.8);
        assert!((back - x).abs().max_element() < 1e-7, "{back:?}");
        // Half a period later the displacement is A (sin(pi + phase) - sin(phase)).
        let half = m.moved::<D3>(&[], x, 0.0, 0.4) - x;
        let want = 0.1 * (-2.0 * 0.3f64.sin());
        assert!((half.x as f64 - want).abs() < 1e-7, "{} vs {want}", half.x);
        let (v0, v1) = (
            m.velocity_at::<D3>(&[], x, 0.0, 0.0),
            m.velocity_at::<D3>(&[], x, 0.8, 0.8),
        );
        assert!((v0 - v1).abs().max_element() < 1e-6);
        let w = 2.0 * PI / 0.8;
        assert!((v0.x as f64 - 0.1 * w * 0.3f64.cos()).abs() < 1e-6);
    }

    #[test]
    fn a_turn_about_a_tilted_axis_leaves_the_axis_and_the_distance_to_it() {
        let n = 1.0 / 3.0f32.sqrt();
        let m = MfMotion {
            pivot: [0.0; 3],
            axis: [n, n, n],
            angle: 0.7,
            angle_period: 2.0,
            ..Default::default()
        };
        let on_axis = Vec3A::splat(0.4);
        assert!((m.moved::<D3>(&[], on_axis, 0.0, 0.37) - on_axis).length() < 1e-7);
        let x = Vec3A::new(1.0, 0.0, 0.0);
        let y = m.moved::<D3>(&[], x, 0.0, 0.5); // a quarter period: theta = 0.7
        let a = Vec3A::splat(n);
        assert!((y.dot(a) - x.dot(a)).abs() < 1e-6);
        assert!((y.length() - 1.0).abs() < 1e-6);
        let turned = (x - a * x.dot(a)).angle_between(y - a * y.dot(a));
        assert!((turned - 0.7).abs() < 1e-5, "{turned}");
    }

    /// The knots of `f` (t -> [s_x, s_y, s_z, theta]) at `n` + 1 times over [0, t_end].
    fn sampled(f: impl Fn(f64) -> [f64; 4], t_end: f64, n: usize) -> Vec<f64> {
        let mut k = Vec::new();
        for j in 0..=n {
            let t = t_end * j as f64 / n as f64;
            k.push(t);
            k.extend(f(t));
        }
        k
    }

    #[test]
    fn a_series_sampled_from_an_oscillation_moves_as_the_oscillation_does() {
        // x = A sin(w t), A = 0.1, period 1, sampled every h = 0.01. Linear interpolation
        // errs by at most A w^2 h^2 / 8 = 4.9e-5 in position; the cubic Hermite's error is
        // of order h^4 in position and h^3 in velocity.
        let (a, w) = (0.1, 2.0 * PI);
        let law = MfMotion {
            amplitude: [a as f32, 0.0, 0.0],
            period: 1.0,
            ..Default::default()
        };
        let knots = sampled(|t| [a * (w * t).sin(), 0.0, 0.0, 0.0], 2.0, 200);
        let series = |cubic| MfMotion {
            series_count: 201,
            series_cubic: cubic,
            ..Default::default()
        };
        let (lin, cub) = (series(0), series(1));
        assert!(!lin.steady());
        let (mut e_lin, mut e_cub, mut ev_lin, mut ev_cub) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for j in 0..1000 {
            let t = 0.0017 + 1.993 * j as f64 / 1000.0;
            let s = law.at(&[], t);
            let (l, c) = (lin.at(&knots, t), cub.at(&knots, t));
            e_lin = e_lin.max((l.s[0] - s.s[0]).abs());
            e_cub = e_cub.max((c.s[0] - s.s[0]).abs());
            ev_lin = ev_lin.max((l.ds[0] - s.ds[0]).abs());
            ev_cub = ev_cub.max((c.ds[0] - s.ds[0]).abs());
        }
        assert!(e_lin < 5.0e-5 && e_lin > 1.0e-5, "linear {e_lin}");
        assert!(e_cub < 2.0e-6, "cubic {e_cub}");
        // The chord's slope is off by up to A w^2 h / 2 = 2.0e-2; the Hermite's by far less.
        assert!(
            ev_lin < 2.0e-2 && ev_lin > 1.0e-2,
            "linear velocity {ev_lin}"
        );
        assert!(ev_cub < 1.0e-3, "cubic velocity {ev_cub}");
        // The cubic's velocity is continuous at a knot; the linear's jumps there, by A w^2 h
        // = 4e-2 at the crest.
        let jump = |m: &MfMotion| {
            (m.at(&knots, 0.25 + 1e-9).ds[0] - m.at(&knots, 0.25 - 1e-9).ds[0]).abs()
        };
        assert!(jump(&cub) < 1.0e-6, "{}", jump(&cub));
        assert!(jump(&lin) > 3.0e-2, "{}", jump(&lin));
        // A particle moved through the series over 2000 steps ends where the law's does.
        let (mut x, mut y) = (Vec2::new(0.3, 0.2), Vec2::new(0.3, 0.2));
        for k in 0..2000 {
            let (t0, t1) = (k as f64 * 1e-3, (k + 1) as f64 * 1e-3);
            x = cub.moved::<D2>(&knots, x, t0, t1);
            y = law.moved::<D2>(&[], y, t0, t1);
        }
        assert!((x - y).abs().max_element() < 2.0e-6, "{x} vs {y}");
    }

    #[test]
    fn a_series_turn_about_its_pivot_is_the_steady_turn_it_samples() {
        // theta = 2 t, sampled every 0.25 s: both interpolations are exact for a line.
        let law = spin(2.0, 0.0);
        let knots = sampled(|t| [0.0, 0.0, 0.0, 2.0 * t], 3.0, 12);
        for cubic in [0, 1] {
            let m = MfMotion {
                pivot: [1.0, 0.5, 0.0],
                axis: [0.0, 0.0, 1.0],
                series_count: 13,
                series_cubic: cubic,
                ..Default::default()
            };
            let (mut x, mut y) = (Vec2::new(2.0, 0.5), Vec2::new(2.0, 0.5));
            for k in 0..2500 {
                let (t0, t1) = (k as f64 * 1e-3, (k + 1) as f64 * 1e-3);
                x = m.moved::<D2>(&knots, x, t0, t1);
                y = law.moved::<D2>(&[], y, t0, t1);
            }
            assert!((x - y).length() < 1e-6, "{x} vs {y}");
            let (v, u) = (
                m.velocity_at::<D2>(&knots, x, 2.5, 2.5),
                law.velocity_at::<D2>(&[], y, 2.5, 2.5),
            );
            assert!((v - u).length() < 1e-5, "{v} vs {u}");
        }
    }

    #[test]
    fn a_series_holds_its_last_pose_after_its_end() {
        let knots = sampled(|t| [0.5 * t, -t, 0.0, 0.1 * t], 1.0, 4);
        let m = MfMotion {
            series_count: 5,
            ..Default::default()
        };
        let end = m.at(&knots, 1.0);
        let later = m.at(&knots, 7.0);
        assert_eq!(later.s, [0.5, -1.0, 0.0]);
        assert_eq!((later.q, later.ds, later.dq), (0.1, [0.0; 3], 0.0));
        assert_eq!(end.s, later.s);
        // A series' knots start at series_first: a second object's after the first's.
        let mut two = knots.clone();
        two.extend(sampled(|t| [t, 0.0, 0.0, 0.0], 1.0, 2));
        let second = MfMotion {
            series_first: 5,
            series_count: 3,
            ..Default::default()
        };
        assert!((second.at(&two, 0.25).s[0] - 0.25).abs() < 1e-15);
    }
}
