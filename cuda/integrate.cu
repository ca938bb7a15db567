// Time integration: the kick (v += dt a; v set in the inflow band; a driven group's
// velocity set) and the drift (x += dt (v + xsph), eq. (18), with the periodic wrap;
// rho += dt d rho/dt; S += dt dS/dt; the device clock). dt is read on the device (written
// by sph_step_size): no host round trip per step.
// Twin: src/backend/cpu/integrate.rs; parity test: tests/cuda_parity.rs.
#include "common.cuh"

// The driven group: `is_driven` in common.cuh.

// Inflow band (`p.inflow`): fluid particles with inflow_lo <= x[inflow_axis] < inflow_hi
// get their velocity set to inflow_velocity instead of integrated (twin: `in_inflow_band`).
template <int DIM>
__device__ void sph_kick_body(const SphParams p, unsigned n, const float* __restrict__ dt_dev,
                              const unsigned char* __restrict__ kind, const unsigned* __restrict__ group,
                              const float* __restrict__ pos, float* __restrict__ vel,
                              const float* __restrict__ acc) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    if (p.inflow && kind[i] == MF_KIND_FLUID) {
        const float c = vload<DIM>(pos, i).c[p.inflow_axis];
        if (c >= p.inflow_lo && c < p.inflow_hi) {
            Vec<DIM> v;
#pragma unroll
            for (int d = 0; d < DIM; ++d) v.c[d] = p.inflow_velocity[d];
            vel_store<DIM>(vel, i, v);
            return;
        }
    }
    // Driven group: prescribed velocity, whatever the forces.
    if (is_driven(p, group[i])) {
        Vec<DIM> u;
#pragma unroll
        for (int d = 0; d < DIM; ++d) u.c[d] = p.driven_velocity[d];
        vel_store<DIM>(vel, i, u);
        return;
    }
    if (kind[i] == MF_KIND_BOUNDARY) return;
    const float dt = *dt_dev;
    vel_store<DIM>(vel, i, vel_load<DIM>(vel, i) + vload<DIM>(acc, i) * dt);  // keeps rho, m (common.cuh)
}
MF_ENTRY2(sph_kick,
          (const SphParams p, unsigned n, const float* dt_dev, const unsigned char* kind, const unsigned* group,
           const float* pos, float* vel, const float* acc),
          (p, n, dt_dev, kind, group, pos, vel, acc))

// drho: null without the continuity density; stress, rate: null without solids.
template <int DIM>
__device__ void sph_drift_body(const SphParams p, unsigned n, const float* __restrict__ dt_dev,
                               double* __restrict__ time, const unsigned char* __restrict__ kind,
                               const unsigned* __restrict__ group, float* __restrict__ pos, const float* __restrict__ vel,
                               const float* __restrict__ xsph, float* __restrict__ rho,
                               const float* __restrict__ drho, float* __restrict__ stress,
                               const float* __restrict__ rate) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    const float dt = *dt_dev;
    if (i == 0) *time += (double)dt;
    if (i >= n) return;
    const unsigned char k = kind[i];
    // Dynamic wall particles take part; their d rho/dt is zero otherwise. Under
    // wall_rho_floor a wall's density is held at >= rho0 (`wall_density_floor` in
    // src/backend/cpu/integrate.rs; DualSPHysics' DBC).
    if (drho) {
        float r = rho[i] + dt * drho[i];
        if (p.wall_rho_floor && k == MF_KIND_BOUNDARY) r = fmaxf(r, p.rho0);
        rho[i] = r;
    }
    // A driven group moves at its prescribed velocity (no XSPH), whatever its kind.
    const bool driven = is_driven(p, group[i]);
    if (k == MF_KIND_BOUNDARY && !driven) return;
    Vec<DIM> x;
    if (driven) {
        Vec<DIM> u;
#pragma unroll
        for (int d = 0; d < DIM; ++d) u.c[d] = p.driven_velocity[d];
        x = vload<DIM>(pos, i) + u * dt;
    } else {
        x = vload<DIM>(pos, i) + (vel_load<DIM>(vel, i) + vload<DIM>(xsph, i)) * dt;
    }
#pragma unroll
    for (int d = 0; d < DIM; ++d) {  // wrap on periodic axes
        if (p.periodic[d]) {
            const float lo = p.domain_min[d], hi = p.domain_max[d];
            if (x.c[d] < lo) x.c[d] += hi - lo;
            else if (x.c[d] >= hi) x.c[d] -= hi - lo;
        }
    }
    vstore_keep_w<DIM>(pos, i, x);  // w: the mass in 3D (vel_load in common.cuh)
    if (stress && k == MF_KIND_SOLID) {
#pragma unroll
        for (int c = 0; c < Sym<DIM>::N; ++c) stress[c * n + i] += rate[c * n + i] * dt;
    }
}
MF_ENTRY2(sph_drift,
          (const SphParams p, unsigned n, const float* dt_dev, double* time, const unsigned char* kind,
           const unsigned* group, float* pos, const float* vel, const float* xsph, float* rho, const float* drho,
           float* stress, const float* rate),
          (p, n, dt_dev, time, kind, group, pos, vel, xsph, rho, drho, stress, rate))
