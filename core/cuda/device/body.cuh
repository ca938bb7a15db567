// Floating rigid bodies (`MfBody` in sph_params.h): the Newton-Euler kick and drift of one
// body, and a particle's move and velocity with it, in double precision. Twin:
// src/physics/body.rs (the equations and the integrator there); parity test:
// tests/cuda_parity/.
#pragma once
#include "sph_params.h"
#include "vectors.cuh"

// The rotation matrix (row-major) of the unit quaternion q = (w, x, y, z). Twin: `matrix`.
__device__ __forceinline__ void body_matrix(const double* q, double* m) {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    m[0] = 1.0 - 2.0 * (y * y + z * z);
    m[1] = 2.0 * (x * y - w * z);
    m[2] = 2.0 * (x * z + w * y);
    m[3] = 2.0 * (x * y + w * z);
    m[4] = 1.0 - 2.0 * (x * x + z * z);
    m[5] = 2.0 * (y * z - w * x);
    m[6] = 2.0 * (x * z - w * y);
    m[7] = 2.0 * (y * z + w * x);
    m[8] = 1.0 - 2.0 * (x * x + y * y);
}

__device__ __forceinline__ bool body_moves(const MfBody& b, int a) { return (b.free >> a) & 1; }
__device__ __forceinline__ bool body_turns(const MfBody& b, int a) { return (b.free >> (3 + a)) & 1; }

// The angular velocity [rad/T] of angular momentum l at the body's orientation: I_w^-1 L over
// the free axes (held rows and columns the identity, their components zero). Twin:
// `MfBody::omega_of`.
__device__ __forceinline__ void body_omega(const MfBody& b, const double* l, double* w) {
    double r[9], iw[9];
    body_matrix(b.orientation, r);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0.0;
            for (int k = 0; k < 3; ++k)
                for (int m = 0; m < 3; ++m) s += r[3 * i + k] * b.inertia[3 * k + m] * r[3 * j + m];
            iw[3 * i + j] = s;
        }
    for (int a = 0; a < 3; ++a)
        if (!body_turns(b, a))
            for (int c = 0; c < 3; ++c) {
                iw[3 * a + c] = a == c ? 1.0 : 0.0;
                iw[3 * c + a] = a == c ? 1.0 : 0.0;
            }
    const double c[9] = {iw[4] * iw[8] - iw[5] * iw[7], iw[2] * iw[7] - iw[1] * iw[8], iw[1] * iw[5] - iw[2] * iw[4],
                         iw[5] * iw[6] - iw[3] * iw[8], iw[0] * iw[8] - iw[2] * iw[6], iw[2] * iw[3] - iw[0] * iw[5],
                         iw[3] * iw[7] - iw[4] * iw[6], iw[1] * iw[6] - iw[0] * iw[7], iw[0] * iw[4] - iw[1] * iw[3]};
    const double det = iw[0] * c[0] + iw[1] * c[3] + iw[2] * c[6];
    for (int a = 0; a < 3; ++a) {
        double s = 0.0;
        if (det != 0.0)
            for (int k = 0; k < 3; ++k) s += (c[3 * a + k] / det) * l[k];
        w[a] = body_turns(b, a) ? s : 0.0;
    }
}

// The kick over span [T] under load = (fluid force, its torque, contact force, its torque):
// V += span (F + C + M g) / M, L += span (T + T_C) along the free axes, omega from L. Twin:
// `MfBody::kick`.
__device__ __forceinline__ void body_kick(MfBody& b, const double* load, const float* g, float span) {
    const double s = (double)span;
    for (int a = 0; a < 3; ++a) {
        b.force[a] = load[a];
        b.torque[a] = load[3 + a];
        b.contact[a] = load[6 + a];
        b.contact_torque[a] = load[9 + a];
        if (body_moves(b, a)) {
            const double f = load[a] + load[6 + a] + b.mass * (double)g[a];
            b.velocity[a] += s * f / b.mass;
        }
        if (body_turns(b, a)) b.momentum[a] += s * (load[3 + a] + load[9 + a]);
    }
    body_omega(b, b.momentum, b.omega);
}

// The drift over dt [T]: c += dt V, q turned by the rotation vector dt omega (kept with the
// shift for the particles) and renormalised. Twin: `MfBody::drift`.
__device__ __forceinline__ void body_drift(MfBody& b, float dt_f) {
    const double dt = (double)dt_f;
    for (int a = 0; a < 3; ++a) {
        b.shift[a] = dt * b.velocity[a];
        b.centre[a] += b.shift[a];
    }
    const double phi[3] = {b.omega[0] * dt, b.omega[1] * dt, b.omega[2] * dt};
    const double angle = sqrt(phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]);
    double dq[4] = {1.0, 0.0, 0.0, 0.0};
    if (angle > 0.0) {
        const double s = sin(0.5 * angle), c = cos(0.5 * angle);
        dq[0] = c;
        dq[1] = s * phi[0] / angle;
        dq[2] = s * phi[1] / angle;
        dq[3] = s * phi[2] / angle;
    }
    body_matrix(dq, b.turn);
    const double* q = b.orientation;
    double r[4] = {dq[0] * q[0] - dq[1] * q[1] - dq[2] * q[2] - dq[3] * q[3],
                   dq[0] * q[1] + dq[1] * q[0] + dq[2] * q[3] - dq[3] * q[2],
                   dq[0] * q[2] - dq[1] * q[3] + dq[2] * q[0] + dq[3] * q[1],
                   dq[0] * q[3] + dq[1] * q[2] - dq[2] * q[1] + dq[3] * q[0]};
    const double n = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
    for (int k = 0; k < 4; ++k) b.orientation[k] = r[k] / n;
    body_omega(b, b.momentum, b.omega);
}

// Where the last drift took a particle that was at x [L]: centre + turn (x - centre + shift).
// Twin: `MfBody::moved`.
template <int DIM>
__device__ __forceinline__ Vec<DIM> body_moved(const MfBody& b, const Vec<DIM>& x) {
    double u[3] = {0.0, 0.0, 0.0};
    for (int a = 0; a < 3; ++a) u[a] = (a < DIM ? (double)x.c[a] : 0.0) - b.centre[a] + b.shift[a];
    Vec<DIM> y;
#pragma unroll
    for (int a = 0; a < DIM; ++a)
        y.c[a] = (float)(b.centre[a] + (b.turn[3 * a] * u[0] + b.turn[3 * a + 1] * u[1] + b.turn[3 * a + 2] * u[2]));
    return y;
}

// The velocity of the body's point at x [L/T]: V + omega x (x - c). Twin:
// `MfBody::velocity_at`.
template <int DIM>
__device__ __forceinline__ Vec<DIM> body_point_velocity(const MfBody& b, const Vec<DIM>& x) {
    double u[3] = {0.0, 0.0, 0.0};
    for (int a = 0; a < 3; ++a) u[a] = (a < DIM ? (double)x.c[a] : 0.0) - b.centre[a];
    const double w[3] = {b.omega[1] * u[2] - b.omega[2] * u[1], b.omega[2] * u[0] - b.omega[0] * u[2],
                         b.omega[0] * u[1] - b.omega[1] * u[0]};
    Vec<DIM> v;
#pragma unroll
    for (int a = 0; a < DIM; ++a) v.c[a] = (float)(b.velocity[a] + w[a]);
    return v;
}

// The body whose particles boundary particle i of group g is (-1: none). Twin: `body_of`.
__device__ __forceinline__ int body_index(unsigned n_bodies, const MfBody* __restrict__ bodies, unsigned char k,
                                          unsigned g) {
    if (k != MF_KIND_BOUNDARY) return -1;
    for (unsigned b = 0; b < n_bodies; ++b)
        if ((unsigned)bodies[b].group == g) return (int)b;
    return -1;
}
