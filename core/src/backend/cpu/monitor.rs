//! Force monitors on the solver's own state: the force the fluid and solids exert on the
//! wall particles of one scene group (`Readback::wall_forces`; `crate::measure::monitor` for the
//! read-back path and the statistics). Twin: `cuda/monitor.cu`; parity test
//! `tests/cuda_parity/`.
//!
//! For every wall particle j of the group and every fluid or solid neighbour i, the force
//! stage's own pair term (`ForceSum::add`) of j on i, alone: Lennard-Jones eq. (17); with
//! dynamic walls also the pressure term of eqs. (7)/(16) with the wall cut-off
//! (`wall_pair_stress`), the artificial viscosity eq. (10) and the laminar viscosity of
//! Morris, Fox & Zhu 1997 (with `no_slip`, the wall's extrapolated velocity). By Newton's
//! third law the wall feels F = - sum_i m_i a_i(from wall). [M L T^-2] (per unit depth in
//! 2D: [M T^-2]).

use super::density::pressure;
use super::forces::{lennard_jones, ForceSum};
use super::grid::Grid;
use crate::physics::body::Load;
use crate::physics::dim::Dim;
use crate::physics::pairs::couples;
use crate::physics::params::{SphParams, MF_KIND_BOUNDARY};
use crate::physics::state::State;

/// The pressures the next force stage takes: the equation of state, eq. (9) (the solid
/// pressure law for solids), of the density each particle carries now, for every particle
/// that carries a pressure (`couples`: no wall particle under Lennard-Jones-only walls).
/// The density pass writes the same values before any stage reads them, so a step after
/// this is the step without it. [M L^-d L^2 T^-2]
pub fn refresh_pressure<D: Dim>(p: &SphParams, s: &mut State<D>) {
    for i in 0..s.len() {
        if couples(p, s.kind[i]) {
            s.p[i] = pressure(p, s.kind[i], s.rho[i], s.rho_dev(i)); // eq. (9)
        }
    }
}

/// The force [M L T^-2] on the boundary particles of scene group `group` from the fluid and
/// solid particles of `s`, whose cell ranges are `grid` (built from the current positions)
/// and whose pressures are `s.p`, as three numbers (z = 0 in 2D). Sums in f64, wall
/// particle by wall particle in storage order, each over its neighbours in the grid's order.
/// `surface`: `Setup::wall_surface` (empty unless `no_slip`).
pub fn wall_force<D: Dim>(
    p: &SphParams,
    s: &State<D>,
    grid: &Grid,
    surface: &[[f32; 4]],
    group: u32,
) -> [f64; 3] {
    wall_load(p, s, grid, surface, group, None).force
}

/// `wall_force` as a floating body's `Load` (`physics::body`): with a `centre` \[L\] the
/// torque about it \[M L^2 T^-2\], sum of (x_j - centre) x f_j over the wall particles j;
/// and the contacts: the Lennard-Jones repulsion of eq. (17) on each particle j from every
/// boundary particle of another group closer than r0 (its repulsive branch), m_j C0 [(r0/r)^p1 - (r0/r)^p2] r_ji / r,
/// with its torque. Without a centre, the force alone (a monitor).
pub fn wall_load<D: Dim>(
    p: &SphParams,
    s: &State<D>,
    grid: &Grid,
    surface: &[[f32; 4]],
    group: u32,
    centre: Option<[f64; 3]>,
) -> Load {
    let mut load = Load::default();
    let torque = |t: &mut [f64; 3], u: [f64; 3], f: [f64; 3]| {
        t[0] += u[1] * f[2] - u[2] * f[1];
        t[1] += u[2] * f[0] - u[0] * f[2];
        t[2] += u[0] * f[1] - u[1] * f[0];
    };
    for j in 0..s.len() {
        // A halo copy's force is summed by the subdomain that owns it (`SphParams::owns`).
        if s.kind[j] as u32 != MF_KIND_BOUNDARY
            || s.group[j] != group
            || !p.owns(D::comp(s.pos[j], p.own_axis as usize))
        {
            continue;
        }
        let (mut fj, mut cj) = ([0.0f64; 3], [0.0f64; 3]);
        grid.for_each_neighbor::<D>(p, &s.pos, s.pos[j], |i, r_ji, r2| {
            if s.kind[i] as u32 == MF_KIND_BOUNDARY {
                // The force stage computes no acceleration of a wall particle; a body's
                // particle meets another object's by contact.
                if centre.is_some() && s.group[i] != group && r2 < p.lj_r0 * p.lj_r0 {
                    let a = D::to3(lennard_jones::<D>(p, r_ji, r2.sqrt())); // eq. (17)
                    for (c, a) in cj.iter_mut().zip(a) {
                        *c += s.mass[j] as f64 * a as f64;
                    }
                }
                return;
            }
            // The force stage's pair term of wall particle j on particle i, alone.
            let mut f = ForceSum::new(p, s, surface, None, i, D::V::default());
            f.add(p, j, -r_ji, r2); // r_ij = x_i - x_j
            let a = D::to3(f.acc);
            for (f, a) in fj.iter_mut().zip(a) {
                *f -= s.mass[i] as f64 * a as f64;
            }
        });
        for a in 0..3 {
            load.force[a] += fj[a];
            load.contact[a] += cj[a];
        }
        if let Some(c) = centre {
            let x = D::to3(s.pos[j]);
            let u = [0, 1, 2].map(|a| x[a] as f64 - c[a]);
            torque(&mut load.torque, u, fj);
            torque(&mut load.contact_torque, u, cj);
        }
    }
    load
}
