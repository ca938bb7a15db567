// Rates from the current velocities: d rho/dt (continuity form, with the density diffusion of
// Molteni & Colagrossi 2009 where density_diffusion > 0), the XSPH velocity of eq. (18) with the particle
// shifting velocity where shifting > 0 (Lind et al. 2012, Sun et al. 2017), and for
// solids the velocity gradient eq. (15) with the kernel-gradient correction, strain and
// rotation rates eqs. (13)-(14) and the Jaumann rate eq. (12), as a per-particle sum
// (`RateSum`) that the rates kernel (rates.cu) and the fused forces-and-rates kernel
// (forces_rates.cu) run in their neighbour loops.
// Twin: src/backend/cpu/rates.rs; parity test: tests/cuda_parity/.
#pragma once
#include "sph_consts.h"
#include "device/neighbours.cuh"
#include "device/packing.cuh"
#include "device/pairs.cuh"
#include "device/reductions.cuh"
#include "device/vectors.cuh"


// rho^H_j - rho^H_i of water at rest under gravity, r = r_i - r_j (Fourtakas et al. 2019): the
// Tait density of p^H_j - p^H_i = rho0 g . (r_j - r_i); twin of hydrostatic_rho_ji in
// cpu/rates.rs. [M L^-d]
template <int DIM>
__device__ __forceinline__ float hydrostatic_rho_ji(const SphParams& p, const Vec<DIM>& r) {
    float gr = 0.0f;
#pragma unroll
    for (int a = 0; a < DIM; ++a) gr += p.gravity[a] * r.c[a];
    return p.rho0 * expm1f(log1pf(-p.rho0 * gr / p.tait_b) / p.tait_gamma);
}

// A solid's renormalised density gradient, DIM floats per particle.
template <int DIM> __device__ __forceinline__ Vec<DIM> grad_load(const float* __restrict__ g, unsigned i) {
    Vec<DIM> v;
#pragma unroll
    for (int a = 0; a < DIM; ++a) v.c[a] = g[i * DIM + a];
    return v;
}

// The rates of particle i, summed over its neighbours: `begin`, then `add` for every
// neighbour j != i (in the neighbour loop's order), then `finish` (all lanes of the warp).
// EXTRAS = false: without density diffusion and shifting (the lean kernels, as ForceSum).
template <int DIM, bool SOLIDS, bool EXTRAS = true> struct RateSum {
    bool on;  // i < n and i is no wall, or a dynamic wall (its d rho/dt)
    bool solid_i, diffuse, shift;
    unsigned char ki;
    unsigned gi;
    Vec<DIM> vi;
    float rhoi;
    Vec<DIM> xs;
    float drho, diffusion;
    Vec<DIM> grad_c;  // shifting: sum_j V_j (1 + R f^4) grad_i W_ij
    float div_r;      // shifting: the position divergence -sum_j V_j r_ij . grad_i W_ij
    Mat<DIM> gv, mo;  // solids: velocity gradient and moment, eq. (15)
    const float* gr;  // renormalised density gradients (sph_grad_rho), or null
    Vec<DIM> gri;     // particle i's

    // Particle i of kind k (a wall for i >= n).
    __device__ __forceinline__ void begin(const SphParams& p, unsigned i, unsigned n, unsigned char k,
                                          const float* __restrict__ vel, const float* __restrict__ rho,
                                          const unsigned* __restrict__ group,
                                          const float* __restrict__ grad_rho) {
        ki = k;
        on = i < n && has_rates(p, ki);
        // A total-Lagrangian body takes its stress from F (tlsph.cu): no Jaumann rate (its
        // rate stays 0, as the fluid's).
        solid_i = i < n && ki == MF_KIND_SOLID && p.solid_formulation != MF_SOLID_TOTAL_LAGRANGIAN;
        xs = vzero<DIM>();
        drho = 0.0f;
        // Density diffusion (delta-SPH) within one material (fluid, one body), as in
        // cpu/rates.rs.
        diffuse = EXTRAS && i < n &&
                  ((ki == MF_KIND_FLUID && p.density_diffusion > 0.0f) || (ki == MF_KIND_SOLID && p.solid_density_diffusion > 0.0f));
        diffusion = 0.0f;
        // Particle shifting of fluid particles (cpu/rates.rs `shift_velocity`).
        shift = EXTRAS && p.shifting > 0.0f && i < n && ki == MF_KIND_FLUID;
        grad_c = vzero<DIM>();
        div_r = 0.0f;
        if constexpr (SOLIDS) {
            gv = mzero<DIM>();
            mo = mzero<DIM>();
        }
        gr = nullptr;
        vi = vzero<DIM>();
        if (!on) return;
        vi = vel_load<DIM>(vel, i);
        rhoi = rho[i];
        gi = group[i];
        // Antuono et al. 2010's correction wherever the gradients are held (zero for a
        // particle whose material does not take it).
        if constexpr (EXTRAS) {
            if (diffuse && grad_rho) {
                gr = grad_rho;
                gri = grad_load<DIM>(gr, i);
            }
        }
    }

    // Neighbour nb (j != i).
    __device__ __forceinline__ void add(const SphParams& p, const Neighbour<DIM>& nb,
                                        const unsigned* __restrict__ group) {
        const unsigned char kj = nb.kind;
        if (!couples(p, kj)) return;
        if constexpr (SOLIDS) {
            if (!meets(p, ki, kj)) return;  // a body that skips walls, both ways
        }
        const Vec<DIM> r = nb.r;
        const float r2 = nb.r2, rr = nb.rr, rhoj = nb.rho, mj = nb.m;
        const Vec<DIM> gw = r * nb.fw;  // grad_i W_ij
        const Vec<DIM> vij = vi - nb.v;  // v = 0 on boundary particles
        // Continuity, volume form: d rho_i/dt = rho_i sum_j m_j / rho_j v_ij . grad W
        // (the factor rho_i is applied after the sum, as in cpu/rates.rs).
        // A body meeting the fluid at its extrapolated pressure leaves the fluid out of its
        // own density (extrapolated_pair; cpu/rates.rs says why).
        bool own_rate = true;
        if constexpr (SOLIDS) own_rate = !(ki == MF_KIND_SOLID && extrapolated_pair(p, ki, kj));
        if (own_rate) drho += fast_div(mj, rhoj) * dot(vij, gw);
        // Without solids every particle is fluid or a wall, and same_body is kj == ki (walls
        // return below anyway): no load of the neighbour's group.
        const bool one_body = SOLIDS ? same_body(p, ki, kj, gi, group[nb.j]) : kj == ki;
        if (diffuse && one_body && r2 > 0.0f) {
            // Molteni & Colagrossi 2009 (Comput. Phys. Commun. 180, 861), diffusive term:
            // sum_j psi_ij . grad_i W_ij V_j, psi_ij = 2 (rho_j - rho_i) r_ji / |r_ji|^2 with
            // r_ji = r_j - r_i = -r (diffusive sign, see cpu/rates.rs): 2 (rho_i - rho_j) r . gw / r^2.
            // Fourtakas et al. 2019: rho_i - rho_j less its hydrostatic part (fluid).
            float drho_ij = rhoi - rhoj;
            if (p.density_diffusion_form == MF_DIFFUSION_FOURTAKAS && ki == MF_KIND_FLUID) drho_ij += hydrostatic_rho_ji<DIM>(p, r);
            float psi = 2.0f * drho_ij * dot(r, gw) / r2;
            // Antuono et al. 2010's correction (in a body; in the fluid under
            // MF_DIFFUSION_ANTUONO): less (grad rho_i + grad rho_j) . grad W.
            if (gr) psi -= dot(gri + grad_load<DIM>(gr, nb.j), gw);
            diffusion += psi * (mj / rhoj);
        }
        if (shift) {
            // Every neighbour that couples fills the support (not shifted into a wall).
            const float vjv = fast_div(mj, rhoj);
            const float f = nb.w * p.inv_w_dx;
            grad_c = grad_c + gw * (vjv * (1.0f + MF_SHIFT_ANTI_CLUMP * (f * f) * (f * f)));
            div_r -= vjv * dot(r, gw);
        }
        if (!one_body || ki == MF_KIND_BOUNDARY) return;
        const float s = fast_div(mj, 0.5f * (rhoi + rhoj));
        // XSPH, eq. (18), within one material (one body for solids).
        xs = xs - vij * (p.xsph * s * nb.w);
        if constexpr (SOLIDS) {
            if (solid_i) {
                // Velocity gradient, eq. (15), and the moment A = sum V_j (x_j - x_i) (x) grad W.
#pragma unroll
                for (int a = 0; a < DIM; ++a)
#pragma unroll
                    for (int b = 0; b < DIM; ++b) {
                        gv.m[a][b] += (-vij.c[a] * gw.c[b]) * s;
                        mo.m[a][b] += (-r.c[a] * gw.c[b]) * s;
                    }
            }
        }
    }

    // Combine the L lanes of each particle and store d rho/dt (drho_out null without the
    // continuity density), the XSPH velocity and, with solids, the Jaumann rate (every lane
    // of the warp calls).
    template <int L>
    __device__ __forceinline__ void finish(const SphParams& p, unsigned i, unsigned n, int lane,
                                           const float* __restrict__ stress,
                                           float* __restrict__ drho_out, float* __restrict__ xsph_out,
                                           float* __restrict__ rate_out) {
#pragma unroll
        for (int a = 0; a < DIM; ++a) xs.c[a] = lane_sum<L>(xs.c[a]);
        drho = lane_sum<L>(drho);
        diffusion = lane_sum<L>(diffusion);
        if (EXTRAS && p.shifting > 0.0f) {  // uniform branch: every lane of the warp sums
#pragma unroll
            for (int a = 0; a < DIM; ++a) grad_c.c[a] = lane_sum<L>(grad_c.c[a]);
            div_r = lane_sum<L>(div_r);
            // Lind et al. 2012 / Sun et al. 2017: dv = -C h c0 grad C, none at a free surface
            // (position divergence below d - margin); twin of shift_velocity in cpu/rates.rs.
            if (shift && div_r >= (float)DIM - MF_SHIFT_SURFACE_MARGIN)
                xs = xs - grad_c * (p.shifting * p.h * p.c0);
        }
        if (on) drho *= rhoi;
        // + delta h c sum_j ... with the particle's material's delta and sound speed.
        if (on && diffuse) {
            const bool sol = ki == MF_KIND_SOLID;
            drho += (sol ? p.solid_density_diffusion : p.density_diffusion) * p.h * (sol ? p.solid_c0 : p.c0) * diffusion;
        }
        if constexpr (SOLIDS) {
#pragma unroll
            for (int a = 0; a < DIM; ++a)
#pragma unroll
                for (int b = 0; b < DIM; ++b) {
                    gv.m[a][b] = lane_sum<L>(gv.m[a][b]);
                    mo.m[a][b] = lane_sum<L>(mo.m[a][b]);
                }
        }
        if (i >= n || lane != 0) return;
        vstore<DIM>(xsph_out, i, xs);
        if (drho_out) drho_out[i] = drho;
        if constexpr (SOLIDS) {
            if (!solid_i) {
                sstore<DIM>(rate_out, i, n, mzero<DIM>());
                return;
            }
            // Kernel-gradient correction (Randles & Libersky 1996; Bonet & Lok 1999): G = G_raw A^-1,
            // skipped where A is singular.
            const float d = det<DIM>(mo);
            if (fabsf(d) > MF_MOMENT_DET_MIN) {
                const Mat<DIM> inv = inverse<DIM>(mo, d);
                gv = mat_mul<DIM>(gv, inv);
            }
            Mat<DIM> eps, om;
#pragma unroll
            for (int a = 0; a < DIM; ++a)
#pragma unroll
                for (int b = 0; b < DIM; ++b) {
                    eps.m[a][b] = (gv.m[a][b] + gv.m[b][a]) * 0.5f;  // eq. (13)
                    om.m[a][b] = (gv.m[a][b] - gv.m[b][a]) * 0.5f;   // eq. (14)
                }
            float tr = eps.m[0][0];
#pragma unroll
            for (int a = 1; a < DIM; ++a) tr += eps.m[a][a];
            const Mat<DIM> si = sload<DIM>(stress, i, n);
            // Jaumann rate, eq. (12): 2 mu (eps^ab - delta^ab eps^cc / 3) + S^ac Om^bc + Om^ac S^cb.
            Mat<DIM> out;
#pragma unroll
            for (int a = 0; a < DIM; ++a)
#pragma unroll
                for (int b = 0; b < DIM; ++b) {
                    float dev = eps.m[a][b] - (a == b ? tr / 3.0f : 0.0f);
                    float s1 = si.m[a][0] * om.m[b][0], s2 = om.m[a][0] * si.m[0][b];
#pragma unroll
                    for (int c = 1; c < DIM; ++c) {
                        s1 += si.m[a][c] * om.m[b][c];
                        s2 += om.m[a][c] * si.m[c][b];
                    }
                    out.m[a][b] = dev * (2.0f * p.shear_modulus) + s1 + s2;
                }
            sstore<DIM>(rate_out, i, n, out);
        }
    }
};
