// Density by summation eq. (8), the equations of state eq. (9), and the artificial stress
// of solids (Gray, Monaghan & Swift 2001), fused: one kernel per stage.
// Twin: src/backend/cpu/density.rs (+ update_artificial_stress in stress.rs);
// parity test: tests/cuda_parity/.
#include "device/entries.cuh"
#include "device/kernel.cuh"
#include "device/mdbc.cuh"
#include "device/neighbours.cuh"
#include "device/packing.cuh"
#include "device/pairs.cuh"
#include "device/particle.cuh"
#include "device/reductions.cuh"
#include "device/vectors.cuh"

// Eigen-decomposition of the symmetric upper-left d x d block by cyclic Jacobi rotations:
// line for line the CPU's jacobi_eigen (stress.rs).
__device__ void jacobi_eigen(float a[3][3], int d, float lambda[3], float v[3][3]) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) v[r][c] = r == c ? 1.0f : 0.0f;
    for (int sweep = 0; sweep < MF_JACOBI_SWEEPS; ++sweep) {
        float off = 0.0f;
        for (int pp = 0; pp < d; ++pp)
            for (int qq = pp + 1; qq < d; ++qq) off += fabsf(a[pp][qq]);
        if (off <= MF_JACOBI_OFF_MIN) break;
        for (int pp = 0; pp < d; ++pp) {
            for (int qq = pp + 1; qq < d; ++qq) {
                float apq = a[pp][qq];
                if (fabsf(apq) <= MF_JACOBI_PIVOT_MIN) continue;
                float theta = (a[qq][qq] - a[pp][pp]) / (2.0f * apq);
                float sg = copysignf(1.0f, theta);  // Rust's f32::signum
                float t = sg / (fabsf(theta) + sqrtf(theta * theta + 1.0f));
                float c = 1.0f / sqrtf(t * t + 1.0f);
                float s = t * c;
                for (int k = 0; k < d; ++k) {
                    float akp = a[k][pp], akq = a[k][qq];
                    a[k][pp] = c * akp - s * akq;
                    a[k][qq] = s * akp + c * akq;
                }
                for (int k = 0; k < d; ++k) {
                    float apk = a[pp][k], aqk = a[qq][k];
                    a[pp][k] = c * apk - s * aqk;
                    a[qq][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < d; ++k) {
                    float vkp = v[k][pp], vkq = v[k][qq];
                    v[k][pp] = c * vkp - s * vkq;
                    v[k][qq] = s * vkp + c * vkq;
                }
            }
        }
    }
    lambda[0] = a[0][0]; lambda[1] = a[1][1]; lambda[2] = a[2][2];
}

// Artificial stress R of a solid particle from sigma = -P I + S, eq. (11), or from S alone
// where artificial_stress_from is set (art_pressure in stress.rs): in the principal
// frame R'^aa = -eps sigma'^aa / rho^2 where sigma'^aa > 0 (tension), else 0; rotated back.
template <int DIM>
__device__ Mat<DIM> artificial_stress(const SphParams& p, const Mat<DIM>& si, float pi, float rhoi) {
    float a3[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    if (p.artificial_stress_from != 0) pi = 0.0f;
    for (int r = 0; r < DIM; ++r)
        for (int c = 0; c < DIM; ++c) a3[r][c] = si.m[r][c] - (r == c ? pi : 0.0f);
    float lam[3], v[3][3];
    jacobi_eigen(a3, DIM, lam, v);
    Mat<DIM> R = mzero<DIM>();
    for (int k = 0; k < DIM; ++k) {
        float rk = lam[k] > 0.0f ? -p.artificial_stress * lam[k] / (rhoi * rhoi) : 0.0f;
        if (rk != 0.0f)
            for (int a = 0; a < DIM; ++a)
                for (int b = 0; b < DIM; ++b) R.m[a][b] += (v[a][k] * v[b][k]) * rk;
    }
    return R;
}

// stress, rho_dev and art: null without solids / without artificial stress (all three or art
// alone). rho_dev: the solids' density departure rho - rho0_s (SolidState::rho_dev), set from
// the summed density, read under the continuity density.
template <int DIM, int L>
__device__ void density_impl(const SphParams p, unsigned n, const unsigned* __restrict__ cell_start,
                             const float* __restrict__ pos, float* __restrict__ vel,
                             const unsigned char* __restrict__ kind,
                             float* __restrict__ rho, float* __restrict__ pr, float* __restrict__ rho_dev,
                             const float* __restrict__ stress, float* __restrict__ art) {
    const unsigned t = blockIdx.x * blockDim.x + threadIdx.x;
    const unsigned i = t / L;
    const int lane = (int)(t % L);
    const unsigned char ki = i < n ? kind[i] : (unsigned char)MF_KIND_BOUNDARY;
    // Boundary particles carry density and pressure only with dynamic walls (Crespo 2007).
    const bool active = i < n && (ki != MF_KIND_BOUNDARY || p.wall_coupling != 0);
    // mDBC walls took theirs from their ghost nodes (sph_wall_density).
    const bool summed = ki != MF_KIND_BOUNDARY || p.wall_coupling != MF_WALL_COUPLING_MDBC;
    float r = 0.0f;
    if (p.density_form == MF_DENSITY_SUMMATION) {
        float sum_w = 0.0f;
        if (active && summed)
            for_each_neighbor_split<DIM, L>(p, cell_start, pos, vload<DIM>(pos, i), lane,
                                            [&](unsigned j, Vec<DIM>, float r2, float) {
                                                if (couples(p, kind[j]) && meets(p, ki, kind[j]))
                                                    sum_w += kernel_w(p, sqrtf(r2));
                                            });
        sum_w = lane_sum<L>(sum_w);  // every lane of the warp takes part
        if (active && summed && lane == 0) {
            r = mass_of<DIM>(pos, vel, i) * sum_w;  // eq. (8), number-density form (Hu & Adams 2006)
            rho[i] = r;
        } else if (active && lane == 0) {
            r = rho[i];
        }
    } else if (active && lane == 0) {
        r = rho[i];
    }
    if (i >= n || lane != 0) return;
    float pi = 0.0f;
    if (active) {
        float dev = 0.0f;
        if (rho_dev) {
            if (p.density_form == MF_DENSITY_SUMMATION && ki == MF_KIND_SOLID) rho_dev[i] = r - p.solid_rho0;
            dev = rho_dev[i];
        }
        pi = pressure(p, ki, r, dev);  // eq. (9)
        pr[i] = pi;
    }
    // The density in the velocity's w slot (see vel_load in device/packing.cuh), every particle.
    reinterpret_cast<float4*>(vel)[i].w = vel_w(ki, active ? r : rho[i]);
    if (art) {
        if (ki == MF_KIND_SOLID) {
            sstore<DIM>(art, i, n, artificial_stress<DIM>(p, sload<DIM>(stress, i, n), pi, r));
        } else {
            sstore<DIM>(art, i, n, mzero<DIM>());
        }
    }
}
// One entry per lane count (MF_LANES_EACH): several lanes for small systems (shorter serial
// loops), fewer for large ones (more particles in flight; L = 1 is the CPU's exact summation
// order). The launcher picks.
#define MF_DENSITY_ENTRY(L)                                                                                      \
    template <int DIM>                                                                                         \
    __device__ void sph_density_##L##_body(const SphParams p, unsigned n, const unsigned* cell_start,          \
                                           const float* pos, float* vel, const unsigned char* kind,            \
                                           float* rho, float* pr, float* rho_dev, const float* stress,      \
                                           float* art) {                                                       \
        density_impl<DIM, L>(p, n, cell_start, pos, vel, kind, rho, pr, rho_dev, stress, art);            \
    }                                                                                                          \
    MF_ENTRY2(sph_density_##L,                                                                                 \
              (const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, float* vel,        \
               const unsigned char* kind, float* rho, float* pr, float* rho_dev, const float* stress,      \
               float* art),                                                                                    \
              (p, n, cell_start, pos, vel, kind, rho, pr, rho_dev, stress, art))
MF_LANES_EACH(MF_DENSITY_ENTRY)

// The Tait density of pressure pr, eq. (9) inverted (less the background pressure), held at
// 0.1 rho0 or more. Twin of `tait_density` in cpu/interface.rs. [M L^-d]
__device__ __forceinline__ float tait_density(const SphParams& p, float pr) {
    const float base = fmaxf(1.0f + (pr - p.background_pressure) / p.tait_b, powf(0.1f, p.tait_gamma));
    return p.rho0 * powf(base, 1.0f / p.tait_gamma);
}

// Modified dynamic walls (MF_WALL_COUPLING_MDBC; English et al. 2022, device/mdbc.cuh):
// each wall particle a's density from its ghost node x_g = x_a + 2 d_B n in the fluid
// (surface: Setup::wall_surface as float4 (n, d_B) at id - wall_first_id, n turned as its wall
// has turned by the clock's time, wall_normal_now: a floating body of bodies, a turning driven
// wall; bodies null where n_bodies is 0), by the first-order
// corrected interpolation of the fluid particles around x_g (GhostSums), its pressure cloned
// back to x_a with the hydrostatic term (mdbc_clone) and the Tait density of that; rho0
// where no fluid is near, held at rho0 or more under wall_density_floor; then its Tait
// pressure, eq. (9), and the w slot of vel. A wall particle without a normal, and every other
// particle, is left as it is. One thread per particle, the CPU's neighbour order. Launched
// before the density pass (launch/passes.rs), which then leaves the walls' densities alone.
// Twin: `wall_density` in cpu/density.rs.
template <int DIM>
__device__ void sph_wall_density_body(const SphParams p, unsigned n, const unsigned* __restrict__ cell_start,
                                      const float* __restrict__ pos, float* __restrict__ vel,
                                      const unsigned char* __restrict__ kind, const unsigned* __restrict__ id,
                                      const unsigned* __restrict__ group, const float* __restrict__ surface,
                                      const double* __restrict__ clock, const MfBody* __restrict__ bodies,
                                      unsigned n_bodies, const double* __restrict__ series, float* __restrict__ rho,
                                      float* __restrict__ pr) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != MF_KIND_BOUNDARY) return;
    const float4 s = reinterpret_cast<const float4*>(surface)[id[i] - p.wall_first_id];
    if (s.x == 0.0f && s.y == 0.0f && s.z == 0.0f) return;
    double nn[3] = {(double)s.x, (double)s.y, (double)s.z};
    wall_normal_now<DIM>(p, bodies, n_bodies, series, clock[0], group[i], nn);
    const float two_dn[3] = {2.0f * s.w * (float)nn[0], 2.0f * s.w * (float)nn[1], 2.0f * s.w * (float)nn[2]};
    Vec<DIM> xg = vload<DIM>(pos, i);
#pragma unroll
    for (int a = 0; a < DIM; ++a) xg.c[a] += two_dn[a];
    GhostSums g;
    for_each_neighbor_split<DIM, 1>(p, cell_start, pos, xg, 0, [&](unsigned j, Vec<DIM> r, float r2, float) {
        if (kind[j] != MF_KIND_FLUID) return;
        float w, f;
        kernel_wf(p, sqrtf(r2), w, f);
        const float r3[3] = {r.c[0], r.c[1], DIM == 3 ? r.c[DIM - 1] : 0.0f};
        g.add(DIM, r3, w, f, mass_of<DIM>(pos, vel, j), rho[j]);
    });
    float out = p.rho0, rho_g;
    if (g.density(DIM, p.rho0, p.dx, rho_g)) {
        // The ghost node's pressure, eq. (9), cloned back to the wall particle.
        const float pr_g = pressure(p, MF_KIND_BOUNDARY, rho_g, 0.0f);
        out = tait_density(p, mdbc_clone(p, pr_g, nn, s.w));
    }
    if (p.wall_density_floor != 0) out = fmaxf(out, p.rho0);
    rho[i] = out;
    pr[i] = pressure(p, MF_KIND_BOUNDARY, out, 0.0f);  // eq. (9)
    reinterpret_cast<float4*>(vel)[i].w = vel_w(MF_KIND_BOUNDARY, out);
}
MF_ENTRY2(sph_wall_density,
          (const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, float* vel,
           const unsigned char* kind, const unsigned* id, const unsigned* group, const float* surface,
           const double* clock, const MfBody* bodies, unsigned n_bodies, const double* series, float* rho, float* pr),
          (p, n, cell_start, pos, vel, kind, id, group, surface, clock, bodies, n_bodies, series, rho, pr))

// The fluid's pressure extrapolated to each body's particle b and its Tait density, as
// float2 (P'_b, rho'_b) in iface (solid_fluid_pressure = EXTRAPOLATED; Adami, Hu & Adams
// 2012, eq. (27) without the body's acceleration): P'_b = (sum_f P_f W_bf + rho_f g .
// (x_b - x_f) W_bf) / sum_f W_bf over the fluid neighbours f; (background pressure, rho0)
// for other particles and a body's particle without fluid. One thread per particle.
// Twin: `solid_interface` in cpu/interface.rs.
template <int DIM>
__device__ void sph_solid_interface_body(const SphParams p, unsigned n, const unsigned* __restrict__ cell_start,
                                         const float* __restrict__ pos, const float* __restrict__ rho,
                                         const float* __restrict__ pr, const unsigned char* __restrict__ kind,
                                         float* __restrict__ iface) {
    const unsigned b = blockIdx.x * blockDim.x + threadIdx.x;
    if (b >= n) return;
    float2 out = make_float2(p.background_pressure, p.rho0);
    if (kind[b] == MF_KIND_SOLID) {
        Vec<DIM> g;
#pragma unroll
        for (int a = 0; a < DIM; ++a) g.c[a] = p.gravity[a];
        float sum_w = 0.0f, sum_pw = 0.0f;
        for_each_neighbor_split<DIM, 1>(p, cell_start, pos, vload<DIM>(pos, b), 0,
                                        [&](unsigned f, Vec<DIM> r, float r2, float) {
                                            if (kind[f] != MF_KIND_FLUID) return;
                                            // r = x_b - x_f
                                            const float w = kernel_w(p, sqrtf(r2));
                                            sum_w += w;
                                            sum_pw += (pr[f] + rho[f] * dot(g, r)) * w;
                                        });
        if (sum_w > 0.0f) {
            const float pb = sum_pw / sum_w;
            out = make_float2(pb, tait_density(p, pb));
        }
    }
    reinterpret_cast<float2*>(iface)[b] = out;
}
MF_ENTRY2(sph_solid_interface,
          (const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, const float* rho,
           const float* pr, const unsigned char* kind, float* iface),
          (p, n, cell_start, pos, rho, pr, kind, iface))
