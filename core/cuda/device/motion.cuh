// Prescribed rigid motion of a driven object (`MfMotion` in sph_params.h: a piston, a flap, a
// rotating tank, a clamp): its pivot's displacement s(t) [L] and turn theta(t) [rad], their
// rates, and a particle's move over a step and its velocity. In double precision: a step's
// move is the difference of two poses, rounded to float once. Twin: src/physics/motion.rs;
// parity test: tests/cuda_parity/.
#pragma once
#include "sph_params.h"
#include "vectors.cuh"

// Whether motion m is steady (velocity only, no ramp): its particles take x += velocity dt in
// float, v = velocity, as a constant-velocity piston always did. Twin: `MfMotion::steady`.
__device__ __forceinline__ bool motion_steady(const MfMotion& m) {
    return m.amplitude[0] == 0.0f && m.amplitude[1] == 0.0f && m.amplitude[2] == 0.0f && m.rate == 0.0f &&
           m.angle == 0.0f && m.ramp <= 0.0f;
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

// The pivot's displacement s(t) [L] along axis a, and its rate ds/dt [L/T].
__device__ __forceinline__ double motion_shift(const MfMotion& m, const MotionRamp& r, const MotionWave& w, int a) {
    return (double)m.velocity[a] * r.integral + r.r * (double)m.amplitude[a] * w.f;
}
__device__ __forceinline__ double motion_shift_rate(const MfMotion& m, const MotionRamp& r, const MotionWave& w, int a) {
    return (double)m.velocity[a] * r.r + (double)m.amplitude[a] * (r.dr * w.f + r.r * w.df);
}
// The turn theta(t) [rad] and its rate [rad/T].
__device__ __forceinline__ double motion_turn(const MfMotion& m, const MotionRamp& r, const MotionWave& w) {
    return (double)m.rate * r.integral + r.r * (double)m.angle * w.f;
}
__device__ __forceinline__ double motion_turn_rate(const MfMotion& m, const MotionRamp& r, const MotionWave& w) {
    return (double)m.rate * r.r + (double)m.angle * (r.dr * w.f + r.r * w.df);
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
__device__ __forceinline__ Vec<DIM> motion_moved(const MfMotion& m, const Vec<DIM>& x, double t0, double t1) {
    const MotionRamp r0 = motion_ramp(m, t0), r1 = motion_ramp(m, t1);
    const MotionWave s0 = motion_wave(m.period, m.phase, t0), s1 = motion_wave(m.period, m.phase, t1);
    const MotionWave q0 = motion_wave(m.angle_period, m.angle_phase, t0);
    const MotionWave q1 = motion_wave(m.angle_period, m.angle_phase, t1);
    double u[DIM];
#pragma unroll
    for (int d = 0; d < DIM; ++d) u[d] = (double)x.c[d] - ((double)m.pivot[d] + motion_shift(m, r0, s0, d));
    motion_rotate<DIM>(m, motion_turn(m, r1, q1) - motion_turn(m, r0, q0), u);
    Vec<DIM> y;
#pragma unroll
    for (int d = 0; d < DIM; ++d) y.c[d] = (float)((double)m.pivot[d] + motion_shift(m, r1, s1, d) + u[d]);
    return y;
}

// The velocity at time t of the object's particle at x, whose pivot is where it was at t0
// [L/T]: ds/dt + dtheta/dt axis x (x - c(t0)). Twin: `MfMotion::velocity_at`.
template <int DIM>
__device__ __forceinline__ Vec<DIM> motion_velocity(const MfMotion& m, const Vec<DIM>& x, double t0, double t) {
    const MotionRamp r0 = motion_ramp(m, t0), r = motion_ramp(m, t);
    const MotionWave s0 = motion_wave(m.period, m.phase, t0), s = motion_wave(m.period, m.phase, t);
    const double om = motion_turn_rate(m, r, motion_wave(m.angle_period, m.angle_phase, t));
    double u[3] = {0.0, 0.0, 0.0};
#pragma unroll
    for (int d = 0; d < DIM; ++d) u[d] = (double)x.c[d] - ((double)m.pivot[d] + motion_shift(m, r0, s0, d));
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
    for (int d = 0; d < DIM; ++d) v.c[d] = (float)(motion_shift_rate(m, r, s, d) + w[d]);
    return v;
}

// The velocity of a particle at x of driven object k at time t, its object's pivot where it
// was at t0 [L/T]: a steady motion's velocity as it is. Twin: `driven_velocity` in
// src/backend/cpu/integrate.rs.
template <int DIM>
__device__ __forceinline__ Vec<DIM> driven_velocity(const SphParams& p, int k, const Vec<DIM>& x, double t0, double t) {
    const MfMotion& m = p.driven_motion[k];
    if (!motion_steady(m)) return motion_velocity<DIM>(m, x, t0, t);
    Vec<DIM> u;
#pragma unroll
    for (int d = 0; d < DIM; ++d) u.c[d] = m.velocity[d];
    return u;
}

// Where a particle at x of driven object k is after the step [t0, t0 + dt] [L]: a steady
// motion's x + velocity dt in float. Twin: `driven_moved` in src/backend/cpu/integrate.rs.
template <int DIM>
__device__ __forceinline__ Vec<DIM> driven_moved(const SphParams& p, int k, const Vec<DIM>& x, float dt, double t0) {
    const MfMotion& m = p.driven_motion[k];
    if (!motion_steady(m)) return motion_moved<DIM>(m, x, t0, t0 + (double)dt);
    Vec<DIM> u;
#pragma unroll
    for (int d = 0; d < DIM; ++d) u.c[d] = m.velocity[d];
    return x + u * dt;
}
