// Twin: src/physics/pairs.rs; parity test: tests/cuda_parity/.
// The pair predicates the stages share: whether a neighbour enters a particle's sums
// (couples), whether two kinds meet at all (meets), whether two particles are one body
// (same_body).
#pragma once
#include "sph_params.h"
#include "particle.cuh"

// Whether particle j of kind kj enters the sums of a non-boundary particle.
__device__ __forceinline__ bool couples(const SphParams& p, unsigned char kj) {
    return kj != MF_KIND_BOUNDARY || p.wall_coupling != 0;
}
// Whether particles of kinds ki and kj meet at all: a solid and a wall particle skip each
// other, both ways, where the scene says so (wall_contact): no Lennard-Jones force, no
// wall pressure, no density sum over the other.
__device__ __forceinline__ bool meets(const SphParams& p, unsigned char ki, unsigned char kj) {
    return p.wall_contact != 0 || !((ki == MF_KIND_SOLID && kj == MF_KIND_BOUNDARY) ||
                                         (ki == MF_KIND_BOUNDARY && kj == MF_KIND_SOLID));
}

// Whether a pair of kinds ki, kj is a fluid particle and a body's particle that meet at the
// fluid's pressure extrapolated to the body (solid_fluid_pressure): the body's particle takes
// part as fluid of its own volume, and its continuity leaves the fluid out.
__device__ __forceinline__ bool extrapolated_pair(const SphParams& p, unsigned char ki, unsigned char kj) {
    return p.solid_fluid_pressure == MF_SOLID_FLUID_PRESSURE_EXTRAPOLATED &&
           ((ki == MF_KIND_FLUID && kj == MF_KIND_SOLID) || (ki == MF_KIND_SOLID && kj == MF_KIND_FLUID));
}

// Whether i and j count as one body for XSPH (eq. 18), the velocity gradient (eq. 15) and
// the artificial stress: all fluid; one solid group; and a driven solid (a clamp) bonded to
// every solid it neighbours, so the held part passes stress into the body it holds.
__device__ __forceinline__ bool same_body(const SphParams& p, unsigned char ki, unsigned char kj, unsigned gi,
                                          unsigned gj) {
    return kj == ki &&
           (ki == MF_KIND_FLUID || gi == gj || (ki == MF_KIND_SOLID && (is_driven(p, gi) || is_driven(p, gj))));
}
