// Accelerations (ForceSum in forces.cuh) and the block maxima of |v|, |a| and c for the step
// size (the velocities do not change between forces and time_step in either integrator
// order). At one lane per particle it also records the accepted candidates of every particle
// with rates for the rates pass at the same positions (PairBits in device/neighbours.cuh;
// pair_a, pair_b: null for none). Twin: src/backend/cpu/forces.rs (+ extremes in reduce.rs);
// parity test: tests/cuda_parity/.
#include "forces.cuh"
#include "device/entries.cuh"
#include "device/neighbours.cuh"

template <int DIM, bool SOLIDS, bool EXTRAS, int L>
__device__ void forces_impl(const SphParams& p, unsigned n, const unsigned* __restrict__ cell_start,
                            const unsigned char* __restrict__ stamp, const float* __restrict__ pos, const float* __restrict__ vel,
                            const float* __restrict__ rho, const float* __restrict__ pr,
                            const unsigned char* __restrict__ kind,
                            const unsigned* __restrict__ group, const float* __restrict__ stress,
                            const float* __restrict__ art, const float* __restrict__ iface,
                            const unsigned* __restrict__ id,
                            const float* __restrict__ surf, float* __restrict__ acc_out, unsigned* __restrict__ red,
                            unsigned* __restrict__ pair_a, unsigned* __restrict__ pair_b) {
    __shared__ float sh[MF_BLOCK / 32];
    const unsigned t = blockIdx.x * blockDim.x + threadIdx.x;
    const unsigned i = t / L;
    const int lane = (int)(t % L);
    const unsigned char ki = i < n ? kind[i] : (unsigned char)MF_KIND_BOUNDARY;
    ForceSum<DIM, SOLIDS, EXTRAS> f;
    f.begin(p, i, n, ki, lane, vel, rho, pr, group, stress, iface);
    // A particle with rates and no forces (a dynamic wall) only records its candidates; a
    // wall at rest only those in the rows with a moving particle, none among walls at rest
    // alone (its rates are 0: the rates pass walks the same rows, `walked_rows`).
    const PairBits<DIM> pb{L == 1 ? pair_a : nullptr, pair_b, n};
    const unsigned walk = i < n ? walked_rows<DIM>(p, stamp, ki, vload<DIM>(pos, i)) : 0u;
    const bool record = pb.a != nullptr && i < n && has_rates(p, ki) && walk != 0u;
    neighbour_loop<DIM, L, MF_PAIRS_RECORD>(p, cell_start, pos, i, f.on || record, lane,
                                            [&](unsigned j, Vec<DIM> r, float r2, float pw) {
        if (j == i) return;
        f.add(p, i, n, neighbour<DIM, SOLIDS>(p, j, r, r2, pw, vel, kind), pr, group, stress, art, iface, id, surf);
    }, pb, f.on, walk);
    f.template finish<L>(p, i, n, lane, acc_out, red, sh, i < n && owns_slot<DIM>(p, pos, i));
}

// Per dimension and lane count (MF_LANES_EACH): with solids (stress, artificial stress) and
// fluid only (no tensor registers), picked by the launcher. The fluid-only variants are
// bounded to 4 blocks of 256 per SM (64 registers), the solid ones to 3.
#define MF_FORCES_ENTRY(name, DIM, SOLIDS, EXTRAS, L)                                                                        \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK, SOLIDS ? 3 : MF_FLUID_BLOCKS)                                         \
        name(const SphParams p, unsigned n, const unsigned* cell_start, const unsigned char* stamp, const float* pos, \
             const float* vel, const float* rho, const float* pr, const unsigned char* kind,                    \
             const unsigned* group, const float* stress, const float* art, const float* iface,      \
             const unsigned* id,                                                                        \
             const float* surf, float* acc, unsigned* red, unsigned* pair_a, unsigned* pair_b) {                      \
        forces_impl<DIM, SOLIDS, EXTRAS, L>(p, n, cell_start, stamp, pos, vel, rho, pr, kind, group, stress, art, iface, id, surf, acc, red, \
                                            pair_a, pair_b);                                                    \
    }
#define MF_FORCES_LANES(L) MF_SCHEMES(MF_FORCES_ENTRY, sph_forces, L)
MF_LANES_EACH(MF_FORCES_LANES)
