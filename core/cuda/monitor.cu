// Force monitors (`[[monitors]]`, `Solver::wall_forces`): the force the fluid and solids
// exert on the wall particles of one scene group, summed on the device; only three doubles
// per group come back. For every wall particle j of the group and every fluid or solid
// neighbour i, the force kernel's own pair term (`ForceSum::add` in forces.cuh) of j on i,
// alone: Lennard-Jones eq. (17); with dynamic walls also the pressure term of eqs. (7)/(16)
// with the wall cut-off, the artificial viscosity eq. (10) and the laminar viscosity of
// Morris, Fox & Zhu 1997 (with no_slip, the wall's extrapolated velocity). By Newton's third
// law the wall feels F = - sum_i m_i a_i(from wall) [M L T^-2] (per unit depth in 2D).
// The launcher first rebuilds the grid from the current positions and, unless that build
// applied it, refreshes the equation of state (sph_monitor_eos), as the next step's build
// and density pass will (src/backend/cuda/launch/reduce.rs `wall_forces`).
// Twin: src/backend/cpu/monitor.rs; parity test: tests/cuda_parity/.
#include "forces.cuh"
#include "device/entries.cuh"
#include "device/neighbours.cuh"

// The pressure of every particle that carries one (`couples`) from the density it carries
// now, eq. (9) (the solid pressure law for solids), and the density in every velocity's w
// slot (vel_w), as the density pass writes them: the step after this is the step without it.
extern "C" __global__ void __launch_bounds__(MF_BLOCK)
sph_monitor_eos(const SphParams p, unsigned n, const unsigned char* __restrict__ kind, const float* __restrict__ rho,
                const float* __restrict__ rho_dev, float* __restrict__ pr, float* __restrict__ vel) {
    const unsigned i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const unsigned char k = kind[i];
    const float r = rho[i];
    // rho_dev: the solids' departure rho - rho0_s (null without solids).
    if (couples(p, k)) pr[i] = pressure(p, k, r, rho_dev ? rho_dev[i] : 0.0f);  // eq. (9)
    reinterpret_cast<float4*>(vel)[i].w = vel_w(k, r);
}

// Lanes per wall particle: its candidates split over MF_LANES_MAX consecutive threads
// (for_each_neighbor_split), each lane summing its own pairs; a monitored wall object is a
// few hundred to a few thousand particles, so its pairs spread over more threads this way.
#define MF_MONITOR_LANES MF_LANES_MAX

// The pairs of wall particle j (taken by this lane) with its fluid and solid neighbours,
// added to F = - sum_i m_i a_i(from j) [M L T^-2], and with a centre c [L] (a floating body's)
// their torque (x_j - c) x f [M L^2 T^-2] to T.
template <int DIM, bool SOLIDS, bool PERIODIC, bool TORQUE>
__device__ __forceinline__ void wall_pairs(const SphParams& p, unsigned n, unsigned j, int lane,
                                           const unsigned* __restrict__ cell_start, const float* __restrict__ pos,
                                           const float* __restrict__ vel, const float* __restrict__ rho,
                                           const float* __restrict__ pr, const unsigned char* __restrict__ kind,
                                           const unsigned* __restrict__ group, const float* __restrict__ stress,
                                           const unsigned* __restrict__ id, const float* __restrict__ surf,
                                           const double* __restrict__ centre, unsigned wall_group, double F[3],
                                           double T[3], double C[3], double TC[3]) {
    float wj;  // 3D: m_j (the w slot of its position)
    const Vec<DIM> xj = vload_w<DIM>(pos, j, wj);
    double u[3] = {0.0, 0.0, 0.0};
    if (TORQUE)
        for (int a = 0; a < DIM; ++a) u[a] = (double)xj.c[a] - centre[a];
    for_each_neighbor_split<DIM, MF_MONITOR_LANES, MF_NB_BATCH, PERIODIC>(
        p, cell_start, pos, xj, lane, [&](unsigned i, Vec<DIM> r_ji, float r2, float) {
            const unsigned char ki = kind[i];
            if (ki == MF_KIND_BOUNDARY) {
                // The force kernel computes no acceleration of a wall particle; a floating
                // body's particle meets another object's by contact: the repulsive branch of
                // eq. (17), m_j C0 [(r0/r)^p1 - (r0/r)^p2] r_ji / r.
                if (TORQUE && group[i] != wall_group && r2 < p.lj_r0 * p.lj_r0) {
                    const Vec<DIM> a = lennard_jones<DIM>(p, r_ji, sqrtf(r2));
                    double cj[3] = {0.0, 0.0, 0.0};
#pragma unroll
                    for (int d = 0; d < DIM; ++d) {
                        cj[d] = (double)mass_of<DIM>(pos, vel, j) * (double)a.c[d];
                        C[d] += cj[d];
                    }
                    TC[0] += u[1] * cj[2] - u[2] * cj[1];
                    TC[1] += u[2] * cj[0] - u[0] * cj[2];
                    TC[2] += u[0] * cj[1] - u[1] * cj[0];
                }
                return;
            }
            // The force kernel's pair term of wall particle j on particle i, alone: i's sum
            // started at zero (no gravity), r_ij = x_i - x_j.
            ForceSum<DIM, SOLIDS> f;
            f.begin(p, i, n, ki, 0, vel, rho, pr, group, stress, nullptr);
            f.acc = vzero<DIM>();
            f.add(p, i, n, neighbour<DIM, SOLIDS>(p, j, r_ji * -1.0f, r2, wj, vel, kind), pr, group, stress,
                  nullptr, nullptr, id, surf);
            const double mi = (double)mass_of<DIM>(pos, vel, i);
            double fj[3] = {0.0, 0.0, 0.0};
#pragma unroll
            for (int a = 0; a < DIM; ++a) {
                fj[a] = -mi * (double)f.acc.c[a];
                F[a] += fj[a];
            }
            if (TORQUE) {
                T[0] += u[1] * fj[2] - u[2] * fj[1];
                T[1] += u[2] * fj[0] - u[0] * fj[2];
                T[2] += u[0] * fj[1] - u[1] * fj[0];
            }
        });
}

// One wall group's force, as per-block partial sums: partial[(slot * gridDim.x + block) * 3
// + axis] (z = 0 in 2D); with TORQUE (a floating body's load about `centre`) the fluid's
// force, its torque, the contacts' force and their torque in slots 4 slot .. 4 slot + 3. Any grid of MF_BLOCK threads: the wall
// particles are taken MF_BLOCK / MF_MONITOR_LANES per block and pass, striding over the
// storage. Deterministic: every lane sums its pairs in the grid's order, and the block sums
// in a fixed order.
template <int DIM, bool SOLIDS, bool TORQUE>
__device__ void wall_force_impl(const SphParams& p, unsigned n, unsigned wall_group, unsigned slot,
                                const unsigned* __restrict__ cell_start, const float* __restrict__ pos,
                                const float* __restrict__ vel, const float* __restrict__ rho,
                                const float* __restrict__ pr, const unsigned char* __restrict__ kind,
                                const unsigned* __restrict__ group, const float* __restrict__ stress,
                                const unsigned* __restrict__ id, const float* __restrict__ surf,
                                const double* __restrict__ centre, double* __restrict__ partial) {
    __shared__ double sh[MF_BLOCK / 32];
    const int lane = (int)(threadIdx.x % MF_MONITOR_LANES);
    const unsigned per_pass = gridDim.x * (blockDim.x / MF_MONITOR_LANES);
    const bool periodic = p.periodic[0] || p.periodic[1] || p.periodic[2];
    double F[3] = {0.0, 0.0, 0.0}, T[3] = {0.0, 0.0, 0.0}, C[3] = {0.0, 0.0, 0.0}, TC[3] = {0.0, 0.0, 0.0};
    for (unsigned j = (blockIdx.x * blockDim.x + threadIdx.x) / MF_MONITOR_LANES; j < n; j += per_pass) {
        // Owned wall particles only (one domain: all): a subdomain's halo copies are summed
        // by their owner, so the subdomains' sums add up to the one-domain force.
        if (kind[j] != MF_KIND_BOUNDARY || group[j] != wall_group || !owns_slot<DIM>(p, pos, j)) continue;
        if (periodic)
            wall_pairs<DIM, SOLIDS, true, TORQUE>(p, n, j, lane, cell_start, pos, vel, rho, pr, kind, group, stress,
                                                  id, surf, centre, wall_group, F, T, C, TC);
        else
            wall_pairs<DIM, SOLIDS, false, TORQUE>(p, n, j, lane, cell_start, pos, vel, rho, pr, kind, group, stress,
                                                   id, surf, centre, wall_group, F, T, C, TC);
    }
    const size_t first = TORQUE ? 4 * (size_t)slot : slot;
    double* const parts[4] = {F, T, C, TC};
    for (int q = 0; q < (TORQUE ? 4 : 1); ++q) {
#pragma unroll
        for (int a = 0; a < 3; ++a) {
            const double s = block_sum(parts[q][a], sh);
            if (threadIdx.x == 0) partial[((first + q) * gridDim.x + blockIdx.x) * 3 + a] = s;
        }
    }
}

// With solids (stress terms, kinds from the kind array) and fluid-only (kinds from the sign
// of vel.w, no tensor loads), picked by the launcher as for the forces kernel. Both with
// every optional term compiled in (EXTRAS): the lean scenes have them all off, so they add
// nothing there.
#define MF_WALL_FORCE_ENTRY(name, DIM, SOLIDS)                                                                     \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK)                                                         \
        name(const SphParams p, unsigned n, unsigned wall_group, unsigned slot, const unsigned* cell_start,        \
             const float* pos, const float* vel, const float* rho, const float* pr, const unsigned char* kind,     \
             const unsigned* group, const float* stress, const unsigned* id, const float* surf, double* partial) { \
        wall_force_impl<DIM, SOLIDS, false>(p, n, wall_group, slot, cell_start, pos, vel, rho, pr, kind, group,   \
                                            stress, id, surf, nullptr, partial);                                   \
    }
MF_WALL_FORCE_ENTRY(sph_wall_force_2d, 2, true)
MF_WALL_FORCE_ENTRY(sph_wall_force_3d, 3, true)
MF_WALL_FORCE_ENTRY(sph_wall_force_fluid_2d, 2, false)
MF_WALL_FORCE_ENTRY(sph_wall_force_fluid_3d, 3, false)

// A floating body's load (cuda/bodies.cu, `launch::bodies`): the fluid's force and its torque
// about the body's centre of mass on the particles of body `body`, as the monitors sum a
// wall's force, and the contacts' (`wall_pairs`); slots 4 body .. 4 body + 3 of `partial`.
// Twin: `wall_load` in src/backend/cpu/monitor.rs.
#define MF_BODY_LOAD_ENTRY(name, DIM, SOLIDS)                                                                      \
    extern "C" __global__ void __launch_bounds__(MF_BLOCK)                                                         \
        name(const SphParams p, unsigned n, const MfBody* bodies, unsigned body, const unsigned* cell_start,       \
             const float* pos, const float* vel, const float* rho, const float* pr, const unsigned char* kind,     \
             const unsigned* group, const float* stress, const unsigned* id, const float* surf, double* partial) { \
        wall_force_impl<DIM, SOLIDS, true>(p, n, (unsigned)bodies[body].group, body, cell_start, pos, vel, rho,   \
                                           pr, kind, group, stress, id, surf, bodies[body].centre, partial);       \
    }
MF_BODY_LOAD_ENTRY(sph_body_load_2d, 2, true)
MF_BODY_LOAD_ENTRY(sph_body_load_3d, 3, true)
MF_BODY_LOAD_ENTRY(sph_body_load_fluid_2d, 2, false)
MF_BODY_LOAD_ENTRY(sph_body_load_fluid_3d, 3, false)
