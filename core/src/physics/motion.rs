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
//! without a ramp) and I(t) its integral over [0, t] (t without a ramp). Evaluated in double
//! precision from the simulated time, so a step's move is the difference of two exact poses:
//! a rotating tank keeps its radius over any number of steps. Twin:
//! `cuda/device/motion.cuh`; parity test `tests/cuda_parity/`.

use std::f64::consts::PI;

use super::dim::Dim;
use super::params::MfMotion;

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

impl MfMotion {
    /// Velocity only and no ramp: the particles take x += velocity dt in float and
    /// v = velocity, as a constant-velocity piston always did. Twin: `motion_steady`.
    pub fn steady(&self) -> bool {
        self.amplitude == [0.0; 3] && self.rate == 0.0 && self.angle == 0.0 && self.ramp <= 0.0
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

    fn shift(&self, r: Ramp, w: Wave, a: usize) -> f64 {
        self.velocity[a] as f64 * r.integral + r.r * self.amplitude[a] as f64 * w.f
    }

    fn shift_rate(&self, r: Ramp, w: Wave, a: usize) -> f64 {
        self.velocity[a] as f64 * r.r + self.amplitude[a] as f64 * (r.dr * w.f + r.r * w.df)
    }

    fn turn(&self, r: Ramp, w: Wave) -> f64 {
        self.rate as f64 * r.integral + r.r * self.angle as f64 * w.f
    }

    fn turn_rate(&self, r: Ramp, w: Wave) -> f64 {
        self.rate as f64 * r.r + self.angle as f64 * (r.dr * w.f + r.r * w.df)
    }

    /// The pivot's displacement s(t) from its place at t = 0 \[L\] and the turn theta(t)
    /// \[rad\] at time t \[T\].
    pub fn pose(&self, t: f64) -> ([f64; 3], f64) {
        let r = self.ramp_at(t);
        let w = wave(self.period, self.phase, t);
        let q = wave(self.angle_period, self.angle_phase, t);
        ([0, 1, 2].map(|a| self.shift(r, w, a)), self.turn(r, q))
    }

    /// `u` turned as the object has turned by time `t` \[T\]: by theta(t) about its axis
    /// (`pose`, `rotate`). Twin: `motion_turn` and `motion_rotate` in `cuda/device/motion.cuh`.
    pub fn turn_vector<D: Dim>(&self, t: f64, u: &mut [f64; 3]) {
        let (_, q) = self.pose(t);
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

    /// The arm of a particle at `x` at time `t0` from the pivot then, x - c(t0) \[L\].
    fn arm<D: Dim>(&self, x: D::V, t0: f64) -> [f64; 3] {
        let (r0, s0) = (self.ramp_at(t0), wave(self.period, self.phase, t0));
        let x = D::to3(x);
        let mut u = [0.0; 3];
        for (d, u) in u.iter_mut().enumerate().take(D::D) {
            *u = x[d] as f64 - (self.pivot[d] as f64 + self.shift(r0, s0, d));
        }
        u
    }

    /// Where the object's particle at `x` at time `t0` is at `t1` \[L\]:
    /// c(t1) + R(theta(t1) - theta(t0)) (x - c(t0)), rounded to float once. Twin:
    /// `motion_moved`.
    pub fn moved<D: Dim>(&self, x: D::V, t0: f64, t1: f64) -> D::V {
        let (r0, r1) = (self.ramp_at(t0), self.ramp_at(t1));
        let s1 = wave(self.period, self.phase, t1);
        let q0 = wave(self.angle_period, self.angle_phase, t0);
        let q1 = wave(self.angle_period, self.angle_phase, t1);
        let mut u = self.arm::<D>(x, t0);
        self.rotate::<D>(self.turn(r1, q1) - self.turn(r0, q0), &mut u);
        let mut y = [0.0f32; 3];
        for (d, y) in y.iter_mut().enumerate().take(D::D) {
            *y = (self.pivot[d] as f64 + self.shift(r1, s1, d) + u[d]) as f32;
        }
        D::from3(y)
    }

    /// The velocity at time `t` of the object's particle at `x`, its pivot where it was at
    /// `t0` \[L/T\]: ds/dt + dtheta/dt axis x (x - c(t0)). Twin: `motion_velocity`.
    pub fn velocity_at<D: Dim>(&self, x: D::V, t0: f64, t: f64) -> D::V {
        let (r, s) = (self.ramp_at(t), wave(self.period, self.phase, t));
        let om = self.turn_rate(r, wave(self.angle_period, self.angle_phase, t));
        let u = self.arm::<D>(x, t0);
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
            *v = (self.shift_rate(r, s, d) + w[d]) as f32;
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
            x = m.moved::<D2>(x, k as f64 * dt, (k + 1) as f64 * dt);
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
        assert_eq!(m.pose(0.0).1, 0.0);
        let v0 = m.velocity_at::<D2>(Vec2::new(2.0, 0.5), 0.0, 0.0);
        assert_eq!(v0, Vec2::ZERO);
        // theta(t) against the trapezoidal integral of its rate, through and past the ramp.
        let (mut sum, h) = (0.0, 1.0e-4);
        let rate = |t: f64| {
            let v = m.velocity_at::<D2>(Vec2::new(2.0, 0.5), t, t);
            v.y as f64 // the arm is (1, 0): v = omega x arm = (0, omega)
        };
        for k in 0..10_000 {
            let t = k as f64 * h;
            sum += 0.5 * h * (rate(t) + rate(t + h));
        }
        let theta = m.pose(1.0).1;
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
        let back = m.moved::<D3>(x, 0.0, 0.8);
        assert!((back - x).abs().max_element() < 1e-7, "{back:?}");
        // Half a period later the displacement is A (sin(pi + phase) - sin(phase)).
        let half = m.moved::<D3>(x, 0.0, 0.4) - x;
        let want = 0.1 * (-2.0 * 0.3f64.sin());
        assert!((half.x as f64 - want).abs() < 1e-7, "{} vs {want}", half.x);
        let (v0, v1) = (
            m.velocity_at::<D3>(x, 0.0, 0.0),
            m.velocity_at::<D3>(x, 0.8, 0.8),
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
        assert!((m.moved::<D3>(on_axis, 0.0, 0.37) - on_axis).length() < 1e-7);
        let x = Vec3A::new(1.0, 0.0, 0.0);
        let y = m.moved::<D3>(x, 0.0, 0.5); // a quarter period: theta = 0.7
        let a = Vec3A::splat(n);
        assert!((y.dot(a) - x.dot(a)).abs() < 1e-6);
        assert!((y.length() - 1.0).abs() < 1e-6);
        let turned = (x - a * x.dot(a)).angle_between(y - a * y.dot(a));
        assert!((turned - 0.7).abs() < 1e-5, "{turned}");
    }
}
