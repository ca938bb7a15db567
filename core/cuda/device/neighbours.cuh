// The neighbour loops: the candidates of `rows` tested against the support in batches
// (batch_accept), split over L lanes (for_each_neighbor_split) or, at one lane, queued per
// plane of rows (queued_neighbours); and the `Neighbour` record the pair sums of forces and
// rates take. Twin: Grid::for_each_neighbor in src/backend/cpu/grid.rs (same neighbours, same
// order); parity test: tests/cuda_parity/.
#pragma once
#include "sph_consts.h"
#include "sph_params.h"
#include "grid.cuh"
#include "kernel.cuh"
#include "packing.cuh"
#include "vectors.cuh"

// The neighbour's kind: in fluid-only scenes from the sign of its vel.w, else from the kind
// array.
template <int DIM, bool SOLIDS>
__device__ __forceinline__ unsigned char neighbour_kind(const unsigned char* __restrict__ kind, unsigned j, float vw) {
    if constexpr (!SOLIDS)
        return vel_w_boundary(vw) ? (unsigned char)MF_KIND_BOUNDARY : (unsigned char)MF_KIND_FLUID;
    else
        return kind[j];
}

// A neighbour j of particle i as the pair sums (ForceSum in forces.cuh, RateSum in
// rates.cuh) take it: loaded and its kernel gradient computed once, whichever sums run.
template <int DIM> struct Neighbour {
    unsigned j;
    unsigned char kind;
    Vec<DIM> r;    // x_i - x_j (minimum image) [L]
    float r2, rr;  // |r|^2 [L^2], |r| [L]
    float fw;      // (dW/dr)/r at |r| (kernel_wf): grad_i W_ij = fw r [L^-(d+2)]
    float w;       // W_ij [L^-d]
    Vec<DIM> v;    // v_j [L/T]
    float m, rho;  // m_j [M], rho_j [M L^-d]
};
// j at r = x_i - x_j (r2 = |r|^2), pw the w slot of its stored position (3D: m_j): v_j,
// m_j, rho_j and (fluid-only scenes) the kind from the spare slots of its position and
// velocity (see vel_load), else the kind array.
// Under the leapfrog (half_dt > 0: the rates pass, cpu/rates.rs `midpoint_pair`) the pair
// is taken where the drift puts it halfway, r + half_dt (v_i - v_j), vi being v_i, unless
// it or its midpoint is in the kernel's core (q < kernel_gradient_peak_q): there at x^n.
template <int DIM, bool SOLIDS>
__device__ __forceinline__ Neighbour<DIM> neighbour(const SphParams& p, unsigned j, Vec<DIM> r, float r2, float pw,
                                                    const float* __restrict__ vel,
                                                    const unsigned char* __restrict__ kind,
                                                    const Vec<DIM>& vi = Vec<DIM>{}, float half_dt = 0.0f) {
    Neighbour<DIM> nb;
    float vm, vw;
    nb.j = j;
    nb.v = vel_load<DIM>(vel, j, vm, vw);
    if (half_dt != 0.0f) {  // uniform: the same for every thread
        const float core = kernel_gradient_peak_q(p) * p.h, core_r2 = core * core;
        const Vec<DIM> rm = r + (vi - nb.v) * half_dt;
        const float rm2 = dot(rm, rm);
        if (r2 >= core_r2 && rm2 >= core_r2) {
            r = rm;
            r2 = rm2;
        }
    }
    nb.r = r;
    nb.r2 = r2;
    nb.kind = neighbour_kind<DIM, SOLIDS>(kind, j, vw);
    nb.rr = fast_norm(r2);
    kernel_wf(p, nb.rr, nb.w, nb.fw);
    nb.m = DIM == 3 ? pw : vm;
    nb.rho = fabsf(vw);
    return nb;
}

// Candidates s + lane, s + lane + L, ... < e in batches of B: the B position loads issued
// before any is used (in flight together), then accept(j) for the accepted ones
// (|x_i - x_j| < support) in candidate order.
template <int DIM, int L, int B, bool PERIODIC, class F>
__device__ __forceinline__ void batch_accept(const SphParams& p, const float* __restrict__ pos, Vec<DIM> xi,
                                             unsigned s, unsigned e, int lane, F&& accept) {
    for (unsigned base = s + lane; base < e; base += B * L) {
        Vec<DIM> xj[B];
#pragma unroll
        for (int k = 0; k < B; ++k) xj[k] = vload<DIM>(pos, min(base + k * L, e - 1));
        unsigned mask = 0;
#pragma unroll
        for (int k = 0; k < B; ++k) {
            const Vec<DIM> r = separation<DIM, PERIODIC>(p, xi, xj[k]);
            if (base + k * L < e && dot(r, r) < p.support2) mask |= 1u << k;
        }
        while (mask) {
            const int k = __ffs(mask) - 1;
            mask &= mask - 1;
            accept(base + k * L);
        }
    }
}

// f(j, r_ij, r_ij^2, w_j) for candidate j, which passed the support test.
template <int DIM, bool PERIODIC, class F>
__device__ __forceinline__ void call_neighbour(const SphParams& p, const float* __restrict__ pos, Vec<DIM> xi,
                                               unsigned j, F&& f) {
    float wj;
    const Vec<DIM> r = separation<DIM, PERIODIC>(p, xi, vload_w<DIM>(pos, j, wj));
    f(j, r, dot(r, r), wj);
}

// Candidates per batch, their position loads in flight together: MF_NB_BATCH in the loop
// of several lanes per particle (batch_accept, below 150,000 particles: a build with 8 in
// both loops stepped 3-6 % slower at 3,800 and 10,000 particles), MF_QUEUE_BATCH_2D/_3D in
// the one-lane queued loop (queued_neighbours): in 2D 8 (against 4, 4M 4 % faster), in 3D
// 4 (8 doubled the 3D kernels' spills at 64 registers: the fused pass 4.6 % slower at
// 4.7M). H100 figures: docs/journal/2026-11-27-neighbour-pass.md.
#ifndef MF_NB_BATCH
#define MF_NB_BATCH 4
#endif
#ifndef MF_QUEUE_BATCH_2D
#define MF_QUEUE_BATCH_2D 8
#endif
#ifndef MF_QUEUE_BATCH_3D
#define MF_QUEUE_BATCH_3D 4
#endif

// Calls f(j, r_ij, r_ij^2, w_j) for every j (i included) within the support of xi (w_j: the
// w slot of j's stored position, its mass in 3D; 0 in 2D), the candidates of `rows` split
// over L lanes (lane l takes every L-th), in candidate order.
template <int DIM, int L, int B = MF_NB_BATCH, bool PERIODIC = true, class F>
__device__ __forceinline__ void for_each_neighbor_split(const SphParams& p, const unsigned* __restrict__ cell_start,
                                                        const float* __restrict__ pos, Vec<DIM> xi, int lane,
                                                        F&& f) {
    rows<DIM>(p, xi, [&](unsigned row, int x0, int x1) {
        row_ranges(p, cell_start, row, x0, x1, [&](unsigned s, unsigned e) {
            batch_accept<DIM, L, B, PERIODIC>(p, pos, xi, s, e, lane,
                                              [&](unsigned j) { call_neighbour<DIM, PERIODIC>(p, pos, xi, j, f); });
        });
    });
}

// The accepted-candidate queue of the one-lane neighbour loop (queued_neighbours): up to
// MF_QUEUE entries (first candidate, mask of the accepted ones among the 32 from there) per
// thread in shared memory, entry e of thread t at [e * MF_BLOCK + t]; MF_QUEUE 0: no queue
// (batch_accept's pair sums after each batch). 8 entries of 8 B: 16 KB per block of 256; more
// takes L1 cache from the candidate loads and was slower (docs/reference/performance.md).
#ifndef MF_QUEUE
#define MF_QUEUE 8
#endif

// |r|^2 of the one-lane loop's candidate test in explicitly rounded operations, in the order
// the compiler chose for dot(r, r) in every kernel before (y^2, then x, then z fused in):
// never contracted otherwise, so that the forces pass and the rates pass accept the same
// candidates (PairBits below; see slab_gap2 in grid.cuh).
template <int DIM> __device__ __forceinline__ float dist2_rn(Vec<DIM> r) {
    float s = __fmaf_rn(r.c[0], r.c[0], __fmul_rn(r.c[1], r.c[1]));
    if constexpr (DIM == 3) s = __fmaf_rn(r.c[2], r.c[2], s);
    return s;
}

// The accepted candidates of one particle's one-lane pass (queued_neighbours) as bits in
// candidate order (the loop's chunks of up to 32, one after the other), recorded by the
// forces pass and replayed by the rates pass of the symplectic Euler and the leapfrog, which
// runs on the same positions and cell ranges (only the kick, which writes velocities, and the
// step size run between them; the leapfrog's midpoint shifts each accepted pair after the
// walk, in `neighbour`, as without the record): the rates pass takes the recorded candidates
// without their position loads and distance tests. Same neighbours, same order: the rates
// are those of the full test bit for bit. The bits live in the reorder's second set of
// arrays (`Buffers::alt`, which no stage reads between two grid builds: the next reorder
// writes it before anything reads it; `Buffers::pairs_recorded` says while the record
// holds): word k < 4 of particle i at
// a[k * n + i] (alt's velocities, float4 per particle), word k >= 4 at b[(k - 4) * n + i]
// (alt's positions: float4 per particle in 3D, float2 in 2D): 256 bits a particle in 3D
// (170-185 candidates at h = 1.3 dx), 192 in 2D (about 40). A chunk that does not fit
// within them, and every chunk after it, is tested again by the rates pass.
#define MF_PAIRS_NONE 0
#define MF_PAIRS_RECORD 1
#define MF_PAIRS_REPLAY 2
template <int DIM> struct PairBits {
    unsigned* a;  // null: nothing recorded (forces) or to replay (rates)
    unsigned* b;
    unsigned n;  // the particles of the pass (the planes' stride)
    static constexpr unsigned BITS = 32u * (DIM == 3 ? 8u : 6u);
    __device__ __forceinline__ unsigned* word(unsigned k, unsigned i) const {
        return k < 4u ? a + (size_t)k * n + i : b + (size_t)(k - 4u) * n + i;
    }
    // The cnt bits of chunk `mask` at bit off of particle i; pending: the bits of word
    // off / 32 below off % 32, not yet written.
    __device__ __forceinline__ void write(unsigned i, unsigned off, unsigned cnt, unsigned mask,
                                          unsigned& pending) const {
        const unsigned sh = off & 31u;
        if (off + cnt <= BITS) {
            pending |= mask << sh;
            if (sh + cnt >= 32u) {
                *word(off >> 5, i) = pending;
                pending = __funnelshift_l(mask, 0u, sh);  // mask >> (32 - sh); 0 where sh = 0
            }
        } else if (off < BITS && sh != 0u) {
            *word(off >> 5, i) = pending;  // the last bits that fit
        }
    }
    // After a particle's last chunk (off: its candidates).
    __device__ __forceinline__ void flush(unsigned i, unsigned off, unsigned pending) const {
        if (off < BITS && (off & 31u) != 0u) *word(off >> 5, i) = pending;
    }
    // The cnt bits at bit off of particle i (off + cnt <= BITS).
    __device__ __forceinline__ unsigned read(unsigned i, unsigned off, unsigned cnt) const {
        const unsigned sh = off & 31u;
        const unsigned lo = __ldg(word(off >> 5, i));
        const unsigned hi = sh + cnt > 32u ? __ldg(word((off >> 5) + 1u, i)) : 0u;
        return __funnelshift_r(lo, hi, sh) & (0xffffffffu >> (32u - cnt));
    }
};

// The one-lane neighbour loop in two phases per plane of rows, for the pair sums' SIMT
// efficiency: the lanes of a warp accept different numbers of candidates from each batch
// and row, and a warp runs a pair sum while any lane has one, so summing after each batch
// (batch_accept) runs the sum for the maximum over the lanes of every batch. Here the
// candidates of one plane of rows (one z offset; 2D: all rows) are only tested (B position
// loads in flight, as batch_accept), each chunk of 32 consecutive candidates with an accepted
// one leaving (first, mask) in the queue q; then one loop takes one accepted neighbour per
// pass, from whichever entry the lane is at, so that the warp runs the pair sum for the
// maximum over the lanes of their plane totals. A plane with more than MF_QUEUE such chunks
// (a dense cluster) is tested again from its next unqueued chunk after each drain, so that
// the fill and the pair sum each stay one site in the code (a second copy of the inlined
// pair sum cost registers). Same neighbours, same order as for_each_neighbor_split with
// L = 1: the same results bit for bit. MODE (PairBits): MF_PAIRS_RECORD writes each chunk's
// accepted candidates into pb (i: the particle's slot), MF_PAIRS_REPLAY takes them from pb
// instead of testing (where pb.a is set); sum = false: record only, no pair sums (a
// particle the rates pass sums and the forces pass does not, a dynamic wall); walk: the
// rows taken (`walked_rows`), the same in the pass that records and the one that replays.
template <int DIM, int B, bool PERIODIC, int MODE, class F>
__device__ __forceinline__ void queued_neighbours(const SphParams& p, const unsigned* __restrict__ cell_start,
                                                  const float* __restrict__ pos, Vec<DIM> xi, uint2* q,
                                                  unsigned* po, const PairBits<DIM>& pb, unsigned i, bool sum,
                                                  unsigned walk, F&& f) {
    static_assert(32 % B == 0, "batches must tile the 32-candidate chunks");
    const unsigned t = threadIdx.x;
    const bool record = MODE == MF_PAIRS_RECORD && pb.a != nullptr;
    const bool replay = MODE == MF_PAIRS_REPLAY && pb.a != nullptr;
    unsigned off = 0u, pending = 0u;  // candidates so far; the record's unwritten bits
    int ci[3];
    cell_coords<DIM>(p, xi, ci);
    const int rz = DIM == 3 ? MF_CELL_REACH : 0;
    for (int dz = -rz; dz <= rz; ++dz) {
        if (MODE != MF_PAIRS_NONE) po[t] = off;  // the plane's first bit, for a second pass
        for (int skip = 0;; skip += MF_QUEUE) {
            int seen = 0;  // chunks with an accepted candidate, this pass
            if (MODE != MF_PAIRS_NONE && skip > 0) off = po[t];
            plane_rows<DIM>(p, xi, ci, dz, [&](unsigned row, int x0, int x1) {
                row_ranges(p, cell_start, row, x0, x1, [&](unsigned s, unsigned e) {
                    for (unsigned c = s; c < e; c += 32) {
                        const unsigned cnt = min(e - c, 32u);
                        unsigned mask = 0;
                        if (replay && off + cnt <= PairBits<DIM>::BITS) {
                            mask = pb.read(i, off, cnt);
                        } else {
                            // Batches of B with no test of the range per candidate: the loads
                            // past e - 1 repeat it, and their bits are cleared once per chunk.
                            for (unsigned b = 0; b < cnt; b += B) {
                                const unsigned base = c + b;
                                Vec<DIM> xj[B];
#pragma unroll
                                for (int k = 0; k < B; ++k) xj[k] = vload<DIM>(pos, min(base + k, e - 1));
                                unsigned bits = 0;
#pragma unroll
                                for (int k = 0; k < B; ++k) {
                                    const Vec<DIM> r = separation<DIM, PERIODIC>(p, xi, xj[k]);
                                    bits |= (dist2_rn<DIM>(r) < p.support2 ? 1u : 0u) << k;
                                }
                                mask |= bits << b;
                            }
                            mask &= 0xffffffffu >> (32u - cnt);
                            if (record && skip == 0) pb.write(i, off, cnt, mask, pending);
                        }
                        off += cnt;
                        if (!sum || mask == 0u) continue;
                        const int slot = seen - skip;
                        if (slot >= 0 && slot < MF_QUEUE) q[slot * MF_BLOCK + t] = make_uint2(c, mask);
                        ++seen;
                    }
                });
            }, walk >> ((dz + rz) * (2 * MF_CELL_REACH + 1)));
            const int ne = min(seen - skip, MF_QUEUE);
            // The accepted neighbours of the queued entries, in order: every entry holds one
            // at least, so the next entry is read as the last bit of one is taken (a loop
            // over empty-handed entries before each sum: 0.6-0.9 % slower at 4M, H100).
            if (ne > 0) {
                int k = 0;
                uint2 en = q[t];
                do {
                    const unsigned j = en.x + (unsigned)(__ffs(en.y) - 1);
                    en.y &= en.y - 1u;
                    if (en.y == 0u && ++k < ne) en = q[k * MF_BLOCK + t];
                    call_neighbour<DIM, PERIODIC>(p, pos, xi, j, f);
                } while (k < ne);
            }
            if (seen - skip <= MF_QUEUE) break;
        }
    }
    if (record) pb.flush(i, off, pending);
}

// The neighbour loop of the forces and rates kernels (for_each_neighbor_split, or
// queued_neighbours for one lane), with the minimum image compiled in only where the scene
// has a periodic axis: tested once here, not per candidate. on: whether this lane takes
// particle i's candidates; sum: whether it calls f for its neighbours (false: it only
// records them, MODE and pb as for queued_neighbours: one lane only, and nothing is recorded
// or replayed without the queue, MF_QUEUE 0); walk: the candidate rows walked
// (`walked_rows`; every one but at one lane with the stamps).
template <int DIM, int L, int MODE = MF_PAIRS_NONE, class F>
__device__ __forceinline__ void neighbour_loop(const SphParams& p, const unsigned* __restrict__ cell_start,
                                               const float* __restrict__ pos, unsigned i, bool on, int lane,
                                               F&& f, const PairBits<DIM>& pb = PairBits<DIM>{}, bool sum = true,
                                               unsigned walk = ~0u) {
#if MF_QUEUE > 0
    if constexpr (L == 1) {
        __shared__ uint2 q[MF_QUEUE * MF_BLOCK];
        __shared__ unsigned po[MODE == MF_PAIRS_NONE ? 1 : MF_BLOCK];
        constexpr int QB = DIM == 2 ? MF_QUEUE_BATCH_2D : MF_QUEUE_BATCH_3D;
        if (!on) return;
        if (p.periodic[0] || p.periodic[1] || p.periodic[2])
            queued_neighbours<DIM, QB, true, MODE>(p, cell_start, pos, vload<DIM>(pos, i), q, po, pb, i, sum, walk, f);
        else
            queued_neighbours<DIM, QB, false, MODE>(p, cell_start, pos, vload<DIM>(pos, i), q, po, pb, i, sum, walk, f);
        return;
    }
#endif
    if (!on || !sum) return;
    if (p.periodic[0] || p.periodic[1] || p.periodic[2])
        for_each_neighbor_split<DIM, L, MF_NB_BATCH, true>(p, cell_start, pos, vload<DIM>(pos, i), lane, f);
    else
        for_each_neighbor_split<DIM, L, MF_NB_BATCH, false>(p, cell_start, pos, vload<DIM>(pos, i), lane, f);
}
