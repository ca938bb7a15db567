//! Neighbour search: a cell grid built by sorting particles by (cell, id), then reordering
//! the storage so that a cell's particles are contiguous. Twin: `cuda/grid.cu`; parity test
//! `tests/cuda_parity/`. Cells are at least support / `MF_CELL_REACH` wide; neighbours
//! are visited row by row in a fixed order (`rows`: z, then y offsets, then x cells), and
//! within a cell in storage order, on both backends, so that sums run in the same order.

use rayon::prelude::*;

use crate::consts::MF_PRUNE_SLACK;
use crate::physics::dim::Dim;
use crate::physics::pairs::separation;
use crate::physics::params::{SphParams, MF_CELL_REACH};
use crate::physics::state::State;

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
    /// support radius of position `xi`, in the order of `rows`.
    #[inline]
    pub fn for_each_neighbor<D: Dim>(
        &self,
        p: &SphParams,
        pos: &[D::V],
        xi: D::V,
        mut f: impl FnMut(usize, D::V, f32),
    ) {
        rows::<D>(p, xi, |row, x0, x1| {
            let nx = p.grid_dims[0];
            for cx in x0..=x1 {
                // On a periodic x axis the row wraps around; else x0..=x1 is inside the grid.
                let cell = row as usize + ((cx + nx) % nx) as usize;
                for j in self.cell_start[cell]..self.cell_end[cell] {
                    let j = j as usize;
                    let r = separation::<D>(p, xi, pos[j]);
                    let r2 = D::length2(r);
                    if r2 < p.support2 {
                        f(j, r, r2);
                    }
                }
            }
        });
    }
}

/// Squared distance [L^2] from coordinate `x` to the slab of (unwrapped) cell `c` on axis `a`.
#[inline]
fn slab_gap2(p: &SphParams, a: usize, c: i32, x: f32) -> f32 {
    let lo = p.domain_min[a] + c as f32 * p.cell_size[a];
    let g = (lo - x).max(x - (lo + p.cell_size[a])).max(0.0);
    g * g
}

/// The neighbour candidates of position `xi` as rows of cells: for each (z, y) cell offset
/// within `MF_CELL_REACH` (z outer, then y, each from -reach to reach), skipping rows whose
/// slab lies beyond the support, calls `row(first cell index of the row, x0, x1)` with the
/// x cells x0..=x1 (unwrapped on a periodic x axis) that the support's cross-section at
/// that row reaches. Within a row the cells are contiguous in storage. Twin of `rows` in
/// `cuda/device/grid.cuh`: both backends visit the same candidates in the same order.
#[inline]
pub fn rows<D: Dim>(p: &SphParams, xi: D::V, mut row: impl FnMut(u32, i32, i32)) {
    let reach = MF_CELL_REACH as i32;
    let ci = cell_coords::<D>(p, xi);
    let r2max = p.support2;
    let rz = if D::D == 3 { reach } else { 0 };
    let x = D::comp(xi, 0);
    let nx = p.grid_dims[0];
    // The pruning's relative slack: rounding never drops a neighbour.
    let slack = MF_PRUNE_SLACK as f32;
    for dz in -rz..=rz {
        let Some(cz) = wrap_cell(p, 2, ci[2] + dz) else {
            continue;
        };
        let gz = if D::D == 3 {
            slab_gap2(p, 2, ci[2] + dz, D::comp(xi, 2))
        } else {
            0.0
        };
        for dy in -reach..=reach {
            let Some(cy) = wrap_cell(p, 1, ci[1] + dy) else {
                continue;
            };
            let d2 = gz + slab_gap2(p, 1, ci[1] + dy, D::comp(xi, 1));
            if d2 > r2max * (1.0 + slack) {
                continue;
            }
            // Half-width of the support's cross-section at this row, then the x cells it spans.
            let w = (r2max - d2).max(0.0).sqrt() + slack * p.support;
            let cell_of = |v: f32| ((v - p.domain_min[0]) / p.cell_size[0]).floor() as i32;
            let mut x0 = (ci[0] - reach).max(cell_of(x - w));
            let mut x1 = (ci[0] + reach).min(cell_of(x + w));
            if p.periodic[0] == 0 {
                x0 = x0.max(0);
                x1 = x1.min(nx - 1);
            }
            if x0 > x1 {
                continue;
            }
            row((p.grid_dims[0] * (cy + p.grid_dims[1] * cz)) as u32, x0, x1);
        }
    }
}

/// Cell coordinate `c` on axis `a` wrapped on a periodic axis; `None` outside a closed one.
#[inline]
fn wrap_cell(p: &SphParams, a: usize, c: i32) -> Option<i32> {
    let n = p.grid_dims[a];
    if (0..n).contains(&c) {
        Some(c)
    } else if p.periodic[a] != 0 {
        Some((c + n) % n)
    } else {
        None
    }
}
