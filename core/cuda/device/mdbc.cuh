// Modified dynamic boundary conditions (mDBC; English et al. 2022, Comput. Part. Mech. 9,
// 1-15): the sums of a wall particle's ghost node, the ghost node's density, and its pressure
// cloned back to the wall particle.
// Twin: src/physics/mdbc.rs (GhostSums); parity test: tests/cuda_parity/.
#pragma once
#include "sph_consts.h"
#include "sph_params.h"
#include "body.cuh"
#include "motion.cuh"

// A wall particle's unit normal now, at time t [T]: its t = 0 normal n turned as its group g
// has turned since, a floating body's by its orientation, a driven wall's by its motion's
// turn theta(t); any other group's as it was. Twin: `normal_now` in src/physics/mdbc.rs.
template <int DIM>
__device__ __forceinline__ void wall_normal_now(const SphParams& p, const MfBody* __restrict__ bodies,
                                                unsigned n_bodies, const double* __restrict__ series, double t,
                                                unsigned g, double* n) {
    for (int k = 0; k < p.driven; ++k) {
        const MfMotion& m = p.driven_motion[k];
        if ((unsigned)m.group != g) continue;
        if (m.floating) {
            for (unsigned b = 0; b < n_bodies; ++b) {
                if ((unsigned)bodies[b].group != g) continue;
                double r[9];
                body_matrix(bodies[b].orientation, r);
                const double u[3] = {n[0], n[1], n[2]};
                for (int a = 0; a < 3; ++a) n[a] = r[3 * a] * u[0] + r[3 * a + 1] * u[1] + r[3 * a + 2] * u[2];
                break;
            }
        } else if (m.rate != 0.0f || m.angle != 0.0f || m.series_count > 0) {
            motion_rotate<DIM>(m, motion_at(m, series, t).q, n);
        }
        return;
    }
}

// Over the fluid particles b around a ghost node, r = x_g - x_b [L], V_b = m_b / rho_b:
// a = [[sum V W, sum V W r^T], [sum V grad W, sum V grad W r^T]], b = [sum m W, sum m grad W].
struct GhostSums {
    float a[4][4] = {{0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}};
    float b[4] = {0, 0, 0, 0};

    __device__ __forceinline__ void add(int d, const float* r, float w, float f, float m, float rho) {
        const float v = m / rho;
        const float vw = w * v;
        b[0] += m * w;
        a[0][0] += vw;
        for (int k = 0; k < d; ++k) a[0][1 + k] += r[k] * vw;
        for (int q = 0; q < d; ++q) {
            const float g = f * r[q];
            b[1 + q] += m * g;
            const float vg = g * v;
            a[1 + q][0] += vg;
            for (int k = 0; k < d; ++k) a[1 + q][1 + k] += r[k] * vg;
        }
    }

    // The ghost node's density: first order where |det A| >= MF_MDBC_DET_MIN, the scaled
    // condition number dx^2 |A| |A^-1| <= MF_MDBC_COND_MAX and a[0][0] >= MF_MDBC_SUM_MIN, else
    // Shepard (at least rho0 where the kernel sum is thin); false where no fluid is near.
    // Twin: `GhostSums::density`.
    __device__ __forceinline__ bool density(int d, float rho0, float dx, float& out) const {
        if (a[0][0] <= 0.0f) return false;
        const float shepard = b[0] / a[0][0];
        if ((double)a[0][0] < MF_MDBC_SUM_MIN) {
            out = fmaxf(shepard, rho0);
            return true;
        }
        // [A | b | I]: the solution and the inverse by one elimination.
        const int m = d + 1, w = 2 * m + 1;
        double e[4][9];
        double norm_a = 0.0;
        for (int r = 0; r < m; ++r) {
            double row = 0.0;
            for (int c = 0; c < w; ++c) e[r][c] = 0.0;
            for (int c = 0; c < m; ++c) {
                e[r][c] = (double)a[r][c];
                row += fabs(e[r][c]);
            }
            norm_a = fmax(norm_a, row);
            e[r][m] = (double)b[r];
            e[r][m + 1 + r] = 1.0;
        }
        double det = 1.0;
        for (int c = 0; c < m; ++c) {
            int piv = c;
            for (int r = c + 1; r < m; ++r)
                if (fabs(e[r][c]) > fabs(e[piv][c])) piv = r;
            if (piv != c) {
                for (int k = 0; k < w; ++k) {
                    const double t = e[piv][k];
                    e[piv][k] = e[c][k];
                    e[c][k] = t;
                }
                det = -det;
            }
            det *= e[c][c];
            if (e[c][c] == 0.0) break;
            for (int r = c + 1; r < m; ++r) {
                const double k = e[r][c] / e[c][c];
                for (int cc = c; cc < w; ++cc) e[r][cc] -= k * e[c][cc];
            }
        }
        if (fabs(det) < MF_MDBC_DET_MIN) {
            out = shepard;
            return true;
        }
        double x[4][9];
        for (int k = m; k < w; ++k)
            for (int r = m - 1; r >= 0; --r) {
                double s = e[r][k];
                for (int c = r + 1; c < m; ++c) s -= e[r][c] * x[c][k];
                x[r][k] = s / e[r][r];
            }
        double norm_inv = 0.0;
        for (int r = 0; r < m; ++r) {
            double row = 0.0;
            for (int j = 0; j < m; ++j) row += fabs(x[r][m + 1 + j]);
            norm_inv = fmax(norm_inv, row);
        }
        if ((double)dx * (double)dx * norm_a * norm_inv > MF_MDBC_COND_MAX) {
            out = shepard;
            return true;
        }
        out = (float)x[0][m];
        return true;
    }
};

// The wall particle's pressure from its ghost node's, cloned back across the wall along the
// unit normal n with the hydrostatic term: P_a = P_g - 2 d_B rho0 (g . n) [M L^-d L^2 T^-2].
// Twin: `cloned_pressure` in src/physics/mdbc.rs.
__device__ __forceinline__ float mdbc_clone(const SphParams& p, float pr_ghost, const double* n, float d_b) {
    float g_n = 0.0f;
    for (int a = 0; a < p.dim; ++a) g_n += p.gravity[a] * (float)n[a];
    return pr_ghost - 2.0f * d_b * p.rho0 * g_n;
}
