// Reductions: the step size on the device (eq. (19) with force and viscous limits),
// diagnostics, the health check, and the SphParams layout probe.
// Twin: src/backend/cpu/reduce.rs; parity test: tests/cuda_parity/.
#include "device/entries.cuh"
#include "device/packing.cuh"
#include "device/particle.cuh"
#include "device/reductions.cuh"
#include "device/step_size.cuh"
#include "device/vectors.cuh"
#include <stddef.h>

// red = (max |v|, max |a|, max c) as float bits, filled by sph_forces_*. Writes dt, clears
// red (step_size_of in device/step_size.cuh). Where a kick or drift-kick follows at once,
// the launcher lets that kernel take dt itself instead (`Buffers::dt_pending`).
extern "C" __global__ void sph_step_size(const SphParams p, unsigned* __restrict__ red, float* __restrict__ dt_out) {
    if (threadIdx.x != 0 || blockIdx.x != 0) return;
    const float dt = step_size_of(p, red);
    red[0] = red[1] = red[2] = 0u;
    *dt_out = dt;
}

// Totals of per-block partial sums, in a fixed order (so that they come out the same bits
// from run to run, as atomics would not): block g sums the n_blocks partials of slot g,
// partial[(g * n_blocks + b) * 3 + k], k = 0..2, into out[3 g + k]. The force monitors'
// wall forces and the diagnostics' sums end here.
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
sph_sum_partials(unsigned n_blocks, const double* __restrict__ partial, double* __restrict__ out) {
    __shared__ double sh[MF_BLOCK / 32];
    const double* q = partial + (size_t)blockIdx.x * n_blocks * 3;
    for (int a = 0; a < 3; ++a) {
        double s = 0.0;
        for (unsigned b = threadIdx.x; b < n_blocks; b += blockDim.x) s += q[(size_t)b * 3 + a];
        s = block_sum(s, sh);
        if (threadIdx.x == 0) out[(size_t)blockIdx.x * 3 + a] = s;
    }
}

// The sums, as per-block partials for sph_sum_partials (two slots: kinetic energy [M L^2
// T^-2] and momentum x, y [M L/T]; momentum z and two zeros); maxes = (max speed, density
// error) as float bits; counts = (fluid, solid, boundary). The caller zeroes maxes and
// counts.
template <int DIM>
__device__ void sph_diagnostics_body(const SphParams p, unsigned n, const unsigned char* __restrict__ kind,
                                     const float* __restrict__ pos, const float* __restrict__ vel,
                                     const float* __restrict__ rho, double* __restrict__ partial,
                                     unsigned* __restrict__ maxes, unsigned* __restrict__ counts) {
    __shared__ double shd[MF_BLOCK / 32];
    __shared__ float shf[MF_BLOCK / 32];
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    double ke = 0.0, mom[3] = {0.0, 0.0, 0.0};
    float vmax = 0.0f, derr = 0.0f;
    unsigned char k = i < n ? kind[i] : (unsigned char)255;
    if (i < n && k != MF_KIND_BOUNDARY) {
        Vec<DIM> v = vel_load<DIM>(vel, i);
        double m = (double)mass_of<DIM>(pos, vel, i), v2 = 0.0;
        for (int a = 0; a < DIM; ++a) {
            v2 += (double)v.c[a] * (double)v.c[a];
            mom[a] = m * (double)v.c[a];
        }
        ke = 0.5 * m * v2;
        vmax = (float)sqrt(v2);
        if (k == MF_KIND_FLUID) derr = fabsf(rho[i] / p.rho0 - 1.0f);
    }
    // counts: warp ballots
    const unsigned bf = __ballot_sync(0xffffffffu, k == MF_KIND_FLUID);
    const unsigned bs = __ballot_sync(0xffffffffu, k == MF_KIND_SOLID);
    const unsigned bb = __ballot_sync(0xffffffffu, k == MF_KIND_BOUNDARY);
    if ((threadIdx.x & 31) == 0) {
        if (bf) atomicAdd(&counts[0], (unsigned)__popc(bf));
        if (bs) atomicAdd(&counts[1], (unsigned)__popc(bs));
        if (bb) atomicAdd(&counts[2], (unsigned)__popc(bb));
    }
    const double totals[6] = {block_sum(ke, shd),     block_sum(mom[0], shd), block_sum(mom[1], shd),
                              block_sum(mom[2], shd), 0.0,                    0.0};
    if (threadIdx.x == 0)
        for (int k = 0; k < 6; ++k) partial[((size_t)(k / 3) * gridDim.x + blockIdx.x) * 3 + k % 3] = totals[k];
    vmax = block_max(vmax, shf);
    if (threadIdx.x == 0) atomicMax(&maxes[0], __float_as_uint(vmax));
    derr = block_max(derr, shf);
    if (threadIdx.x == 0) atomicMax(&maxes[1], __float_as_uint(derr));
}
MF_ENTRY2(sph_diagnostics,
          (const SphParams p, unsigned n, const unsigned char* kind, const float* pos, const float* vel,
           const float* rho, double* partial, unsigned* maxes, unsigned* counts),
          (p, n, kind, pos, vel, rho, partial, maxes, counts))

// Health check: the first unhealthy slot, as atomicMax of the complement of (slot <<
// MF_FAULT_SLOT_SHIFT) | fault class (MF_FAULT_* in sph_consts.h) into *first (the caller
// sets it to 0: healthy; the complement, so that the lowest slot wins and a zeroed word
// means none).
template <int DIM>
__device__ void sph_check_body(const SphParams p, unsigned n, const unsigned char* __restrict__ kind,
                               const float* __restrict__ pos, const float* __restrict__ vel,
                               const float* __restrict__ rho, unsigned long long* __restrict__ first) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const unsigned char k = kind[i];
    // A wall particle is checked for its place alone (cpu/reduce.rs): a driven or floating
    // one may move out of the domain; its density is a wall's.
    const bool wall = k == MF_KIND_BOUNDARY;
    const Vec<DIM> x = vload<DIM>(pos, i);
    unsigned code = 0;
    for (int a = 0; a < DIM && !code; ++a)
        if (!isfinite(x.c[a])) code = MF_FAULT_NON_FINITE_POSITION;
    if (!wall) {
        const Vec<DIM> v = vel_load<DIM>(vel, i);
        for (int a = 0; a < DIM && !code; ++a)
            if (!isfinite(v.c[a])) code = MF_FAULT_NON_FINITE_VELOCITY;
        const float r = rho[i];
        if (!code && !isfinite(r)) code = MF_FAULT_NON_FINITE_DENSITY;
        const float r0 = rest_density(p, k);
        if (!code && (r < MF_DENSITY_SANE_LOW * r0 || r > MF_DENSITY_SANE_HIGH * r0)) code = MF_FAULT_DENSITY_RANGE;
    }
    for (int a = 0; a < DIM && !code; ++a)
        if (!p.periodic[a] && (x.c[a] < p.domain_min[a] || x.c[a] > p.domain_max[a])) code = MF_FAULT_ESCAPED;
    if (code) atomicMax(first, ~(((unsigned long long)i << MF_FAULT_SLOT_SHIFT) | code));
}
MF_ENTRY2(sph_check,
          (const SphParams p, unsigned n, const unsigned char* kind, const float* pos, const float* vel,
           const float* rho, unsigned long long* first),
          (p, n, kind, pos, vel, rho, first))

// After a queued check (`Solver::queue_check`, one thread): where sph_check found a fault
// (*first != 0) and no earlier check did (clock[1] == 0), the fault is kept for the host's
// next read of the clock: clock[1] = *first (read back with the time, clock[0]), and the
// faulty particle's record into rec (MF_FAULT_RECORD_WORDS words: id, kind, position x y z,
// velocity x y z, density, the step (2 words) and the time (2 words) of the check).
// *first is cleared for the next check.
template <int DIM>
__device__ void sph_check_record_body(unsigned long long step, unsigned long long* __restrict__ first,
                                      double* __restrict__ clock, unsigned* __restrict__ rec,
                                      const unsigned* __restrict__ id, const unsigned char* __restrict__ kind,
                                      const float* __restrict__ pos, const float* __restrict__ vel,
                                      const float* __restrict__ rho) {
    if (threadIdx.x != 0 || blockIdx.x != 0) return;
    const unsigned long long found = *first;
    if (!found) return;
    *first = 0ull;
    unsigned long long* kept = reinterpret_cast<unsigned long long*>(clock) + 1;
    if (*kept) return;  // an earlier check's fault stands
    *kept = found;
    const unsigned i = (unsigned)(~found >> MF_FAULT_SLOT_SHIFT);
    const Vec<DIM> x = vload<DIM>(pos, i), v = vel_load<DIM>(vel, i);
    rec[0] = id[i];
    rec[1] = kind[i];
    for (int a = 0; a < 3; ++a) {
        rec[2 + a] = __float_as_uint(a < DIM ? x.c[a] : 0.0f);
        rec[5 + a] = __float_as_uint(a < DIM ? v.c[a] : 0.0f);
    }
    rec[8] = __float_as_uint(rho[i]);
    rec[9] = (unsigned)step;
    rec[10] = (unsigned)(step >> 32);
    const unsigned long long t = (unsigned long long)__double_as_longlong(clock[0]);
    rec[11] = (unsigned)t;
    rec[12] = (unsigned)(t >> 32);
}
MF_ENTRY2(sph_check_record,
          (unsigned long long step, unsigned long long* first, double* clock, unsigned* rec, const unsigned* id,
           const unsigned char* kind, const float* pos, const float* vel, const float* rho),
          (step, first, clock, rec, id, kind, pos, vel, rho))

// Layout probe: out = (sizeof(SphParams), offsetof dt, offsetof gravity, p.dim).
extern "C" __global__ void sph_params_layout(const SphParams p, unsigned* out) {
    if (threadIdx.x == 0 && blockIdx.x == 0) {
        out[0] = (unsigned)sizeof(SphParams);
        out[1] = (unsigned)offsetof(SphParams, dt);
        out[2] = (unsigned)offsetof(SphParams, gravity);
        out[3] = (unsigned)p.dim;
    }
}
