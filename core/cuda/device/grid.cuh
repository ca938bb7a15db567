// The neighbour grid: cell coordinates and index, a particle filed in its cell (hist_one),
// the minimum-image separation, and the candidate rows of cells around a position (rows,
// row_ranges). Twin: src/backend/cpu/grid.rs; parity test: tests/cuda_parity/.
#pragma once
#include "sph_consts.h"
#include "sph_params.h"
#include "vectors.cuh"

template <int DIM> __device__ __forceinline__ void cell_coords(const SphParams& p, Vec<DIM> x, int c[3]) {
    c[0] = c[1] = c[2] = 0;
#pragma unroll
    for (int a = 0; a < DIM; ++a) {
        int v = (int)floorf((x.c[a] - p.domain_min[a]) / p.cell_size[a]);
        c[a] = min(max(v, 0), p.grid_dims[a] - 1);
    }
}
__device__ __forceinline__ unsigned cell_index(const SphParams& p, const int c[3]) {
    return (unsigned)(c[0] + p.grid_dims[0] * (c[1] + p.grid_dims[1] * c[2]));
}
// The grid build's first step for particle i at x (grid.cu): its cell, counted. The drift
// does it for the next build, from the positions it writes (`Buffers::hist_done`).
template <int DIM>
__device__ __forceinline__ void hist_one(const SphParams& p, unsigned i, Vec<DIM> x, unsigned* __restrict__ cell,
                                         unsigned* __restrict__ count) {
    int c[3];
    cell_coords<DIM>(p, x, c);
    const unsigned k = cell_index(p, c);
    cell[i] = k;
    atomicAdd(&count[k], 1u);
}
// Minimum-image r_i - r_j on periodic axes (twin: src/physics/pairs.rs `separation`; tlsph.cu takes
// it for the reference separations X0_a - X0_b too); PERIODIC = false: the scene has none (the
// neighbour loops test that once, not per candidate: see neighbour_loop).
template <int DIM, bool PERIODIC = true>
__device__ __forceinline__ Vec<DIM> separation(const SphParams& p, Vec<DIM> xi, Vec<DIM> xj) {
    Vec<DIM> r = xi - xj;
    if constexpr (PERIODIC) {
#pragma unroll
        for (int a = 0; a < DIM; ++a) {
            if (p.periodic[a]) {
                float len = p.domain_max[a] - p.domain_min[a];
                float d = r.c[a];
                if (d > 0.5f * len) r.c[a] = d - len;
                else if (d < -0.5f * len) r.c[a] = d + len;
            }
        }
    }
    return r;
}

// Squared distance from coordinate x to the slab of (unwrapped) cell c on axis a. The row
// bounds are written in explicitly rounded operations (__fmul_rn, __fadd_rn, ...), which the
// compiler never contracts into fused multiply-adds: every kernel then walks the same
// candidates, as the forces pass's record of accepted candidates needs (PairBits in
// neighbours.cuh: the rates pass replays it bit by bit along its own walk; with the
// contraction left to the compiler, the walks of two kernels differed for a few particles).
__device__ __forceinline__ float slab_gap2(const SphParams& p, int a, int c, float x) {
    const float lo = __fadd_rn(p.domain_min[a], __fmul_rn((float)c, p.cell_size[a]));
    const float g = fmaxf(fmaxf(__fsub_rn(lo, x), __fsub_rn(x, __fadd_rn(lo, p.cell_size[a]))), 0.0f);
    return __fmul_rn(g, g);
}

// The neighbour candidates of xi as rows of cells: for each (z, y) cell offset within
// MF_CELL_REACH (z outer, then y), skipping rows whose slab lies beyond the support, calls
// row(first cell index of the row, x0, x1) with the x cells x0..x1 (unwrapped on a periodic
// x axis) that the support's cross-section at that row reaches. Twin of `rows` in
// src/backend/cpu/grid.rs: the same neighbours in the same order (the candidates may differ
// by a cell beyond the support, see the row bounds below). `plane_rows` visits the rows of one
// z offset dz (ci: the cell of xi, from cell_coords) whose bit dy + MF_CELL_REACH in live is
// set (`walked_rows`), in 3D taken from the set bits (against a counted loop with a test of
// the bit per row: the 3D passes 0.6-1.4 % shorter, H200, every particle; 2D walks every row).
template <int DIM, class R>
__device__ __forceinline__ void plane_rows(const SphParams& p, Vec<DIM> xi, const int ci[3], int dz, R&& row,
                                           unsigned live = ~0u) {
    const int reach = MF_CELL_REACH;
    const int nx = p.grid_dims[0];
    const float r2max = p.support2;
    int cz = ci[2] + dz;
    if (cz < 0 || cz >= p.grid_dims[2]) {
        if (!p.periodic[2]) return;
        cz = (cz + p.grid_dims[2]) % p.grid_dims[2];
    }
    float gz = 0.0f;
    if constexpr (DIM == 3) gz = slab_gap2(p, 2, ci[2] + dz, xi.c[2]);
    const float inv_cx = 1.0f / p.cell_size[0];
    auto one_row = [&](int dy) {
        int cy = ci[1] + dy;
        if (cy < 0 || cy >= p.grid_dims[1]) {
            if (!p.periodic[1]) return;
            cy = (cy + p.grid_dims[1]) % p.grid_dims[1];
        }
        const float d2 = __fadd_rn(gz, slab_gap2(p, 1, ci[1] + dy, xi.c[1]));
        if (d2 > r2max * (1.0f + MF_PRUNE_SLACK)) return;
        // Half-width of the support's cross-section at this row, then the x cells it spans.
        // The root and the cell quotient are the fast ones (rsqrt, a product by the
        // reciprocal: IEEE's root and two divisions took about a third of the row's
        // instructions). Their rounding (about 1e-7 of the root and of the quotient, the
        // size of the rounding already in x +- w) is covered by the pruning's slack, as the
        // GPU's rounding of the slack term already is: the CPU's exact forms prune to the
        // same neighbours. Explicitly rounded, as slab_gap2.
        const float h2 = fmaxf(__fsub_rn(r2max, d2), 0.0f);
        const float w = __fadd_rn(h2 > 0.0f ? __fmul_rn(h2, rsqrtf(h2)) : 0.0f, MF_PRUNE_SLACK * p.support);
        int x0 = max(ci[0] - reach, (int)floorf(__fmul_rn(__fsub_rn(__fsub_rn(xi.c[0], w), p.domain_min[0]), inv_cx)));
        int x1 = min(ci[0] + reach, (int)floorf(__fmul_rn(__fsub_rn(__fadd_rn(xi.c[0], w), p.domain_min[0]), inv_cx)));
        if (!p.periodic[0]) {
            x0 = max(x0, 0);
            x1 = min(x1, nx - 1);
        }
        if (x0 > x1) return;
        row((unsigned)(nx * (cy + p.grid_dims[1] * cz)), x0, x1);
    };
    if constexpr (DIM == 3) {
        for (unsigned m = live & ((1u << (2 * reach + 1)) - 1u); m != 0u; m &= m - 1u) one_row(__ffs(m) - 1 - reach);
    } else {
        for (int dy = -reach; dy <= reach; ++dy) one_row(dy);
    }
}
template <int DIM, class R> __device__ __forceinline__ void rows(const SphParams& p, Vec<DIM> xi, R&& row) {
    int ci[3];
    cell_coords<DIM>(p, xi, ci);
    const int rz = DIM == 3 ? MF_CELL_REACH : 0;
    for (int dz = -rz; dz <= rz; ++dz) plane_rows<DIM>(p, xi, ci, dz, row);
}

// The candidate ranges of one row (see `rows`): a row that does not wrap around a periodic x
// axis is one contiguous range of storage (cells are x-fastest and the storage is sorted by
// cell); a row that wraps across one end is two, its cells before the seam and then those
// after it (x0 < 0: cells nx + x0 .. nx - 1, then 0 .. x1; x1 >= nx: x0 .. nx - 1, then
// 0 .. x1 - nx), the cells in the same order as cell by cell. Cell by cell, every cell a range
// of its own, a particle at the seam took five times the batches and their load chains of
// any other: the warps at the seam set a pass's length (vortex-street-re140 on an H200: the
// forces pass 36 us where a dam break of its size takes 14 us for as many instructions).
// A row longer than the axis (fewer than 2 MF_CELL_REACH + 1 cells) is still taken cell by
// cell. Calls range(s, e) for each.
template <class F>
__device__ __forceinline__ void row_ranges(const SphParams& p, const unsigned* __restrict__ cell_start,
                                           unsigned row, int x0, int x1, F&& range) {
    const int nx = p.grid_dims[0];
    if (x0 >= 0 && x1 < nx) {
        range(cell_start[row + x0], cell_start[row + x1 + 1]);
        return;
    }
    if (x1 - x0 < nx && (x0 < 0) != (x1 >= nx)) {
        const int a = x0 < 0 ? x0 + nx : x0;  // the first cell, before the seam
        const int b = x0 < 0 ? x1 : x1 - nx;  // the last cell, after it
        range(cell_start[row + a], cell_start[row + nx]);
        range(cell_start[row], cell_start[row + b + 1]);
        return;
    }
    for (int cx = x0; cx <= x1; ++cx) {
        const unsigned c = row + (unsigned)((cx + nx) % nx);
        range(cell_start[c], cell_start[c + 1]);
    }
}

// The rows of walls at rest. The grid build (`sph_grid_gather`) stamps, for every moving
// particle (any but a wall at rest, `wall_at_rest`), the cells within MF_CELL_REACH of its
// cell along x with the build's epoch (stamp[n_cells], 1 ... 255, advanced by
// `sph_grid_scatter`), and for a moving wall (around) those of every row within reach:
// stamp_moving. A particle's candidates (`rows`) lie within MF_CELL_REACH cells of its own on
// every axis, so the cell of its own x column in a row around it carries the epoch where that
// row holds a moving candidate, and in every row where it is itself a moving wall
// (moving_rows). A dynamic wall walks only those rows (walked_rows): each pair's term
// m_j / rho_j v_ij . grad_i W_ij of eq. (8) between two walls at rest has v_ij = 0, and a wall
// has no other rate (`RateSum`), so the rows of walls at rest alone add 0 to its sum, and a
// wall with none walks nothing and writes 0 (the CPU sums the zeros: the same rates). A
// non-driven wall's velocity does not change within a step (the kick leaves it), so the
// stamps hold from the build to the rates pass, and the forces pass records the candidates of
// the rows the rates pass replays. An epoch met again 255 builds later may find a stale
// stamp: a row read as moving, which costs a walk, never a rate.
template <int DIM>
__device__ __forceinline__ void stamp_moving(const SphParams& p, unsigned char* __restrict__ stamp, const int cc[3],
                                             unsigned char epoch, bool around) {
    const int nx = p.grid_dims[0];
    const int r = around ? MF_CELL_REACH : 0;
    for (int dz = -r; dz <= r; ++dz) {
        int cz = cc[2] + dz;
        if (cz < 0 || cz >= p.grid_dims[2]) {
            if (!p.periodic[2]) continue;
            cz = (cz + p.grid_dims[2]) % p.grid_dims[2];
        }
        for (int dy = -r; dy <= r; ++dy) {
            int cy = cc[1] + dy;
            if (cy < 0 || cy >= p.grid_dims[1]) {
                if (!p.periodic[1]) continue;
                cy = (cy + p.grid_dims[1]) % p.grid_dims[1];
            }
            const unsigned row = (unsigned)nx * ((unsigned)cy + (unsigned)p.grid_dims[1] * (unsigned)cz);
#pragma unroll
            for (int d = -MF_CELL_REACH; d <= MF_CELL_REACH; ++d) {
                int x = cc[0] + d;
                if (x < 0 || x >= nx) {
                    if (!p.periodic[0]) continue;
                    x = ((x % nx) + nx) % nx;
                }
                stamp[row + (unsigned)x] = epoch;
            }
        }
    }
}
// One cell coordinate on axis a, c + d (|d| <= MF_CELL_REACH), wrapped on a periodic axis
// (one wrap, then the clamp that an axis of one cell needs: selects, where a modulo's
// division, computed under a predicate for every load, cost 1.5 % of db3d-ppH70's step);
// outside a closed axis, own (the particle's, whose own cell the test reads anyway: no
// branch around the loads).
__device__ __forceinline__ int stamp_axis(const SphParams& p, int a, int c, int d, int own) {
    const int n = p.grid_dims[a];
    const int v = c + d;
    if (p.periodic[a]) return min(max(v < 0 ? v + n : (v >= n ? v - n : v), 0), n - 1);
    return v < 0 || v >= n ? own : v;
}
// Bit (dz + R) (2 R + 1) + (dy + R) (R = MF_CELL_REACH) set where the candidate row of xi
// at that (z, y) offset (`rows`) holds a moving particle: the cell of that row in xi's x
// column carries the epoch. Every bit without stamps (2D, or a build that did not stamp).
template <int DIM>
__device__ __forceinline__ unsigned moving_rows(const SphParams& p, const unsigned char* __restrict__ stamp,
                                                Vec<DIM> xi) {
    if constexpr (DIM == 2) {
        return ~0u;  // 3D only (`Buffers::stamp`): no code in the 2D kernels
    } else {
        if (stamp == nullptr) return ~0u;
        const unsigned char epoch = stamp[p.n_cells];
        int ci[3];
        cell_coords<DIM>(p, xi, ci);
        // Every load's address first, then the loads, independent of each other (a chain of
        // dependent cache misses per wall cost more than the skip saved).
        unsigned moving = 0;
        int bit = 0;
#pragma unroll
        for (int dz = -MF_CELL_REACH; dz <= MF_CELL_REACH; ++dz) {
            const int cz = stamp_axis(p, 2, ci[2], dz, ci[2]);
#pragma unroll
            for (int dy = -MF_CELL_REACH; dy <= MF_CELL_REACH; ++dy, ++bit) {
                const int c[3] = {ci[0], stamp_axis(p, 1, ci[1], dy, ci[1]), cz};
                moving |= (unsigned)(__ldg(&stamp[cell_index(p, c)]) == epoch) << bit;
            }
        }
        return moving;
    }
}
// The candidate rows that a particle of kind ki at xi walks (bits as moving_rows): a dynamic
// wall only those with a moving candidate (every one if it moves itself), any other particle
// every row (see stamp_moving).
template <int DIM>
__device__ __forceinline__ unsigned walked_rows(const SphParams& p, const unsigned char* __restrict__ stamp,
                                                unsigned char ki, Vec<DIM> xi) {
    return ki == MF_KIND_BOUNDARY ? moving_rows<DIM>(p, stamp, xi) : ~0u;
}
