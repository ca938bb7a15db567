// Elastic solids: velocity gradient eq. (15), strain/rotation rates eqs. (13)-(14), Jaumann
// rate eq. (12), artificial stress (Gray, Monaghan & Swift 2001).
// Twin: src/backend/cpu/stress.rs; parity test: tests/cuda_parity.rs.
#include "common.cuh"

// Eigen-decomposition of the symmetric upper-left d x d block by cyclic Jacobi rotations:
// line for line the CPU's jacobi_eigen.
__device__ void jacobi_eigen(float a[3][3], int d, float lambda[3], float v[3][3]) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) v[r][c] = r == c ? 1.0f : 0.0f;
    for (int sweep = 0; sweep < 8; ++sweep) {
        float off = 0.0f;
        for (int pp = 0; pp < d; ++pp)
            for (int qq = pp + 1; qq < d; ++qq) off += fabsf(a[pp][qq]);
        if (off <= 1e-20f) break;
        for (int pp = 0; pp < d; ++pp) {
            for (int qq = pp + 1; qq < d; ++qq) {
                float apq = a[pp][qq];
                if (fabsf(apq) <= 1e-30f) continue;
                float theta = (a[qq][qq] - a[pp][pp]) / (2.0f * apq);
                float sg = theta > 0.0f ? 1.0f : (theta < 0.0f ? -1.0f : copysignf(1.0f, theta));
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

template <int DIM>
__device__ void sph_stress_rate_body(const SphParams p, unsigned n, const unsigned* __restrict__ cell_start,
                                     const float* __restrict__ pos, const float* __restrict__ vel,
                                     const float* __restrict__ rho, const float* __restrict__ pr,
                                     const float* __restrict__ mass, const unsigned char* __restrict__ kind,
                                     const unsigned* __restrict__ group, const float* __restrict__ stress,
                                     float* __restrict__ rate, float* __restrict__ art) {
    unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    if (kind[i] != MF_KIND_SOLID) {
        Mat<DIM> z = mzero<DIM>();
        sstore<DIM>(rate, i, n, z);
        if (art) sstore<DIM>(art, i, n, z);
        return;
    }
    const Vec<DIM> vi = vload<DIM>(vel, i);
    const float rhoi = rho[i];
    const unsigned gi = group[i];
    // Velocity gradient, eq. (15): dv^a/dx^b = sum_j m_j / rho_bar_ij (v_j - v_i)^a dW/dx_i^b.
    Mat<DIM> g = mzero<DIM>();
    for_each_neighbor<DIM>(p, cell_start, pos, vload<DIM>(pos, i), [&](unsigned j, Vec<DIM> r, float r2) {
        if (j == i || kind[j] != MF_KIND_SOLID || group[j] != gi) return;
        Vec<DIM> gw = r * kernel_f(p, sqrtf(r2));
        float rho_bar = 0.5f * (rhoi + rho[j]);
        Vec<DIM> dv = vload<DIM>(vel, j) - vi;
        float s = mass[j] / rho_bar;
#pragma unroll
        for (int a = 0; a < DIM; ++a)
#pragma unroll
            for (int b = 0; b < DIM; ++b) g.m[a][b] += (dv.c[a] * gw.c[b]) * s;
    });
    Mat<DIM> eps, om;
#pragma unroll
    for (int a = 0; a < DIM; ++a)
#pragma unroll
        for (int b = 0; b < DIM; ++b) {
            eps.m[a][b] = (g.m[a][b] + g.m[b][a]) * 0.5f;  // eq. (13)
            om.m[a][b] = (g.m[a][b] - g.m[b][a]) * 0.5f;   // eq. (14)
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
    sstore<DIM>(rate, i, n, out);
    if (art) {
        // sigma = -P I + S, eq. (11); R'^aa = -eps sigma'^aa / rho^2 where sigma'^aa > 0.
        float a3[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
        for (int r = 0; r < DIM; ++r)
            for (int c = 0; c < DIM; ++c) a3[r][c] = si.m[r][c] - (r == c ? pr[i] : 0.0f);
        float lam[3], v[3][3];
        jacobi_eigen(a3, DIM, lam, v);
        Mat<DIM> R = mzero<DIM>();
        for (int k = 0; k < DIM; ++k) {
            float rk = lam[k] > 0.0f ? -p.art_stress_eps * lam[k] / (rhoi * rhoi) : 0.0f;
            if (rk != 0.0f)
                for (int a = 0; a < DIM; ++a)
                    for (int b = 0; b < DIM; ++b) R.m[a][b] += (v[a][k] * v[b][k]) * rk;
        }
        sstore<DIM>(art, i, n, R);
    }
}
MF_ENTRY2(sph_stress_rate,
          (const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, const float* vel,
           const float* rho, const float* pr, const float* mass, const unsigned char* kind, const unsigned* group,
           const float* stress, float* rate, float* art),
          (p, n, cell_start, pos, vel, rho, pr, mass, kind, group, stress, rate, art))
