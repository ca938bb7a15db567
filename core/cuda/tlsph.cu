// The total-Lagrangian elastic solid (`[solid] formulation = "total-lagrangian"`; O'Connor &
// Rogers 2021, J. Fluids Struct. 104, 103312; hourglass control of Ganzenmueller 2015,
// Comput. Methods Appl. Mech. Engrg. 286, 87): the slot map solid index -> storage slot after
// each reorder, the stress from the deformation gradient (Saint Venant-Kirchhoff), the
// internal force with the hourglass control, and the displacement's drift. One thread per
// solid particle (solid index a = its rank by id), its reference neighbours in the CSR order
// the host built (src/physics/tlsph/mod.rs `Reference`), so the sums run in the CPU's order; no atomics
// (each solid adds to its own slot). dt is read on the device (written by sph_step_size).
// Twin: src/backend/cpu/tlsph.rs (material law and reference set-up: src/physics/tlsph/mod.rs); parity
// test: tests/cuda_parity/.
//
// Layout (src/backend/cuda/buffers.rs `TlBuffers`): x0 and disp as float2 (2D) / float4 (3D,
// w = 0) per solid; grad (H = F - I) row-major, DIM * DIM floats per solid; corr (C, the
// reference gradient's second-order correction, src/physics/tlsph/gradient.rs) and pk1_corr ((omega / V0) P C) as
// TL_Q columns of DIM floats per solid; face (F_a, the clamp's face points' basis sum,
// src/physics/tlsph/mod.rs `faces`) TL_Q floats per solid and face_clamp (the clamp particle whose
// displacement the face takes, NONE where a has no face) one per solid; the face points within
// a's support as a CSR (face_start, face_pts: DIM + 1 + TL_Q floats each, X0_m, V_m, then the
// fit's value weights r_am, src/physics/tlsph/mod.rs `FacePair`); quad (omega / V0, the strain energy's
// quadrature weight, src/physics/tlsph/quadrature.rs) one per solid; slot NONE (0xffffffff) for a
// removed particle.
//
// Every reference separation X0_a - X0_b (and X0_a - X0_m of a face point) is the minimum image
// on periodic axes (separation, device/grid.cuh), as the host's set-up took it: a body or a
// clamp may cross the seam (src/physics/tlsph/mod.rs).
#include "device/entries.cuh"
#include "device/grid.cuh"
#include "device/kernel.cuh"
#include "device/motion.cuh"
#include "device/packing.cuh"
#include "device/particle.cuh"
#include "device/reductions.cuh"
#include "device/vectors.cuh"

#define MF_TL_NONE 0xffffffffu

template <int DIM> __device__ __forceinline__ Mat<DIM> tl_mload(const float* __restrict__ a, unsigned i) {
    Mat<DIM> r;
#pragma unroll
    for (int x = 0; x < DIM; ++x)
#pragma unroll
        for (int y = 0; y < DIM; ++y) r.m[x][y] = a[i * DIM * DIM + x * DIM + y];
    return r;
}
template <int DIM> __device__ __forceinline__ void tl_mstore(float* __restrict__ a, unsigned i, const Mat<DIM>& r) {
#pragma unroll
    for (int x = 0; x < DIM; ++x)
#pragma unroll
        for (int y = 0; y < DIM; ++y) a[i * DIM * DIM + x * DIM + y] = r.m[x][y];
}
// The quadratic basis (src/physics/tlsph/gradient.rs): TL_Q = DIM + DIM (DIM + 1) / 2 functions of
// s = (X0_b - X0_a) / h: s_1 .. s_DIM, then s_i s_j for i <= j.
template <int DIM> struct TlBasis {
    static constexpr int Q = DIM + DIM * (DIM + 1) / 2;
    float p[Q];
};
template <int DIM> __device__ __forceinline__ TlBasis<DIM> tl_basis(const Vec<DIM>& s) {
    TlBasis<DIM> b;
    int k = DIM;
#pragma unroll
    for (int i = 0; i < DIM; ++i) {
        b.p[i] = s.c[i];
#pragma unroll
        for (int j = i; j < DIM; ++j) b.p[k++] = s.c[i] * s.c[j];
    }
    return b;
}
// C p: the sum of column m of solid a's block (TL_Q columns of DIM floats) times p_m
// (gradient.rs `apply`).
template <int DIM>
__device__ __forceinline__ Vec<DIM> tl_apply(const float* __restrict__ c, unsigned a, const TlBasis<DIM>& b) {
    constexpr int Q = TlBasis<DIM>::Q;
    Vec<DIM> out = vzero<DIM>();
#pragma unroll
    for (int m = 0; m < Q; ++m)
#pragma unroll
        for (int d = 0; d < DIM; ++d) out.c[d] += c[(a * Q + m) * DIM + d] * b.p[m];
    return out;
}
// Solid a's face basis sum F_a (src/physics/tlsph/mod.rs `Reference::face`) as a TlBasis.
template <int DIM> __device__ __forceinline__ TlBasis<DIM> tl_face(const float* __restrict__ face, unsigned a) {
    TlBasis<DIM> b;
#pragma unroll
    for (int m = 0; m < TlBasis<DIM>::Q; ++m) b.p[m] = face[a * TlBasis<DIM>::Q + m];
    return b;
}
// The clamp whose displacement a's face takes, NONE where a has none or the clamp is gone
// (src/physics/tlsph/mod.rs `clamp_of`, as the CPU's stages read it).
__device__ __forceinline__ unsigned tl_face_clamp(const unsigned* __restrict__ face_clamp,
                                                  const unsigned* __restrict__ slot, unsigned a) {
    const unsigned c = face_clamp[a];
    return c != MF_TL_NONE && slot[c] != MF_TL_NONE ? c : MF_TL_NONE;
}

// The pair's reference kernel weight w = -(dW/dr) / r [L^-d-2], W0 [L^-d] and the scaled
// separation s = (X0_b - X0_a) / h from x0ab = X0_a - X0_b, the minimum image (gradient.rs `pair`).
template <int DIM>
__device__ __forceinline__ Vec<DIM> tl_pair(const SphParams& p, const Vec<DIM>& x0ab, float& w, float& w0) {
    float f;
    kernel_wf(p, sqrtf(dot(x0ab, x0ab)), w0, f);
    w = -f;
    return (vzero<DIM>() - x0ab) * (1.0f / p.h);
}

// The elastic constants of the Saint Venant-Kirchhoff law (src/physics/tlsph/mod.rs `Material::of`):
// K = rho0_s c_s^2, mu = G, lambda = K - 2 G / 3, E = 9 K G / (3 K + G) [M L^-d L^2 T^-2].
__device__ __forceinline__ void tl_material(const SphParams& p, float& lambda, float& mu, float& young) {
    const float k = p.solid_rho0 * p.solid_c0 * p.solid_c0;
    const float g = p.shear_modulus;
    lambda = k - 2.0f * g / 3.0f;
    mu = g;
    young = 3.0f * k + g > 0.0f ? 9.0f * k * g / (3.0f * k + g) : 0.0f;
}

// slot[index[id[i]]] = i for every solid particle i of the storage (after each reorder).
// Slots of removed solids stay NONE (set at upload; the set of solids changes only there).
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
    sph_tl_slots(unsigned n, unsigned n_index, const unsigned* __restrict__ id, const unsigned char* __restrict__ kind,
                 const unsigned* __restrict__ index, unsigned* __restrict__ slot) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n || kind[i] != MF_KIND_SOLID) return;
    const unsigned q = id[i];
    if (q >= n_index) return;
    const unsigned a = index[q];
    if (a != MF_TL_NONE) slot[a] = i;
}

// The stress stage of solid a (src/backend/cpu/tlsph.rs `TlBodies::stress`): the displacement
// gradient H_a = sum_b (u_b - u_a) (x) g_ab, g_ab = V0_b w_ab C_a p(s_ab) [-] over the reference
// neighbours present (src/physics/tlsph/mod.rs `displacement_gradient`), the Saint Venant-Kirchhoff
// stress (src/physics/tlsph/mod.rs `svk`): Green strain E = (H + H^T + H^T H) / 2, S = lambda tr(E) I + 2 mu E, P = F S, J = det F; kept: H and (omega / V0) P C (quad: the energy's quadrature weight, src/physics/tlsph/quadrature.rs);
// written into a's slot: the deviator sigma + p I of the Cauchy stress sigma = J^-1 P F^T,
// p = -tr(sigma) / 3 (2D plane strain: + sigma_zz = J^-1 lambda tr(E)), into stress. The
// slot's density and pressure stay the continuity density's and its equation of state's,
// as a dynamic wall particle's: they are what the fluid meets at the interface (with the
// solid's own -p I in them, the fluid ran into the gate and squeezed the impinging bodies).
template <int DIM>
__device__ void sph_tl_stress_body(const SphParams p, unsigned n, unsigned n_solid, const unsigned* __restrict__ slot,
                                   const unsigned* __restrict__ start, const unsigned* __restrict__ nbr,
                                   const float* __restrict__ x0, const float* __restrict__ vol,
                                   const float* __restrict__ corr, const float* __restrict__ quad,
                                   const float* __restrict__ face, const unsigned* __restrict__ face_clamp,
                                   const float* __restrict__ disp,
                                   float* __restrict__ grad, float* __restrict__ pk1_corr,
                                   float* __restrict__ stress) {
    const unsigned a = blockIdx.x * blockDim.x + threadIdx.x;
    if (a >= n_solid) return;
    const unsigned i = slot[a];
    constexpr int Q = TlBasis<DIM>::Q;
    if (i == MF_TL_NONE) {
        tl_mstore<DIM>(grad, a, mzero<DIM>());
        for (int m = 0; m < Q * DIM; ++m) pk1_corr[a * Q * DIM + m] = 0.0f;
        return;
    }
    const Vec<DIM> ua = vload<DIM>(disp, a), xa = vload<DIM>(x0, a);
    Mat<DIM> h = mzero<DIM>();
    for (unsigned e = start[a], end = start[a + 1]; e < end; ++e) {
        const unsigned b = nbr[e];
        if (slot[b] == MF_TL_NONE) continue;
        float w, w0;
        const Vec<DIM> s = tl_pair<DIM>(p, separation<DIM>(p, xa, vload<DIM>(x0, b)), w, w0);
        const Vec<DIM> gw = tl_apply<DIM>(corr, a, tl_basis<DIM>(s)) * (vol[b] * w);
        const Vec<DIM> du = vload<DIM>(disp, b) - ua;
#pragma unroll
        for (int x = 0; x < DIM; ++x)
#pragma unroll
            for (int y = 0; y < DIM; ++y) h.m[x][y] += du.c[x] * gw.c[y];
    }
    // The clamp's face: + (u_clamp - u_a) (x) C_a F_a.
    const unsigned c = tl_face_clamp(face_clamp, slot, a);
    if (c != MF_TL_NONE) {
        const Vec<DIM> gw = tl_apply<DIM>(corr, a, tl_face<DIM>(face, a));
        const Vec<DIM> du = vload<DIM>(disp, c) - ua;
#pragma unroll
        for (int x = 0; x < DIM; ++x)
#pragma unroll
            for (int y = 0; y < DIM; ++y) h.m[x][y] += du.c[x] * gw.c[y];
    }
    // Saint Venant-Kirchhoff, as `svk`.
    float lambda, mu, young;
    tl_material(p, lambda, mu, young);
    const Mat<DIM> ht = transpose<DIM>(h);
    const Mat<DIM> hth = mat_mul<DIM>(ht, h);
    Mat<DIM> e, s, f;
#pragma unroll
    for (int x = 0; x < DIM; ++x)
#pragma unroll
        for (int y = 0; y < DIM; ++y) e.m[x][y] = (h.m[x][y] + ht.m[x][y] + hth.m[x][y]) * 0.5f;
    const float tr_e = trace<DIM>(e);
#pragma unroll
    for (int x = 0; x < DIM; ++x)
#pragma unroll
        for (int y = 0; y < DIM; ++y) {
            s.m[x][y] = (x == y ? lambda * tr_e : 0.0f) + e.m[x][y] * (2.0f * mu);
            f.m[x][y] = (x == y ? 1.0f : 0.0f) + h.m[x][y];
        }
    const Mat<DIM> pk1 = mat_mul<DIM>(f, s);
    const float inv_j = 1.0f / det<DIM>(f);
    Mat<DIM> sigma = mat_mul<DIM>(pk1, transpose<DIM>(f));
#pragma unroll
    for (int x = 0; x < DIM; ++x)
#pragma unroll
        for (int y = 0; y < DIM; ++y) sigma.m[x][y] *= inv_j;
    const float zz = DIM == 2 ? lambda * tr_e * inv_j : 0.0f;
    const float pressure = -(trace<DIM>(sigma) + zz) / 3.0f;
#pragma unroll
    for (int x = 0; x < DIM; ++x) sigma.m[x][x] += pressure;  // the deviator sigma + p I
    tl_mstore<DIM>(grad, a, h);
    // The energy's quadrature weight omega_a = quad_a V0_a (src/physics/tlsph/quadrature.rs): (omega / V0) P C.
    Mat<DIM> pkw = pk1;
#pragma unroll
    for (int x = 0; x < DIM; ++x)
#pragma unroll
        for (int y = 0; y < DIM; ++y) pkw.m[x][y] *= quad[a];
#pragma unroll
    for (int m = 0; m < Q; ++m) {
        Vec<DIM> c;
#pragma unroll
        for (int d = 0; d < DIM; ++d) c.c[d] = corr[(a * Q + m) * DIM + d];
        const Vec<DIM> pc = mat_vec<DIM>(pkw, c);
#pragma unroll
        for (int d = 0; d < DIM; ++d) pk1_corr[(a * Q + m) * DIM + d] = pc.c[d];
    }
    if (stress) sstore<DIM>(stress, i, n, sigma);
}
MF_ENTRY2(sph_tl_stress,
          (const SphParams p, unsigned n, unsigned n_solid, const unsigned* slot, const unsigned* start,
           const unsigned* nbr, const float* x0, const float* vol, const float* corr, const float* quad,
           const float* face, const unsigned* face_clamp, const float* disp, float* grad, float* pk1_corr,
           float* stress),
          (p, n, n_solid, slot, start, nbr, x0, vol, corr, quad, face, face_clamp, disp, grad, pk1_corr, stress))

// The internal force of solid a (src/backend/cpu/tlsph.rs `TlBodies::forces`), added to the
// force stage's acceleration of its slot [L/T^2]:
// acc_a += (1 / rho0_s) (sum_b V0_b w_ab [P_a C_a p(s_ab) - P_b C_b p(-s_ab)] + P_a C_a F_a) (F_a: the
// clamp's face, src/physics/tlsph/mod.rs `faces`; src/physics/tlsph/mod.rs:
// the derivative of the discrete strain energy; m_a dv_a/dt = sum_b V0_a V0_b w_ab [...],
// V0_a / m_a = 1 / rho0_s), plus Ganzenmueller 2015's
// hourglass control eq. (10) (src/physics/tlsph/mod.rs `hourglass`): with eps = (H_a + H_b) X0_ab - 2 u_ab,
// acc_a += (alpha / 2) (V0_b / rho0_s) W0_ab / |X0_ab|^2 E (eps . x_ab) x_ab / |x_ab|^2;
// and the same over a's face points m (b -> m, V0_m, u_m = u_clamp, x_am = X0_am + u_a - u_clamp,
// eps = 2 (u_clamp - u_fit(X0_m)), u_fit(X0_m) = u_a + sum_k r_k B_k: a's fit at the face point,
// src/backend/cpu/tlsph.rs `TlBodies::fit_sum`), which hold the root of a thin gate on the face.
// The hourglass term of one pair with the error eps of its separation (src/physics/tlsph/mod.rs `hourglass`).
template <int DIM>
__device__ __forceinline__ Vec<DIM> tl_hourglass(const SphParams& p, float young, float vb, float w0,
                                                 const Vec<DIM>& x0ab, const Vec<DIM>& xab, const Vec<DIM>& eps) {
    const float r0_2 = dot(x0ab, x0ab), r2 = dot(xab, xab);
    if (!(r0_2 > 0.0f && r2 > 0.0f)) return vzero<DIM>();
    const float k = 0.5f * p.hourglass * vb / p.solid_rho0 * w0 / r0_2 * young * dot(eps, xab) / r2;
    return xab * k;
}
// B_a = sum_b V0_b w_ab p(s_ab) (u_b - u_a) + F_a (u_c - u_a), the sum a's fit reads, as TL_Q
// vectors (src/backend/cpu/tlsph.rs `TlBodies::fit_sum`), and with it a's fit at the face point
// whose value weights are r (TL_Q floats): u_a + sum_k r_k B_k.
template <int DIM> struct TlFitSum {
    Vec<DIM> b[TlBasis<DIM>::Q];
};
template <int DIM>
__device__ TlFitSum<DIM> tl_fit_sum(const SphParams& p, unsigned a, const Vec<DIM>& ua, const Vec<DIM>& uc,
                                    const unsigned* __restrict__ slot, const unsigned* __restrict__ start,
                                    const unsigned* __restrict__ nbr, const float* __restrict__ x0,
                                    const float* __restrict__ vol, const float* __restrict__ face,
                                    const float* __restrict__ disp) {
    constexpr int Q = TlBasis<DIM>::Q;
    TlFitSum<DIM> f;
    const TlBasis<DIM> fa = tl_face<DIM>(face, a);
    const Vec<DIM> duc = uc - ua;
#pragma unroll
    for (int k = 0; k < Q; ++k) f.b[k] = duc * fa.p[k];
    const Vec<DIM> xa = vload<DIM>(x0, a);
    for (unsigned e = start[a], end = start[a + 1]; e < end; ++e) {
        const unsigned b = nbr[e];
        if (slot[b] == MF_TL_NONE) continue;
        float w, w0;
        const TlBasis<DIM> pb = tl_basis<DIM>(tl_pair<DIM>(p, separation<DIM>(p, xa, vload<DIM>(x0, b)), w, w0));
        const Vec<DIM> du = (vload<DIM>(disp, b) - ua) * (vol[b] * w);
#pragma unroll
        for (int k = 0; k < Q; ++k) f.b[k] = f.b[k] + du * pb.p[k];
    }
    return f;
}

// The internal force and hourglass of solid a in slot i, added to acc[i]; returns the new |acc[i]|.
template <int DIM>
__device__ __forceinline__ float tl_force_one(const SphParams& p, unsigned a, unsigned i, const unsigned* __restrict__ slot,
                                              const unsigned* __restrict__ start, const unsigned* __restrict__ nbr,
                                              const float* __restrict__ x0, const float* __restrict__ vol,
                                              const float* __restrict__ face, const unsigned* __restrict__ face_clamp,
                                              const unsigned* __restrict__ face_start,
                                              const float* __restrict__ face_pts, const float* __restrict__ disp,
                                              const float* __restrict__ grad, const float* __restrict__ pk1_corr,
                                              const float* __restrict__ pos, float* __restrict__ acc) {
    float lambda, mu, young;
    tl_material(p, lambda, mu, young);
    const Mat<DIM> ha = p.hourglass > 0.0f ? tl_mload<DIM>(grad, a) : mzero<DIM>();
    const Vec<DIM> ua = vload<DIM>(disp, a), xa = vload<DIM>(x0, a);
    const Vec<DIM> xi = p.hourglass > 0.0f ? vload<DIM>(pos, i) : vzero<DIM>();
    Vec<DIM> sum = vzero<DIM>();
    const unsigned c = tl_face_clamp(face_clamp, slot, a);
    if (c != MF_TL_NONE) {
        sum = sum + tl_apply<DIM>(pk1_corr, a, tl_face<DIM>(face, a)) * (1.0f / p.solid_rho0);
        if (p.hourglass > 0.0f) {
            constexpr int Q = TlBasis<DIM>::Q, FP = DIM + 1 + Q;
            const Vec<DIM> uc = vload<DIM>(disp, c);
            const TlFitSum<DIM> fs = tl_fit_sum<DIM>(p, a, ua, uc, slot, start, nbr, x0, vol, face, disp);
            for (unsigned e = face_start[a], end = face_start[a + 1]; e < end; ++e) {
                const float* m = face_pts + e * FP;
                Vec<DIM> xm, u_fit = ua;
#pragma unroll
                for (int d = 0; d < DIM; ++d) xm.c[d] = m[d];
#pragma unroll
                for (int k = 0; k < Q; ++k) u_fit = u_fit + fs.b[k] * m[DIM + 1 + k];
                const Vec<DIM> x0am = separation<DIM>(p, xa, xm);
                const float w0 = kernel_w(p, sqrtf(dot(x0am, x0am)));
                sum = sum + tl_hourglass<DIM>(p, young, m[DIM], w0, x0am, x0am + (ua - uc), (uc - u_fit) * 2.0f);
            }
        }
    }
    for (unsigned e = start[a], end = start[a + 1]; e < end; ++e) {
        const unsigned b = nbr[e];
        const unsigned j = slot[b];
        if (j == MF_TL_NONE) continue;
        const Vec<DIM> x0ab = separation<DIM>(p, xa, vload<DIM>(x0, b));
        float w, w0;
        const Vec<DIM> s = tl_pair<DIM>(p, x0ab, w, w0);
        const Vec<DIM> f = tl_apply<DIM>(pk1_corr, a, tl_basis<DIM>(s)) -
                           tl_apply<DIM>(pk1_corr, b, tl_basis<DIM>(vzero<DIM>() - s));
        const float vb = vol[b];
        sum = sum + f * (vb * w / p.solid_rho0);
        if (p.hourglass > 0.0f) {
            const Vec<DIM> xab = separation<DIM>(p, xi, vload<DIM>(pos, j));
            Mat<DIM> hs = tl_mload<DIM>(grad, b);
#pragma unroll
            for (int x = 0; x < DIM; ++x)
#pragma unroll
                for (int y = 0; y < DIM; ++y) hs.m[x][y] = ha.m[x][y] + hs.m[x][y];
            // eps = (H_a + H_b) X0_ab - 2 u_ab (src/physics/tlsph/mod.rs `pair_error`).
            const Vec<DIM> eps = mat_vec<DIM>(hs, x0ab) - (ua - vload<DIM>(disp, b)) * 2.0f;
            sum = sum + tl_hourglass<DIM>(p, young, vb, w0, x0ab, xab, eps);
        }
    }
    const Vec<DIM> out = vload<DIM>(acc, i) + sum;
    vstore<DIM>(acc, i, out);
    return sqrtf(dot(out, out));
}

template <int DIM>
__device__ void sph_tl_forces_body(const SphParams p, unsigned n_solid, const unsigned* __restrict__ slot,
                                   const unsigned* __restrict__ start, const unsigned* __restrict__ nbr,
                                   const float* __restrict__ x0, const float* __restrict__ vol,
                                   const float* __restrict__ face, const unsigned* __restrict__ face_clamp,
                                   const unsigned* __restrict__ face_start, const float* __restrict__ face_pts,
                                   const float* __restrict__ disp, const float* __restrict__ grad,
                                   const float* __restrict__ pk1_corr, const float* __restrict__ pos,
                                   float* __restrict__ acc, unsigned* __restrict__ red) {
    const unsigned a = blockIdx.x * blockDim.x + threadIdx.x;
    const unsigned i = a < n_solid ? slot[a] : MF_TL_NONE;
    float amax = 0.0f;
    if (i != MF_TL_NONE) {
        amax = tl_force_one<DIM>(p, a, i, slot, start, nbr, x0, vol, face, face_clamp, face_start, face_pts, disp, grad,
                                 pk1_corr, pos, acc);
        if (!owns_slot<DIM>(p, pos, i)) amax = 0.0f;  // a subdomain's halo copy: its owner's
    }
    // |a| into the step size's maximum (the forces pass left these particles out; twin:
    // reduce.rs `extremes` over the final accelerations); per warp, as ForceSum::finish.
    amax = warp_max(amax);
    if ((threadIdx.x & 31) == 0) atomicMax(&red[1], __float_as_uint(amax));
}
MF_ENTRY2(sph_tl_forces,
          (const SphParams p, unsigned n_solid, const unsigned* slot, const unsigned* start, const unsigned* nbr,
           const float* x0, const float* vol, const float* face, const unsigned* face_clamp,
           const unsigned* face_start, const float* face_pts, const float* disp, const float* grad,
           const float* pk1_corr, const float* pos, float* acc, unsigned* red),
          (p, n_solid, slot, start, nbr, x0, vol, face, face_clamp, face_start, face_pts, disp, grad, pk1_corr, pos, acc,
           red))

// The displacement's drift (src/backend/cpu/tlsph.rs `TlBodies::drift`): u += dt (v + xsph),
// or a driven object's move over the step (`driven_moved`), what sph_drift adds to the
// position (launched before it, so v is the velocity the drift takes: the new one in the
// symplectic Euler, the old one in sph_drift_kick, and pos the step's start; time[2] the
// step's start, from the kick) [L].
template <int DIM>
__device__ void sph_tl_drift_body(const SphParams p, unsigned n_solid, const float* __restrict__ dt_dev,
                                  const double* __restrict__ time, const unsigned* __restrict__ slot,
                                  const unsigned* __restrict__ group, const float* __restrict__ pos,
                                  const float* __restrict__ vel, const float* __restrict__ xsph,
                                  float* __restrict__ disp, const double* __restrict__ series) {
    const unsigned a = blockIdx.x * blockDim.x + threadIdx.x;
    if (a >= n_solid) return;
    const unsigned i = slot[a];
    if (i == MF_TL_NONE) return;
    const float dt = *dt_dev;
    Vec<DIM> du;
    if (const int dk = driven_index(p, group[i]); dk >= 0) {
        const Vec<DIM> x = vload<DIM>(pos, i);
        du = driven_moved<DIM>(p, series, dk, x, dt, time[2]) - x;
    } else {
        du = (vel_load<DIM>(vel, i) + vload<DIM>(xsph, i)) * dt;
    }
    vstore<DIM>(disp, a, vload<DIM>(disp, a) + du);
}
MF_ENTRY2(sph_tl_drift,
          (const SphParams p, unsigned n_solid, const float* dt_dev, const double* time, const unsigned* slot,
           const unsigned* group, const float* pos, const float* vel, const float* xsph, float* disp,
           const double* series),
          (p, n_solid, dt_dev, time, slot, group, pos, vel, xsph, disp, series))
