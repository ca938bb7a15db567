// Rates from the current velocities (RateSum in rates.cuh): d rho/dt, XSPH and, with solids,
// the Jaumann stress rate. Twin: src/backend/cpu/rates.rs; parity test: tests/cuda_parity.rs.
#include "rates.cuh"

// drho: null without the continuity density; stress, rate: null without solids.
template <int DIM, bool SOLIDS, bool EXTRAS, int L>
__device__ void rates_impl(const SphParams& p, unsigned n, const unsigned* __restrict__ cell_start,
                           const float* __restrict__ pos, const float* __restrict__ vel,
                           const float* __restrict__ rho,
                           const unsigned char* __restrict__ kind, const unsigned* __restrict__ group,
                           const float* __restrict__ stress, float* __restrict__ drho_out,
                           float* __restrict__ xsph_out, float* __restrict__ rate_out) {
    const unsigned t = blockIdx.x * blockDim.x + threadIdx.x;
    const unsigned i = t / L;
    const int lane = (int)(t % L);
    RateSum<DIM, SOLIDS, EXTRAS> r;
    r.begin(p, i, n, i < n ? kind[i] : (unsigned char)MF_KIND_BOUNDARY, vel, rho, group);
    neighbour_loop<DIM, L>(p, cell_start, pos, i, r.on, lane,
                              [&](unsigned j, Vec<DIM> rij, float r2, float pw) {
        if (j == i) return;
        r.add(p, neighbour<DIM, SOLIDS>(p, j, rij, r2, pw, vel, kind), group);
    });
    r.template finish<L>(p, i, n, lane, stress, drho_out, xsph_out, rate_out);
}

// Per dimension and lane count (MF_LANES_EACH), as for forces: with / without solids; same
// signature, picked by the launcher. The fluid-only variants are bounded to 4 blocks of 256
// per SM (64 registers; unbounded they take 78-79 in 3D: 3 blocks).
#define MF_RATES_ENTRY(name, DIM, SOLIDS, EXTRAS, L)                                                                   \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK, SOLIDS ? 1 : MF_FLUID_BLOCKS)                                   \
        name(const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, const float* vel, \
             const float* rho, const unsigned char* kind, const unsigned* group,          \
             const float* stress, float* drho, float* xsph, float* rate) {                                    \
        rates_impl<DIM, SOLIDS, EXTRAS, L>(p, n, cell_start, pos, vel, rho, kind, group, stress, drho, xsph, rate); \
    }
#define MF_RATES_LANES(L) MF_SCHEMES(MF_RATES_ENTRY, sph_rates, L)
MF_LANES_EACH(MF_RATES_LANES)

