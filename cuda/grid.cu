// Neighbour grid: cell index, deterministic counting sort by (cell, id) fused with the
// reorder.
// Twin: src/backend/cpu/grid.rs; parity test: tests/cuda_parity.rs.
#include "common.cuh"

#define MF_SCAN_BLOCK 1024

// 1. Cell of every particle and its arrival rank in that cell (any order: fixed in 5.);
// skipped where the last drift did it (hist_one in common.cuh).
template <int DIM>
__device__ void sph_grid_hist_body(const SphParams p, unsigned n, const float* __restrict__ pos,
                                   unsigned* __restrict__ cell, unsigned* __restrict__ rank,
                                   unsigned* __restrict__ count) {
    unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    hist_one<DIM>(p, i, vload<DIM>(pos, i), cell, rank, count);
}
MF_ENTRY2(sph_grid_hist,
          (const SphParams p, unsigned n, const float* pos, unsigned* cell, unsigned* rank, unsigned* count),
          (p, n, pos, cell, rank, count))

// 2. Exclusive scan of the counts within blocks of MF_SCAN_BLOCK cells, written to the cell
// starts (relative to the block until 5. adds the block's offset: no array of its own, 4 B
// per cell less); block totals to bsum.
extern "C" __global__ void __launch_bounds__(MF_SCAN_BLOCK)
sph_scan_local(unsigned n_cells, const unsigned* __restrict__ count, unsigned* __restrict__ local,
               unsigned* __restrict__ bsum) {
    __shared__ unsigned sh[MF_SCAN_BLOCK / 32];
    unsigned c = blockIdx.x * MF_SCAN_BLOCK + threadIdx.x;
    unsigned v = c < n_cells ? count[c] : 0u;
    const int w = threadIdx.x >> 5, l = threadIdx.x & 31;
    unsigned x = v;  // inclusive warp scan
    for (int o = 1; o < 32; o <<= 1) {
        unsigned y = __shfl_up_sync(0xffffffffu, x, o);
        if (l >= o) x += y;
    }
    if (l == 31) sh[w] = x;
    __syncthreads();
    if (w == 0) {
        unsigned s = sh[l];
        for (int o = 1; o < 32; o <<= 1) {
            unsigned y = __shfl_up_sync(0xffffffffu, s, o);
            if (l >= o) s += y;
        }
        sh[l] = s;  // inclusive over warps
    }
    __syncthreads();
    unsigned incl = x + (w > 0 ? sh[w - 1] : 0u);
    if (c < n_cells) local[c] = incl - v;
    if (threadIdx.x == MF_SCAN_BLOCK - 1) bsum[blockIdx.x] = incl;
}

// 3. Exclusive scan of the block totals, in place (one block, chunk by chunk).
extern "C" __global__ void __launch_bounds__(MF_SCAN_BLOCK)
sph_scan_top(unsigned n_blocks, unsigned* __restrict__ bsum) {
    __shared__ unsigned sh[MF_SCAN_BLOCK / 32];
    __shared__ unsigned carry;
    if (threadIdx.x == 0) carry = 0;
    __syncthreads();
    const int w = threadIdx.x >> 5, l = threadIdx.x & 31;
    for (unsigned base = 0; base < n_blocks; base += MF_SCAN_BLOCK) {
        unsigned b = base + threadIdx.x;
        unsigned v = b < n_blocks ? bsum[b] : 0u;
        unsigned x = v;
        for (int o = 1; o < 32; o <<= 1) {
            unsigned y = __shfl_up_sync(0xffffffffu, x, o);
            if (l >= o) x += y;
        }
        if (l == 31) sh[w] = x;
        __syncthreads();
        if (w == 0) {
            unsigned s = sh[l];
            for (int o = 1; o < 32; o <<= 1) {
                unsigned y = __shfl_up_sync(0xffffffffu, s, o);
                if (l >= o) s += y;
            }
            sh[l] = s;
        }
        __syncthreads();
        unsigned incl = x + (w > 0 ? sh[w - 1] : 0u);
        unsigned c0 = carry;
        if (b < n_blocks) bsum[b] = c0 + incl - v;
        __syncthreads();
        if (threadIdx.x == MF_SCAN_BLOCK - 1) carry = c0 + incl;
        __syncthreads();
    }
}

// 4. Scatter: slot = cell start + arrival rank (order inside a cell still arbitrary).
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
sph_grid_scatter(unsigned n, const unsigned* __restrict__ cell, const unsigned* __restrict__ rank,
                 const unsigned* __restrict__ local, const unsigned* __restrict__ bsum,
                 unsigned* __restrict__ order) {
    unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    unsigned k = cell[i];
    order[local[k] + bsum[k / MF_SCAN_BLOCK] + rank[i]] = i;
}

// 5. One thread per slot of the scatter's order: the particle's rank by id among its
// cell's (every slot compares against the whole segment: cells hold a few dozen particles,
// and the lanes of a warp mostly share one cell, so the segment's loads are broadcasts),
// which makes the order (cell, id) as on the CPU; the particle goes straight to its sorted
// slot, moving every persistent array (the mass travels in pos.w / vel.z, mass_of in
// common.cuh). cell_start holds the scan's block-relative starts (made absolute by 6.).
// eos != 0 (continuity density without artificial stress, where the density pass has
// nothing else to do): the equation of state eq. (9) is applied here, from the density
// the particle carries, and the velocity's w slot set (vel_w): the density pass is skipped.
template <int DIM>
__device__ void sph_grid_gather_body(const SphParams p, unsigned n, unsigned eos, const unsigned* __restrict__ order,
                                     const unsigned* __restrict__ cell, const unsigned* __restrict__ count,
                                     const unsigned* __restrict__ local, const unsigned* __restrict__ bsum,
                                     const unsigned* __restrict__ id, const unsigned char* __restrict__ kind,
                                     const unsigned* __restrict__ group,
                                     const float* __restrict__ pos, const float* __restrict__ vel,
                                     const float* __restrict__ rho, const float* __restrict__ pr,
                                     const float* __restrict__ stress, unsigned* __restrict__ id2,
                                     unsigned char* __restrict__ kind2, unsigned* __restrict__ group2,
                                     float* __restrict__ pos2, float* __restrict__ vel2,
                                     float* __restrict__ rho2, float* __restrict__ pr2, float* __restrict__ stress2) {
    unsigned a = blockIdx.x * blockDim.x + threadIdx.x;
    if (a >= n) return;
    const unsigned o = order[a];
    const unsigned c = cell[o];
    const unsigned s = local[c] + bsum[c / MF_SCAN_BLOCK], e = s + count[c];
    const unsigned key = id[o];
    unsigned k = s;
    for (unsigned b = s; b < e; ++b) k += id[order[b]] < key;  // ids are unique
    id2[k] = key;
    const unsigned char ki = kind[o];
    kind2[k] = ki;
    group2[k] = group[o];
    if constexpr (DIM == 2) {
        reinterpret_cast<float2*>(pos2)[k] = reinterpret_cast<const float2*>(pos)[o];
    } else {
        reinterpret_cast<float4*>(pos2)[k] = reinterpret_cast<const float4*>(pos)[o];
    }
    float4 v = reinterpret_cast<const float4*>(vel)[o];  // float4 in 2D too
    const float r = rho[o];
    rho2[k] = r;
    if (eos && (ki != MF_KIND_BOUNDARY || p.wall_pressure != 0)) {
        pr2[k] = pressure(p, ki, r);  // eq. (9), as the density pass
        v.w = vel_w(ki, r);
    } else {
        pr2[k] = pr[o];
        if (eos) v.w = vel_w(ki, r);
    }
    reinterpret_cast<float4*>(vel2)[k] = v;
    if (stress) {
#pragma unroll
        for (int q = 0; q < Sym<DIM>::N; ++q) stress2[q * n + k] = stress[q * n + o];
    }
}
MF_ENTRY2(sph_grid_gather,
          (const SphParams p, unsigned n, unsigned eos, const unsigned* order, const unsigned* cell,
           const unsigned* count, const unsigned* local, const unsigned* bsum, const unsigned* id,
           const unsigned char* kind, const unsigned* group, const float* pos, const float* vel, const float* rho,
           const float* pr, const float* stress, unsigned* id2, unsigned char* kind2, unsigned* group2,
           float* pos2, float* vel2, float* rho2, float* pr2, float* stress2),
          (p, n, eos, order, cell, count, local, bsum, id, kind, group, pos, vel, rho, pr, stress, id2, kind2,
           group2, pos2, vel2, rho2, pr2, stress2))

// 6. One thread per cell: the final cell ranges (block-relative start of 2. plus the
// block's offset of 3.; cell_start has n_cells + 1 entries) and the counts cleared for the
// next step's 1.
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
sph_grid_finish(unsigned n_cells, unsigned* __restrict__ count, const unsigned* __restrict__ bsum,
                unsigned* __restrict__ cell_start) {
    unsigned c = blockIdx.x * blockDim.x + threadIdx.x;
    if (c >= n_cells) return;
    const unsigned s = cell_start[c] + bsum[c / MF_SCAN_BLOCK];
    cell_start[c] = s;
    if (c == n_cells - 1) cell_start[n_cells] = s + count[c];
    count[c] = 0;
}
