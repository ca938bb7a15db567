// XSPH motion eq. (18) and forward Euler eq. (19); the stress update; the device clock.
// Twin: src/backend/cpu/integrate.rs; parity test: tests/cuda_parity.rs.
#include "common.cuh"

template <int DIM>
__device__ void sph_integrate_body(const SphParams p, unsigned n, const float* __restrict__ dt_dev,
                                   double* __restrict__ time, const unsigned char* __restrict__ kind,
                                   float* __restrict__ pos, float* __restrict__ vel, const float* __restrict__ acc,
                                   const float* __restrict__ xsph, float* __restrict__ rho,
                                   const float* __restrict__ drho, float* __restrict__ stress,
                                   const float* __restrict__ rate) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    const float dt = *dt_dev;
    if (i == 0) *time += (double)dt;
    if (i >= n) return;
    const unsigned char k = kind[i];
    if (k == MF_KIND_BOUNDARY) return;
    Vec<DIM> x = vload<DIM>(pos, i), v = vload<DIM>(vel, i);
    const Vec<DIM> a = vload<DIM>(acc, i), xs = vload<DIM>(xsph, i);
    if (p.integrator == MF_INTEGRATOR_EULER) {
        // eq. (19) with eq. (18): x^{n+1} = x^n + dt (v^n + xsph), v^{n+1} = v^n + dt a^n
        x = x + (v + xs) * dt;
        v = v + a * dt;
    } else {
        // semi-implicit (symplectic) Euler: the position takes the new velocity
        v = v + a * dt;
        x = x + (v + xs) * dt;
    }
#pragma unroll
    for (int d = 0; d < DIM; ++d) {  // wrap on periodic axes
        if (p.periodic[d]) {
            const float lo = p.domain_min[d], hi = p.domain_max[d];
            if (x.c[d] < lo) x.c[d] += hi - lo;
            else if (x.c[d] >= hi) x.c[d] -= hi - lo;
        }
    }
    vstore<DIM>(pos, i, x);
    vstore<DIM>(vel, i, v);
    if (drho) rho[i] += dt * drho[i];
    if (stress && k == MF_KIND_SOLID) {
#pragma unroll
        for (int c = 0; c < Sym<DIM>::N; ++c) stress[c * n + i] += rate[c * n + i] * dt;  // Euler on eq. (12)
    }
}
MF_ENTRY2(sph_integrate,
          (const SphParams p, unsigned n, const float* dt_dev, double* time, const unsigned char* kind, float* pos,
           float* vel, const float* acc, const float* xsph, float* rho, const float* drho, float* stress,
           const float* rate),
          (p, n, dt_dev, time, kind, pos, vel, acc, xsph, rho, drho, stress, rate))
