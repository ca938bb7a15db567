// Open boundaries (`MfOpen` in sph_params.h): which buffer a group is, a point's side of the
// plane, an inlet's velocity, and what the open-boundary stage does with one particle.
// Twin: src/physics/open.rs; the stage: open.cu (twin src/backend/cpu/open.rs).
#pragma once
#include "sph_params.h"

// The open boundary whose buffer scene group `group` is, or -1. Twin: `open_index`.
__device__ __forceinline__ int open_index(const SphParams& p, unsigned group) {
    for (int b = 0; b < p.open_count && b < MF_MAX_OPEN; ++b)
        if (group == (unsigned)p.open[b].group) return b;
    return -1;
}

// s = sign (x[axis] - plane) [L]: x's distance on the fluid's side (`MfOpen::side`).
__device__ __forceinline__ float open_side(const MfOpen& o, const float* x) {
    return o.sign * (x[o.axis] - o.plane);
}

// Whether x lies within the box across the normal (`MfOpen::beside`).
__device__ __forceinline__ bool open_beside(const MfOpen& o, const float* x, int dim) {
    for (int a = 0; a < dim; ++a)
        if (a != o.axis && (x[a] < o.lo[a] || x[a] > o.hi[a])) return false;
    return true;
}

// An inlet's velocity profile at x [-]: the product over the axes of `profile_axes` of
// 6 eta (1 - eta), eta = (x_a - lo_a) / (hi_a - lo_a) clamped to [0, 1] (mean 1); 1 where no
// axis is set. Twin: `MfOpen::profile`.
__device__ __forceinline__ float open_profile(const MfOpen& o, const float* x) {
    float f = 1.0f;
    for (int a = 0; a < 3; ++a) {
        if (!(o.profile_axes & (1 << a))) continue;
        const float eta = fminf(fmaxf((x[a] - o.lo[a]) / (o.hi[a] - o.lo[a]), 0.0f), 1.0f);
        f *= 6.0f * eta * (1.0f - eta);
    }
    return f;
}

// The smooth start r(t) over tr [T]: (1 - cos(pi t / tr)) / 2 up to tr, then 1 (1 without a
// ramp). Twin: `smooth_ramp` in src/backend/cpu/integrate.rs.
__device__ __forceinline__ double smooth_ramp(double tr, double t) {
    if (tr <= 0.0 || t >= tr) return 1.0;
    if (t <= 0.0) return 0.0;
    return 0.5 * (1.0 - cos(3.14159265358979323846 * t / tr));
}

// The fates of `Fate` in src/physics/open.rs: the code in the low byte, the boundary above.
#define MF_FATE_KEEP 0u
#define MF_FATE_SPAWN 1u
#define MF_FATE_ENTER 2u
#define MF_FATE_LEAVE 3u
#define MF_FATE_REMOVE 4u

// What the open-boundary stage does with a particle of kind k and group g at x (3
// components; only fluid particles have a fate but KEEP): code | boundary << 8. Twin: `fate`.
__device__ __forceinline__ unsigned open_fate(const SphParams& p, unsigned char k, unsigned g, const float* x) {
    if (p.open_count == 0 || k != MF_KIND_FLUID) return MF_FATE_KEEP;
    const int b = open_index(p, g);
    if (b >= 0) {
        const MfOpen& o = p.open[b];
        const float s = open_side(o, x);
        const unsigned at = (unsigned)b << 8;
        if (o.kind == MF_OPEN_INLET) return s >= 0.0f ? (MF_FATE_SPAWN | at) : MF_FATE_KEEP;
        if (s >= 0.0f) return MF_FATE_LEAVE | at;
        if (s < -o.depth || !open_beside(o, x, p.dim)) return MF_FATE_REMOVE | at;
        return MF_FATE_KEEP;
    }
    for (int c = 0; c < p.open_count && c < MF_MAX_OPEN; ++c) {
        const MfOpen& o = p.open[c];
        const float s = open_side(o, x);
        if (s < 0.0f && open_beside(o, x, p.dim)) {
            const unsigned at = (unsigned)c << 8;
            if (o.kind == MF_OPEN_INLET) {
                if (s >= -o.depth) return MF_FATE_REMOVE | at;
            } else if (s < -o.depth) {
                return MF_FATE_REMOVE | at;
            } else {
                return MF_FATE_ENTER | at;
            }
        }
    }
    return MF_FATE_KEEP;
}
