// Open boundaries (`[[open_boundaries]]`, device/open.cuh): the open-boundary stage's marks,
// its changes in place and its tally, the new inlet particles' ids and places, and the
// buffers' densities. The moves between them are the exchange's (exchange.cu: packing the
// particles an inlet copies, compacting the storage, unpacking the copies at its end),
// driven by src/backend/cuda/launch/open.rs. Twin: src/backend/cpu/open.rs; parity test:
// tests/cuda_parity/open.rs.
#include "device/entries.cuh"
#include "device/kernel.cuh"
#include "device/mdbc.cuh"
#include "device/neighbours.cuh"
#include "device/open.cuh"
#include "device/packing.cuh"
#include "device/particle.cuh"
#include "device/vectors.cuh"

// Slot i's position as 3 floats (z = 0 in 2D).
template <int DIM>
__device__ __forceinline__ void pos3(const float* __restrict__ pos, unsigned i, float* x) {
    const Vec<DIM> v = vload<DIM>(pos, i);
    x[0] = v.c[0];
    x[1] = v.c[1];
    x[2] = DIM == 3 ? v.c[DIM - 1] : 0.0f;
}

// mark[i] = 1 where slot i is an inlet's buffer particle that joins the fluid (a copy of it
// goes behind), else 0; mark[n] = 0 (the scan's sentinel). Grid of n + 1 threads.
template <int DIM>
__device__ void sph_open_mark_body(const SphParams p, unsigned n, const unsigned char* __restrict__ kind,
                                   const unsigned* __restrict__ group, const float* __restrict__ pos,
                                   unsigned* __restrict__ mark) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i > n) return;
    if (i == n) {
        mark[n] = 0;
        return;
    }
    float x[3];
    pos3<DIM>(pos, i, x);
    mark[i] = (open_fate(p, kind[i], group[i], x) & 0xffu) == MF_FATE_SPAWN ? 1u : 0u;
}
MF_ENTRY2(sph_open_mark,
          (const SphParams p, unsigned n, const unsigned char* kind, const unsigned* group, const float* pos,
           unsigned* mark),
          (p, n, kind, group, pos, mark))

// Each slot's fate applied in place: the group of a particle that joins the fluid or a
// buffer; mark[i] = 0 where it is removed, else 1 (mark[n] = 0); the tally, 4 doubles per
// boundary (count in, mass in, count out, mass out: `OpenTally`), added to atomically
// (equal masses sum to the same bits in any order). Grid of n + 1 threads. After the copies
// were packed (their parents still in the inlet's group).
template <int DIM>
__device__ void sph_open_apply_body(const SphParams p, unsigned n, const unsigned char* __restrict__ kind,
                                    unsigned* __restrict__ group, const float* __restrict__ pos,
                                    const float* __restrict__ vel, unsigned* __restrict__ mark,
                                    double* __restrict__ tally) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i > n) return;
    if (i == n) {
        mark[n] = 0;
        return;
    }
    float x[3];
    pos3<DIM>(pos, i, x);
    const unsigned f = open_fate(p, kind[i], group[i], x);
    const unsigned code = f & 0xffu, b = f >> 8;
    unsigned keep = 1;
    if (code == MF_FATE_SPAWN || code == MF_FATE_REMOVE) {
        double* t = tally + 4 * b + (code == MF_FATE_SPAWN ? 0 : 2);
        atomicAdd(t, 1.0);
        atomicAdd(t + 1, (double)mass_of<DIM>(pos, vel, i));
    }
    if (code == MF_FATE_SPAWN || code == MF_FATE_LEAVE) group[i] = (unsigned)p.open[b].through;
    else if (code == MF_FATE_ENTER) group[i] = (unsigned)p.open[b].group;
    else if (code == MF_FATE_REMOVE) keep = 0;
    mark[i] = keep;
}
MF_ENTRY2(sph_open_apply,
          (const SphParams p, unsigned n, const unsigned char* kind, unsigned* group, const float* pos,
           const float* vel, unsigned* mark, double* tally),
          (p, n, kind, group, pos, vel, mark, tally))

// The m copies unpacked at slots base .. base + m (in their parents' storage order): ids
// next_id + k, and each `depth` behind its parent along its inlet's normal (`MfOpen::behind`).
template <int DIM>
__device__ void sph_open_born_body(const SphParams p, unsigned base, unsigned m, unsigned next_id,
                                   unsigned* __restrict__ id, const unsigned* __restrict__ group,
                                   float* __restrict__ pos) {
    const unsigned k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= m) return;
    const unsigned i = base + k;
    id[i] = next_id + k;
    const int b = open_index(p, group[i]);
    if (b < 0) return;
    const MfOpen& o = p.open[b];
    Vec<DIM> x = vload<DIM>(pos, i);
    x.c[o.axis] -= o.sign * o.depth;
    vstore_keep_w<DIM>(pos, i, x);
}
MF_ENTRY2(sph_open_born,
          (const SphParams p, unsigned base, unsigned m, unsigned next_id, unsigned* id, const unsigned* group,
           float* pos),
          (p, base, m, next_id, id, group, pos))

// The buffers' densities and pressures after the density pass: an inlet's particle at s < 0
// takes the fluid's density at its mirror node x + 2 |s| n, by the first-order corrected
// interpolation of the fluid outside every buffer (GhostSums, device/mdbc.cuh; its own density
// where no fluid is near); an outlet's rho0; then the Tait pressure and vel's w slot. One
// thread per particle, the CPU's neighbour order. Twin: `buffer_density` in cpu/open.rs.
template <int DIM>
__device__ void sph_buffer_density_body(const SphParams p, unsigned n, const unsigned* __restrict__ cell_start,
                                        const float* __restrict__ pos, float* __restrict__ vel,
                                        const unsigned char* __restrict__ kind,
                                        const unsigned* __restrict__ group, float* __restrict__ rho,
                                        float* __restrict__ pr) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const int b = open_index(p, group[i]);
    if (b < 0) return;
    const MfOpen& o = p.open[b];
    float out = p.rho0;
    if (o.kind == MF_OPEN_INLET) {
        Vec<DIM> xg = vload<DIM>(pos, i);
        float x3[3];
        pos3<DIM>(pos, i, x3);
        xg.c[o.axis] = xg.c[o.axis] - 2.0f * open_side(o, x3) * o.sign;
        GhostSums g;
        for_each_neighbor_split<DIM, 1>(p, cell_start, pos, xg, 0, [&](unsigned j, Vec<DIM> r, float r2, float) {
            if (kind[j] != MF_KIND_FLUID || open_index(p, group[j]) >= 0) return;
            float w, f;
            kernel_wf(p, sqrtf(r2), w, f);
            const float r3[3] = {r.c[0], r.c[1], DIM == 3 ? r.c[DIM - 1] : 0.0f};
            g.add(DIM, r3, w, f, mass_of<DIM>(pos, vel, j), rho[j]);
        });
        float rho_g;
        out = g.density(DIM, p.rho0, p.dx, rho_g) ? rho_g : rho[i];
    }
    rho[i] = out;
    pr[i] = pressure(p, MF_KIND_FLUID, out, 0.0f);  // eq. (9)
    reinterpret_cast<float4*>(vel)[i].w = vel_w(MF_KIND_FLUID, out);
}
MF_ENTRY2(sph_buffer_density,
          (const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, float* vel,
           const unsigned char* kind, const unsigned* group, float* rho, float* pr),
          (p, n, cell_start, pos, vel, kind, group, rho, pr))
