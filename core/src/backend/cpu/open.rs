//! The open-boundary stage (`Solver::open_boundaries`): each fluid particle's `fate`
//! (`physics::open`) applied, in storage order, and the buffers' densities. Twin:
//! `cuda/open.cu` (launched by `backend/cuda/launch/open.rs`); parity test:
//! `tests/cuda_parity/open.rs`.

use rayon::prelude::*;

use crate::physics::dim::Dim;
use crate::physics::open::{fate, Fate, OpenState};
use crate::physics::params::SphParams;
use crate::physics::state::State;

/// Apply every particle's fate: groups changed in place, the particles removed dropped (the
/// others keep their order), and the new inlet buffer particles appended after them, in the
/// storage order of the particles they replace, with ids from `open.next_id` on. The tally
/// counts each boundary's particles and mass in and out. Returns whether the particles
/// changed (the grid must be rebuilt).
pub fn open_boundaries<D: Dim>(p: &SphParams, s: &mut State<D>, open: &mut OpenState) -> bool {
    if p.open_count == 0 {
        return false;
    }
    let fates: Vec<Fate> = (0..s.len())
        .into_par_iter()
        .map(|i| fate(p, s.kind[i], s.group[i], D::to3(s.pos[i])))
        .collect();
    if fates.iter().all(|f| *f == Fate::Keep) {
        return false;
    }
    open.tally.resize(p.open_count as usize, Default::default());
    // The copies first, while their parents still hold the inlet's group.
    let parents: Vec<usize> = (0..s.len())
        .filter(|&i| matches!(fates[i], Fate::Spawn(_)))
        .collect();
    let mut born = s.select(&parents);
    for (k, &i) in parents.iter().enumerate() {
        let Fate::Spawn(b) = fates[i] else {
            unreachable!()
        };
        let o = &p.open[b];
        born.id[k] = open.next_id + k as u32;
        born.pos[k] = D::from3(o.behind(D::to3(s.pos[i])));
        let t = &mut open.tally[b];
        t.count_in += 1;
        t.mass_in += s.mass[i] as f64;
    }
    open.next_id += parents.len() as u32;
    for (i, f) in fates.iter().enumerate() {
        match *f {
            Fate::Keep => {}
            Fate::Spawn(b) | Fate::Leave(b) => s.group[i] = p.open[b].through as u32,
            Fate::Enter(b) => s.group[i] = p.open[b].group as u32,
            Fate::Remove(b) => {
                let t = &mut open.tally[b];
                t.count_out += 1;
                t.mass_out += s.mass[i] as f64;
            }
        }
    }
    s.retain(|i| !matches!(fates[i], Fate::Remove(_)));
    s.extend(&born);
    true
}

/// The open boundaries' buffer densities [M L^-d] and pressures, after the density stage's
/// (Tafuni et al. 2018's conditions): an inlet's particle at s < 0 behind the plane takes the
/// fluid's density at its mirror node x + 2 |s| n in the fluid (n the inward normal), by the
/// first-order corrected interpolation of the fluid particles outside every buffer
/// (`mdbc::GhostSums`, as mDBC's ghost nodes; it keeps its density where no fluid is near):
/// the pressure's zero gradient across the plane, so that the fluid sets the pressure an
/// inflow needs; an outlet's particle takes rho0, the reference pressure (0, or
/// `background_pressure`). Nothing without open boundaries. Twin: `sph_buffer_density` in
/// `cuda/open.cu`.
pub fn buffer_density<D: Dim>(p: &SphParams, grid: &super::grid::Grid, s: &mut State<D>) {
    if p.open_count == 0 {
        return;
    }
    let (pos, kind, mass, rho, group) = (&s.pos, &s.kind, &s.mass, &s.rho, &s.group);
    let new: Vec<Option<f32>> = (0..s.len())
        .into_par_iter()
        .map(|i| {
            let b = crate::physics::open::open_index(p, group[i])?;
            let o = &p.open[b];
            if !o.is_inlet() {
                return Some(p.rho0);
            }
            let mut xg = pos[i];
            let a = o.axis as usize;
            let mirrored = D::comp(xg, a) - 2.0 * o.side(D::to3(pos[i])) * o.sign;
            D::set_comp(&mut xg, a, mirrored);
            let mut g = crate::physics::mdbc::GhostSums::default();
            grid.for_each_neighbor::<D>(p, pos, xg, |j, r, r2| {
                if kind[j] as u32 == crate::physics::params::MF_KIND_FLUID
                    && crate::physics::open::open_index(p, group[j]).is_none()
                {
                    let len = r2.sqrt();
                    let (w, f) = (
                        crate::physics::kernel::w(p, len),
                        crate::physics::kernel::f(p, len),
                    );
                    g.add(D::D, &D::to3(r), w, f, mass[j], rho[j]);
                }
            });
            Some(g.density(D::D, p.rho0, p.dx).unwrap_or(rho[i]))
        })
        .collect();
    for (i, n) in new.into_iter().enumerate() {
        if let Some(r) = n {
            s.rho[i] = r;
            s.p[i] = super::density::pressure(p, s.kind[i], r, 0.0);
        }
    }
}
