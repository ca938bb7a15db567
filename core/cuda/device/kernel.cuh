// Smoothing kernels, eqs. (1)-(4): W and (dW/dr) / r. Twin: src/physics/kernel.rs; parity test:
// tests/cuda_parity/.
#pragma once
#include "sph_params.h"
#include "vectors.cuh"

// W [L^-d], eqs. (1)-(4), and (dW/dr) / r [L^-(d+2)] (grad_i W_ij = f r_ij) at one r, under
// one branch on the kernel and on q: the pair sums need both (W for XSPH and shifting).
__device__ __forceinline__ void kernel_wf(const SphParams& p, float r, float& w, float& f) {
    const float q = fast_div(r, p.h);
    float sw = 0.0f, sf = 0.0f;
    if (p.kernel == MF_KERNEL_WENDLAND_C2) {
        if (q < 2.0f) {
            float t = 1.0f - 0.5f * q;
            sw = t * t * t * t * (2.0f * q + 1.0f);
            sf = -5.0f * t * t * t;
        }
    } else if (q < 1.0f) {
        sw = 1.0f - 1.5f * q * q + 0.75f * q * q * q;
        sf = -3.0f + 2.25f * q;
    } else if (q < 2.0f) {
        float t = 2.0f - q;
        sw = 0.25f * t * t * t;
        sf = fast_div(-0.75f * t * t, q);
    }
    w = p.kernel_norm * sw;
    f = p.kernel_norm / (p.h * p.h) * sf;
}
// The q = r / h at which |dW/dr| peaks (2/3 cubic spline, 1/2 Wendland C2) [-]: closer,
// |grad W| falls as r falls. Twin: `gradient_peak_q` in src/physics/kernel.rs.
__device__ __forceinline__ float kernel_gradient_peak_q(const SphParams& p) {
    return p.kernel == MF_KERNEL_WENDLAND_C2 ? 0.5f : 2.0f / 3.0f;
}
// W(r, h) [L^-d] alone (the gradient's arithmetic is dead code here and compiled out).
__device__ __forceinline__ float kernel_w(const SphParams& p, float r) {
    float w, f;
    kernel_wf(p, r, w, f);
    return w;
}
