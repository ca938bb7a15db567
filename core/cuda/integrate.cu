// Time integration: the kick (v += dt a; v set in the inflow band; a driven group's
// velocity set) and the drift (x += dt (v + xsph), eq. (18), with the periodic wrap;
// rho += dt d rho/dt, for solids rho_dev += dt d rho/dt and rho = rho0_s + rho_dev; S += dt dS/dt; the device clock; the next grid build's cell counts). dt is read on the device (written
// by sph_step_size): no host round trip per step. The kick and the drift-kick take dt
// from the forces pass's maxima themselves where `red` is given (step_size_of in
// device/step_size.cuh; they write it to dt_dev and leave red for the next grid build's
// scatter to clear), which saves the step-size kernel's launch.
// Twin: src/backend/cpu/integrate.rs; parity test: tests/cuda_parity.rs.
#include "device/entries.cuh"
#include "device/grid.cuh"
#include "device/packing.cuh"
#include "device/particle.cuh"
#include "device/step_size.cuh"
#include "device/vectors.cuh"

// The driven group: `is_driven` in device/particle.cuh. The group array is read only where a group
// is driven (its one use here; 4 B per particle less in every other scene).
__device__ __forceinline__ unsigned driven_test_group(const SphParams& p, const unsigned* __restrict__ group,
                                                      unsigned i) {
    return p.driven ? group[i] : 0u;
}

// The kick of one particle (kind k, group g, position x): v += dt a; the velocity of the
// inflow band (`p.inflow`: fluid particles with inflow_lo <= x[inflow_axis] < inflow_hi;
// twin: `in_inflow_band`) or of the driven group instead; false where v stays (walls).
template <int DIM>
__device__ __forceinline__ bool kick_one(const SphParams& p, unsigned char k, unsigned g, const Vec<DIM>& x, float dt,
                                         const float* __restrict__ acc, unsigned i, Vec<DIM>& v) {
    if (p.inflow && k == MF_KIND_FLUID) {
        const float c = x.c[p.inflow_axis];
        if (c >= p.inflow_lo && c < p.inflow_hi) {
#pragma unroll
            for (int d = 0; d < DIM; ++d) v.c[d] = p.inflow_velocity[d];
            return true;
        }
    }
    // Driven group: prescribed velocity, whatever the forces.
    if (is_driven(p, g)) {
#pragma unroll
        for (int d = 0; d < DIM; ++d) v.c[d] = p.driven_velocity[d];
        return true;
    }
    if (k == MF_KIND_BOUNDARY) return false;
    v = v + vload<DIM>(acc, i) * dt;
    return true;
}

// dt_dev holds 2 floats: [0] this step's dt (written by the kick, the drift-kick or
// sph_step_size), [1] the last completed step's (written by the drift; 0 before the first
// step): the leapfrog's kick spans their mean.

// The time a kick spans [T]: dt, or under the leapfrog (dt_prev + dt) / 2, from the middle
// of the last step to the middle of this one. Twin: `kick_span` in cpu/integrate.rs.
__device__ __forceinline__ float kick_span(const SphParams& p, const float* __restrict__ dt_dev, float dt) {
    return p.integrator == MF_INTEGRATOR_LEAPFROG ? 0.5f * (dt_dev[1] + dt) : dt;
}

// The step's dt: from the forces pass's maxima `red` where given (every thread computes it,
// the first writes it to dt_dev[0]), else the one sph_step_size wrote to dt_dev[0].
__device__ __forceinline__ float step_dt(const SphParams& p, const unsigned* __restrict__ red,
                                         float* __restrict__ dt_dev) {
    if (!red) return *dt_dev;
    const float dt = step_size_of(p, red);
    if (blockIdx.x == 0 && threadIdx.x == 0) *dt_dev = dt;
    return dt;
}

template <int DIM>
__device__ void sph_kick_body(const SphParams p, unsigned n, float* __restrict__ dt_dev, const unsigned* __restrict__ red,
                              const unsigned char* __restrict__ kind, const unsigned* __restrict__ group,
                              const float* __restrict__ pos, float* __restrict__ vel,
                              const float* __restrict__ acc) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    const float dt = kick_span(p, dt_dev, step_dt(p, red, dt_dev));
    if (i >= n) return;
    const Vec<DIM> x = p.inflow ? vload<DIM>(pos, i) : vzero<DIM>();
    Vec<DIM> v = vel_load<DIM>(vel, i);
    if (kick_one<DIM>(p, kind[i], driven_test_group(p, group, i), x, dt, acc, i, v)) vel_store<DIM>(vel, i, v);  // keeps rho, m
}
MF_ENTRY2(sph_kick,
          (const SphParams p, unsigned n, float* dt_dev, const unsigned* red, const unsigned char* kind, const unsigned* group,
           const float* pos, float* vel, const float* acc),
          (p, n, dt_dev, red, kind, group, pos, vel, acc))

// The drift of one particle (kind k, group g, velocity v) by dt; returns its new position.
// drho: null without the continuity density; rho_dev, stress, rate: null without solids. The callers
// then file the particle in its cell for the next grid build (hist_one).
template <int DIM>
__device__ __forceinline__ Vec<DIM> drift_one(const SphParams& p, unsigned n, unsigned i, unsigned char k, unsigned g,
                                              const Vec<DIM>& v, float dt, float* __restrict__ pos,
                                              const float* __restrict__ xsph, float* __restrict__ rho,
                                              const float* __restrict__ drho, float* __restrict__ rho_dev,
                                              float* __restrict__ stress, const float* __restrict__ rate) {
    // Dynamic wall particles take part; their d rho/dt is zero otherwise. Under
    // wall_density_floor a wall's density is held at >= rho0 (`wall_density_floor` in
    // src/backend/cpu/integrate.rs; DualSPHysics' DBC).
    // Solids integrate their departure from rest, rho_dev += dt d rho/dt, and take
    // rho = rho0_s + rho_dev [M/L^3] (SolidState::rho_dev: in rho itself a stiff solid's change
    // per step rounds away). S below needs none: it starts at zero (see `drift` in
    // src/backend/cpu/integrate.rs).
    if (drho) {
        if (rho_dev && k == MF_KIND_SOLID) {
            const float d = rho_dev[i] + dt * drho[i];
            rho_dev[i] = d;
            rho[i] = p.solid_rho0 + d;
        } else {
            float r = rho[i] + dt * drho[i];
            if (p.wall_density_floor && k == MF_KIND_BOUNDARY) r = fmaxf(r, p.rho0);
            rho[i] = r;
        }
    }
    Vec<DIM> x = vload<DIM>(pos, i);
    // A driven group moves at its prescribed velocity (no XSPH), whatever its kind.
    const bool driven = is_driven(p, g);
    if (k == MF_KIND_BOUNDARY && !driven) return x;
    if (driven) {
        Vec<DIM> u;
#pragma unroll
        for (int d = 0; d < DIM; ++d) u.c[d] = p.driven_velocity[d];
        x = x + u * dt;
    } else {
        x = x + (v + vload<DIM>(xsph, i)) * dt;  // eq. (18)
    }
#pragma unroll
    for (int d = 0; d < DIM; ++d) {  // wrap on periodic axes
        if (p.periodic[d]) {
            const float lo = p.domain_min[d], hi = p.domain_max[d];
            if (x.c[d] < lo) x.c[d] += hi - lo;
            else if (x.c[d] >= hi) x.c[d] -= hi - lo;
        }
    }
    vstore_keep_w<DIM>(pos, i, x);  // w: the mass in 3D (vel_load in device/packing.cuh)
    if (stress && k == MF_KIND_SOLID) {
#pragma unroll
        for (int c = 0; c < Sym<DIM>::N; ++c) stress[c * n + i] += rate[c * n + i] * dt;
    }
    return x;
}

template <int DIM>
__device__ void sph_drift_body(const SphParams p, unsigned n, float* __restrict__ dt_dev,
                               double* __restrict__ time, const unsigned char* __restrict__ kind,
                               const unsigned* __restrict__ group, float* __restrict__ pos, const float* __restrict__ vel,
                               const float* __restrict__ xsph, float* __restrict__ rho,
                               const float* __restrict__ drho, float* __restrict__ rho_dev,
                               float* __restrict__ stress, const float* __restrict__ rate, unsigned* __restrict__ cell,
                               unsigned* __restrict__ count) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    const float dt = dt_dev[0];
    if (i == 0) {
        *time += (double)dt;
        dt_dev[1] = dt;  // the step is done: the next kick's dt_prev
    }
    if (i >= n) return;
    const Vec<DIM> x =
        drift_one<DIM>(p, n, i, kind[i], driven_test_group(p, group, i), vel_load<DIM>(vel, i), dt, pos, xsph, rho, drho, rho_dev, stress, rate);
    hist_one<DIM>(p, i, x, cell, count);
}
MF_ENTRY2(sph_drift,
          (const SphParams p, unsigned n, float* dt_dev, double* time, const unsigned char* kind,
           const unsigned* group, float* pos, const float* vel, const float* xsph, float* rho, const float* drho,
           float* rho_dev, float* stress, const float* rate, unsigned* cell, unsigned* count),
          (p, n, dt_dev, time, kind, group, pos, vel, xsph, rho, drho, rho_dev, stress, rate, cell, count))

// The forward Euler's drift then kick in one pass (`Solver::drift_kick`): the drift takes
// the old velocity, the kick's inflow test the new position, as the two kernels in turn.
template <int DIM>
__device__ void sph_drift_kick_body(const SphParams p, unsigned n, float* __restrict__ dt_dev,
                                    const unsigned* __restrict__ red, double* __restrict__ time, const unsigned char* __restrict__ kind,
                                    const unsigned* __restrict__ group, float* __restrict__ pos,
                                    float* __restrict__ vel, const float* __restrict__ xsph,
                                    float* __restrict__ rho, const float* __restrict__ drho,
                                    float* __restrict__ rho_dev, float* __restrict__ stress, const float* __restrict__ rate,
                                    const float* __restrict__ acc, unsigned* __restrict__ cell,
                                    unsigned* __restrict__ count) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    const float dt = step_dt(p, red, dt_dev);
    if (i == 0) *time += (double)dt;
    if (i >= n) return;
    const unsigned char k = kind[i];
    const unsigned g = driven_test_group(p, group, i);
    Vec<DIM> v = vel_load<DIM>(vel, i);
    const Vec<DIM> x = drift_one<DIM>(p, n, i, k, g, v, dt, pos, xsph, rho, drho, rho_dev, stress, rate);
    if (kick_one<DIM>(p, k, g, x, dt, acc, i, v)) vel_store<DIM>(vel, i, v);  // keeps rho, m
    hist_one<DIM>(p, i, x, cell, count);
}
MF_ENTRY2(sph_drift_kick,
          (const SphParams p, unsigned n, float* dt_dev, const unsigned* red, double* time, const unsigned char* kind,
           const unsigned* group, float* pos, float* vel, const float* xsph, float* rho, const float* drho,
           float* rho_dev, float* stress, const float* rate, const float* acc, unsigned* cell, unsigned* count),
          (p, n, dt_dev, red, time, kind, group, pos, vel, xsph, rho, drho, rho_dev, stress, rate, acc, cell, count))
