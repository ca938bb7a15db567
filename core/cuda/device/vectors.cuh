// Vectors and tensors for DIM = 2/3 (`Vec`, `Mat`) and the fast division and norm of the
// pair sums. Twin: src/physics/dim.rs (glam's Vec2 / Vec3A, Mat2 / Mat3A); parity test:
// tests/cuda_parity/.
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
// a b, the sum over k in ascending order (glam's).
template <int DIM> __device__ __forceinline__ Mat<DIM> mat_mul(const Mat<DIM>& a, const Mat<DIM>& b) {
    Mat<DIM> r;
#pragma unroll
    for (int x = 0; x < DIM; ++x)
#pragma unroll
        for (int y = 0; y < DIM; ++y) {
            float s = a.m[x][0] * b.m[0][y];
#pragma unroll
            for (int k = 1; k < DIM; ++k) s += a.m[x][k] * b.m[k][y];
            r.m[x][y] = s;
        }
    return r;
}
template <int DIM> __device__ __forceinline__ Mat<DIM> transpose(const Mat<DIM>& a) {
    Mat<DIM> r;
#pragma unroll
    for (int x = 0; x < DIM; ++x)
#pragma unroll
        for (int y = 0; y < DIM; ++y) r.m[x][y] = a.m[y][x];
    return r;
}
template <int DIM> __device__ __forceinline__ float trace(const Mat<DIM>& a) {
    float s = a.m[0][0];
#pragma unroll
    for (int x = 1; x < DIM; ++x) s += a.m[x][x];
    return s;
}
template <int DIM> __device__ __forceinline__ float det(const Mat<DIM>& a) {
    if constexpr (DIM == 2) {
        return a.m[0][0] * a.m[1][1] - a.m[0][1] * a.m[1][0];
    } else {
        return a.m[0][0] * (a.m[1][1] * a.m[2][2] - a.m[1][2] * a.m[2][1]) -
               a.m[0][1] * (a.m[1][0] * a.m[2][2] - a.m[1][2] * a.m[2][0]) +
               a.m[0][2] * (a.m[1][0] * a.m[2][1] - a.m[1][1] * a.m[2][0]);
    }
}
// Inverse by the adjugate (the caller has checked |det| > MF_MOMENT_DET_MIN).
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
