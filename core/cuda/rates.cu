// Rates from the current velocities (RateSum in rates.cuh): d rho/dt, XSPH and, with solids,
// the Jaumann stress rate; at one lane per particle from the accepted candidates that the
// forces pass recorded at the same positions, where pair_a and pair_b hold them (PairBits in
// device/neighbours.cuh; null: every candidate tested). Twin: src/backend/cpu/rates.rs;
// parity test: tests/cuda_parity/.
#include "rates.cuh"
#include "device/entries.cuh"
#include "device/neighbours.cuh"
#include "device/pairs.cuh"

// drho: null without the continuity density; stress, rate: null without solids.
// Under the leapfrog every pair at the drift's midpoint (`neighbour`'s half_dt: dt_dev[0] / 2,
// the step size the kick took).
template <int DIM, bool SOLIDS, bool EXTRAS, int L>
__device__ void rates_impl(const SphParams& p, unsigned n, const float* __restrict__ dt_dev,
                           const unsigned* __restrict__ cell_start, const unsigned char* __restrict__ stamp,
                           const float* __restrict__ pos, const float* __restrict__ vel,
                           const float* __restrict__ rho,
                           const unsigned char* __restrict__ kind, const unsigned* __restrict__ group,
                           const float* __restrict__ stress, const float* __restrict__ grad_rho,
                           float* __restrict__ drho_out,
                           float* __restrict__ xsph_out, float* __restrict__ rate_out,
                           const unsigned* __restrict__ pair_a, const unsigned* __restrict__ pair_b) {
    const unsigned t = blockIdx.x * blockDim.x + threadIdx.x;
    const unsigned i = t / L;
    const int lane = (int)(t % L);
    RateSum<DIM, SOLIDS, EXTRAS> r;
    r.begin(p, i, n, i < n ? kind[i] : (unsigned char)MF_KIND_BOUNDARY, vel, rho, group, grad_rho);
    const float half_dt = p.integrator == MF_INTEGRATOR_LEAPFROG ? 0.5f * dt_dev[0] : 0.0f;
    // The record is read only (PairBits writes nothing in MF_PAIRS_REPLAY). It holds the
    // candidates accepted at these positions, x^n: the leapfrog's midpoint shifts each
    // accepted pair after (`neighbour`), replayed or tested, so the set is x^n's either way.
    const PairBits<DIM> pb{const_cast<unsigned*>(pair_a), const_cast<unsigned*>(pair_b), n};
    // A wall at rest: the rows with a moving particle only, the rows the forces pass
    // recorded; among walls at rest alone rates 0 and no walk (`walked_rows`).
    const unsigned walk = r.on ? walked_rows<DIM>(p, stamp, r.ki, vload<DIM>(pos, i)) : 0u;
    neighbour_loop<DIM, L, MF_PAIRS_REPLAY>(p, cell_start, pos, i, r.on && walk != 0u, lane,
                              [&](unsigned j, Vec<DIM> rij, float r2, float pw) {
        if (j == i) return;
        r.add(p, neighbour<DIM, SOLIDS>(p, j, rij, r2, pw, vel, kind, r.vi, half_dt), group);
    }, pb, true, walk);
    r.template finish<L>(p, i, n, lane, stress, drho_out, xsph_out, rate_out);
}

// Per dimension and lane count (MF_LANES_EACH), as for forces: with / without solids; same
// signature, picked by the launcher. The fluid-only variants are bounded to 4 blocks of 256
// per SM (64 registers; unbounded they take 78-79 in 3D: 3 blocks).
#define MF_RATES_ENTRY(name, DIM, SOLIDS, EXTRAS, L)                                                                   \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK, SOLIDS ? 1 : MF_FLUID_BLOCKS)                                   \
        name(const SphParams p, unsigned n, const float* dt_dev, const unsigned* cell_start,                   \
             const unsigned char* stamp, const float* pos, const float* vel, const float* rho,                   \
             const unsigned char* kind, const unsigned* group,                                                   \
             const float* stress, const float* grad_rho, float* drho, float* xsph, float* rate,                  \
             const unsigned* pair_a, const unsigned* pair_b) {                                                   \
        rates_impl<DIM, SOLIDS, EXTRAS, L>(p, n, dt_dev, cell_start, stamp, pos, vel, rho, kind, group, stress, grad_rho,  \
                                           drho, xsph, rate, pair_a, pair_b);                                    \
    }
#define MF_RATES_LANES(L) MF_SCHEMES(MF_RATES_ENTRY, sph_rates, L)
MF_LANES_EACH(MF_RATES_LANES)


// The renormalised density gradient of each particle within its material, for the density
// diffusion in Antuono, Colagrossi, Marrone & Molteni 2010's form (Comput. Phys. Commun. 181,
// 532): grad_i = (sum_j V_j (x_j - x_i) (x) grad_i W_ij)^-T sum_j V_j (rho_j - rho_i)
// grad_i W_ij over the neighbours of one body (solids, solid_density_diffusion > 0) or over the fluid
// (fluid_density_gradient), V_j = m_j / rho_j, exact for a linear density; zero
// for other particles and where the moment is singular (|det| <= MF_MOMENT_DET_MIN). One thread per
// particle. Twin: `density_gradient` in cpu/rates.rs. [M L^-d L^-1]
template <int DIM>
__device__ void sph_grad_rho_body(const SphParams p, unsigned n, const unsigned* __restrict__ cell_start,
                                  const float* __restrict__ pos, const float* __restrict__ vel,
                                  const float* __restrict__ rho, const unsigned char* __restrict__ kind,
                                  const unsigned* __restrict__ group, float* __restrict__ grad) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    const unsigned char ki = i < n ? kind[i] : (unsigned char)MF_KIND_BOUNDARY;
    const bool on = (ki == MF_KIND_SOLID && p.solid_density_diffusion > 0.0f) ||
                    (ki == MF_KIND_FLUID && p.fluid_density_gradient != 0);
    const float rhoi = on ? rho[i] : 0.0f;
    const unsigned gi = on ? group[i] : 0u;
    Vec<DIM> g = vzero<DIM>();
    Mat<DIM> m = mzero<DIM>();
    neighbour_loop<DIM, 1>(p, cell_start, pos, i, on, 0, [&](unsigned j, Vec<DIM> rij, float r2, float pw) {
        if (j == i) return;
        const Neighbour<DIM> nb = neighbour<DIM, true>(p, j, rij, r2, pw, vel, kind);
        if (!same_body(p, ki, nb.kind, gi, group[j])) return;
        const Vec<DIM> gw = rij * nb.fw;
        const float vj = nb.m / nb.rho;
        g = g + gw * ((nb.rho - rhoi) * vj);
#pragma unroll
        for (int a = 0; a < DIM; ++a)
#pragma unroll
            for (int b = 0; b < DIM; ++b) m.m[a][b] += (-rij.c[a] * gw.c[b]) * vj;
    });
    if (i >= n) return;
    Vec<DIM> out = vzero<DIM>();
    const float d = det<DIM>(m);
    if (on && fabsf(d) > MF_MOMENT_DET_MIN) {
        const Mat<DIM> inv = inverse<DIM>(m, d);
        // (M^T)^-1 g = (M^-1)^T g.
#pragma unroll
        for (int a = 0; a < DIM; ++a) {
            float s = inv.m[0][a] * g.c[0];
#pragma unroll
            for (int b = 1; b < DIM; ++b) s += inv.m[b][a] * g.c[b];
            out.c[a] = s;
        }
    }
#pragma unroll
    for (int a = 0; a < DIM; ++a) grad[i * DIM + a] = out.c[a];
}
MF_ENTRY2(sph_grad_rho,
          (const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, const float* vel,
           const float* rho, const unsigned char* kind, const unsigned* group, float* grad),
          (p, n, cell_start, pos, vel, rho, kind, group, grad))
