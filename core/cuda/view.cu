// The viewer's vertex fill (CUDA-OpenGL interop): every particle's position, shown quantity
// and kind written straight into the renderer's vertex buffers (meshfree-viewer's layout:
// vec3 of f32, one f32, one u8 per particle) in the viewer's kind order (the fluid, then the
// solids, then the rest, each in storage order: `ParticleBuffers`), and the colour range
// reduced over the particles that set it. Twin: the host-copy path, `Solver::snapshot`
// (src/solver.rs, the CUDA backend's in src/backend/cuda/mod.rs), the viewer's upload
// (`Renderer::upload`, which orders the kinds alike) and `value_range`; test:
// app/tests/render_interop.rs.
#include "device/entries.cuh"
#include "device/packing.cuh"
#include "device/scan.cuh"
#include "device/vectors.cuh"

// A float's bits in an order that unsigned comparison keeps (negatives reversed); every
// float maps above 0, so a zeroed word is below them all.
__device__ __forceinline__ unsigned ordered_bits(float v) {
    const unsigned b = __float_as_uint(v);
    return (b >> 31) ? ~b : (b | 0x80000000u);
}

// Maximum over the warp (every lane must call; valid in every lane).
__device__ __forceinline__ unsigned warp_max_u(unsigned v) {
    for (int o = 16; o > 0; o >>= 1) v = max(v, __shfl_xor_sync(0xffffffffu, v, o));
    return v;
}

// mark_fluid[i] = 1 for a fluid particle, mark_solid[i] = 1 for a solid one (else 0), i < n:
// scanned (sph_scan_local, sph_scan_top), they rank each particle among its kind for the
// fill's kind order. mark_solid null: no solids (not marked).
extern "C" __global__ void sph_view_mark(unsigned n, const unsigned char* __restrict__ kind,
                                         unsigned* __restrict__ mark_fluid, unsigned* __restrict__ mark_solid) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const unsigned char k = kind[i];
    mark_fluid[i] = k == MF_KIND_FLUID;
    if (mark_solid) mark_solid[i] = k == MF_KIND_SOLID;
}

// Particle i's place in the kind order: the fluid first, then the n_solid solids, then every
// other kind, each in storage order; f_* and s_* the scans of sph_view_mark's marks (s_*
// null where n_solid = 0).
__device__ __forceinline__ unsigned kind_order_slot(unsigned i, unsigned char k, const unsigned* __restrict__ f_local,
                                                    const unsigned* __restrict__ f_bsum,
                                                    const unsigned* __restrict__ s_local,
                                                    const unsigned* __restrict__ s_bsum, unsigned n_fluid,
                                                    unsigned n_solid) {
    const unsigned f = compacted(f_local, f_bsum, i);
    const unsigned s = s_local ? compacted(s_local, s_bsum, i) : 0u;
    if (k == MF_KIND_FLUID) return f;
    if (k == MF_KIND_SOLID) return n_fluid + s;
    return n_fluid + n_solid + (i - f - s);
}

// out_pos: 3 floats per particle [L] (z = 0 in 2D); out_val: the quantity `shown`
// (MF_SHOWN_*), as the host path computes it (speed: sqrt of the sum of squares in the
// components' order, rounded alike: no contraction into fma); out_kind: the kind. range:
// two words, zeroed by the caller: range[0] = max of ~ordered_bits (the minimum), range[1]
// = max of ordered_bits (the maximum) over the finite values of particles that are neither
// boundary nor hidden (bit k of `hidden` hides kind k), as `value_range` takes them; with
// range == null nothing is reduced (a fixed range).
template <int DIM>
__device__ void sph_view_fill_body(const SphParams p, unsigned n, unsigned shown, unsigned hidden,
                                   const float* __restrict__ pos, const float* __restrict__ vel,
                                   const float* __restrict__ rho, const float* __restrict__ pr,
                                   const unsigned char* __restrict__ kind, float* __restrict__ out_pos,
                                   float* __restrict__ out_val, unsigned char* __restrict__ out_kind,
                                   unsigned* __restrict__ range, const unsigned* __restrict__ f_local,
                                   const unsigned* __restrict__ f_bsum, const unsigned* __restrict__ s_local,
                                   const unsigned* __restrict__ s_bsum, unsigned n_fluid, unsigned n_solid) {
    (void)p;
    __shared__ unsigned sh[2];
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (range && threadIdx.x == 0) sh[0] = sh[1] = 0u;
    unsigned lo = 0u, hi = 0u;
    if (i < n) {
        const unsigned char k = kind[i];
        const size_t j = kind_order_slot(i, k, f_local, f_bsum, s_local, s_bsum, n_fluid, n_solid);
        const Vec<DIM> x = vload<DIM>(pos, i);
        out_pos[3 * j] = x.c[0];
        out_pos[3 * j + 1] = x.c[1];
        float z = 0.0f;
        if constexpr (DIM == 3) z = x.c[2];
        out_pos[3 * j + 2] = z;
        float v;
        if (shown == MF_SHOWN_SPEED) {
            const Vec<DIM> u = vel_load<DIM>(vel, i);
            float s = 0.0f;
            for (int a = 0; a < DIM; ++a) s = __fadd_rn(s, __fmul_rn(u.c[a], u.c[a]));
            v = sqrtf(s);
        } else if (shown == MF_SHOWN_PRESSURE) {
            v = pr[i];
        } else if (shown == MF_SHOWN_DENSITY) {
            v = rho[i];
        } else {
            v = (float)k;
        }
        out_val[j] = v;
        out_kind[j] = k;
        if (k != MF_KIND_BOUNDARY && !((hidden >> k) & 1u) && isfinite(v)) {
            hi = ordered_bits(v);
            lo = ~hi;
        }
    }
    if (!range) return;
    lo = warp_max_u(lo);
    hi = warp_max_u(hi);
    __syncthreads();
    if ((threadIdx.x & 31) == 0 && hi != 0u) {
        atomicMax(&sh[0], lo);
        atomicMax(&sh[1], hi);
    }
    __syncthreads();
    if (threadIdx.x == 0 && sh[1] != 0u) {
        atomicMax(&range[0], sh[0]);
        atomicMax(&range[1], sh[1]);
    }
}

MF_ENTRY2(sph_view_fill,
          (const SphParams p, unsigned n, unsigned shown, unsigned hidden, const float* __restrict__ pos,
           const float* __restrict__ vel, const float* __restrict__ rho, const float* __restrict__ pr,
           const unsigned char* __restrict__ kind, float* __restrict__ out_pos, float* __restrict__ out_val,
           unsigned char* __restrict__ out_kind, unsigned* __restrict__ range, const unsigned* __restrict__ f_local,
           const unsigned* __restrict__ f_bsum, const unsigned* __restrict__ s_local,
           const unsigned* __restrict__ s_bsum, unsigned n_fluid, unsigned n_solid),
          (p, n, shown, hidden, pos, vel, rho, pr, kind, out_pos, out_val, out_kind, range, f_local, f_bsum, s_local,
           s_bsum, n_fluid, n_solid))
