// Accelerations eqs. (7), (10), (16), (17), laminar viscosity, artificial stress, fluid
// cohesion (Akinci et al. 2013), gravity;
// fused: the block maxima of |v|, |a| and c for the step size (the velocities do not change
// between forces and time_step in either integrator order).
// Twin: src/backend/cpu/forces.rs (+ extremes in reduce.rs); parity test: tests/cuda_parity.rs.
#include "common.cuh"

// Lennard-Jones boundary force per unit mass, eq. (17).
template <int DIM> __device__ __forceinline__ Vec<DIM> lennard_jones(const SphParams& p, Vec<DIM> r, float rr) {
    if (rr <= 0.0f || rr >= (p.lj_attractive ? p.support : p.lj_r0)) return vzero<DIM>();
    float q = p.lj_r0 / rr;
    float mag = p.lj_c0 * (powf(q, (float)p.lj_p1) - powf(q, (float)p.lj_p2));
    return r * (mag / rr);
}
// Artificial viscosity Pi_ij, eq. (10).
__device__ __forceinline__ float artificial_viscosity(const SphParams& p, float vr, float r2, float c_bar,
                                                      float rho_bar) {
    if (vr >= 0.0f) return 0.0f;
    float mu = p.h * vr / (r2 + p.av_eta2);
    return (-p.alpha * c_bar * mu + p.beta * mu * mu) / rho_bar;
}
// Laminar viscosity factor (Morris, Fox & Zhu 1997).
__device__ __forceinline__ float laminar(const SphParams& p, float r2, float f, float rho_i, float rho_j) {
    return p.nu * (rho_i + rho_j) / (rho_i * rho_j) * (r2 * f) / (r2 + p.visc_eta2);
}

// Cohesion spline of Akinci, Akinci & Teschner 2013, eq. (2), over s = 2h, divided by r
// (3D normalisation in 2D too); twin of `cohesion_over_r` in cpu/forces.rs. [L^-d-1]
__device__ __forceinline__ float cohesion_over_r(float support, float rr) {
    if (rr <= 0.0f || rr > support) return 0.0f;
    const float x = rr / support;
    const float y = 1.0f - x;
    const float poly = y * y * y * x * x * x;
    const float c = x > 0.5f ? poly : 2.0f * poly - 1.0f / 64.0f;
    return 32.0f / (3.14159265358979323846f * support * support * support) * c / rr;
}

// Whether a pair exchanges the whole stress -P I + S of eq. (16) or only -P I
// (`interface_stress`): by default only two particles of one body (or two fluid particles);
// across a fluid-solid interface, two bodies or a body and a wall, pressure alone (Antoci,
// Gallati & Sibilla 2007). Twin of `whole_stress_pair` in cpu/forces.rs.
__device__ __forceinline__ bool whole_stress_pair(const SphParams& p, bool same_body) {
    return same_body || p.interface_stress != 0;
}

template <int DIM, bool SOLIDS, int L, int B = Batch<L, SOLIDS>::B>
__device__ void forces_impl(const SphParams& p, unsigned n, const unsigned* __restrict__ cell_start,
                            const float* __restrict__ pos, const float* __restrict__ vel,
                            const float* __restrict__ rho, const float* __restrict__ pr,
                            const float* __restrict__ mass, const unsigned char* __restrict__ kind,
                            const unsigned* __restrict__ group, const float* __restrict__ stress,
                            const float* __restrict__ art, float* __restrict__ acc_out, unsigned* __restrict__ red) {
    __shared__ float sh[MF_BLOCK / 32];
    const unsigned t = blockIdx.x * blockDim.x + threadIdx.x;
    const unsigned i = t / L;
    const int lane = (int)(t % L);
    float vmax = 0.0f, amax = 0.0f, cmax = 0.0f;
    const unsigned char ki = i < n ? kind[i] : (unsigned char)MF_KIND_BOUNDARY;
    Vec<DIM> acc = vzero<DIM>();
    if (i < n && ki == MF_KIND_BOUNDARY && lane == 0) vstore<DIM>(acc_out, i, vzero<DIM>());
    if (i < n && ki != MF_KIND_BOUNDARY) {
        const Vec<DIM> xi = vload<DIM>(pos, i), vi = vload<DIM>(vel, i);
        const float rhoi = rho[i], pi = pr[i];
        const float ci = sound_speed(p, ki);
        const unsigned gi = group[i];
        const float inv_r2i = 1.0f / (rhoi * rhoi);
        // sigma_i / rho_i^2 with sigma = -P I + S, eq. (11); S = 0 for fluid.
        Mat<DIM> sig_i;
        float psi = 0.0f;  // fluid-only scenes: P_i / rho_i^2
        if constexpr (SOLIDS) {
            sig_i = sload<DIM>(stress, i, n);
#pragma unroll
            for (int a = 0; a < DIM; ++a) {
#pragma unroll
                for (int b = 0; b < DIM; ++b) sig_i.m[a][b] = (sig_i.m[a][b] - (a == b ? pi : 0.0f)) * inv_r2i;
            }
        } else {
            psi = -pi * inv_r2i;
        }
        if (lane == 0) {
#pragma unroll
            for (int a = 0; a < DIM; ++a) acc.c[a] = p.gravity[a];
        }
        for_each_neighbor_split<DIM, L, B>(p, cell_start, pos, xi, lane, [&](unsigned j, Vec<DIM> r, float r2,
                                                                         float pw) {
            if (j == i) return;
            // v_j, and in 3D m_j, rho_j and (fluid-only scenes) the kind from the w slots.
            float vw;
            const Vec<DIM> vj = vload_w<DIM>(vel, j, vw);
            unsigned char kj;
            if constexpr (Packed<DIM>::W && !SOLIDS)
                kj = vel_w_boundary(vw) ? (unsigned char)MF_KIND_BOUNDARY : (unsigned char)MF_KIND_FLUID;
            else
                kj = kind[j];
            const float rr = sqrtf(r2);
            const float fw = kernel_f(p, rr);
            const Vec<DIM> gw = r * fw;  // grad_i W_ij
            const float mj = Packed<DIM>::W ? pw : mass[j];
            if (kj == MF_KIND_BOUNDARY) {
                // A body that skips walls (`meets`) feels nothing of them.
                if constexpr (SOLIDS) {
                    if (!meets(p, ki, kj)) return;
                }
                acc = acc + lennard_jones<DIM>(p, r, rr);  // eq. (17)
                // Dynamic walls: then like any other neighbour (own P_j, rho_j, v_j = 0,
                // stress 0, sound speed c0).
                if (!couples(p, kj)) return;
            }
            const float rhoj = Packed<DIM>::W ? fabsf(vw) : rho[j];
            const Vec<DIM> vij = vi - vj;
            const float vr = dot(vij, r);
            const float inv_r2j = 1.0f / (rhoj * rhoj);
            const bool bonded = SOLIDS && same_body(p, ki, kj, gi, group[j]);
            // Stress term, eq. (16); eq. (7) when both are fluid (sigma = -P I); across two
            // objects the pressure part only (whole_stress_pair).
            if constexpr (SOLIDS) {
                const bool whole = whole_stress_pair(p, bonded);
                Mat<DIM> sj = whole ? sload<DIM>(stress, j, n) : mzero<DIM>();
                const float pj = pr[j];
#pragma unroll
                for (int a = 0; a < DIM; ++a)
#pragma unroll
                    for (int b = 0; b < DIM; ++b) {
                        // sigma_i / rho_i^2, or its pressure part (0 - P_i delta) / rho_i^2.
                        const float si_ab = whole ? sig_i.m[a][b] : (0.0f - (a == b ? pi : 0.0f)) * inv_r2i;
                        sj.m[a][b] = si_ab + (sj.m[a][b] - (a == b ? pj : 0.0f)) * inv_r2j;
                    }
                acc = acc + mat_vec<DIM>(sj, gw) * mj;
            } else {
                acc = acc + (gw * (psi + -pr[j] * inv_r2j)) * mj;
            }
            if (kj == MF_KIND_BOUNDARY) {
                // A wall pushes and never pulls: negative pressures are cut to zero across a
                // fluid-wall pair (twin of the same lines in cpu/forces.rs).
                const float neg = fmaxf(-pi, 0.0f) * inv_r2i + fmaxf(-pr[j], 0.0f) * inv_r2j;
                acc = acc - gw * (neg * mj);
            }
            // Artificial viscosity, eq. (10).
            const float c_bar = 0.5f * (ci + sound_speed(p, kj));
            const float rho_bar = 0.5f * (rhoi + rhoj);
            const float pij = artificial_viscosity(p, vr, r2, c_bar, rho_bar);
            acc = acc - gw * (mj * pij);
            if (p.nu > 0.0f && (ki == MF_KIND_FLUID || kj == MF_KIND_FLUID))
                acc = acc + vij * (mj * laminar(p, r2, fw, rhoi, rhoj));
            // Fluid-fluid cohesion, Akinci et al. 2013, eq. (2): -gamma m_j C(r) r_ij / r
            // (uniform branch: nothing when gamma = 0).
            if (p.cohesion != 0.0f && ki == MF_KIND_FLUID && kj == MF_KIND_FLUID)
                acc = acc - r * (p.cohesion * mj * cohesion_over_r(p.support, rr));
            if constexpr (SOLIDS) {
                if (art && bonded && ki == MF_KIND_SOLID) {
                    // Gray, Monaghan & Swift 2001: f_ij^n (R_i + R_j) . grad W.
                    float fij = powf(kernel_w(p, rr) * p.inv_w_dx, p.art_stress_n);
                    Mat<DIM> ra = sload<DIM>(art, i, n), rb = sload<DIM>(art, j, n);
#pragma unroll
                    for (int a = 0; a < DIM; ++a)
#pragma unroll
                        for (int b = 0; b < DIM; ++b) ra.m[a][b] += rb.m[a][b];
                    acc = acc + mat_vec<DIM>(ra, gw) * (mj * fij);
                }
            }
        });
    }
    // Combine the lanes of each particle (every lane of the warp takes part).
#pragma unroll
    for (int a = 0; a < DIM; ++a) {
        acc.c[a] = lane_sum<L>(acc.c[a]);
    }
    if (i < n && ki != MF_KIND_BOUNDARY && lane == 0) {
        vstore<DIM>(acc_out, i, acc);
        const Vec<DIM> vi = vload<DIM>(vel, i);
        vmax = sqrtf(dot(vi, vi));
        amax = sqrtf(dot(acc, acc));
        cmax = sound_speed(p, ki);
    }
    // Extremes over fluid and solid particles (twin: reduce.rs `extremes`); non-negative
    // floats order like their bit patterns, so atomicMax on the bits is a float max.
    vmax = block_max(vmax, sh);
    if (threadIdx.x == 0) atomicMax(&red[0], __float_as_uint(vmax));
    amax = block_max(amax, sh);
    if (threadIdx.x == 0) atomicMax(&red[1], __float_as_uint(amax));
    cmax = block_max(cmax, sh);
    if (threadIdx.x == 0) atomicMax(&red[2], __float_as_uint(cmax));
}

// Per dimension and lane count (MF_LANES_EACH): with solids (stress, artificial stress) and
// fluid only (no tensor registers), picked by the launcher. The fluid-only variants are
// bounded to 4 blocks of 256 per SM (64 registers), the solid ones to 3.
#define MF_FORCES_ENTRY(name, DIM, SOLIDS, L)                                                                        \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK, SOLIDS ? 3 : 4)                                         \
        name(const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, const float* vel,      \
             const float* rho, const float* pr, const float* mass, const unsigned char* kind,                    \
             const unsigned* group, const float* stress, const float* art, float* acc, unsigned* red) {           \
        forces_impl<DIM, SOLIDS, L>(p, n, cell_start, pos, vel, rho, pr, mass, kind, group, stress, art, acc, red); \
    }
#define MF_FORCES_LANES(L)                                \
    MF_FORCES_ENTRY(sph_forces_##L##_2d, 2, true, L)       \
    MF_FORCES_ENTRY(sph_forces_##L##_3d, 3, true, L)       \
    MF_FORCES_ENTRY(sph_forces_fluid_##L##_2d, 2, false, L) \
    MF_FORCES_ENTRY(sph_forces_fluid_##L##_3d, 3, false, L)
MF_LANES_EACH(MF_FORCES_LANES)

