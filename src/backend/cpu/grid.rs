//! Neighbour search: a cell grid built by sorting particles by (cell, id), then reordering
//! the storage so that a cell's particles are contiguous. Twin: `cuda/grid.cu`; parity test
//! `tests/cuda_parity.rs`. Neighbours are visited cell by cell in a fixed order
//! (z, then y, then x offsets from -1 to 1), and within a cell in storage order, on both
//! backends, so that sums run in the same order.

use rayon::prelude::*;

use crate::dim::Dim;
use crate::params::SphParams;
use crate::state::State;

/// Cell ranges of the sorted storage: particles of cell `c` are slots
/// `cell_start[c] .. cell_end[c]`.
#[derive(Clone, Debug, Default)]
pub struct Grid {
    pub cell_start: Vec<u32>,
    pub cell_end: Vec<u32>,
}

/// Integer cell coordinates of position `x` (clamped into the grid).
#[inline]
pub fn cell_coords<D: Dim>(p: &SphParams, x: D::V) -> [i32; 3] {
    let mut c = [0; 3];
    for (a, ca) in c.iter_mut().enumerate().take(D::D) {
        let v = ((D::comp(x, a) - p.domain_min[a]) / p.cell_size[a]).floor() as i32;
        *ca = v.clamp(0, p.grid_dims[a] - 1);
    }
    c
}

/// Linear cell index, x fastest.
#[inline]
pub fn cell_index(p: &SphParams, c: [i32; 3]) -> u32 {
    (c[0] + p.grid_dims[0] * (c[1] + p.grid_dims[1] * c[2])) as u32
}

/// The minimum-image separation r_i - r_j on periodic axes.
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

impl Grid {
    /// Sort `state` by (cell, id) and record the cell ranges.
    pub fn build<D: Dim>(&mut self, p: &SphParams, state: &mut State<D>) {
        let mut keys: Vec<(u64, usize)> = state
            .pos
            .par_iter()
            .zip(state.id.par_iter())
            .enumerate()
            .map(|(i, (&x, &id))| {
                let cell = cell_index(p, cell_coords::<D>(p, x)) as u64;
                ((cell << 32) | id as u64, i)
            })
            .collect();
        keys.par_sort_unstable_by_key(|k| k.0);
        let order: Vec<usize> = keys.iter().map(|k| k.1).collect();
        state.gather(&order);

        let n_cells = p.n_cells as usize;
        self.cell_start.clear();
        self.cell_start.resize(n_cells, 0);
        self.cell_end.clear();
        self.cell_end.resize(n_cells, 0);
        for (slot, k) in keys.iter().enumerate() {
            let cell = (k.0 >> 32) as usize;
            if slot == 0 || (keys[slot - 1].0 >> 32) as usize != cell {
                self.cell_start[cell] = slot as u32;
            }
            self.cell_end[cell] = slot as u32 + 1;
        }
    }

    /// Call `f(j, r_ij, r_ij^2)` for every particle j (i itself included) within the
    /// support radius of position `xi`.
    #[inline]
    pub fn for_each_neighbor<D: Dim>(
        &self,
        p: &SphParams,
        pos: &[D::V],
        xi: D::V,
        mut f: impl FnMut(usize, D::V, f32),
    ) {
        let ci = cell_coords::<D>(p, xi);
        let reach = |a: usize| if a < D::D { 1 } else { 0 };
        for dz in -reach(2)..=reach(2) {
            for dy in -reach(1)..=reach(1) {
                'cell: for dx in -reach(0)..=reach(0) {
                    let mut c = [ci[0] + dx, ci[1] + dy, ci[2] + dz];
                    for (a, ca) in c.iter_mut().enumerate().take(D::D) {
                        let n = p.grid_dims[a];
                        if *ca < 0 || *ca >= n {
                            if p.periodic[a] == 0 {
                                continue 'cell;
                            }
                            *ca = (*ca + n) % n;
                        }
                    }
                    let cell = cell_index(p, c) as usize;
                    for j in self.cell_start[cell]..self.cell_end[cell] {
                        let j = j as usize;
                        let r = separation::<D>(p, xi, pos[j]);
                        let r2 = D::length2(r);
                        if r2 < p.support2 {
                            f(j, r, r2);
                        }
                    }
                }
            }
        }
    }
}
