// The per-point sums of the probes (sph_sample_points in probes.cu): kernel interpolation,
// eqs. (1)-(4), with Shepard normalisation, f(x) = sum_j f_j W V_j / sum_j W V_j,
// V_j = m_j / rho_j [L^d]. Twin: PointSum in src/backend/cpu/probes.rs; parity test:
// tests/cuda_parity/.
#pragma once
#include "sph_consts.h"
#include "sph_params.h"
#include "kernel.cuh"
#include "particle.cuh"
#include "vectors.cuh"

template <int DIM> struct PointSum {
    float weight = 0.0f;    // sum W V over the interpolated particles (Shepard's denominator) [-]
    float colour = 0.0f;    // sum W V over fluid particles [-]
    float pressure = 0.0f;  // sum P W V [M L^-d L^2 T^-2]
    Vec<DIM> velocity = vzero<DIM>();  // sum v W V [L/T]
    float density = 0.0f;   // sum rho W V [M L^-d]
    unsigned neighbours = 0;

    // Neighbour j of kind k at distance r [L], mass m [M], density rho, velocity v; wall
    // particles enter only where walls.
    __device__ __forceinline__ void add(const SphParams& p, bool walls, unsigned char k, float r, float m,
                                        float rho, Vec<DIM> v) {
        const bool fluid = k == MF_KIND_FLUID;
        if (!(fluid || (walls && k == MF_KIND_BOUNDARY))) return;
        const float wv = kernel_w(p, r) * (m / rho);  // W(x - x_j) m_j / rho_j, eqs. (1)-(4)
        if (fluid) colour += wv;
        weight += wv;
        // (Fluid and wall particles only: the solid departure argument is never read.)
        pressure += ::pressure(p, k, rho, rho - p.solid_rho0) * wv;  // eq. (9) at the neighbour's density
        velocity = velocity + v * wv;
        density += rho * wv;
        ++neighbours;
    }

    // The Shepard-normalised sample into out[0..MF_SAMPLE_FLOATS) (sph_consts.h: pressure,
    // velocity x, y, z, density, colour, neighbours as an unsigned's bits, 0): NaN fields
    // where no neighbour entered, the colour as summed.
    __device__ __forceinline__ void finish(float* out) const {
        const bool any = neighbours > 0 && weight > 0.0f;
        const float inv = any ? 1.0f / weight : 0.0f;
        const float nan = __int_as_float(0x7fc00000);
        out[0] = any ? pressure * inv : nan;
        out[1] = any ? velocity.c[0] * inv : nan;
        out[2] = any ? velocity.c[1] * inv : nan;
        out[3] = any ? (DIM == 3 ? velocity.c[DIM - 1] * inv : 0.0f) : nan;
        out[4] = any ? density * inv : nan;
        out[5] = colour;
        out[6] = __uint_as_float(neighbours);
        out[7] = 0.0f;
    }
};
