//! Twin: `cuda/device/pairs.cuh` (`separation`: `cuda/device/grid.cuh`); parity test
//! `tests/cuda_parity/`.
//! The pair predicates that the CPU stages (density, forces, rates) and the force monitors
//! share: whether a neighbour enters a particle's sums (`couples`), whether two kinds meet at
//! all (`meets`), and whether two particles count as one body (`same_body`); and the pair's
//! separation on periodic axes (`separation`), which the neighbour grid and the
//! total-Lagrangian reference configuration (`crate::physics::tlsph`) both take.

use crate::physics::dim::Dim;
use crate::physics::params::{
    SphParams, MF_KIND_BOUNDARY, MF_KIND_FLUID, MF_KIND_SOLID,
    MF_SOLID_FLUID_PRESSURE_EXTRAPOLATED, MF_WALL_COUPLING_DYNAMIC,
};

/// The minimum-image separation r_i - r_j \[L\]: on a periodic axis of length len the image
/// of j nearest i, |r| <= len / 2 (for |x_i - x_j| < 3 len / 2, as for positions inside the
/// domain and points within a support of one).
#[inline]
pub fn separation<D: Dim>(p: &SphParams, xi: D::V, xj: D::V) -> D::V {
    let mut r = xi - xj;
    for a in 0..D::D {
        if p.periodic[a] != 0 {
            let len = p.domain_max[a] - p.domain_min[a];
            let d = D::comp(r, a);
            if d > 0.5 * len {
                D::set_comp(&mut r, a, d - len);
            } else if d < -0.5 * len {
                D::set_comp(&mut r, a, d + len);
            }
        }
    }
    r
}

/// Whether particle j of kind `kj` enters the SPH sums of another particle: boundary
/// particles only with dynamic walls (`wall_coupling`, Crespo et al. 2007: wall particles
/// carry density and pressure like fluid but do not move); with the paper's walls they act
/// through the Lennard-Jones force alone.
#[inline]
pub fn couples(p: &SphParams, kj: u8) -> bool {
    kj as u32 != MF_KIND_BOUNDARY || p.wall_coupling != 0
}

/// Whether a particle of kind `k` has rates (d rho/dt, XSPH, stress rate): every kind but
/// walls other than dynamic ones (an mDBC wall takes its density from its ghost node,
/// `backend::cpu::density::wall_density`; the paper's carries none). Twin: `has_rates` in
/// `cuda/device/particle.cuh`.
#[inline]
pub fn has_rates(p: &SphParams, k: u8) -> bool {
    k as u32 != MF_KIND_BOUNDARY || p.wall_coupling as u32 == MF_WALL_COUPLING_DYNAMIC
}

/// Whether particles of kinds `ki` and `kj` meet at all: a solid and a wall particle skip
/// each other, both ways, where the scene says so (`[solid] wall_contact = false`,
/// `wall_contact`): no Lennard-Jones force, eq. (17), no wall pressure, and neither
/// enters the other's density (continuity or summation). A body that meets only the fluid
/// and other bodies: the free end of a gate standing on the tank floor, whose continuity
/// density read the foot leaving the floor's wall particles as a dilatation
/// (docs/reference/accuracy.md, elastic gate).
#[inline]
pub fn meets(p: &SphParams, ki: u8, kj: u8) -> bool {
    let (s, b) = (MF_KIND_SOLID, MF_KIND_BOUNDARY);
    let (ki, kj) = (ki as u32, kj as u32);
    p.wall_contact != 0 || !((ki == s && kj == b) || (ki == b && kj == s))
}

/// Whether particles i (kind `ki`, scene group `gi`) and j count as one body for the terms
/// that act only within a body: XSPH, eq. (18), the velocity gradient of eq. (15) (so the
/// Jaumann stress rate, eq. (12)) and the artificial stress. All fluid is one body; a solid
/// is its own scene group; and a driven solid (a clamp: one of the `driven_motion` groups, held by
/// its `motion`) is bonded to every solid particle it neighbours, so the held part takes up
/// strain and passes stress into the body it holds (a cantilever's root, both ends of a
/// plate held by two clamps).
#[inline]
pub fn same_body(p: &SphParams, ki: u8, kj: u8, gi: u32, gj: u32) -> bool {
    let clamp = |g: u32| p.is_driven(g);
    ki == kj
        && (ki as u32 == MF_KIND_FLUID
            || gi == gj
            || (ki as u32 == MF_KIND_SOLID && (clamp(gi) || clamp(gj))))
}

/// Whether bodies meet the fluid at its extrapolated pressure (`[solid] fluid_pressure`);
/// the interface stage runs where the scene also has solids.
#[inline]
pub fn extrapolated(p: &SphParams) -> bool {
    p.solid_fluid_pressure as u32 == MF_SOLID_FLUID_PRESSURE_EXTRAPOLATED
}

/// Whether a pair of kinds `ki`, `kj` is a fluid particle and a body's particle that meet at
/// the fluid's pressure extrapolated to the body (`[solid] fluid_pressure = "extrapolated"`,
/// `backend/cpu/interface.rs`): there the body's particle takes part as fluid of its own
/// volume, and its continuity density leaves the fluid out.
#[inline]
pub fn extrapolated_pair(p: &SphParams, ki: u8, kj: u8) -> bool {
    let (f, s) = (MF_KIND_FLUID, MF_KIND_SOLID);
    let (ki, kj) = (ki as u32, kj as u32);
    extrapolated(p) && ((ki == f && kj == s) || (ki == s && kj == f))
}
