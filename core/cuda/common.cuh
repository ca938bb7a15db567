// Shared device code: kernels W and F (twin of src/kernel.rs), vectors and tensors for
// DIM = 2/3, the neighbour rows and loop (twin of src/backend/cpu/grid.rs), min-image
// separation, the `Neighbour` record the pair sums of forces and rates take, and the fast
// division and norm of the pair terms.
// Parity test: tests/cuda_parity.rs.
#pragma once
#include "sph_consts.h"
#include "sph_params.h"

// Positions, velocities, accelerations: float2 in 2D, float4 (w unused) in 3D, so one
// aligned load per particle; the layout is glam's Vec2 / Vec3A.
template <int DIM> struct VS { static constexpr int S = DIM == 2 ? 2 : 4; };

template <int DIM> struct Vec { float c[DIM]; };

template <int DIM> __device__ __forceinline__ Vec<DIM> vload(const float* a, unsigned i) {
    Vec<DIM> v;
    if constexpr (DIM == 2) {
        float2 t = reinterpret_cast<const float2*>(a)[i];
        v.c[0] = t.x; v.c[1] = t.y;
    } else {
        float4 t = reinterpret_cast<const float4*>(a)[i];
        v.c[0] = t.x; v.c[1] = t.y; v.c[2] = t.z;
    }
    return v;
}
template <int DIM> __device__ __forceinline__ void vstore(float* a, unsigned i, Vec<DIM> v) {
    if constexpr (DIM == 2) {
        reinterpret_cast<float2*>(a)[i] = make_float2(v.c[0], v.c[1]);
    } else {
        reinterpret_cast<float4*>(a)[i] = make_float4(v.c[0], v.c[1], v.c[2], 0.0f);
    }
}
// Velocities are float4 in both dimensions and carry per-particle scalars in their spare
// slots (twin: `flat_vel` in src/backend/cuda/buffers.rs), so that the neighbour loops read a
// neighbour's mass, density and (fluid-only scenes) kind from the vectors they load anyway
// instead of three more arrays: vel.w = rho, negated on boundary particles (written by the
// density pass and at upload, kept by the kick); the mass m (constant: written at upload,
// kept by the kick, the drift and the grid's reorder) is pos.w in 3D and vel.z in 2D (whose
// positions stay float2: the candidate test loads them, most candidates are rejected). The
// mass has no array of its own on the device (mass_of); the density's reference is rho[].
// vel.w of a particle of kind k and density rho.
__device__ __forceinline__ float vel_w(unsigned char k, float rho) { return k == MF_KIND_BOUNDARY ? -rho : rho; }
// Tait eq. (9) for fluid and dynamic wall particles; P = c_s^2 (rho - rho0_s) for solids
// (Gray & Monaghan 2001); 0 for the paper's walls.
// [P] from rho [M/L^3]; the density pass and the continuity scheme's reorder (grid.cu).
__device__ __forceinline__ float pressure(const SphParams& p, unsigned char kind, float rho) {
    if (kind == MF_KIND_SOLID) return p.solid_c0 * p.solid_c0 * (rho - p.solid_rho0);
    // eq. (9) plus the background pressure (cpu/density.rs `pressure`).
    if (kind == MF_KIND_FLUID || p.wall_pressure != 0)
        return p.tait_b * (powf(rho / p.rho0, p.tait_gamma) - 1.0f) + p.p_background;
    return 0.0f;
}

// Whether vel.w marks a boundary particle (the sign bit: -0.0 counts).
__device__ __forceinline__ bool vel_w_boundary(float w) { return (__float_as_uint(w) >> 31) != 0; }
// Store the DIM components of v, keeping the w slot of a 3D vector (positions).
template <int DIM> __device__ __forceinline__ void vstore_keep_w(float* a, unsigned i, Vec<DIM> v) {
    if constexpr (DIM == 2) {
        vstore<DIM>(a, i, v);
    } else {
        float4* q = reinterpret_cast<float4*>(a);
        q[i] = make_float4(v.c[0], v.c[1], v.c[2], q[i].w);
    }
}
// Load the DIM components and the w slot (0 in 2D) of a position.
template <int DIM> __device__ __forceinline__ Vec<DIM> vload_w(const float* a, unsigned i, float& w) {
    if constexpr (DIM == 2) {
        w = 0.0f;
        return vload<DIM>(a, i);
    } else {
        const float4 t = reinterpret_cast<const float4*>(a)[i];
        w = t.w;
        Vec<DIM> v;
        v.c[0] = t.x; v.c[1] = t.y; v.c[2] = t.z;
        return v;
    }
}
// Particle i's mass [M]: pos.w in 3D, vel.z in 2D (see above).
template <int DIM>
__device__ __forceinline__ float mass_of(const float* __restrict__ pos, const float* __restrict__ vel, unsigned i) {
    if constexpr (DIM == 3) return reinterpret_cast<const float4*>(pos)[i].w;
    else return reinterpret_cast<const float4*>(vel)[i].z;
}
// Velocity i (float4 in both dimensions), its w slot in w and, in 2D, the mass (vel.z) in m.
template <int DIM> __device__ __forceinline__ Vec<DIM> vel_load(const float* v, unsigned i, float& m, float& w) {
    const float4 t = reinterpret_cast<const float4*>(v)[i];
    Vec<DIM> r;
    r.c[0] = t.x; r.c[1] = t.y;
    if constexpr (DIM == 3) r.c[2] = t.z;
    m = t.z;  // the mass in 2D only
    w = t.w;
    return r;
}
template <int DIM> __device__ __forceinline__ Vec<DIM> vel_load(const float* v, unsigned i) {
    float m, w;
    return vel_load<DIM>(v, i, m, w);
}
// Store velocity i, keeping the scalars in its spare slots (2D: only the first half is written).
template <int DIM> __device__ __forceinline__ void vel_store(float* v, unsigned i, Vec<DIM> u) {
    if constexpr (DIM == 2) {
        reinterpret_cast<float2*>(v)[2 * i] = make_float2(u.c[0], u.c[1]);
    } else {
        vstore_keep_w<DIM>(v, i, u);
    }
}

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
// Symmetric storage: 2D (xx, yy, xy); 3D (xx, yy, zz, xy, xz, yz); component k of slot i
// at a[k * n + i].
template <int DIM> struct Sym { static constexpr int N = DIM == 2 ? 3 : 6; };
template <int DIM> __device__ __forceinline__ Mat<DIM> sload(const float* a, unsigned i, unsigned n) {
    Mat<DIM> r;
    if constexpr (DIM == 2) {
        r.m[0][0] = a[i]; r.m[1][1] = a[n + i];
        r.m[0][1] = r.m[1][0] = a[2 * n + i];
    } else {
        r.m[0][0] = a[i]; r.m[1][1] = a[n + i]; r.m[2][2] = a[2 * n + i];
        r.m[0][1] = r.m[1][0] = a[3 * n + i];
        r.m[0][2] = r.m[2][0] = a[4 * n + i];
        r.m[1][2] = r.m[2][1] = a[5 * n + i];
    }
    return r;
}
template <int DIM> __device__ __forceinline__ void sstore(float* a, unsigned i, unsigned n, const Mat<DIM>& r) {
    if constexpr (DIM == 2) {
        a[i] = r.m[0][0]; a[n + i] = r.m[1][1];
        a[2 * n + i] = 0.5f * (r.m[0][1] + r.m[1][0]);
    } else {
        a[i] = r.m[0][0]; a[n + i] = r.m[1][1]; a[2 * n + i] = r.m[2][2];
        a[3 * n + i] = 0.5f * (r.m[0][1] + r.m[1][0]);
        a[4 * n + i] = 0.5f * (r.m[0][2] + r.m[2][0]);
        a[5 * n + i] = 0.5f * (r.m[1][2] + r.m[2][1]);
    }
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

// ---- kernels: twin of src/kernel.rs ----
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
// W(r, h) [L^-d] alone (the gradient's arithmetic is dead code here and compiled out).
__device__ __forceinline__ float kernel_w(const SphParams& p, float r) {
    float w, f;
    kernel_wf(p, r, w, f);
    return w;
}

// The neighbour's kind: in fluid-only scenes from the sign of its vel.w, else from the kind
// array.
template <int DIM, bool SOLIDS>
__device__ __forceinline__ unsigned char neighbour_kind(const unsigned char* __restrict__ kind, unsigned j, float vw) {
    if constexpr (!SOLIDS)
        return vel_w_boundary(vw) ? (unsigned char)MF_KIND_BOUNDARY : (unsigned char)MF_KIND_FLUID;
    else
        return kind[j];
}

// A neighbour j of particle i as the pair sums (ForceSum in forces.cuh, RateSum in
// rates.cuh) take it: loaded and its kernel gradient computed once, whichever sums run.
template <int DIM> struct Neighbour {
    unsigned j;
    unsigned char kind;
    Vec<DIM> r;    // x_i - x_j (minimum image) [L]
    float r2, rr;  // |r|^2 [L^2], |r| [L]
    float fw;      // (dW/dr)/r at |r| (kernel_wf): grad_i W_ij = fw r [L^-(d+2)]
    float w;       // W_ij [L^-d]
    Vec<DIM> v;    // v_j [L/T]
    float m, rho;  // m_j [M], rho_j [M L^-d]
};
// j at r = x_i - x_j (r2 = |r|^2), pw the w slot of its stored position (3D: m_j): v_j,
// m_j, rho_j and (fluid-only scenes) the kind from the spare slots of its position and
// velocity (see vel_load), else the kind array.
template <int DIM, bool SOLIDS>
__device__ __forceinline__ Neighbour<DIM> neighbour(const SphParams& p, unsigned j, Vec<DIM> r, float r2, float pw,
                                                    const float* __restrict__ vel,
                                                    const unsigned char* __restrict__ kind) {
    Neighbour<DIM> nb;
    float vm, vw;
    nb.j = j;
    nb.r = r;
    nb.r2 = r2;
    nb.v = vel_load<DIM>(vel, j, vm, vw);
    nb.kind = neighbour_kind<DIM, SOLIDS>(kind, j, vw);
    nb.rr = fast_norm(r2);
    kernel_wf(p, nb.rr, nb.w, nb.fw);
    nb.m = DIM == 3 ? pw : vm;
    nb.rho = fabsf(vw);
    return nb;
}

__device__ __forceinline__ float sound_speed(const SphParams& p, unsigned char kind) {
    if (kind == MF_KIND_SOLID)
        return sqrtf(p.solid_c0 * p.solid_c0 +
                     4.0f / 3.0f * p.shear_modulus / fmaxf(p.solid_rho0, 1.17549435e-38f));
    return p.c0;
}
__device__ __forceinline__ float rest_density(const SphParams& p, unsigned char kind) {
    return kind == MF_KIND_SOLID ? p.solid_rho0 : p.rho0;
}

// Whether particle j of kind kj enters the sums of a non-boundary particle.
__device__ __forceinline__ bool couples(const SphParams& p, unsigned char kj) {
    return kj != MF_KIND_BOUNDARY || p.wall_pressure != 0;
}
// Whether particles of kinds ki and kj meet at all: a solid and a wall particle skip each
// other, both ways, where the scene says so (solid_skips_walls): no Lennard-Jones force, no
// wall pressure, no density sum over the other (twin: `meets` in cpu/density.rs).
__device__ __forceinline__ bool meets(const SphParams& p, unsigned char ki, unsigned char kj) {
    return p.solid_skips_walls == 0 || !((ki == MF_KIND_SOLID && kj == MF_KIND_BOUNDARY) ||
                                         (ki == MF_KIND_BOUNDARY && kj == MF_KIND_SOLID));
}

// The driven group (a piston, a clamp; any kind): moves at driven_velocity whatever the
// forces (twin: `driven_velocity` in cpu/integrate.rs).
__device__ __forceinline__ bool is_driven(const SphParams& p, unsigned group) {
    return p.driven != 0 && group == (unsigned)p.driven_group;
}
// Whether i and j count as one body for XSPH (eq. 18), the velocity gradient (eq. 15) and
// the artificial stress: all fluid; one solid group; and a driven solid (a clamp) bonded to
// every solid it neighbours, so the held part passes stress into the body it holds
// (twin: `same_body` in cpu/density.rs).
__device__ __forceinline__ bool same_body(const SphParams& p, unsigned char ki, unsigned char kj, unsigned gi,
                                          unsigned gj) {
    return kj == ki &&
           (ki == MF_KIND_FLUID || gi == gj || (ki == MF_KIND_SOLID && (is_driven(p, gi) || is_driven(p, gj))));
}

// ---- grid: twin of src/backend/cpu/grid.rs ----
template <int DIM> __device__ __forceinline__ void cell_coords(const SphParams& p, Vec<DIM> x, int c[3]) {
    c[0] = c[1] = c[2] = 0;
#pragma unroll
    for (int a = 0; a < DIM; ++a) {
        int v = (int)floorf((x.c[a] - p.domain_min[a]) / p.cell_size[a]);
        c[a] = min(max(v, 0), p.grid_dims[a] - 1);
    }
}
__device__ __forceinline__ unsigned cell_index(const SphParams& p, const int c[3]) {
    return (unsigned)(c[0] + p.grid_dims[0] * (c[1] + p.grid_dims[1] * c[2]));
}
// The grid build's first step for particle i at x (grid.cu): its cell, counted. The drift
// does it for the next build, from the positions it writes (`Buffers::hist_done`).
template <int DIM>
__device__ __forceinline__ void hist_one(const SphParams& p, unsigned i, Vec<DIM> x, unsigned* __restrict__ cell,
                                         unsigned* __restrict__ count) {
    int c[3];
    cell_coords<DIM>(p, x, c);
    const unsigned k = cell_index(p, c);
    cell[i] = k;
    atomicAdd(&count[k], 1u);
}
// Minimum-image r_i - r_j on periodic axes; PERIODIC = false: the scene has none (the
// neighbour loops test that once, not per candidate: see neighbour_loop).
template <int DIM, bool PERIODIC = true>
__device__ __forceinline__ Vec<DIM> separation(const SphParams& p, Vec<DIM> xi, Vec<DIM> xj) {
    Vec<DIM> r = xi - xj;
    if constexpr (PERIODIC) {
#pragma unroll
        for (int a = 0; a < DIM; ++a) {
            if (p.periodic[a]) {
                float len = p.domain_max[a] - p.domain_min[a];
                float d = r.c[a];
                if (d > 0.5f * len) r.c[a] = d - len;
                else if (d < -0.5f * len) r.c[a] = d + len;
            }
        }
    }
    return r;
}

// Squared distance from coordinate x to the slab of (unwrapped) cell c on axis a.
__device__ __forceinline__ float slab_gap2(const SphParams& p, int a, int c, float x) {
    const float lo = p.domain_min[a] + (float)c * p.cell_size[a];
    const float g = fmaxf(fmaxf(lo - x, x - (lo + p.cell_size[a])), 0.0f);
    return g * g;
}

// The neighbour candidates of xi as rows of cells: for each (z, y) cell offset within
// MF_CELL_REACH (z outer, then y), skipping rows whose slab lies beyond the support, calls
// row(first cell index of the row, x0, x1) with the x cells x0..x1 (unwrapped on a periodic
// x axis) that the support's cross-section at that row reaches. Twin of `rows` in
// src/backend/cpu/grid.rs: same candidates, same order. `plane_rows` visits the rows of one
// z offset dz (ci: the cell of xi, from cell_coords).
template <int DIM, class R>
__device__ __forceinline__ void plane_rows(const SphParams& p, Vec<DIM> xi, const int ci[3], int dz, R&& row) {
    const int reach = MF_CELL_REACH;
    const int nx = p.grid_dims[0];
    const float r2max = p.support2;
    int cz = ci[2] + dz;
    if (cz < 0 || cz >= p.grid_dims[2]) {
        if (!p.periodic[2]) return;
        cz = (cz + p.grid_dims[2]) % p.grid_dims[2];
    }
    float gz = 0.0f;
    if constexpr (DIM == 3) gz = slab_gap2(p, 2, ci[2] + dz, xi.c[2]);
    for (int dy = -reach; dy <= reach; ++dy) {
        int cy = ci[1] + dy;
        if (cy < 0 || cy >= p.grid_dims[1]) {
            if (!p.periodic[1]) continue;
            cy = (cy + p.grid_dims[1]) % p.grid_dims[1];
        }
        const float d2 = gz + slab_gap2(p, 1, ci[1] + dy, xi.c[1]);
        if (d2 > r2max * (1.0f + MF_PRUNE_SLACK)) continue;
        // Half-width of the support's cross-section at this row, then the x cells it spans.
        const float w = sqrtf(fmaxf(r2max - d2, 0.0f)) + MF_PRUNE_SLACK * p.support;
        int x0 = max(ci[0] - reach, (int)floorf((xi.c[0] - w - p.domain_min[0]) / p.cell_size[0]));
        int x1 = min(ci[0] + reach, (int)floorf((xi.c[0] + w - p.domain_min[0]) / p.cell_size[0]));
        if (!p.periodic[0]) {
            x0 = max(x0, 0);
            x1 = min(x1, nx - 1);
        }
        if (x0 > x1) continue;
        row((unsigned)(nx * (cy + p.grid_dims[1] * cz)), x0, x1);
    }
}
template <int DIM, class R> __device__ __forceinline__ void rows(const SphParams& p, Vec<DIM> xi, R&& row) {
    int ci[3];
    cell_coords<DIM>(p, xi, ci);
    const int rz = DIM == 3 ? MF_CELL_REACH : 0;
    for (int dz = -rz; dz <= rz; ++dz) plane_rows<DIM>(p, xi, ci, dz, row);
}

// The candidate ranges of one row (see `rows`): a row that does not wrap around a periodic x
// axis is one contiguous range of storage (cells are x-fastest and the storage is sorted by
// cell); a wrapping row is taken cell by cell, in the same order. Calls range(s, e) for each.
template <class F>
__device__ __forceinline__ void row_ranges(const SphParams& p, const unsigned* __restrict__ cell_start,
                                           unsigned row, int x0, int x1, F&& range) {
    const int nx = p.grid_dims[0];
    if (x0 >= 0 && x1 < nx) {
        range(cell_start[row + x0], cell_start[row + x1 + 1]);
        return;
    }
    for (int cx = x0; cx <= x1; ++cx) {
        const unsigned c = row + (unsigned)((cx + nx) % nx);
        range(cell_start[c], cell_start[c + 1]);
    }
}

// Candidates s + lane, s + lane + L, ... < e in batches of B: the B position loads issued
// before any is used (in flight together), then accept(j) for the accepted ones
// (|x_i - x_j| < support) in candidate order.
template <int DIM, int L, int B, bool PERIODIC, class F>
__device__ __forceinline__ void batch_accept(const SphParams& p, const float* __restrict__ pos, Vec<DIM> xi,
                                             unsigned s, unsigned e, int lane, F&& accept) {
    for (unsigned base = s + lane; base < e; base += B * L) {
        Vec<DIM> xj[B];
#pragma unroll
        for (int k = 0; k < B; ++k) xj[k] = vload<DIM>(pos, min(base + k * L, e - 1));
        unsigned mask = 0;
#pragma unroll
        for (int k = 0; k < B; ++k) {
            const Vec<DIM> r = separation<DIM, PERIODIC>(p, xi, xj[k]);
            if (base + k * L < e && dot(r, r) < p.support2) mask |= 1u << k;
        }
        while (mask) {
            const int k = __ffs(mask) - 1;
            mask &= mask - 1;
            accept(base + k * L);
        }
    }
}

// f(j, r_ij, r_ij^2, w_j) for candidate j, which passed the support test.
template <int DIM, bool PERIODIC, class F>
__device__ __forceinline__ void call_neighbour(const SphParams& p, const float* __restrict__ pos, Vec<DIM> xi,
                                               unsigned j, F&& f) {
    float wj;
    const Vec<DIM> r = separation<DIM, PERIODIC>(p, xi, vload_w<DIM>(pos, j, wj));
    f(j, r, dot(r, r), wj);
}

// The schemes of the forces and rates kernels, for one lane count L: ENTRY(entry name, DIM,
// SOLIDS, EXTRAS, L) for `name_L_{2,3}d` (with solids), `name_fluid_L_{2,3}d` (fluid-only)
// and `name_lean_L_{2,3}d` (fluid-only without the optional terms: params::lean_scheme).
#define MF_SCHEMES(ENTRY, name, L)                       \
    ENTRY(name##_##L##_2d, 2, true, true, L)             \
    ENTRY(name##_##L##_3d, 3, true, true, L)             \
    ENTRY(name##_fluid_##L##_2d, 2, false, true, L)      \
    ENTRY(name##_fluid_##L##_3d, 3, false, true, L)      \
    ENTRY(name##_lean_##L##_2d, 2, false, false, L)      \
    ENTRY(name##_lean_##L##_3d, 3, false, false, L)

// Candidates per batch in the neighbour loops (batch_accept, queued_neighbours): their
// position loads are in flight together. 4 (H100, 4M, docs/performance.md, session 7: with
// the queue, 8 spilled the batch at 64 registers and was 24 % slower in 3D, 2 was 1.5 %
// slower).
#ifndef MF_NB_BATCH
#define MF_NB_BATCH 4
#endif
// Blocks of MF_BLOCK per SM that the fluid-only forces, rates and fused kernels are bounded
// to (4: 64 registers; 3 was slower, session 7).
#ifndef MF_FLUID_BLOCKS
#define MF_FLUID_BLOCKS 4
#endif

// Calls f(j, r_ij, r_ij^2, w_j) for every j (i included) within the support of xi (w_j: the
// w slot of j's stored position, its mass in 3D; 0 in 2D), the candidates of `rows` split
// over L lanes (lane l takes every L-th), in candidate order.
template <int DIM, int L, int B = MF_NB_BATCH, bool PERIODIC = true, class F>
__device__ __forceinline__ void for_each_neighbor_split(const SphParams& p, const unsigned* __restrict__ cell_start,
                                                        const float* __restrict__ pos, Vec<DIM> xi, int lane,
                                                        F&& f) {
    rows<DIM>(p, xi, [&](unsigned row, int x0, int x1) {
        row_ranges(p, cell_start, row, x0, x1, [&](unsigned s, unsigned e) {
            batch_accept<DIM, L, B, PERIODIC>(p, pos, xi, s, e, lane,
                                              [&](unsigned j) { call_neighbour<DIM, PERIODIC>(p, pos, xi, j, f); });
        });
    });
}

// The accepted-candidate queue of the one-lane neighbour loop (queued_neighbours): up to
// MF_QUEUE entries (first candidate, mask of the accepted ones among the 32 from there) per
// thread in shared memory, entry e of thread t at [e * MF_BLOCK + t]; MF_QUEUE 0: no queue
// (batch_accept's pair sums after each batch). 8 entries of 8 B: 16 KB per block of 256; more
// takes L1 cache from the candidate loads and was slower (docs/performance.md, session 7).
#ifndef MF_QUEUE
#define MF_QUEUE 8
#endif

// The one-lane neighbour loop in two phases per plane of rows, for the pair sums' SIMT
// efficiency: the lanes of a warp accept different numbers of candidates from each batch
// and row, and a warp runs a pair sum while any lane has one, so summing after each batch
// (batch_accept) runs the sum for the maximum over the lanes of every batch. Here the
// candidates of one plane of rows (one z offset; 2D: all rows) are only tested (B position
// loads in flight, as batch_accept), each chunk of 32 consecutive candidates with an accepted
// one leaving (first, mask) in the queue q; then one loop takes one accepted neighbour per
// pass, from whichever entry the lane is at, so that the warp runs the pair sum for the
// maximum over the lanes of their plane totals. A plane with more than MF_QUEUE such chunks
// (a dense cluster) is tested again from its next unqueued chunk after each drain, so that
// the fill and the pair sum each stay one site in the code (a second copy of the inlined
// pair sum cost registers). Same neighbours, same order as for_each_neighbor_split with
// L = 1: the same results bit for bit.
template <int DIM, int B, bool PERIODIC, class F>
__device__ __forceinline__ void queued_neighbours(const SphParams& p, const unsigned* __restrict__ cell_start,
                                                  const float* __restrict__ pos, Vec<DIM> xi, uint2* q, F&& f) {
    static_assert(32 % B == 0, "batches must tile the 32-candidate chunks");
    const unsigned t = threadIdx.x;
    int ci[3];
    cell_coords<DIM>(p, xi, ci);
    const int rz = DIM == 3 ? MF_CELL_REACH : 0;
    for (int dz = -rz; dz <= rz; ++dz) {
        for (int skip = 0;; skip += MF_QUEUE) {
            int seen = 0;  // chunks with an accepted candidate, this pass
            plane_rows<DIM>(p, xi, ci, dz, [&](unsigned row, int x0, int x1) {
                row_ranges(p, cell_start, row, x0, x1, [&](unsigned s, unsigned e) {
                    for (unsigned c = s; c < e; c += 32) {
                        unsigned mask = 0;
                        // batch_accept's test, written out: sharing it through a helper
                        // returning the batch's mask (shifted by b here) compiled 1 % slower
                        // at 4M in 2D and 3D (H100, session 7).
                        for (int b = 0; b < 32 && c + b < e; b += B) {
                            const unsigned base = c + (unsigned)b;
                            Vec<DIM> xj[B];
#pragma unroll
                            for (int k = 0; k < B; ++k) xj[k] = vload<DIM>(pos, min(base + k, e - 1));
#pragma unroll
                            for (int k = 0; k < B; ++k) {
                                const Vec<DIM> r = separation<DIM, PERIODIC>(p, xi, xj[k]);
                                if (base + k < e && dot(r, r) < p.support2) mask |= 1u << (b + k);
                            }
                        }
                        if (mask == 0u) continue;
                        const int slot = seen - skip;
                        if (slot >= 0 && slot < MF_QUEUE) q[slot * MF_BLOCK + t] = make_uint2(c, mask);
                        ++seen;
                    }
                });
            });
            const int ne = min(seen - skip, MF_QUEUE);
            // Next accepted neighbour: a short loop over empty-handed entries, then the sum.
            int k = 0;
            uint2 en = ne > 0 ? q[t] : make_uint2(0u, 0u);
            for (;;) {
                while (en.y == 0u && ++k < ne) en = q[k * MF_BLOCK + t];
                if (en.y == 0u) break;
                const int bit = __ffs(en.y) - 1;
                en.y &= en.y - 1u;
                call_neighbour<DIM, PERIODIC>(p, pos, xi, en.x + (unsigned)bit, f);
            }
            if (seen - skip <= MF_QUEUE) break;
        }
    }
}

// The neighbour loop of the forces and rates kernels (for_each_neighbor_split, or
// queued_neighbours for one lane), with the minimum image compiled in only where the scene
// has a periodic axis: tested once here, not per candidate. on: whether this lane sums for
// particle i.
template <int DIM, int L, class F>
__device__ __forceinline__ void neighbour_loop(const SphParams& p, const unsigned* __restrict__ cell_start,
                                               const float* __restrict__ pos, unsigned i, bool on, int lane,
                                               F&& f) {
#if MF_QUEUE > 0
    if constexpr (L == 1) {
        __shared__ uint2 q[MF_QUEUE * MF_BLOCK];
        if (!on) return;
        if (p.periodic[0] || p.periodic[1] || p.periodic[2])
            queued_neighbours<DIM, MF_NB_BATCH, true>(p, cell_start, pos, vload<DIM>(pos, i), q, f);
        else
            queued_neighbours<DIM, MF_NB_BATCH, false>(p, cell_start, pos, vload<DIM>(pos, i), q, f);
        return;
    }
#endif
    if (!on) return;
    if (p.periodic[0] || p.periodic[1] || p.periodic[2])
        for_each_neighbor_split<DIM, L, MF_NB_BATCH, true>(p, cell_start, pos, vload<DIM>(pos, i), lane, f);
    else
        for_each_neighbor_split<DIM, L, MF_NB_BATCH, false>(p, cell_start, pos, vload<DIM>(pos, i), lane, f);
}

// Sum over the L lanes of a particle (all 32 lanes of the warp must call).
template <int L> __device__ __forceinline__ float lane_sum(float v) {
#pragma unroll
    for (int o = L / 2; o > 0; o >>= 1) v += __shfl_xor_sync(0xffffffffu, v, o);
    return v;
}

// Maximum over the warp (every lane must call; valid in every lane).
__device__ __forceinline__ float warp_max(float v) {
    for (int o = 16; o > 0; o >>= 1) v = fmaxf(v, __shfl_xor_sync(0xffffffffu, v, o));
    return v;
}
// Block-wide reductions for blockDim.x == MF_BLOCK (every thread must call).
__device__ __forceinline__ float block_max(float v, float* sh) {
    v = warp_max(v);
    const int w = threadIdx.x >> 5, l = threadIdx.x & 31;
    __syncthreads();
    if (l == 0) sh[w] = v;
    __syncthreads();
    if (w == 0) {
        v = l < (int)(blockDim.x >> 5) ? sh[l] : 0.0f;
        for (int o = 16; o > 0; o >>= 1) v = fmaxf(v, __shfl_xor_sync(0xffffffffu, v, o));
    }
    return v;  // valid in thread 0
}
__device__ __forceinline__ double block_sum(double v, double* sh) {
    for (int o = 16; o > 0; o >>= 1) v += __shfl_xor_sync(0xffffffffu, v, o);
    const int w = threadIdx.x >> 5, l = threadIdx.x & 31;
    __syncthreads();
    if (l == 0) sh[w] = v;
    __syncthreads();
    if (w == 0) {
        v = l < (int)(blockDim.x >> 5) ? sh[l] : 0.0;
        for (int o = 16; o > 0; o >>= 1) v += __shfl_xor_sync(0xffffffffu, v, o);
    }
    return v;  // valid in thread 0
}

#define MF_ENTRY2(name, params, args) \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK) name##_2d params { name##_body<2> args; } \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK) name##_3d params { name##_body<3> args; }
