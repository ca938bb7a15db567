// Rates from the current velocities: d rho/dt (continuity form, with the density diffusion of
// Molteni & Colagrossi 2009 where delta_sph > 0), the XSPH velocity of eq. (18), and for
// solids the velocity gradient eq. (15) with the kernel-gradient correction, strain and
// rotation rates eqs. (13)-(14) and the Jaumann rate eq. (12).
// Twin: src/backend/cpu/rates.rs; parity test: tests/cuda_parity.rs.
#include "common.cuh"

template <int DIM> __device__ __forceinline__ float det(const Mat<DIM>& a) {
    if constexpr (DIM == 2) {
        return a.m[0][0] * a.m[1][1] - a.m[0][1] * a.m[1][0];
    } else {
        return a.m[0][0] * (a.m[1][1] * a.m[2][2] - a.m[1][2] * a.m[2][1]) -
               a.m[0][1] * (a.m[1][0] * a.m[2][2] - a.m[1][2] * a.m[2][0]) +
               a.m[0][2] * (a.m[1][0] * a.m[2][1] - a.m[1][1] * a.m[2][0]);
    }
}
// Inverse by the adjugate (the caller has checked |det| > 1e-3).
template <int DIM> __device__ __forceinline__ Mat<DIM> inverse(const Mat<DIM>& a, float d) {
    Mat<DIM> r;
    const float s = 1.0f / d;
    if constexpr (DIM == 2) {
        r.m[0][0] = a.m[1][1] * s;
        r.m[0][1] = -a.m[0][1] * s;
        r.m[1][0] = -a.m[1][0] * s;
        r.m[1][1] = a.m[0][0] * s;
    } else {
#pragma unroll
        for (int i = 0; i < 3; ++i)
#pragma unroll
            for (int j = 0; j < 3; ++j) {
                // cofactor C_ji, i.e. adj(a)_ij
                const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
                r.m[i][j] = (a.m[r0][c0] * a.m[r1][c1] - a.m[r0][c1] * a.m[r1][c0]) * s;
            }
    }
    return r;
}

// drho: null without the continuity density; stress, rate: null without solids.
template <int DIM, bool SOLIDS, int L, int B = Batch<L, SOLIDS>::B>
__device__ void rates_impl(const SphParams& p, unsigned n, const unsigned* __restrict__ cell_start,
                           const float* __restrict__ pos, const float* __restrict__ vel,
                           const float* __restrict__ rho, const float* __restrict__ mass,
                           const unsigned char* __restrict__ kind, const unsigned* __restrict__ group,
                           const float* __restrict__ stress, float* __restrict__ drho_out,
                           float* __restrict__ xsph_out, float* __restrict__ rate_out) {
    const unsigned t = blockIdx.x * blockDim.x + threadIdx.x;
    const unsigned i = t / L;
    const int lane = (int)(t % L);
    const unsigned char ki = i < n ? kind[i] : (unsigned char)MF_KIND_BOUNDARY;
    const bool active = i < n && (ki != MF_KIND_BOUNDARY || p.wall_pressure != 0);
    const bool solid_i = i < n && ki == MF_KIND_SOLID;
    Vec<DIM> xs = vzero<DIM>();
    float drho = 0.0f;
    // Density diffusion (delta-SPH) between fluid particles only, as in cpu/rates.rs.
    const bool diffuse = p.delta_sph > 0.0f && i < n && ki == MF_KIND_FLUID;
    float diffusion = 0.0f;
    Mat<DIM> gv, mo;
    if constexpr (SOLIDS) {
        gv = mzero<DIM>();
        mo = mzero<DIM>();
    }
    if (active) {
        const Vec<DIM> vi = vload<DIM>(vel, i);
        const float rhoi = rho[i];
        const unsigned gi = group[i];
        for_each_neighbor_split<DIM, L, B>(p, cell_start, pos, vload<DIM>(pos, i), lane,
                                        [&](unsigned j, Vec<DIM> r, float r2, float pw) {
            if (j == i) return;
            // v_j, and in 3D m_j, rho_j and (fluid-only scenes) the kind from the w slots
            // (Packed in common.cuh).
            float vw;
            const Vec<DIM> vj = vload_w<DIM>(vel, j, vw);
            unsigned char kj;
            if constexpr (Packed<DIM>::W && !SOLIDS)
                kj = vel_w_boundary(vw) ? (unsigned char)MF_KIND_BOUNDARY : (unsigned char)MF_KIND_FLUID;
            else
                kj = kind[j];
            if (!couples(p, kj)) return;
            if constexpr (SOLIDS) {
                if (!meets(p, ki, kj)) return;  // a body that skips walls, both ways
            }
            const float rhoj = Packed<DIM>::W ? fabsf(vw) : rho[j];
            const float rr = sqrtf(r2);
            const Vec<DIM> gw = r * kernel_f(p, rr);  // grad_i W_ij
            const Vec<DIM> vij = vi - vj;  // v = 0 on boundary particles
            const float mj = Packed<DIM>::W ? pw : mass[j];
            // Continuity, volume form: d rho_i/dt = rho_i sum_j m_j / rho_j v_ij . grad W
            // (the factor rho_i is applied after the sum, as in cpu/rates.rs).
            drho += mj / rhoj * dot(vij, gw);
            if (diffuse && kj == MF_KIND_FLUID && r2 > 0.0f) {
                // Molteni & Colagrossi 2009 (Comput. Phys. Commun. 180, 861), diffusive term:
                // sum_j psi_ij . grad_i W_ij V_j, psi_ij = 2 (rho_j - rho_i) r_ji / |r_ji|^2 with
                // r_ji = r_j - r_i = -r (diffusive sign, see cpu/rates.rs): 2 (rho_i - rho_j) r . gw / r^2.
                diffusion += 2.0f * (rhoi - rhoj) * dot(r, gw) / r2 * (mj / rhoj);
            }
            if (!same_body(p, ki, kj, gi, group[j]) || ki == MF_KIND_BOUNDARY) return;
            const float s = mj / (0.5f * (rhoi + rhoj));
            // XSPH, eq. (18), within one material (one body for solids).
            xs = xs - vij * (p.xsph_eps * s * kernel_w(p, rr));
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
        });
    }
    // Combine the lanes of each particle (every lane of the warp takes part).
#pragma unroll
    for (int a = 0; a < DIM; ++a) xs.c[a] = lane_sum<L>(xs.c[a]);
    drho = lane_sum<L>(drho);
    diffusion = lane_sum<L>(diffusion);
    if (active) drho *= rho[i];
    if (active && diffuse) drho += p.delta_sph * p.h * p.c0 * diffusion;
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
        if (fabsf(d) > 1e-3f) {
            const Mat<DIM> inv = inverse<DIM>(mo, d);
            Mat<DIM> g2;
#pragma unroll
            for (int a = 0; a < DIM; ++a)
#pragma unroll
                for (int b = 0; b < DIM; ++b) {
                    float s = gv.m[a][0] * inv.m[0][b];
#pragma unroll
                    for (int c = 1; c < DIM; ++c) s += gv.m[a][c] * inv.m[c][b];
                    g2.m[a][b] = s;
                }
            gv = g2;
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

// Per dimension and lane count (MF_LANES_EACH), as for forces: with / without solids; same
// signature, picked by the launcher. The fluid-only variants are bounded to 4 blocks of 256
// per SM (64 registers; unbounded they take 78-79 in 3D: 3 blocks).
#define MF_RATES_ENTRY(name, DIM, SOLIDS, L)                                                                   \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK, SOLIDS ? 1 : 4)                                   \
        name(const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, const float* vel, \
             const float* rho, const float* mass, const unsigned char* kind, const unsigned* group,          \
             const float* stress, float* drho, float* xsph, float* rate) {                                    \
        rates_impl<DIM, SOLIDS, L>(p, n, cell_start, pos, vel, rho, mass, kind, group, stress, drho, xsph, rate); \
    }
#define MF_RATES_LANES(L)                                \
    MF_RATES_ENTRY(sph_rates_##L##_2d, 2, true, L)        \
    MF_RATES_ENTRY(sph_rates_##L##_3d, 3, true, L)        \
    MF_RATES_ENTRY(sph_rates_fluid_##L##_2d, 2, false, L) \
    MF_RATES_ENTRY(sph_rates_fluid_##L##_3d, 3, false, L)
MF_LANES_EACH(MF_RATES_LANES)

