// Accelerations eqs. (7), (10), (16), (17), laminar viscosity, artificial stress, fluid
// cohesion (Akinci et al. 2013), gravity, as a per-particle sum (`ForceSum`) that the forces
// kernel (forces.cu) and the fused forces-and-rates kernel (forces_rates.cu) run in their
// neighbour loops. Twin: src/backend/cpu/forces.rs (+ extremes in reduce.rs);
// parity test: tests/cuda_parity/.
#pragma once
#include "device/neighbours.cuh"
#include "device/packing.cuh"
#include "device/pairs.cuh"
#include "device/particle.cuh"
#include "device/reductions.cuh"
#include "device/vectors.cuh"

// Lennard-Jones boundary force per unit mass, eq. (17), for r < lj_range.
template <int DIM> __device__ __forceinline__ Vec<DIM> lennard_jones(const SphParams& p, Vec<DIM> r, float rr) {
    if (rr <= 0.0f || rr >= p.lj_range) return vzero<DIM>();
    float q = p.lj_r0 / rr;
    float mag = p.lj_c0 * (powf(q, (float)p.lj_p1) - powf(q, (float)p.lj_p2));
    return r * (mag / rr);
}
// Artificial viscosity Pi_ij, eq. (10).
__device__ __forceinline__ float artificial_viscosity(const SphParams& p, float vr, float r2, float c_bar,
                                                      float rho_bar) {
    if (vr >= 0.0f) return 0.0f;
    float mu = fast_div(p.h * vr, r2 + p.av_eta2);
    return fast_div(-p.alpha * c_bar * mu + p.beta * mu * mu, rho_bar);
}
// Laminar viscosity factor (Morris, Fox & Zhu 1997).
__device__ __forceinline__ float laminar(const SphParams& p, float r2, float f, float rho_i, float rho_j) {
    return p.viscosity * (rho_i + rho_j) / (rho_i * rho_j) * (r2 * f) / (r2 + p.visc_eta2);
}

// The no-slip factor beta of Morris, Fox & Zhu 1997 (boundary conditions) for the laminar
// term between fluid particle A and wall particle B at r = x_A - x_B [L]: B takes the
// velocity v_w - (d_B / d_A) (v_A - v_w), so v_AB = beta (v_A - v_w),
// beta = min(beta_max, 1 + d_B / d_A) [-]. surf = (n, d_B) per boundary particle
// (Setup::wall_surface, at id - wall_first_id): n the unit normal into the fluid, d_B [L]
// B's distance behind the surface; d_A = r . n - d_B [L]. Twin of `no_slip_factor` in
// cpu/forces.rs.
template <int DIM>
__device__ __forceinline__ float no_slip_factor(const SphParams& p, Vec<DIM> r, const float* __restrict__ surf,
                                                unsigned b) {
    const float4 s = reinterpret_cast<const float4*>(surf)[b];
    Vec<DIM> nrm;
    nrm.c[0] = s.x;
    nrm.c[1] = s.y;
    if constexpr (DIM == 3) nrm.c[2] = s.z;
    const float d_a = dot(r, nrm) - s.w;
    return d_a > 0.0f ? fminf(1.0f + s.w / d_a, p.no_slip_beta_max) : p.no_slip_beta_max;
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
// (`interface`): by default only two particles of one body (or two fluid particles);
// across a fluid-solid interface, two bodies or a body and a wall, pressure alone (Antoci,
// Gallati & Sibilla 2007). Twin of `whole_stress_pair` in cpu/forces.rs.
__device__ __forceinline__ bool whole_stress_pair(const SphParams& p, bool same_body) {
    return same_body || p.interface != 0;
}

// The acceleration of particle i, summed over its neighbours: `begin`, then `add` for every
// neighbour j != i (in the neighbour loop's order), then `finish` (all threads of the block).
// EXTRAS = false compiles out the terms beyond the paper's fluid scheme (laminar viscosity,
// Morris's no-slip walls, cohesion), for the lean kernels that run where all are off
// (`params::lean_scheme`; `Scheme::of` in src/backend/cuda/kernels.rs).
template <int DIM, bool SOLIDS, bool EXTRAS = true> struct ForceSum {
    bool on;  // i < n and i is no wall: walls get a = 0
    unsigned char ki;
    unsigned gi;
    Vec<DIM> vi;
    float rhoi, pi, ci, inv_r2i;
    // sigma_i / rho_i^2 with sigma = -P I + S, eq. (11); S = 0 for fluid (solids only).
    Mat<DIM> sig_i;
    float psi;  // fluid-only scenes: -P_i / rho_i^2
    // A body's particle i under the extrapolated coupling: (P'_i, rho'_i) (iface).
    float pe_i, rhoe_i;
    Vec<DIM> acc;

    // Particle i of kind k (a wall for i >= n); lane 0 starts from gravity. iface: the
    // interface stage's (P', rho') per particle (sph_solid_interface), null unless the bodies
    // meet the fluid at its extrapolated pressure.
    __device__ __forceinline__ void begin(const SphParams& p, unsigned i, unsigned n, unsigned char k, int lane,
                                          const float* __restrict__ vel, const float* __restrict__ rho,
                                          const float* __restrict__ pr, const unsigned* __restrict__ group,
                                          const float* __restrict__ stress, const float* __restrict__ iface) {
        ki = k;
        on = i < n && ki != MF_KIND_BOUNDARY;
        acc = vzero<DIM>();
        psi = 0.0f;
        if (!on) return;
        vi = vel_load<DIM>(vel, i);
        rhoi = rho[i];
        pi = pr[i];
        ci = sound_speed(p, ki);
        gi = group[i];
        inv_r2i = 1.0f / (rhoi * rhoi);
        if constexpr (SOLIDS) {
            if (iface && ki == MF_KIND_SOLID) {
                const float2 e = reinterpret_cast<const float2*>(iface)[i];
                pe_i = e.x;
                rhoe_i = e.y;
            }
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
    }

    // Neighbour nb (j != i). id and surf (null unless no_slip): the wall surface of Morris's
    // no-slip walls (no_slip_factor).
    __device__ __forceinline__ void add(const SphParams& p, unsigned i, unsigned n, const Neighbour<DIM>& nb,
                                        const float* __restrict__ pr, const unsigned* __restrict__ group,
                                        const float* __restrict__ stress, const float* __restrict__ art,
                                        const float* __restrict__ iface, const unsigned* __restrict__ id,
                                        const float* __restrict__ surf) {
        const unsigned j = nb.j;
        const unsigned char kj = nb.kind;
        const Vec<DIM> r = nb.r;
        const float r2 = nb.r2, rr = nb.rr, fw = nb.fw, mj = nb.m;
        const Vec<DIM> gw = r * fw;  // grad_i W_ij
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
        if constexpr (SOLIDS) {
            if (iface && extrapolated_pair(p, ki, kj)) {
                acc = acc + fluid_body(p, nb, pr, iface);
                return;
            }
        }
        const float rhoj = nb.rho;
        const Vec<DIM> vj = nb.v;
        const Vec<DIM> vij = vi - vj;
        const float vr = dot(vij, r);
        const float inv_r2j = fast_div(1.0f, rhoj * rhoj);
        const bool bonded = SOLIDS && same_body(p, ki, kj, gi, group[j]);
        // Stress term, eq. (16); eq. (7) when both are fluid (sigma = -P I); across two
        // objects the pressure part only (whole_stress_pair). Within a total-Lagrangian body
        // the internal force replaces it (sph_tl_forces in tlsph.cu).
        if constexpr (SOLIDS) {
            const bool tl_internal =
                bonded && ki == MF_KIND_SOLID && p.solid_formulation == MF_SOLID_TOTAL_LAGRANGIAN;
            if (!tl_internal) {
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
            }
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
        // Laminar viscosity (Morris et al. 1997); a wall's velocity extrapolated under
        // no_slip (twin of `laminar_velocity` in cpu/forces.rs).
        if (EXTRAS && p.viscosity > 0.0f && (ki == MF_KIND_FLUID || kj == MF_KIND_FLUID)) {
            Vec<DIM> v_visc = vij;
            if (p.no_slip == MF_NO_SLIP_MORRIS && kj == MF_KIND_BOUNDARY)
                v_visc = vij * no_slip_factor<DIM>(p, r, surf, id[j] - p.wall_first_id);
            acc = acc + v_visc * (mj * laminar(p, r2, fw, rhoi, rhoj));
        }
        // Fluid-fluid cohesion, Akinci et al. 2013, eq. (2): -gamma m_j C(r) r_ij / r
        // (uniform branch: nothing when gamma = 0).
        if (EXTRAS && p.cohesion != 0.0f && ki == MF_KIND_FLUID && kj == MF_KIND_FLUID)
            acc = acc - r * (p.cohesion * mj * cohesion_over_r(p.support, rr));
        if constexpr (SOLIDS) {
            if (art && bonded && ki == MF_KIND_SOLID) {
                // Gray, Monaghan & Swift 2001: f_ij^n (R_i + R_j) . grad W.
                float fij = powf(nb.w * p.inv_w_dx, p.artificial_stress_exponent);
                Mat<DIM> ra = sload<DIM>(art, i, n), rb = sload<DIM>(art, j, n);
#pragma unroll
                for (int a = 0; a < DIM; ++a)
#pragma unroll
                    for (int b = 0; b < DIM; ++b) ra.m[a][b] += rb.m[a][b];
                acc = acc + mat_vec<DIM>(ra, gw) * (mj * fij);
            }
        }
    }

    // What j exerts on i where one is a fluid particle and the other a body's particle that
    // meet at the fluid's extrapolated pressure: the body's particle b as fluid of its own
    // volume m_b / rho_b, mass rho'_b m_b / rho_b, at (P'_b, rho'_b), in eq. (7), eq. (10)
    // (with the fluid's c0) and the laminar term; on b the reaction over its own mass, the
    // fluid form times rho'_b / rho_b. Twin of `fluid_body` in cpu/forces.rs.
    __device__ __forceinline__ Vec<DIM> fluid_body(const SphParams& p, const Neighbour<DIM>& nb,
                                                   const float* __restrict__ pr, const float* __restrict__ iface) {
        const unsigned j = nb.j;
        float pj, rhoj, mj;
        if (nb.kind == MF_KIND_SOLID) {
            const float2 e = reinterpret_cast<const float2*>(iface)[j];
            pj = e.x;
            rhoj = e.y;
            mj = e.y * nb.m / nb.rho;
        } else {
            pj = pr[j];
            rhoj = nb.rho;
            mj = nb.m;
        }
        const bool body_i = ki == MF_KIND_SOLID;
        const float pi_s = body_i ? pe_i : pi, rhoi_s = body_i ? rhoe_i : rhoi;
        const float scale = body_i ? rhoe_i / rhoi : 1.0f;
        const Vec<DIM> gw = nb.r * nb.fw;
        const Vec<DIM> vij = vi - nb.v;
        Vec<DIM> a = gw * (-mj * (pi_s / (rhoi_s * rhoi_s) + pj / (rhoj * rhoj)));  // eq. (7)
        const float pij = artificial_viscosity(p, dot(vij, nb.r), nb.r2, p.c0, 0.5f * (rhoi_s + rhoj));
        a = a - gw * (mj * pij);  // eq. (10)
        if (EXTRAS && p.viscosity > 0.0f) a = a + vij * (mj * laminar(p, nb.r2, nb.fw, rhoi_s, rhoj));
        return a * scale;
    }

    // Combine the L lanes of each particle, store a (0 on walls), and fold |v|, |a| and c
    // into the step size's maxima where the particle is `owned` (`owns_slot` in
    // device/particle.cuh: every particle in one domain; a subdomain's halo copies are
    // counted by their owner) (every thread of the block calls).
    template <int L>
    __device__ __forceinline__ void finish(const SphParams& p, unsigned i, unsigned n, int lane, float* __restrict__ acc_out,
                                           unsigned* __restrict__ red, float* sh, bool owned) {
        float vmax = 0.0f, amax = 0.0f, cmax = 0.0f;
#pragma unroll
        for (int a = 0; a < DIM; ++a) acc.c[a] = lane_sum<L>(acc.c[a]);
        if (i < n && lane == 0) {
            vstore<DIM>(acc_out, i, on ? acc : vzero<DIM>());
            if (on && owned) {
                vmax = sqrtf(dot(vi, vi));
                // A total-Lagrangian body's |a| comes with its internal force (sph_tl_forces).
                const bool tl = SOLIDS && ki == MF_KIND_SOLID && p.solid_formulation == MF_SOLID_TOTAL_LAGRANGIAN;
                amax = tl ? 0.0f : sqrtf(dot(acc, acc));
                cmax = sound_speed(p, ki);
            }
        }
        // Extremes over fluid and solid particles (twin: reduce.rs `extremes`); non-negative
        // floats order like their bit patterns, so atomicMax on the bits is a float max.
        if constexpr (L == 1) {
            // One lane per particle (large systems): per warp, not per block, so that no
            // warp waits at a barrier for the slowest of its block (H100, 4M: forward Euler
            // steps 0.6-0.8 % shorter, docs/reference/performance.md).
            vmax = warp_max(vmax);
            amax = warp_max(amax);
            cmax = warp_max(cmax);
            if ((threadIdx.x & 31) == 0) {
                atomicMax(&red[0], __float_as_uint(vmax));
                atomicMax(&red[1], __float_as_uint(amax));
                atomicMax(&red[2], __float_as_uint(cmax));
            }
        } else {
            // Small systems (several lanes): per block, 8 times fewer atomics on the same
            // three words at the end of a short pass (per warp was 4 us slower at 30,000).
            vmax = block_max(vmax, sh);
            if (threadIdx.x == 0) atomicMax(&red[0], __float_as_uint(vmax));
            amax = block_max(amax, sh);
            if (threadIdx.x == 0) atomicMax(&red[1], __float_as_uint(amax));
            cmax = block_max(cmax, sh);
            if (threadIdx.x == 0) atomicMax(&red[2], __float_as_uint(cmax));
        }
    }
};
