// How particle data is laid out on the device: vectors as float2 (2D) / float4 (3D),
// velocities as float4 with the mass and density in their spare slots, symmetric tensors as
// planes of components. Twin: src/backend/cuda/buffers.rs (`flat_v`, `flat_vel`, `flat_s`);
// parity test: tests/cuda_parity/.
#pragma once
#include "sph_params.h"
#include "vectors.cuh"

// Positions, velocities, accelerations: float2 in 2D, float4 (w unused) in 3D, so one
// aligned load per particle; the layout is glam's Vec2 / Vec3A.
template <int DIM> struct VS { static constexpr int S = DIM == 2 ? 2 : 4; };

template <int DIM> __device__ __forceinline__ Vec<DIM> vload(const float* a, unsigned i) {
    Vec<DIM> v;
    if constexpr (DIM == 2) {
        float2 t = reinterpret_cast<const float2*>(a)[i];
        v.c[0] = t.x; v.c[1] = t.y;
    } else {
        float4 t = reinterpret_cast<const float4*>(a)[i];
        v.c[0] = t.x; v.c[1] = t.y; v.c[2] = t.z;
    }
    return v;
}
template <int DIM> __device__ __forceinline__ void vstore(float* a, unsigned i, Vec<DIM> v) {
    if constexpr (DIM == 2) {
        reinterpret_cast<float2*>(a)[i] = make_float2(v.c[0], v.c[1]);
    } else {
        reinterpret_cast<float4*>(a)[i] = make_float4(v.c[0], v.c[1], v.c[2], 0.0f);
    }
}
// Velocities are float4 in both dimensions and carry per-particle scalars in their spare
// slots (twin: `flat_vel` in src/backend/cuda/buffers.rs), so that the neighbour loops read a
// neighbour's mass, density and (fluid-only scenes) kind from the vectors they load anyway
// instead of three more arrays: vel.w = rho, negated on boundary particles (written by the
// density pass and at upload, kept by the kick); the mass m (constant: written at upload,
// kept by the kick, the drift and the grid's reorder) is pos.w in 3D and vel.z in 2D (whose
// positions stay float2: the candidate test loads them, most candidates are rejected). The
// mass has no array of its own on the device (mass_of); the density's reference is rho[].
// vel.w of a particle of kind k and density rho.
__device__ __forceinline__ float vel_w(unsigned char k, float rho) { return k == MF_KIND_BOUNDARY ? -rho : rho; }
// Whether vel.w marks a boundary particle (the sign bit: -0.0 counts).
__device__ __forceinline__ bool vel_w_boundary(float w) { return (__float_as_uint(w) >> 31) != 0; }
// Store the DIM components of v, keeping the w slot of a 3D vector (positions).
template <int DIM> __device__ __forceinline__ void vstore_keep_w(float* a, unsigned i, Vec<DIM> v) {
    if constexpr (DIM == 2) {
        vstore<DIM>(a, i, v);
    } else {
        float4* q = reinterpret_cast<float4*>(a);
        q[i] = make_float4(v.c[0], v.c[1], v.c[2], q[i].w);
    }
}
// Load the DIM components and the w slot (0 in 2D) of a position.
template <int DIM> __device__ __forceinline__ Vec<DIM> vload_w(const float* a, unsigned i, float& w) {
    if constexpr (DIM == 2) {
        w = 0.0f;
        return vload<DIM>(a, i);
    } else {
        const float4 t = reinterpret_cast<const float4*>(a)[i];
        w = t.w;
        Vec<DIM> v;
        v.c[0] = t.x; v.c[1] = t.y; v.c[2] = t.z;
        return v;
    }
}
// Particle i's mass [M]: pos.w in 3D, vel.z in 2D (see above).
template <int DIM>
__device__ __forceinline__ float mass_of(const float* __restrict__ pos, const float* __restrict__ vel, unsigned i) {
    if constexpr (DIM == 3) return reinterpret_cast<const float4*>(pos)[i].w;
    else return reinterpret_cast<const float4*>(vel)[i].z;
}
// Velocity i (float4 in both dimensions), its w slot in w and, in 2D, the mass (vel.z) in m.
template <int DIM> __device__ __forceinline__ Vec<DIM> vel_load(const float* v, unsigned i, float& m, float& w) {
    const float4 t = reinterpret_cast<const float4*>(v)[i];
    Vec<DIM> r;
    r.c[0] = t.x; r.c[1] = t.y;
    if constexpr (DIM == 3) r.c[2] = t.z;
    m = t.z;  // the mass in 2D only
    w = t.w;
    return r;
}
template <int DIM> __device__ __forceinline__ Vec<DIM> vel_load(const float* v, unsigned i) {
    float m, w;
    return vel_load<DIM>(v, i, m, w);
}
// Store velocity i, keeping the scalars in its spare slots (2D: only the first half is written).
template <int DIM> __device__ __forceinline__ void vel_store(float* v, unsigned i, Vec<DIM> u) {
    if constexpr (DIM == 2) {
        reinterpret_cast<float2*>(v)[2 * i] = make_float2(u.c[0], u.c[1]);
    } else {
        vstore_keep_w<DIM>(v, i, u);
    }
}

// Symmetric storage: 2D (xx, yy, xy); 3D (xx, yy, zz, xy, xz, yz); component k of slot i
// at a[k * n + i].
template <int DIM> struct Sym { static constexpr int N = DIM == 2 ? 3 : 6; };
template <int DIM> __device__ __forceinline__ Mat<DIM> sload(const float* a, unsigned i, unsigned n) {
    Mat<DIM> r;
    if constexpr (DIM == 2) {
        r.m[0][0] = a[i]; r.m[1][1] = a[n + i];
        r.m[0][1] = r.m[1][0] = a[2 * n + i];
    } else {
        r.m[0][0] = a[i]; r.m[1][1] = a[n + i]; r.m[2][2] = a[2 * n + i];
        r.m[0][1] = r.m[1][0] = a[3 * n + i];
        r.m[0][2] = r.m[2][0] = a[4 * n + i];
        r.m[1][2] = r.m[2][1] = a[5 * n + i];
    }
    return r;
}
template <int DIM> __device__ __forceinline__ void sstore(float* a, unsigned i, unsigned n, const Mat<DIM>& r) {
    if constexpr (DIM == 2) {
        a[i] = r.m[0][0]; a[n + i] = r.m[1][1];
        a[2 * n + i] = 0.5f * (r.m[0][1] + r.m[1][0]);
    } else {
        a[i] = r.m[0][0]; a[n + i] = r.m[1][1]; a[2 * n + i] = r.m[2][2];
        a[3 * n + i] = 0.5f * (r.m[0][1] + r.m[1][0]);
        a[4 * n + i] = 0.5f * (r.m[0][2] + r.m[2][0]);
        a[5 * n + i] = 0.5f * (r.m[1][2] + r.m[2][1]);
    }
}
