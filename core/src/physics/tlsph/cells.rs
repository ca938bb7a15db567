//! The candidate search of the reference set-up (`Reference::new`, `faces`): points filed in
//! cells at least one support wide, so that every point within a support of x lies in the
//! 3^d cells around x's.
//!
//! On a periodic axis the cells tile the period, n = floor(len / support) cells of len / n
//! each (n >= 3 in a valid scene: `scene::validate` asks the neighbour grid for 3 cells of
//! 2h), and wrap, as the neighbour grid's do (`backend/cpu/grid.rs`): a body or a clamp that
//! crosses the seam finds its neighbours on the other side, and the callers measure the pair
//! by the minimum image (`pairs::separation`). On the other axes the cells are one support
//! wide from the origin and unbounded (a clamp's face point may lie a little outside the
//! domain).

use std::collections::HashMap;
use std::marker::PhantomData;

use crate::physics::dim::Dim;
use crate::physics::params::SphParams;

/// Points (by their index in the list they came from) filed by cell.
pub struct Cells<D: Dim> {
    map: HashMap<[i32; 3], Vec<u32>>,
    /// [L] the cells' width on each axis.
    width: [f32; 3],
    /// [L] the domain's lower corner and length (periodic axes).
    min: [f32; 3],
    len: [f32; 3],
    /// The number of cells round a periodic axis; 0 on the others.
    wrap: [i32; 3],
    dim: PhantomData<D>,
}

impl<D: Dim> Cells<D> {
    /// The cells of `points`.
    pub fn new(p: &SphParams, points: impl IntoIterator<Item = D::V>) -> Self {
        let mut c = Cells {
            map: HashMap::new(),
            width: [p.support; 3],
            min: p.domain_min,
            len: [0.0; 3],
            wrap: [0; 3],
            dim: PhantomData,
        };
        for a in 0..D::D {
            if p.periodic[a] != 0 {
                c.len[a] = p.domain_max[a] - p.domain_min[a];
                c.wrap[a] = ((c.len[a] / p.support).floor() as i32).max(1);
                c.width[a] = c.len[a] / c.wrap[a] as f32;
            }
        }
        for (m, x) in points.into_iter().enumerate() {
            let k = c.key(x);
            c.map.entry(k).or_default().push(m as u32);
        }
        c
    }

    /// The cell of position `x` (wrapped into the period on a periodic axis).
    fn key(&self, x: D::V) -> [i32; 3] {
        let mut k = [0i32; 3];
        for (a, ka) in k.iter_mut().enumerate().take(D::D) {
            let v = D::comp(x, a);
            *ka = if self.wrap[a] > 0 {
                // rem_euclid may round up to len itself: the last cell.
                let rel = (v - self.min[a]).rem_euclid(self.len[a]);
                ((rel / self.width[a]).floor() as i32).min(self.wrap[a] - 1)
            } else {
                (v / self.width[a]).floor() as i32
            };
        }
        k
    }

    /// The points in the 3^d cells around x (one cell each way, round a periodic axis), each
    /// once: cell by cell (z, then y, then x offsets), within a cell in the order filed.
    pub fn around(&self, x: D::V) -> Vec<u32> {
        let c = self.key(x);
        let reach_z = if D::D == 3 { 1 } else { 0 };
        let mut keys = Vec::with_capacity(27);
        for dz in -reach_z..=reach_z {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let mut k = [c[0] + dx, c[1] + dy, c[2] + dz];
                    for (a, ka) in k.iter_mut().enumerate() {
                        if self.wrap[a] > 0 {
                            *ka = ka.rem_euclid(self.wrap[a]);
                        }
                    }
                    // Fewer than 3 cells round a periodic axis would visit a cell twice.
                    if !keys.contains(&k) {
                        keys.push(k);
                    }
                }
            }
        }
        keys.iter()
            .filter_map(|k| self.map.get(k))
            .flatten()
            .copied()
            .collect()
    }
}
