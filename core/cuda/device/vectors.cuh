// Vectors and tensors for DIM = 2/3 (`Vec`, `Mat`) and the fast division and norm of the
// pair sums. Twin: src/dim.rs (glam's Vec2 / Vec3A, Mat2 / Mat3A); parity test:
// tests/cuda_parity.rs.
#pragma once

template <int DIM> struct Vec { float c[DIM]; };

template <int DIM> __device__ __forceinline__ Vec<DIM> vzero() {
    Vec<DIM> v;
#pragma unroll
    for (int a = 0; a < DIM; ++a) v.c[a] = 0.0f;
    return v;
}
template <int DIM> __device__ __forceinline__ Vec<DIM> operator+(Vec<DIM> x, Vec<DIM> y) {
#pragma unroll
    for (int a = 0; a < DIM; ++a) x.c[a] += y.c[a];
    return x;
}
template <int DIM> __device__ __forceinline__ Vec<DIM> operator-(Vec<DIM> x, Vec<DIM> y) {
#pragma unroll
    for (int a = 0; a < DIM; ++a) x.c[a] -= y.c[a];
    return x;
}
template <int DIM> __device__ __forceinline__ Vec<DIM> operator*(Vec<DIM> x, float s) {
#pragma unroll
    for (int a = 0; a < DIM; ++a) x.c[a] *= s;
    return x;
}
template <int DIM> __device__ __forceinline__ float dot(Vec<DIM> x, Vec<DIM> y) {
    float s = x.c[0] * y.c[0];
#pragma unroll
    for (int a = 1; a < DIM; ++a) s += x.c[a] * y.c[a];
    return s;
}

// A DIM x DIM tensor, m[row][col] (glam's entry(row, col)).
template <int DIM> struct Mat { float m[DIM][DIM]; };
template <int DIM> __device__ __forceinline__ Mat<DIM> mzero() {
    Mat<DIM> r;
#pragma unroll
    for (int a = 0; a < DIM; ++a)
#pragma unroll
        for (int b = 0; b < DIM; ++b) r.m[a][b] = 0.0f;
    return r;
}
template <int DIM> __device__ __forceinline__ Vec<DIM> mat_vec(const Mat<DIM>& m, Vec<DIM> v) {
    Vec<DIM> r;
#pragma unroll
    for (int a = 0; a < DIM; ++a) {
        float s = m.m[a][0] * v.c[0];
#pragma unroll
        for (int b = 1; b < DIM; ++b) s += m.m[a][b] * v.c[b];
        r.c[a] = s;
    }
    return r;
}

// a / b to within 2 ulp (__fdividef: one reciprocal and one product, without the IEEE
// division's correction steps and slow-path branch), for the divisors of the per-pair
// sums: h, q in [1, 2), densities and r^2 + eta^2, all far inside the range where it is
// accurate (|b| < 2^126). The CPU twins divide exactly; the parity tolerances (>= 2e-5
// relative) are 100x its error.
__device__ __forceinline__ float fast_div(float a, float b) { return __fdividef(a, b); }
// |r| from r^2 to within 3 ulp (a reciprocal square root and a product; 0 at 0), for the
// per-pair sums; the CPU twins take the exact root.
__device__ __forceinline__ float fast_norm(float r2) { return r2 > 0.0f ? r2 * rsqrtf(r2) : 0.0f; }
