// Prescribed rigid motion of a driven object (`MfMotion` in sph_params.h: a piston, a flap, a
// rotating tank, a clamp, a recorded paddle): its pivot's displacement s(t) [L] and turn theta(t)
// [rad] (the laws' plus a series'), their rates, and a particle's move over a step and its velocity. In double precision: a step's
// move is the difference of two poses, rounded to float once. Twin: src/physics/motion.rs;
// parity test: tests/cuda_parity/.
#pragma once
#include "sph_params.h"
#include "vectors.cuh"

// Whether motion m is steady (velocity only, no ramp, no series): its particles take x +=
// velocity dt in float, v = velocity, as a constant-velocity piston always did. Twin:
// `MfMotion::steady`.
__device__ __forceinline__ bool motion_steady(const MfMotion& m) {
    return m.amplitude[0] == 0.0f && m.amplitude[1] == 0.0f && m.amplitude[2] == 0.0f && m.rate == 0.0f &&
           m.angle == 0.0f && m.ramp <= 0.0f && m.series_count == 0;
}

// The smooth start at time t [T]: r = (1 - cos(pi t / T_r)) / 2 up to T_r, then 1; its rate
// dr/dt [1/T]; and its integral over [0, t] [T] (t without a ramp).
struct MotionRamp {
    double r, dr, integral;
};
__device__ __forceinline__ MotionRamp motion_ramp(const MfMotion& m, double t) {
    const double tr = (double)m.ramp;
    if (tr <= 0.0) return {1.0, 0.0, t};
    if (t <= 0.0) return {0.0, 0.0, 0.0};
    if (t >= tr) return {1.0, 0.0, t - 0.5 * tr};
    const double w = 3.14159265358979323846 / tr;
    return {0.5 * (1.0 - cos(w * t)), 0.5 * w * sin(w * t), 0.5 * (t - sin(w * t) / w)};
}

// An oscillation's shape sin(2 pi t / T + phase) - sin(phase) [-] and its rate [1/T]; 0 for
// T <= 0 (no oscillation: the scene check asks for T > 0 where the amplitude is not 0).
struct MotionWave {
    double f, df;
};
__device__ __forceinline__ MotionWave motion_wave(float period, float phase, double t) {
    if (period <= 0.0f) return {0.0, 0.0};
    const double w = 2.0 * 3.14159265358979323846 / (double)period;
    return {sin(w * t + (double)phase) - sin((double)phase), w * cos(w * t + (double)phase)};
}

// The pivot's displacement s(t) [L] and turn theta(t) [rad] at a time, and their rates [L/T],
// [rad/T]. Twin: `physics::motion::At`.
struct MotionAt {
    double s[3], q, ds[3], dq;
};

// A series' interpolation between knots i and i + 1 at t: value and rate of component c (1..4
// of a knot: s_x, s_y, s_z, theta). Linear: the chord; cubic: Hermite with Catmull-Rom tangents
// (one-sided at the ends). Twin: `series_segment`.
__device__ __forceinline__ void motion_series_segment(const double* knots, int n, bool cubic, int i, double t, int c,
                                                      double* f, double* df) {
    const double t0 = knots[i * MF_SERIES_STRIDE], t1 = knots[(i + 1) * MF_SERIES_STRIDE];
    const double h = t1 - t0;
    const double u = (t - t0) / h;
    const double f0 = knots[i * MF_SERIES_STRIDE + c], f1 = knots[(i + 1) * MF_SERIES_STRIDE + c];
    if (!cubic) {
        *f = f0 + (f1 - f0) * u;
        *df = (f1 - f0) / h;
        return;
    }
    double m[2];
#pragma unroll
    for (int e = 0; e < 2; ++e) {
        const int j = i + e;
        const int a = j > 0 ? j - 1 : 0, b = j + 1 < n - 1 ? j + 1 : n - 1;
        m[e] = (knots[b * MF_SERIES_STRIDE + c] - knots[a * MF_SERIES_STRIDE + c]) /
               (knots[b * MF_SERIES_STRIDE] - knots[a * MF_SERIES_STRIDE]) * h;
    }
    const double u2 = u * u, u3 = u * u * u;
    *f = (2.0 * u3 - 3.0 * u2 + 1.0) * f0 + (u3 - 2.0 * u2 + u) * m[0] + (-2.0 * u3 + 3.0 * u2) * f1 +
         (u3 - u2) * m[1];
    const double d = (6.0 * u2 - 6.0 * u) * f0 + (3.0 * u2 - 4.0 * u + 1.0) * m[0] + (-6.0 * u2 + 6.0 * u) * f1 +
                     (3.0 * u2 - 2.0 * u) * m[1];
    *df = d / h;
}

// The n knots of the table series (`Setup::motion_series`) from knot first at time t [T]: their
// values and rates, linear or cubic between knots; held at the first knot before it and at the
// last after it (rates 0); zero without knots. Twin: `knots_at` in src/physics/motion.rs.
__device__ __forceinline__ MotionAt series_knots_at(const double* series, int first, int n, bool cubic, double t) {
    MotionAt at = {{0.0, 0.0, 0.0}, 0.0, {0.0, 0.0, 0.0}, 0.0};
    if (n <= 0) return at;
    const double* knots = series + (size_t)first * MF_SERIES_STRIDE;
    int hold = -1;
    if (n == 1 || t < knots[0]) hold = 0;
    else if (t >= knots[(n - 1) * MF_SERIES_STRIDE]) hold = n - 1;
    if (hold >= 0) {
        const double* k = knots + hold * MF_SERIES_STRIDE;
        at.s[0] = k[1];
        at.s[1] = k[2];
        at.s[2] = k[3];
        at.q = k[4];
        return at;
    }
    // The last knot at or before t: time(lo) <= t < time(hi).
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if (knots[mid * MF_SERIES_STRIDE] <= t) lo = mid;
        else hi = mid;
    }
#pragma unroll
    for (int c = 0; c < 3; ++c) motion_series_segment(knots, n, cubic, lo, t, c + 1, &at.s[c], &at.ds[c]);
    motion_series_segment(knots, n, cubic, lo, t, 4, &at.q, &at.dq);
    return at;
}

// A driven motion's series at time t (`series_knots_at`). Twin: `MfMotion::series_at`.
__device__ __forceinline__ MotionAt motion_series_at(const MfMotion& m, const double* series, double t) {
    return series_knots_at(series, m.series_first, m.series_count, m.series_cubic != 0, t);
}

// The pivot's displacement s(t) from its place at t = 0 [L], the turn theta(t) [rad] and their
// rates at time t [T]: the laws' plus the series'. Twin: `MfMotion::at`.
__device__ __forceinline__ MotionAt motion_at(const MfMotion& m, const double* series, double t) {
    const MotionRamp r = motion_ramp(m, t);
    const MotionWave w = motion_wave(m.period, m.phase, t);
    const MotionWave a = motion_wave(m.angle_period, m.angle_phase, t);
    MotionAt at = motion_series_at(m, series, t);
#pragma unroll
    for (int d = 0; d < 3; ++d) {
        const double v = (double)m.velocity[d], amp = (double)m.amplitude[d];
        at.s[d] += v * r.integral + r.r * amp * w.f;
        at.ds[d] += v * r.r + amp * (r.dr * w.f + r.r * w.df);
    }
    const double rate = (double)m.rate, angle = (double)m.angle;
    at.q += rate * r.integral + r.r * angle * a.f;
    at.dq += rate * r.r + angle * (r.dr * a.f + r.r * a.df);
    return at;
}

// u turned by angle q [rad] about the unit axis (Rodrigues; in 2D about z).
template <int DIM>
__device__ __forceinline__ void motion_rotate(const MfMotion& m, double q, double* u) {
    const double c = cos(q), s = sin(q);
    if constexpr (DIM == 2) {
        const double x = u[0], y = u[1];
        u[0] = c * x - s * y;
        u[1] = s * x + c * y;
    } else {
        const double a[3] = {(double)m.axis[0], (double)m.axis[1], (double)m.axis[2]};
        const double x[3] = {u[0], u[1], u[2]};
        const double ax = a[0] * x[0] + a[1] * x[1] + a[2] * x[2];
        const double cr[3] = {a[1] * x[2] - a[2] * x[1], a[2] * x[0] - a[0] * x[2], a[0] * x[1] - a[1] * x[0]};
        for (int d = 0; d < 3; ++d) u[d] = x[d] * c + cr[d] * s + a[d] * ax * (1.0 - c);
    }
}

// Where a particle of the object at x at time t0 is at t1 [L]: c(t1) + R(theta(t1) -
// theta(t0)) (x - c(t0)), rounded to float once. Twin: `MfMotion::moved`.
template <int DIM>
__device__ __forceinline__ Vec<DIM> motion_moved(const MfMotion& m, const double* series, const Vec<DIM>& x,
                                                 double t0, double t1) {
    const MotionAt a0 = motion_at(m, series, t0), a1 = motion_at(m, series, t1);
    double u[DIM];
#pragma unroll
    for (int d = 0; d < DIM; ++d) u[d] = (double)x.c[d] - ((double)m.pivot[d] + a0.s[d]);
    motion_rotate<DIM>(m, a1.q - a0.q, u);
    Vec<DIM> y;
#pragma unroll
    for (int d = 0; d < DIM; ++d) y.c[d] = (float)((double)m.pivot[d] + a1.s[d] + u[d]);
    return y;
}

// The velocity at time t of the object's particle at x, whose pivot is where it was at t0
// [L/T]: ds/dt + dtheta/dt axis x (x - c(t0)). Twin: `MfMotion::velocity_at`.
template <int DIM>
__device__ __forceinline__ Vec<DIM> motion_velocity(const MfMotion& m, const double* series, const Vec<DIM>& x,
                                                    double t0, double t) {
    const MotionAt at = motion_at(m, series, t);
    const double om = at.dq;
    const MotionAt a0 = motion_at(m, series, t0);
    double u[3] = {0.0, 0.0, 0.0};
#pragma unroll
    for (int d = 0; d < DIM; ++d) u[d] = (double)x.c[d] - ((double)m.pivot[d] + a0.s[d]);
    double w[3];
    if constexpr (DIM == 2) {
        w[0] = -om * u[1];
        w[1] = om * u[0];
    } else {
        const double a[3] = {(double)m.axis[0], (double)m.axis[1], (double)m.axis[2]};
        w[0] = om * (a[1] * u[2] - a[2] * u[1]);
        w[1] = om * (a[2] * u[0] - a[0] * u[2]);
        w[2] = om * (a[0] * u[1] - a[1] * u[0]);
    }
    Vec<DIM> v;
#pragma unroll
    for (int d = 0; d < DIM; ++d) v.c[d] = (float)(at.ds[d] + w[d]);
    return v;
}

// The velocity of a particle at x of driven object k at time t, its object's pivot where it
// was at t0 [L/T]: a steady motion's velocity as it is. Twin: `driven_velocity` in
// src/backend/cpu/integrate.rs.
template <int DIM>
__device__ __forceinline__ Vec<DIM> driven_velocity(const SphParams& p, const double* series, int k, const Vec<DIM>& x,
                                                    double t0, double t) {
    const MfMotion& m = p.driven_motion[k];
    if (!motion_steady(m)) return motion_velocity<DIM>(m, series, x, t0, t);
    Vec<DIM> u;
#pragma unroll
    for (int d = 0; d < DIM; ++d) u.c[d] = m.velocity[d];
    return u;
}

// Where a particle at x of driven object k is after the step [t0, t0 + dt] [L]: a steady
// motion's x + velocity dt in float. Twin: `driven_moved` in src/backend/cpu/integrate.rs.
template <int DIM>
__device__ __forceinline__ Vec<DIM> driven_moved(const SphParams& p, const double* series, int k, const Vec<DIM>& x,
                                                 float dt, double t0) {
    const MfMotion& m = p.driven_motion[k];
    if (!motion_steady(m)) return motion_moved<DIM>(m, series, x, t0, t0 + (double)dt);
    Vec<DIM> u;
#pragma unroll
    for (int d = 0; d < DIM; ++d) u.c[d] = m.velocity[d];
    return x + u * dt;
}
