// What one particle's kind and group make of the parameters: its pressure (equation of
// state), sound speed, rest density, and whether it is driven. Twins: `pressure` in
// src/backend/cpu/density.rs, SphParams::sound_speed / rest_density in src/physics/params/mod.rs,
// `driven_velocity` in src/backend/cpu/integrate.rs, `SphParams::owns`; parity test:
// tests/cuda_parity/.
#pragma once
#include "sph_params.h"
#include "vectors.cuh"

// Tait eq. (9) for fluid and dynamic wall particles; P = c_s^2 (rho - rho0_s) for solids
// (Gray & Monaghan 2001), from the departure rho_dev = rho - rho0_s [M/L^3] (the solids'
// rho_dev array: rho itself rounds a stiff solid's compression away; unused for other
// kinds); 0 for the paper's walls.
// [P] from rho [M/L^3]; the density pass, the continuity scheme's reorder (grid.cu), the
// monitors' refresh (monitor.cu).
__device__ __forceinline__ float pressure(const SphParams& p, unsigned char kind, float rho, float rho_dev) {
    if (kind == MF_KIND_SOLID) return p.solid_c0 * p.solid_c0 * rho_dev;
    // eq. (9) plus the background pressure (cpu/density.rs `pressure`).
    if (kind == MF_KIND_FLUID || p.wall_coupling != 0)
        return p.tait_b * (powf(rho / p.rho0, p.tait_gamma) - 1.0f) + p.background_pressure;
    return 0.0f;
}

// Whether a particle of kind k has rates (RateSum in rates.cuh: d rho/dt, XSPH, stress
// rate): every kind but walls other than dynamic ones (a dynamic wall has its d rho/dt; an
// mDBC wall takes its density from its ghost node, the paper's has none). The forces pass
// records the accepted candidates of these particles for the rates pass (PairBits in
// device/neighbours.cuh). Twin: `has_rates` in src/physics/pairs.rs.
__device__ __forceinline__ bool has_rates(const SphParams& p, unsigned char k) {
    return k != MF_KIND_BOUNDARY || p.wall_coupling == MF_WALL_COUPLING_DYNAMIC;
}

__device__ __forceinline__ float sound_speed(const SphParams& p, unsigned char kind) {
    if (kind == MF_KIND_SOLID)
        return sqrtf(p.solid_c0 * p.solid_c0 +
                     4.0f / 3.0f * p.shear_modulus / fmaxf(p.solid_rho0, 1.17549435e-38f));
    return p.c0;
}
__device__ __forceinline__ float rest_density(const SphParams& p, unsigned char kind) {
    return kind == MF_KIND_SOLID ? p.solid_rho0 : p.rho0;
}

// Which driven object scene group `group` is (a piston, a clamp, a flap; any kind): k where
// driven_motion[k].group == group, following driven_motion[k] whatever the forces; -1 for
// none (twin: `SphParams::driven_index`).
__device__ __forceinline__ int driven_index(const SphParams& p, unsigned group) {
    for (int k = 0; k < p.driven && k < MF_MAX_DRIVEN; ++k)
        if (group == (unsigned)p.driven_motion[k].group) return k;
    return -1;
}
__device__ __forceinline__ bool is_driven(const SphParams& p, unsigned group) {
    return driven_index(p, group) >= 0;
}
// A wall at rest: a wall particle of group g that is not driven, at velocity v = 0 [L/T].
// Two of them add nothing to each other's d rho/dt, eq. (8) (`stamp_moving`, `walked_rows`).
template <int DIM>
__device__ __forceinline__ bool wall_at_rest(const SphParams& p, unsigned char k, unsigned g, Vec<DIM> v) {
    bool still = k == MF_KIND_BOUNDARY && !is_driven(p, g);
#pragma unroll
    for (int a = 0; a < DIM; ++a) still = still && v.c[a] == 0.0f;
    return still;
}

// Whether this solver owns a particle at coordinate c [L] of the slab's axis: always in one
// domain (own_slab = 0); in a subdomain of a decomposed run (crate::exchange) own_lo <= c <
// own_hi. The step size's extremes and the wall forces count only owned particles, so that
// each particle counts once over the subdomains. Twin: SphParams::owns (src/physics/params/mod.rs).
__device__ __forceinline__ bool owns(const SphParams& p, float c) {
    return p.own_slab == 0 || (c >= p.own_lo && c < p.own_hi);
}
// owns() of the particle in storage slot i of pos (float2 per particle in 2D, float4 in 3D:
// device/packing.cuh); one domain reads nothing.
template <int DIM>
__device__ __forceinline__ bool owns_slot(const SphParams& p, const float* __restrict__ pos, unsigned i) {
    return p.own_slab == 0 || owns(p, pos[(size_t)i * (DIM == 2 ? 2 : 4) + p.own_axis]);
}
