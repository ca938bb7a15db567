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

// The viewer's visibility splat (`SplatView` in viewer/src/device_fill.rs): the nearest
// sphere at each pixel of a width x height view, for the renderer's resolve pass, which
// shades it (shaders/splat.frag) where the sprites' pass would have ray-cast every sprite on
// the few SMs that run graphics. cam: 17 floats, the world-to-view rows (3 x 4), the pixel
// ray u_ray of sphere.glsl (a pixel centre (X, Y) looks along (X ray0 + ray1, Y ray2 + ray3,
// -1) in view space: perspective only) and the radius r [L].

// The least and greatest slope x / -z of the two lines from the eye that touch the circle
// of radius r about (x, z) (particle.vert's `slopes`); false where the eye is in the circle
// or a touching line does not point forward.
__device__ __forceinline__ bool splat_slopes(float x, float z, float r, float& lo, float& hi) {
    const float t2 = x * x + z * z - r * r;
    if (t2 <= 0.0f) return false;
    const float t = sqrtf(t2);
    const float ax = x * t - z * r, ay = x * r + z * t;
    const float bx = x * t + z * r, by = z * t - x * r;
    if (ay >= 0.0f || by >= 0.0f) return false;
    const float sa = ax / -ay, sb = bx / -by;
    lo = fminf(sa, sb);
    hi = fmaxf(sa, sb);
    return true;
}

// The pixels [p0, p1] whose centres' coordinate X has X ray_a + ray_b within [lo, hi],
// widened by a pixel each side for rounding, clipped to [0, size).
__device__ __forceinline__ void splat_span(float lo, float hi, float ray_a, float ray_b, unsigned size, int& p0,
                                           int& p1) {
    p0 = max(0, (int)floorf((lo - ray_b) / ray_a - 0.5f) - 1);
    p1 = min((int)size - 1, (int)ceilf((hi - ray_b) / ray_a - 0.5f) + 1);
}

// key[Y width + X] = the greatest ~((bits of the hit's view distance) << 32 | j) over the
// particles first <= j < first + n whose kind is not hidden (bit k of `hidden`) and whose sphere the pixel's
// ray hits (sphere.glsl's `sphere_hit`, the stable form): the nearest sphere; 0 where none
// (the caller zeroes key). A sphere that reaches the eye's plane is left out (the sprites'
// pass draws such views: the renderer splats only where every sprite is small).
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
sph_view_splat(unsigned first, unsigned n, const float* __restrict__ pos, const unsigned char* __restrict__ kind, unsigned hidden,
               const float* __restrict__ cam, unsigned width, unsigned height, unsigned long long* __restrict__ key) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const unsigned j = first + i;
    const unsigned char k = kind[j];
    if (k < 8 && ((hidden >> k) & 1u)) return;
    const float x = pos[3 * j], y = pos[3 * j + 1], z = pos[3 * j + 2];
    const float cx = cam[0] * x + cam[1] * y + cam[2] * z + cam[3];
    const float cy = cam[4] * x + cam[5] * y + cam[6] * z + cam[7];
    const float cz = cam[8] * x + cam[9] * y + cam[10] * z + cam[11];
    const float r = cam[16];
    float xlo, xhi, ylo, yhi;
    if (cz + r >= 0.0f || !splat_slopes(cx, cz, r, xlo, xhi) || !splat_slopes(cy, cz, r, ylo, yhi)) return;
    int x0, x1, y0, y1;
    splat_span(xlo, xhi, cam[12], cam[13], width, x0, x1);
    splat_span(ylo, yhi, cam[14], cam[15], height, y0, y1);
    for (int py = y0; py <= y1; ++py) {
        const float sy = (py + 0.5f) * cam[14] + cam[15];
        for (int px = x0; px <= x1; ++px) {
            const float sx = (px + 0.5f) * cam[12] + cam[13];
            const float il = rsqrtf(sx * sx + sy * sy + 1.0f);
            const float rx = sx * il, ry = sy * il, rz = -il;
            // oc = -c; b = rd . oc; q = oc - b rd; disc = r^2 - q . q
            const float b = -(rx * cx + ry * cy + rz * cz);
            const float qx = -cx - b * rx, qy = -cy - b * ry, qz = -cz - b * rz;
            const float disc = r * r - (qx * qx + qy * qy + qz * qz);
            if (disc < 0.0f) continue;
            const float t = -b - sqrtf(disc);
            const float dist = fmaxf(-t * rz, 0.0f);  // the hit's view distance -z
            const unsigned long long kk =
                ~(((unsigned long long)__float_as_uint(dist) << 32) | (unsigned long long)j);
            atomicMax(key + (size_t)py * width + px, kk);
        }
    }
}

// Per pixel p < pixels, from key (sph_view_splat): the nearest sphere's world centre and
// value in out4[p] (4 floats) and its kind in out_kind[p], or kind 255 where no sphere is.
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
sph_view_pixels(unsigned pixels, const unsigned long long* __restrict__ key, const float* __restrict__ pos,
                const float* __restrict__ val, const unsigned char* __restrict__ kind, float* __restrict__ out4,
                unsigned char* __restrict__ out_kind) {
    const unsigned p = blockIdx.x * blockDim.x + threadIdx.x;
    if (p >= pixels) return;
    const unsigned long long kk = key[p];
    if (kk == 0ull) {
        out_kind[p] = 255;
        return;
    }
    const unsigned j = (unsigned)~kk;
    reinterpret_cast<float4*>(out4)[p] = make_float4(pos[3 * j], pos[3 * j + 1], pos[3 * j + 2], val[j]);
    out_kind[p] = kind[j];
}
