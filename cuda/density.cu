// Density by summation eq. (8) and the equations of state eq. (9).
// Twin: src/backend/cpu/density.rs; parity test: tests/cuda_parity.rs.
#include "common.cuh"

// Tait eq. (9) for fluid; P = c_s^2 (rho - rho0_s) for solids (Gray & Monaghan 2001).
__device__ __forceinline__ float pressure(const SphParams& p, unsigned char kind, float rho) {
    if (kind == MF_KIND_FLUID) return p.tait_b * (powf(rho / p.rho0, p.tait_gamma) - 1.0f);
    if (kind == MF_KIND_SOLID) return p.solid_c0 * p.solid_c0 * (rho - p.solid_rho0);
    return 0.0f;
}

template <int DIM, int L>
__device__ void density_impl(const SphParams p, unsigned n, const unsigned* __restrict__ cell_start,
                                 const float* __restrict__ pos, const unsigned char* __restrict__ kind,
                                 const float* __restrict__ mass, float* __restrict__ rho, float* __restrict__ pr) {
    const unsigned t = blockIdx.x * blockDim.x + threadIdx.x;
    const unsigned i = t / L;
    const int lane = (int)(t % L);
    const unsigned char ki = i < n ? kind[i] : (unsigned char)MF_KIND_BOUNDARY;
    const bool active = ki != MF_KIND_BOUNDARY;
    if (p.density_mode == MF_DENSITY_SUMMATION) {
        float sum_w = 0.0f;
        if (active)
            for_each_neighbor_split<DIM, L>(p, cell_start, pos, vload<DIM>(pos, i), lane,
                                            [&](unsigned j, Vec<DIM>, float r2) {
                                                if (couples(p, kind[j])) sum_w += kernel_w(p, sqrtf(r2));
                                            });
        sum_w = lane_sum<L>(sum_w);  // every lane of the warp takes part
        if (active && lane == 0) {
            const float r = mass[i] * sum_w;  // eq. (8), number-density form (Hu & Adams 2006)
            rho[i] = r;
            pr[i] = pressure(p, ki, r);  // eq. (9)
        }
    } else if (active && lane == 0) {
        pr[i] = pressure(p, ki, rho[i]);  // eq. (9)
    }
}
// Split lanes (small systems: shorter serial loops) and one lane per particle (large
// systems: more particles in flight; the CPU's exact summation order). The launcher picks.
template <int DIM>
__device__ void sph_density_body(const SphParams p, unsigned n, const unsigned* cell_start, const float* pos,
                                 const unsigned char* kind, const float* mass, float* rho, float* pr) {
    density_impl<DIM, Lanes<DIM>::L>(p, n, cell_start, pos, kind, mass, rho, pr);
}
template <int DIM>
__device__ void sph_density_1_body(const SphParams p, unsigned n, const unsigned* cell_start, const float* pos,
                                   const unsigned char* kind, const float* mass, float* rho, float* pr) {
    density_impl<DIM, 1>(p, n, cell_start, pos, kind, mass, rho, pr);
}
MF_ENTRY2(sph_density,
          (const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, const unsigned char* kind,
           const float* mass, float* rho, float* pr),
          (p, n, cell_start, pos, kind, mass, rho, pr))
MF_ENTRY2(sph_density_1,
          (const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, const unsigned char* kind,
           const float* mass, float* rho, float* pr),
          (p, n, cell_start, pos, kind, mass, rho, pr))
