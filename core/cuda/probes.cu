// Probes: pressure, velocity, density and the fluid's colour kernel-interpolated at points
// (Solver::sample_points), eqs. (1)-(4) with Shepard normalisation (PointSum in
// device/probes.cuh). Twin: src/backend/cpu/probes.rs; parity test: tests/cuda_parity/.
#include "device/entries.cuh"
#include "device/neighbours.cuh"
#include "device/packing.cuh"
#include "device/probes.cuh"
#include "device/vectors.cuh"

// One thread per point (a handful to a few thousand points): the neighbours of the grid at
// one lane, in the CPU's order (for_each_neighbor_split with L = 1). points: float4 per point
// (x, y, z, unused); walls != 0: wall particles enter the interpolation too; out:
// MF_SAMPLE_FLOATS per point. The grid must list the particles at their current positions
// (the solver rebuilds it first where they moved).
template <int DIM>
__device__ void sph_sample_points_body(const SphParams p, unsigned n_points, const float* __restrict__ points,
                                       unsigned walls, const unsigned* __restrict__ cell_start,
                                       const float* __restrict__ pos, const float* __restrict__ vel,
                                       const float* __restrict__ rho, const unsigned char* __restrict__ kind,
                                       float* __restrict__ out) {
    const unsigned k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= n_points) return;
    const float4 x4 = reinterpret_cast<const float4*>(points)[k];
    Vec<DIM> x;
    x.c[0] = x4.x;
    x.c[1] = x4.y;
    if constexpr (DIM == 3) x.c[2] = x4.z;
    PointSum<DIM> sum;
    for_each_neighbor_split<DIM, 1>(p, cell_start, pos, x, 0, [&](unsigned j, Vec<DIM>, float r2, float) {
        float m, vw;
        const Vec<DIM> v = vel_load<DIM>(vel, j, m, vw);
        sum.add(p, walls != 0, kind[j], sqrtf(r2), mass_of<DIM>(pos, vel, j), rho[j], v);
    });
    sum.finish(out + (size_t)k * MF_SAMPLE_FLOATS);
}
MF_ENTRY2(sph_sample_points,
          (const SphParams p, unsigned n_points, const float* points, unsigned walls, const unsigned* cell_start,
           const float* pos, const float* vel, const float* rho, const unsigned char* kind, float* out),
          (p, n_points, points, walls, cell_start, pos, vel, rho, kind, out))
