// Forces and rates of one state in one neighbour pass, for the paper's forward Euler
// (`Solver::forces_and_rates`): the accelerations (ForceSum, forces.cuh) with the step
// size's maxima, and d rho/dt, XSPH and, with solids, the Jaumann rate (RateSum, rates.cuh),
// each summed over the neighbours in the same order as by the separate kernels (forces.cu,
// rates.cu), so the results are theirs; every candidate, its velocity and kind are loaded
// once instead of twice. Twin: src/backend/cpu/forces.rs and rates.rs (the trait's default
// runs them one after the other); parity test: tests/cuda_parity/.
#include "forces.cuh"
#include "rates.cuh"
#include "device/entries.cuh"
#include "device/neighbours.cuh"

template <int DIM, bool SOLIDS, bool EXTRAS, int L>
__device__ void forces_rates_impl(const SphParams& p, unsigned n, const unsigned* __restrict__ cell_start,
                                  const unsigned char* __restrict__ stamp, const float* __restrict__ pos, const float* __restrict__ vel,
                                  const float* __restrict__ rho, const float* __restrict__ pr,
                                  const unsigned char* __restrict__ kind,
                                  const unsigned* __restrict__ group, const float* __restrict__ stress,
                                  const float* __restrict__ art, const float* __restrict__ iface,
                                  const unsigned* __restrict__ id,
                                  const float* __restrict__ surf, float* __restrict__ acc_out,
                                  unsigned* __restrict__ red, const float* __restrict__ grad_rho,
                                  float* __restrict__ drho_out,
                                  float* __restrict__ xsph_out, float* __restrict__ rate_out) {
    __shared__ float sh[MF_BLOCK / 32];
    const unsigned t = blockIdx.x * blockDim.x + threadIdx.x;
    const unsigned i = t / L;
    const int lane = (int)(t % L);
    const unsigned char ki = i < n ? kind[i] : (unsigned char)MF_KIND_BOUNDARY;
    ForceSum<DIM, SOLIDS, EXTRAS> f;
    RateSum<DIM, SOLIDS, EXTRAS> r;
    f.begin(p, i, n, ki, lane, vel, rho, pr, group, stress, iface);
    r.begin(p, i, n, ki, vel, rho, group, grad_rho);
    // Every particle with forces has rates (dynamic walls have rates only); a wall at rest
    // walks the rows with a moving particle only, none among walls at rest alone (its rates
    // are 0 there: `walked_rows`).
    const unsigned walk = r.on ? walked_rows<DIM>(p, stamp, ki, vload<DIM>(pos, i)) : 0u;
    neighbour_loop<DIM, L>(p, cell_start, pos, i, r.on && walk != 0u, lane,
                              [&](unsigned j, Vec<DIM> rij, float r2, float pw) {
        if (j == i) return;
        const Neighbour<DIM> nb = neighbour<DIM, SOLIDS>(p, j, rij, r2, pw, vel, kind);
        if (f.on) f.add(p, i, n, nb, pr, group, stress, art, iface, id, surf);
        r.add(p, nb, group);
    }, PairBits<DIM>{}, true, walk);
    f.template finish<L>(p, i, n, lane, acc_out, red, sh, i < n && owns_slot<DIM>(p, pos, i));
    r.template finish<L>(p, i, n, lane, stress, drho_out, xsph_out, rate_out);
}

// Per dimension and lane count (MF_LANES_EACH), with and without solids, as for forces and
// rates; the arguments are those of forces, then those that rates writes. Bounds: as the
// separate kernels (fluid-only 4 blocks of 256 per SM, with solids 1).
#define MF_FORCES_RATES_ENTRY(name, DIM, SOLIDS, EXTRAS, L)                                                                 \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK, SOLIDS ? 1 : MF_FLUID_BLOCKS)                                        \
        name(const SphParams p, unsigned n, const unsigned* cell_start, const unsigned char* stamp, const float* pos, \
             const float* vel, const float* rho, const float* pr, const unsigned char* kind,                    \
             const unsigned* group, const float* stress, const float* art, const float* iface,      \
             const unsigned* id,                                                                        \
             const float* surf, float* acc, unsigned* red,            \
             const float* grad_rho, float* drho, float* xsph, float* rate) {                                     \
        forces_rates_impl<DIM, SOLIDS, EXTRAS, L>(p, n, cell_start, stamp, pos, vel, rho, pr, kind, group, stress, art, iface, id, surf, acc, \
                                          red, grad_rho, drho, xsph, rate);                                      \
    }
#define MF_FORCES_RATES_LANES(L) MF_SCHEMES(MF_FORCES_RATES_ENTRY, sph_forces_rates, L)
MF_LANES_EACH(MF_FORCES_RATES_LANES)
