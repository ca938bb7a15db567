// Neighbour grid: cell index, deterministic counting sort by (cell, id) fused with the
// reorder.
// Twin: src/backend/cpu/grid.rs; parity test: tests/cuda_parity/.
#include "device/entries.cuh"
#include "device/grid.cuh"
#include "device/packing.cuh"
#include "device/particle.cuh"
#include "device/vectors.cuh"

// 1. Cell of every particle and the count of every cell; skipped where the last drift did
// it (hist_one in device/grid.cuh).
template <int DIM>
__device__ void sph_grid_hist_body(const SphParams p, unsigned n, const float* __restrict__ pos,
                                   unsigned* __restrict__ cell, unsigned* __restrict__ count) {
    unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    hist_one<DIM>(p, i, vload<DIM>(pos, i), cell, count);
}
MF_ENTRY2(sph_grid_hist, (const SphParams p, unsigned n, const float* pos, unsigned* cell, unsigned* count),
          (p, n, pos, cell, count))

// Inclusive scan of v over the block's MF_SCAN_BLOCK threads (all of them call it); sh:
// MF_SCAN_BLOCK / 32 words of shared memory, free again after the next __syncthreads.
__device__ __forceinline__ unsigned block_inclusive_scan(unsigned v, unsigned* sh) {
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
    return x + (w > 0 ? sh[w - 1] : 0u);
}

// 2. Exclusive scan of the counts within blocks of MF_SCAN_BLOCK threads, ITEMS consecutive
// cells per thread (16-byte loads and stores), written to `local` (relative to the block);
// returns the block's total to its last thread. Run over n_cells + 1 entries (count[n_cells]
// = 0), so that start(n_cells) = n closes the last cell's range.
template <unsigned ITEMS>
__device__ __forceinline__ unsigned scan_local_block(unsigned n_cells, const unsigned* __restrict__ count,
                                                     unsigned* __restrict__ local) {
    constexpr unsigned Q = ITEMS / 4;  // 16-byte words per thread
    __shared__ unsigned sh[MF_SCAN_BLOCK / 32];
    const unsigned c = blockIdx.x * MF_SCAN_BLOCK * ITEMS + threadIdx.x * ITEMS;
    const bool whole = c + ITEMS <= n_cells;
    unsigned v[ITEMS];
    if (whole) {
#pragma unroll
        for (unsigned q = 0; q < Q; ++q) {
            const uint4 w = reinterpret_cast<const uint4*>(count)[c / 4 + q];
            v[4 * q] = w.x;
            v[4 * q + 1] = w.y;
            v[4 * q + 2] = w.z;
            v[4 * q + 3] = w.w;
        }
    } else {
#pragma unroll
        for (unsigned k = 0; k < ITEMS; ++k) v[k] = c + k < n_cells ? count[c + k] : 0u;
    }
    unsigned t = 0;
#pragma unroll
    for (unsigned k = 0; k < ITEMS; ++k) t += v[k];
    const unsigned incl = block_inclusive_scan(t, sh);
    unsigned e = incl - t;
#pragma unroll
    for (unsigned k = 0; k < ITEMS; ++k) {
        const unsigned x = v[k];
        v[k] = e;
        e += x;
    }
    if (whole) {
#pragma unroll
        for (unsigned q = 0; q < Q; ++q)
            reinterpret_cast<uint4*>(local)[c / 4 + q] = make_uint4(v[4 * q], v[4 * q + 1], v[4 * q + 2], v[4 * q + 3]);
    } else {
#pragma unroll
        for (unsigned k = 0; k < ITEMS; ++k)
            if (c + k < n_cells) local[c + k] = v[k];
    }
    return incl;
}

// Blocks of MF_SCAN_CELLS cells (start(c) = local[c] + bsum[c / MF_SCAN_CELLS] after 3.);
// the blocks' totals to bsum, or, where one block holds every cell, its offset 0, so that 3.
// is not needed.
extern "C" __global__ void __launch_bounds__(MF_SCAN_BLOCK)
sph_scan_local(unsigned n_cells, const unsigned* __restrict__ count, unsigned* __restrict__ local,
               unsigned* __restrict__ bsum) {
    const unsigned incl = scan_local_block<MF_SCAN_ITEMS>(n_cells, count, local);
    if (threadIdx.x == MF_SCAN_BLOCK - 1) bsum[blockIdx.x] = gridDim.x == 1 ? 0u : incl;
}

// The same in one block of twice the cells, for MF_SCAN_CELLS < n_cells <= 2 MF_SCAN_CELLS:
// the scan is complete in `local` and both blocks' offsets in bsum are 0 (a small grid's
// build without 3., one kernel shorter).
extern "C" __global__ void __launch_bounds__(MF_SCAN_BLOCK)
sph_scan_one(unsigned n_cells, const unsigned* __restrict__ count, unsigned* __restrict__ local,
             unsigned* __restrict__ bsum) {
    scan_local_block<2 * MF_SCAN_ITEMS>(n_cells, count, local);
    if (threadIdx.x < 2) bsum[threadIdx.x] = 0u;
}

// 3. Exclusive scan of the block totals, in place (one block, chunk by chunk), where the
// cells fill more than two blocks of MF_SCAN_CELLS.
extern "C" __global__ void __launch_bounds__(MF_SCAN_BLOCK)
sph_scan_top(unsigned n_blocks, unsigned* __restrict__ bsum) {
    __shared__ unsigned sh[MF_SCAN_BLOCK / 32];
    __shared__ unsigned carry;
    if (threadIdx.x == 0) carry = 0;
    __syncthreads();
    for (unsigned base = 0; base < n_blocks; base += MF_SCAN_BLOCK) {
        unsigned b = base + threadIdx.x;
        unsigned v = b < n_blocks ? bsum[b] : 0u;
        unsigned incl = block_inclusive_scan(v, sh);
        unsigned c0 = carry;
        if (b < n_blocks) bsum[b] = c0 + incl - v;
        __syncthreads();
        if (threadIdx.x == MF_SCAN_BLOCK - 1) carry = c0 + incl;
        __syncthreads();
    }
}

// Where cell c's particles start in the sorted order (c <= n_cells), from 2. and 3.
__device__ __forceinline__ unsigned cell_start_of(const unsigned* __restrict__ local, const unsigned* __restrict__ bsum,
                                                  unsigned c) {
    return local[c] + bsum[c / MF_SCAN_CELLS];
}

// 4. Scatter: each particle takes a slot of its cell's range by counting the cell's count
// down (any order inside the cell: 5. sorts), which leaves the counts at zero for the next
// build's 1. The particles are in the last build's cell order, so most lanes of a warp share
// a cell with the lane before: each run of equal cells takes its slots with one atomic,
// from its first lane (__match_any_sync, which would also join runs that are apart,
// measured slower than one atomic per particle on the H100, docs/reference/performance.md).
// It also clears the step size's maxima `red` for the step's forces pass (a kick or a
// drift-kick that took the last step's dt from them left them: integrate.cu), and advances
// (where not null) the build's epoch (1 ... 255, never the 0 of a cell never stamped) with
// which 5. stamps the cells near moving particles (`stamp_moving` in device/grid.cuh).
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
sph_grid_scatter(unsigned n, const unsigned* __restrict__ cell, const unsigned* __restrict__ local,
                 const unsigned* __restrict__ bsum, unsigned* __restrict__ count, unsigned* __restrict__ order,
                 unsigned* __restrict__ red, unsigned char* __restrict__ epoch) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i == 0) {
        red[0] = red[1] = red[2] = 0u;
        // An epoch reused 255 builds later may find a stale stamp: a cell read as moving,
        // which costs a wall's skip, never a rate.
        if (epoch) epoch[0] = (unsigned char)(epoch[0] % 255u + 1u);
    }
    const bool valid = i < n;  // every lane takes part in the warp's exchanges
    const unsigned k = valid ? cell[i] : 0xffffffffu;
    const int lane = threadIdx.x & 31;
    const unsigned before = __shfl_up_sync(0xffffffffu, k, 1);
    const unsigned heads = __ballot_sync(0xffffffffu, lane == 0 || k != before);
    const int head = 31 - __clz(heads & (0xffffffffu >> (31 - lane)));    // my run's first lane
    const unsigned later = heads & ~(0xffffffffu >> (31 - lane));          // heads after me
    const int end = later ? __ffs(later) - 1 : 32;                          // one past my run
    unsigned top = 0;
    // (Lanes past n have the cell 0xffffffff: runs of their own, never counted.)
    if (valid && lane == head) top = atomicSub(&count[k], (unsigned)(end - head));
    top = __shfl_sync(0xffffffffu, top, head);  // the run's count before its atomic
    if (valid) order[cell_start_of(local, bsum, k) + top - 1u - (unsigned)(lane - head)] = i;
}

// 5. One thread per slot of the scatter's order: the particle's rank by id among its
// cell's (every slot compares against the whole segment: cells hold a few dozen particles,
// and the lanes of a warp mostly share one cell, so the segment's loads are broadcasts),
// which makes the order (cell, id) as on the CPU; the particle goes straight to its sorted
// slot, moving every persistent array (the mass travels in pos.w / vel.z, mass_of in
// device/packing.cuh). The first n_cells + 1 threads also write the cell ranges the
// neighbour loops read (cell_start, n_cells + 1 entries); grid: max(n, n_cells + 1) threads.
// eos != 0 (continuity density without artificial stress, where the density pass has
// nothing else to do): the equation of state eq. (9) is applied here, from the density
// the particle carries, and the velocity's w slot set (vel_w): the density pass is skipped.
// Around each moving particle (not a wall at rest: `wall_at_rest`) the cells of its x row
// within reach, and around a moving wall those of every row within reach, are stamped with
// the build's epoch (stamp: n_cells cells, then the epoch that 4.
// advanced: `stamp_moving` in device/grid.cuh; null: none), which lets the neighbour passes
// skip the rows of walls at rest around a wall at rest (`walked_rows`).
template <int DIM>
__device__ void sph_grid_gather_body(const SphParams p, unsigned n, unsigned n_cells, unsigned eos,
                                     const unsigned* __restrict__ order, const unsigned* __restrict__ local, const unsigned* __restrict__ bsum,
                                     unsigned* __restrict__ cell_start, unsigned char* __restrict__ stamp,
                                     const unsigned* __restrict__ id, const unsigned char* __restrict__ kind,
                                     const unsigned* __restrict__ group,
                                     const float* __restrict__ pos, const float* __restrict__ vel,
                                     const float* __restrict__ rho, const float* __restrict__ pr,
                                     const float* __restrict__ stress, const float* __restrict__ rho_dev,
                                     unsigned* __restrict__ id2,
                                     unsigned char* __restrict__ kind2, unsigned* __restrict__ group2,
                                     float* __restrict__ pos2, float* __restrict__ vel2,
                                     float* __restrict__ rho2, float* __restrict__ pr2, float* __restrict__ stress2,
                                     float* __restrict__ rho_dev2) {
    unsigned a = blockIdx.x * blockDim.x + threadIdx.x;
    if (a <= n_cells) cell_start[a] = cell_start_of(local, bsum, a);
    if (a >= n) return;
    const unsigned o = order[a];
    int cc[3];  // its cell, from the position it carries (as 1. found it; no read of cell[])
    cell_coords<DIM>(p, vload<DIM>(pos, o), cc);
    const unsigned c = cell_index(p, cc);
    const unsigned s = cell_start_of(local, bsum, c), e = cell_start_of(local, bsum, c + 1);
    const unsigned key = id[o];
    unsigned k = s;
    for (unsigned b = s; b < e; ++b) k += id[order[b]] < key;  // ids are unique
    id2[k] = key;
    const unsigned char ki = kind[o];
    kind2[k] = ki;
    const unsigned g = group[o];
    group2[k] = g;
    if constexpr (DIM == 2) {
        reinterpret_cast<float2*>(pos2)[k] = reinterpret_cast<const float2*>(pos)[o];
    } else {
        reinterpret_cast<float4*>(pos2)[k] = reinterpret_cast<const float4*>(pos)[o];
    }
    float4 v = reinterpret_cast<const float4*>(vel)[o];  // float4 in 2D too
    const float r = rho[o];
    rho2[k] = r;
    float dev = 0.0f;  // the solids' departure rho - rho0_s (null without solids)
    if (rho_dev) {
        dev = rho_dev[o];
        rho_dev2[k] = dev;
    }
    if (eos && (ki != MF_KIND_BOUNDARY || p.wall_coupling != 0)) {
        pr2[k] = pressure(p, ki, r, dev);  // eq. (9), as the density pass
        v.w = vel_w(ki, r);
    } else {
        pr2[k] = pr[o];
        if (eos) v.w = vel_w(ki, r);
    }
    reinterpret_cast<float4*>(vel2)[k] = v;
    if constexpr (DIM == 3) {  // the stamps are 3D only (`Buffers::stamp`)
        Vec<DIM> vv;
        vv.c[0] = v.x;
        vv.c[1] = v.y;
        vv.c[2] = v.z;
        if (stamp && !wall_at_rest<DIM>(p, ki, g, vv))
            stamp_moving<DIM>(p, stamp, cc, stamp[p.n_cells], ki == MF_KIND_BOUNDARY);
    }
    if (stress) {
#pragma unroll
        for (int q = 0; q < Sym<DIM>::N; ++q) stress2[q * n + k] = stress[q * n + o];
    }
}
MF_ENTRY2(sph_grid_gather,
          (const SphParams p, unsigned n, unsigned n_cells, unsigned eos, const unsigned* order,
           const unsigned* local, const unsigned* bsum, unsigned* cell_start, unsigned char* stamp,
           const unsigned* id, const unsigned char* kind, const unsigned* group, const float* pos, const float* vel, const float* rho,
           const float* pr, const float* stress, const float* rho_dev, unsigned* id2, unsigned char* kind2,
           unsigned* group2, float* pos2, float* vel2, float* rho2, float* pr2, float* stress2, float* rho_dev2),
          (p, n, n_cells, eos, order, local, bsum, cell_start, stamp, id, kind, group, pos, vel, rho, pr, stress, rho_dev,
           id2, kind2, group2, pos2, vel2, rho2, pr2, stress2, rho_dev2))
