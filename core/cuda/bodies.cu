// Floating rigid bodies (`MfBody` in sph_params.h, device/body.cuh): their kick and drift on
// the device, inside the step's graph, with no host copy. The load (the fluid's force and
// torque on each body's particles) is summed before the particles' kick by sph_body_load_*
// in monitor.cu and totalled by sph_sum_partials (reduce.cu): load[12 b .. 12 b + 12] =
// (the fluid's force, its torque, the contacts' force, their torque) of body b. Twin: src/backend/cpu/bodies.rs; parity test:
// tests/cuda_parity/.
#include "device/body.cuh"
#include "device/entries.cuh"
#include "device/packing.cuh"
#include "device/step_size.cuh"

// Every body's kick over the step's kick span (dt read on the device, after the particles'
// kick wrote it): one thread per body.
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
sph_body_kick(const SphParams p, unsigned n_bodies, const float* __restrict__ dt_dev, const double* __restrict__ load,
              MfBody* __restrict__ bodies) {
    const unsigned b = blockIdx.x * blockDim.x + threadIdx.x;
    if (b >= n_bodies) return;
    const float span = kick_span(p, dt_dev, dt_dev[0]);
    body_kick(bodies[b], load + 12 * b, p.gravity, span);
}

// Every body's drift over the step's dt (settled before this launch): one thread per body.
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
sph_body_drift(unsigned n_bodies, const float* __restrict__ dt_dev, MfBody* __restrict__ bodies) {
    const unsigned b = blockIdx.x * blockDim.x + threadIdx.x;
    if (b >= n_bodies) return;
    body_drift(bodies[b], dt_dev[0]);
}

// A body particle's velocity after its body's kick: V + omega x (x - c) (density and mass
// kept in the velocity's other slots).
template <int DIM>
__device__ void sph_body_velocity_body(unsigned n, unsigned n_bodies, const MfBody* __restrict__ bodies,
                                       const unsigned char* __restrict__ kind, const unsigned* __restrict__ group,
                                       const float* __restrict__ pos, float* __restrict__ vel) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const int b = body_index(n_bodies, bodies, kind[i], group[i]);
    if (b < 0) return;
    vel_store<DIM>(vel, i, body_point_velocity<DIM>(bodies[b], vload<DIM>(pos, i)));
}
MF_ENTRY2(sph_body_velocity,
          (unsigned n, unsigned n_bodies, const MfBody* bodies, const unsigned char* kind, const unsigned* group,
           const float* pos, float* vel),
          (n, n_bodies, bodies, kind, group, pos, vel))

// A body particle moved with its body's last drift (before the particles' drift, which
// files it in its new cell).
template <int DIM>
__device__ void sph_body_move_body(unsigned n, unsigned n_bodies, const MfBody* __restrict__ bodies,
                                   const unsigned char* __restrict__ kind, const unsigned* __restrict__ group,
                                   float* __restrict__ pos) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const int b = body_index(n_bodies, bodies, kind[i], group[i]);
    if (b < 0) return;
    vstore_keep_w<DIM>(pos, i, body_moved<DIM>(bodies[b], vload<DIM>(pos, i)));
}
MF_ENTRY2(sph_body_move,
          (unsigned n, unsigned n_bodies, const MfBody* bodies, const unsigned char* kind, const unsigned* group,
           float* pos),
          (n, n_bodies, bodies, kind, group, pos))
