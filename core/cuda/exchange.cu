// Domain decomposition on the device (src/backend/cuda/subdomain.rs, the scheme in
// src/exchange/mod.rs): which particles a halo copies or a subdomain keeps (a mark per
// slot), their slots in a compacted order (the grid build's scans, grid.cu, over the marks),
// and the moves: packing a halo into one flat buffer of 32-bit words, unpacking it at the end
// of the storage, compacting the storage in place of a host round trip, and re-laying the
// stress planes when the particle count changes.
// Twin: src/backend/cpu/subdomain.rs (State::select / extend / retain); test:
// tests/cuda_exchange.rs.
//
// The halo's layout (`CudaHalo` in subdomain.rs, `halo_words` there): one record of `words`
// 32-bit words per particle, records back to back in the storage order of the sender; in a
// record, by word:
//   0          id
//   1          kind (the u8 widened)
//   2          group
//   3 ..       position: S = 2 floats in 2D (x, y), 4 in 3D (x, y, z, mass)
//   3+S ..     velocity, float4 as stored (2D: vx, vy, mass, w; 3D: vx, vy, vz, w; w = the
//              density, negated on walls: vel_load in device/packing.cuh)
//   7+S        rho
//   8+S        p
//   9+S ..     with solids only: the stress's Sym<DIM>::N components (2D xx, yy, xy; 3D xx,
//              yy, zz, xy, xz, yz), then rho_dev (the solids' density departure)
// so 9 + S words without solids (2D 11, 3D 13) and 10 + S + N with (2D 15, 3D 20): every
// persistent array (`Persistent` in buffers.rs), which is all a step reads that an earlier
// step wrote (the others are rewritten each step before they are read). Floats as their bits.
#include "device/entries.cuh"
#include "device/packing.cuh"
#include "device/particle.cuh"
#include "device/scan.cuh"
#include "device/vectors.cuh"

// The persistent arrays of one storage (stress and rho_dev null without solids); the stress
// is Sym<DIM>::N planes of `stride` floats (the storage's particle count: buffers.rs).
struct Store {
    unsigned* id;
    unsigned char* kind;
    unsigned* group;
    float* pos;
    float* vel;
    float* rho;
    float* pr;
    float* stress;
    float* rho_dev;
    unsigned stride;
};

// One particle's record (the layout above) from slot i of s.
template <int DIM>
__device__ __forceinline__ void load_record(const Store& s, unsigned i, unsigned* w) {
    constexpr int S = VS<DIM>::S;
    w[0] = s.id[i];
    w[1] = s.kind[i];
    w[2] = s.group[i];
#pragma unroll
    for (int a = 0; a < S; ++a) w[3 + a] = __float_as_uint(s.pos[(size_t)i * S + a]);
    const float4 v = reinterpret_cast<const float4*>(s.vel)[i];
    w[3 + S] = __float_as_uint(v.x);
    w[4 + S] = __float_as_uint(v.y);
    w[5 + S] = __float_as_uint(v.z);
    w[6 + S] = __float_as_uint(v.w);
    w[7 + S] = __float_as_uint(s.rho[i]);
    w[8 + S] = __float_as_uint(s.pr[i]);
    if (s.stress) {
#pragma unroll
        for (int q = 0; q < Sym<DIM>::N; ++q) w[9 + S + q] = __float_as_uint(s.stress[(size_t)q * s.stride + i]);
        w[9 + S + Sym<DIM>::N] = __float_as_uint(s.rho_dev[i]);
    }
}

// One particle's record into slot k of s.
template <int DIM>
__device__ __forceinline__ void store_record(const Store& s, unsigned k, const unsigned* w) {
    constexpr int S = VS<DIM>::S;
    s.id[k] = w[0];
    s.kind[k] = (unsigned char)w[1];
    s.group[k] = w[2];
#pragma unroll
    for (int a = 0; a < S; ++a) s.pos[(size_t)k * S + a] = __uint_as_float(w[3 + a]);
    reinterpret_cast<float4*>(s.vel)[k] = make_float4(__uint_as_float(w[3 + S]), __uint_as_float(w[4 + S]),
                                                      __uint_as_float(w[5 + S]), __uint_as_float(w[6 + S]));
    s.rho[k] = __uint_as_float(w[7 + S]);
    s.pr[k] = __uint_as_float(w[8 + S]);
    if (s.stress) {
#pragma unroll
        for (int q = 0; q < Sym<DIM>::N; ++q) s.stress[(size_t)q * s.stride + k] = __uint_as_float(w[9 + S + q]);
        s.rho_dev[k] = __uint_as_float(w[9 + S + Sym<DIM>::N]);
    }
}

// The longest record: 3D with solids.
#define MF_RECORD_MAX (9 + 4 + 6 + 1)

// Rust's f32::rem_euclid: the remainder of a / b in [0, |b|).
__device__ __forceinline__ float rem_euclid(float a, float b) {
    const float r = fmodf(a, b);
    return r < 0.0f ? r + fabsf(b) : r;
}

// The distance [L] from coordinate c to the slab [lo, hi) along its axis: 0 inside; on a
// periodic axis spanning [pmin, pmax] the shorter way round, the slab's infinite outer
// bounds taken as the domain's. Twin: Slab::gap (src/exchange/slab.rs), the same operations
// in the same order.
__device__ __forceinline__ float slab_gap(float lo, float hi, float c, bool periodic, float pmin, float pmax) {
    if (c >= lo && c < hi) return 0.0f;
    if (periodic) {
        const float len = pmax - pmin;
        const float l = fmaxf(lo, pmin), h = fminf(hi, pmax);
        return fminf(rem_euclid(l - c, len), rem_euclid(c - h, len));
    }
    return c < lo ? lo - c : c - hi;
}

// mark[i] = 1 for the particles to move, 0 for the others, over slots i < n, and mark[n] = 0
// (the scan's sentinel: its exclusive sum there is the count): with `halo`, those within
// `width` [L] of the slab [lo, hi) of `axis` (slab_gap; periodic: round [pmin, pmax]);
// without, those this solver owns (owns, device/particle.cuh). Grid: n + 1 threads.
template <int DIM>
__device__ void sph_exchange_mark_body(const SphParams p, unsigned n, unsigned halo, unsigned axis, float lo, float hi,
                                       float width, unsigned periodic, float pmin, float pmax,
                                       const float* __restrict__ pos, unsigned* __restrict__ mark) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i > n) return;
    if (i == n) {
        mark[n] = 0u;
        return;
    }
    const float c = pos[(size_t)i * VS<DIM>::S + axis];
    mark[i] = halo ? (slab_gap(lo, hi, c, periodic != 0, pmin, pmax) < width) : owns(p, c);
}
MF_ENTRY2(sph_exchange_mark,
          (const SphParams p, unsigned n, unsigned halo, unsigned axis, float lo, float hi, float width,
           unsigned periodic, float pmin, float pmax, const float* pos, unsigned* mark),
          (p, n, halo, axis, lo, hi, width, periodic, pmin, pmax, pos, mark))

// The compacted slot of a marked slot i: `compacted` (device/scan.cuh) over the scan of the
// marks (sph_scan_local and sph_scan_top over n + 1 entries, grid.cu).

// *total = the number of marked slots (the scan at the sentinel n). One thread.
extern "C" __global__ void sph_exchange_total(unsigned n, const unsigned* __restrict__ local,
                                              const unsigned* __restrict__ bsum, unsigned* __restrict__ total) {
    if (threadIdx.x == 0 && blockIdx.x == 0) *total = compacted(local, bsum, n);
}

// The marked particles of the storage (n slots) as records of `words` words, in storage
// order, into out (count x words).
template <int DIM>
__device__ void sph_exchange_pack_body(unsigned n, unsigned words, const unsigned* __restrict__ mark,
                                       const unsigned* __restrict__ local, const unsigned* __restrict__ bsum,
                                       const unsigned* id, const unsigned char* kind, const unsigned* group,
                                       const float* pos, const float* vel, const float* rho, const float* pr,
                                       const float* stress, const float* rho_dev, unsigned* __restrict__ out) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || !mark[i]) return;
    const Store s{const_cast<unsigned*>(id),   const_cast<unsigned char*>(kind), const_cast<unsigned*>(group),
                  const_cast<float*>(pos),     const_cast<float*>(vel),          const_cast<float*>(rho),
                  const_cast<float*>(pr),      const_cast<float*>(stress),       const_cast<float*>(rho_dev),
                  n};
    unsigned w[MF_RECORD_MAX];
    load_record<DIM>(s, i, w);
    unsigned* o = out + (size_t)compacted(local, bsum, i) * words;
    const unsigned used = 9 + VS<DIM>::S + (stress ? Sym<DIM>::N + 1 : 0);
#pragma unroll
    for (unsigned k = 0; k < MF_RECORD_MAX; ++k)
        if (k < used) o[k] = w[k];
}
MF_ENTRY2(sph_exchange_pack,
          (unsigned n, unsigned words, const unsigned* mark, const unsigned* local, const unsigned* bsum,
           const unsigned* id, const unsigned char* kind, const unsigned* group, const float* pos, const float* vel,
           const float* rho, const float* pr, const float* stress, const float* rho_dev, unsigned* out),
          (n, words, mark, local, bsum, id, kind, group, pos, vel, rho, pr, stress, rho_dev, out))

// m records of `words` words from in, into slots base .. base + m of a storage of `stride`
// particles (the stress planes' stride: the count after the unpack).
template <int DIM>
__device__ void sph_exchange_unpack_body(unsigned m, unsigned base, unsigned stride, unsigned words,
                                         const unsigned* __restrict__ in, unsigned* id, unsigned char* kind,
                                         unsigned* group, float* pos, float* vel, float* rho, float* pr,
                                         float* stress, float* rho_dev) {
    const unsigned j = blockIdx.x * blockDim.x + threadIdx.x;
    if (j >= m) return;
    const Store s{id, kind, group, pos, vel, rho, pr, stress, rho_dev, stride};
    unsigned w[MF_RECORD_MAX];
    const unsigned* r = in + (size_t)j * words;
    const unsigned used = 9 + VS<DIM>::S + (stress ? Sym<DIM>::N + 1 : 0);
#pragma unroll
    for (unsigned k = 0; k < MF_RECORD_MAX; ++k) w[k] = k < used ? r[k] : 0u;
    store_record<DIM>(s, base + j, w);
}
MF_ENTRY2(sph_exchange_unpack,
          (unsigned m, unsigned base, unsigned stride, unsigned words, const unsigned* in, unsigned* id,
           unsigned char* kind, unsigned* group, float* pos, float* vel, float* rho, float* pr, float* stress,
           float* rho_dev),
          (m, base, stride, words, in, id, kind, group, pos, vel, rho, pr, stress, rho_dev))

// The marked particles of the storage (n slots) moved, in storage order, into the first
// `kept` slots of a second storage (the other persistent set), whose stress planes are
// `kept` apart. Stress and rho_dev null in both or in neither.
template <int DIM>
__device__ void sph_exchange_compact_body(unsigned n, unsigned kept, const unsigned* __restrict__ mark,
                                          const unsigned* __restrict__ local, const unsigned* __restrict__ bsum,
                                          const unsigned* id, const unsigned char* kind, const unsigned* group,
                                          const float* pos, const float* vel, const float* rho, const float* pr,
                                          const float* stress, const float* rho_dev, unsigned* id2,
                                          unsigned char* kind2, unsigned* group2, float* pos2, float* vel2,
                                          float* rho2, float* pr2, float* stress2, float* rho_dev2) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || !mark[i]) return;
    const Store s{const_cast<unsigned*>(id),   const_cast<unsigned char*>(kind), const_cast<unsigned*>(group),
                  const_cast<float*>(pos),     const_cast<float*>(vel),          const_cast<float*>(rho),
                  const_cast<float*>(pr),      const_cast<float*>(stress),       const_cast<float*>(rho_dev),
                  n};
    const Store d{id2, kind2, group2, pos2, vel2, rho2, pr2, stress2, rho_dev2, kept};
    unsigned w[MF_RECORD_MAX];
    load_record<DIM>(s, i, w);
    store_record<DIM>(d, compacted(local, bsum, i), w);
}
MF_ENTRY2(sph_exchange_compact,
          (unsigned n, unsigned kept, const unsigned* mark, const unsigned* local, const unsigned* bsum,
           const unsigned* id, const unsigned char* kind, const unsigned* group, const float* pos, const float* vel,
           const float* rho, const float* pr, const float* stress, const float* rho_dev, unsigned* id2,
           unsigned char* kind2, unsigned* group2, float* pos2, float* vel2, float* rho2, float* pr2,
           float* stress2, float* rho_dev2),
          (n, kept, mark, local, bsum, id, kind, group, pos, vel, rho, pr, stress, rho_dev, id2, kind2, group2, pos2,
           vel2, rho2, pr2, stress2, rho_dev2))

// dst[q n_new + i] = src[q n_old + i] for the `planes` planes and i < n_old: a storage's
// stress planes re-laid for a larger count (before an unpack appends to them). Grid: n_old
// threads.
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
sph_exchange_restride(unsigned n_old, unsigned n_new, unsigned planes, const float* __restrict__ src,
                      float* __restrict__ dst) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n_old) return;
    for (unsigned q = 0; q < planes; ++q) dst[(size_t)q * n_new + i] = src[(size_t)q * n_old + i];
}
