// The step size from the forces pass's maxima, eq. (19) with the force and viscous limits,
// for sph_step_size (reduce.cu) and for the kick and drift-kick that take it themselves
// (integrate.cu: one launch fewer a step). Twin: `time_step` in src/backend/cpu/reduce.rs.
#pragma once
#include "sph_params.h"
#include "sph_consts.h"

// red = (max |v|, max |a|, max c) as float bits [L/T, L/T^2, L/T] -> dt [T].
__device__ __forceinline__ float step_size_of(const SphParams& p, const unsigned* __restrict__ red) {
    if (p.dt > 0.0f) return p.dt;
    const float v_max = __uint_as_float(red[0]), a_max = __uint_as_float(red[1]), c_max = __uint_as_float(red[2]);
    float dt = p.h / (c_max + v_max);  // eq. (19)
    if (a_max > 0.0f) dt = fminf(dt, sqrtf(p.h / a_max));
    dt *= p.courant;
    if (p.viscosity > 0.0f) dt = fminf(dt, MF_VISCOUS_DT * p.h * p.h / p.viscosity);
    return dt;
}

// dt_dev holds 2 floats: [0] this step's dt (written by the kick, the drift-kick or
// sph_step_size), [1] the last completed step's (written by the drift; 0 before the first
// step): the leapfrog's kick spans their mean.

// The time a kick spans [T]: dt, or under the leapfrog (dt_prev + dt) / 2, from the middle
// of the last step to the middle of this one (the particles' kick in integrate.cu, the
// floating bodies' in bodies.cu). Twin: `kick_span` in cpu/integrate.rs.
__device__ __forceinline__ float kick_span(const SphParams& p, const float* __restrict__ dt_dev, float dt) {
    return p.integrator == MF_INTEGRATOR_LEAPFROG ? 0.5f * (dt_dev[1] + dt) : dt;
}
