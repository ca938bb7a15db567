// Time integration: the kick (v += dt a; v set in the inflow band, ramped from rest under
// `inflow_ramp`, which also accelerates the rest uniformly; a driven group's velocity set) and the drift (x += dt (v + xsph), eq. (18), with the periodic wrap;
// rho += dt d rho/dt, for solids rho_dev += dt d rho/dt and rho = rho0_s + rho_dev; S += dt dS/dt; the device clock; the next grid build's cell counts). dt is read on the device (written
// by sph_step_size): no host round trip per step. The kick and the drift-kick take dt
// from the forces pass's maxima themselves where `red` is given (step_size_of in
// device/step_size.cuh; they write it to dt_dev and leave red for the next grid build's
// scatter to clear), which saves the step-size kernel's launch.
// Twin: src/backend/cpu/integrate.rs; parity test: tests/cuda_parity/.
#include "device/entries.cuh"
#include "device/grid.cuh"
#include "device/motion.cuh"
#include "device/open.cuh"
#include "device/packing.cuh"
#include "device/particle.cuh"
#include "device/step_size.cuh"
#include "device/vectors.cuh"

// The driven group: `is_driven` in device/particle.cuh. The group array is read only where a group
// is driven (its one use here; 4 B per particle less in every other scene).
__device__ __forceinline__ unsigned driven_test_group(const SphParams& p, const unsigned* __restrict__ group,
                                                      unsigned i) {
    return p.driven || p.open_count ? group[i] : 0u;
}

// The ramp of a ramped start [-] (`inflow_ramp` T_r > 0): r = (1 - cos(pi t / T_r)) / 2 for
// 0 <= t < T_r, 0 before, 1 after; 1 without a ramp and under the forward Euler (the scene
// check rejects that pair: the fused drift-kick below advances the clock in its own pass).
// In double precision: the kick takes its difference over one step. Twin: `ramp_share` in
// src/backend/cpu/integrate.rs.
__device__ __forceinline__ double ramp_share(const SphParams& p, double t) {
    const double tr = (double)p.inflow_ramp;
    if (!p.inflow || tr <= 0.0 || t >= tr || p.integrator == MF_INTEGRATOR_EULER) return 1.0;
    if (t <= 0.0) return 0.0;
    return 0.5 * (1.0 - cos(3.14159265358979323846 * t / tr));
}

// The time a kick taken at time t (the step's start) brings the velocities to [T]: t + dt,
// under the leapfrog t + dt / 2. Twin: `kick_end` in src/backend/cpu/integrate.rs.
__device__ __forceinline__ double kick_end(const SphParams& p, double t, float dt) {
    return p.integrator == MF_INTEGRATOR_LEAPFROG ? t + 0.5 * (double)dt : t + (double)dt;
}

// The damping zone's factor on a fluid particle's velocity over a kick of dt at coordinate c
// along damping_axis: exp(-damping_rate r^2 dt), r = (c - start) / (end - start) in [0, 1]
// (`damping` in sph_params.h). Twin: `damping_factor` in src/backend/cpu/integrate.rs.
__device__ __forceinline__ float damping_factor(const SphParams& p, float c, float dt) {
    const float r = fminf(fmaxf((c - p.damping_start) / (p.damping_end - p.damping_start), 0.0f), 1.0f);
    return expf(-p.damping_rate * r * r * dt);
}

// The kick of one particle (kind k, group g, position x at the step's start t0, the kick
// ending at te): v += dt a + r_step inflow_velocity
// (r_step: the ramp's increase over the kick, 0 without a ramp: a uniform body force, so
// that the fluid outside the band keeps pace with it); the velocity of the inflow band
// (`p.inflow`: fluid particles with inflow_lo <= x[inflow_axis] < inflow_hi; twin:
// `in_inflow_band`), r_now inflow_velocity, or a driven object's velocity at x at te
// (`driven_velocity` in device/motion.cuh) instead; then a fluid particle in the damping zone
// slowed (`damping_factor`); false where v stays (walls). Twin: `kick`
// in src/backend/cpu/integrate.rs.
template <int DIM>
__device__ __forceinline__ bool kick_one(const SphParams& p, unsigned char k, unsigned g, const Vec<DIM>& x, float dt,
                                         float r_now, float r_step, double t0, double te,
                                         const float* __restrict__ acc, const double* __restrict__ series, unsigned i,
                                         Vec<DIM>& v) {
    // An open boundary's buffer: an inlet's prescribed velocity r(t) f(x) velocity, an
    // outlet's as it is (`buffer_velocity` in src/physics/open.rs).
    if (const int ob = open_index(p, g); ob >= 0) {
        const MfOpen& o = p.open[ob];
        if (o.kind != MF_OPEN_INLET) return false;
        // open_profile reads only the axes of profile_axes: below DIM.
        // The series' scale a(t) (its knots' s_x), 1 without one (`MfOpen::scale`).
        const double scale =
            o.series_count > 0 ? series_knots_at(series, o.series_first, o.series_count, o.series_cubic != 0, te).s[0]
                               : 1.0;
        const float r = (float)(smooth_ramp((double)o.ramp, te) * scale) * open_profile(o, x.c);
#pragma unroll
        for (int d = 0; d < DIM; ++d) v.c[d] = o.velocity[d] * r;
        return true;
    }
    Vec<DIM> u;
#pragma unroll
    for (int d = 0; d < DIM; ++d) u.c[d] = p.inflow_velocity[d];
    if (p.inflow && k == MF_KIND_FLUID) {
        const float c = x.c[p.inflow_axis];
        if (c >= p.inflow_lo && c < p.inflow_hi) {
            v = u * r_now;
            return true;
        }
    }
    // Driven object: prescribed velocity, whatever the forces; a floating body's particles
    // are left to its kick (sph_body_velocity in bodies.cu).
    if (const int dk = driven_index(p, g); dk >= 0 && !p.driven_motion[dk].floating) {
        v = driven_velocity<DIM>(p, series, dk, x, t0, te);
        return true;
    }
    if (k == MF_KIND_BOUNDARY) return false;
    v = v + vload<DIM>(acc, i) * dt;
    v = v + u * r_step;
    if (p.damping && k == MF_KIND_FLUID) v = v * damping_factor(p, x.c[p.damping_axis], dt);
    return true;
}

// dt_dev: see `kick_span` in device/step_size.cuh.

// The step's dt: from the forces pass's maxima `red` where given (every thread computes it,
// the first writes it to dt_dev[0]), else the one sph_step_size wrote to dt_dev[0].
__device__ __forceinline__ float step_dt(const SphParams& p, const unsigned* __restrict__ red,
                                         float* __restrict__ dt_dev) {
    if (!red) return *dt_dev;
    const float dt = step_size_of(p, red);
    if (blockIdx.x == 0 && threadIdx.x == 0) *dt_dev = dt;
    return dt;
}

// time: [0] the device clock, the step's start (the drift advances it after the kick); the
// kick copies it to [2], where the drifts after it read the step's start (a driven object's
// motion over the step) while sph_drift advances [0].
template <int DIM>
__device__ void sph_kick_body(const SphParams p, unsigned n, float* __restrict__ dt_dev, const unsigned* __restrict__ red,
                              double* __restrict__ time, const unsigned char* __restrict__ kind,
                              const unsigned* __restrict__ group, const float* __restrict__ pos,
                              float* __restrict__ vel, const float* __restrict__ acc,
                              const double* __restrict__ series) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    const float step = step_dt(p, red, dt_dev);
    const float dt = kick_span(p, dt_dev, step);
    const double t0 = time[0];
    if (blockIdx.x == 0 && threadIdx.x == 0) time[2] = t0;
    if (i >= n) return;
    const double te = kick_end(p, t0, step);
    float r_now = 1.0f, r_step = 0.0f;
    if (p.inflow && p.inflow_ramp > 0.0f) {
        const double t1 = te;
        const double r1 = ramp_share(p, t1), r0 = ramp_share(p, t1 - (double)dt);
        r_now = (float)r1;
        r_step = (float)(r1 - r0);
    }
    // The position where the kick reads it: the inflow band, a driven object's velocity field,
    // the damping zone, an inlet's profile across its face (`open_profile`).
    const bool at_x = p.inflow || p.driven || p.damping || p.open_count > 0;
    const Vec<DIM> x = at_x ? vload<DIM>(pos, i) : vzero<DIM>();
    Vec<DIM> v = vel_load<DIM>(vel, i);
    if (kick_one<DIM>(p, kind[i], driven_test_group(p, group, i), x, dt, r_now, r_step, t0, te, acc, series, i, v))
        vel_store<DIM>(vel, i, v);  // keeps rho, m
}
MF_ENTRY2(sph_kick,
          (const SphParams p, unsigned n, float* dt_dev, const unsigned* red, double* time,
           const unsigned char* kind, const unsigned* group, const float* pos, float* vel, const float* acc,
           const double* series),
          (p, n, dt_dev, red, time, kind, group, pos, vel, acc, series))

// The drift of one particle (kind k, group g, velocity v) by dt from time t0; returns its new
// position.
// drho: null without the continuity density; rho_dev, stress, rate: null without solids. The callers
// then file the particle in its cell for the next grid build (hist_one).
template <int DIM>
__device__ __forceinline__ Vec<DIM> drift_one(const SphParams& p, unsigned n, unsigned i, unsigned char k, unsigned g,
                                              const Vec<DIM>& v, float dt, double t0, float* __restrict__ pos,
                                              const float* __restrict__ xsph, float* __restrict__ rho,
                                              const float* __restrict__ drho, float* __restrict__ rho_dev,
                                              float* __restrict__ stress, const float* __restrict__ rate,
                                              const double* __restrict__ series) {
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
    // A driven object follows its prescribed motion (no XSPH), whatever its kind.
    // A floating body's particles were moved by its drift (sph_body_move in bodies.cu).
    const int dk = driven_index(p, g);
    if (k == MF_KIND_BOUNDARY && (dk < 0 || p.driven_motion[dk].floating)) return x;
    if (dk >= 0) {
        x = driven_moved<DIM>(p, series, dk, x, dt, t0);
    } else if (open_index(p, g) >= 0) {
        x = x + v * dt;  // an open boundary's buffer: no XSPH, no shifting
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
                               unsigned* __restrict__ count, const double* __restrict__ series) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    const float dt = dt_dev[0];
    const double t0 = time[2];  // the step's start, from the kick
    if (i == 0) {
        time[0] += (double)dt;
        dt_dev[1] = dt;  // the step is done: the next kick's dt_prev
    }
    if (i >= n) return;
    const Vec<DIM> x = drift_one<DIM>(p, n, i, kind[i], driven_test_group(p, group, i), vel_load<DIM>(vel, i), dt,
                                      t0, pos, xsph, rho, drho, rho_dev, stress, rate, series);
    hist_one<DIM>(p, i, x, cell, count);
}
MF_ENTRY2(sph_drift,
          (const SphParams p, unsigned n, float* dt_dev, double* time, const unsigned char* kind,
           const unsigned* group, float* pos, const float* vel, const float* xsph, float* rho, const float* drho,
           float* rho_dev, float* stress, const float* rate, unsigned* cell, unsigned* count, const double* series),
          (p, n, dt_dev, time, kind, group, pos, vel, xsph, rho, drho, rho_dev, stress, rate, cell, count, series))

// The forward Euler's drift then kick in one pass (`Solver::drift_kick`): the drift takes
// the old velocity, the kick's inflow test the new position, as the two kernels in turn.
// Driven objects move steadily only (the scene check refuses an oscillation, a rotation or a
// ramp or a series under the forward Euler: no kick before this pass copies the step's start,
// and here thread 0 advances the clock the others would read); t0 and the series go unused.
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
    const Vec<DIM> x = drift_one<DIM>(p, n, i, k, g, v, dt, 0.0, pos, xsph, rho, drho, rho_dev, stress, rate, nullptr);
    // No ramp under the forward Euler (`ramp_share`): the band at inflow_velocity.
    if (kick_one<DIM>(p, k, g, x, dt, 1.0f, 0.0f, 0.0, 0.0, acc, nullptr, i, v)) vel_store<DIM>(vel, i, v);  // keeps rho, m
    hist_one<DIM>(p, i, x, cell, count);
}
MF_ENTRY2(sph_drift_kick,
          (const SphParams p, unsigned n, float* dt_dev, const unsigned* red, double* time, const unsigned char* kind,
           const unsigned* group, float* pos, float* vel, const float* xsph, float* rho, const float* drho,
           float* rho_dev, float* stress, const float* rate, const float* acc, unsigned* cell, unsigned* count),
          (p, n, dt_dev, red, time, kind, group, pos, vel, xsph, rho, drho, rho_dev, stress, rate, acc, cell, count))
