//! A triangle surface's edges: an edge used by one triangle only is open; the open edges
//! joined at their vertices make holes, each as wide as the box of its vertices.

use std::collections::HashMap;

use rayon::prelude::*;

/// What `meshfree check` reports of a surface's edges.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Topology {
    /// Edges used by one triangle only.
    pub open_edges: usize,
    /// Connected sets of open edges.
    pub holes: usize,
    /// \[L\] the diagonal of the largest hole's box (0: closed).
    pub largest_hole: f64,
    /// \[L\] the centre of that box.
    pub hole_at: [f64; 3],
    /// Edges used by more than two triangles (a non-manifold surface: the winding number
    /// still decides inside and outside).
    pub shared_edges: usize,
}

impl Topology {
    pub fn of(v: &[[f64; 3]], tris: &[[u32; 3]]) -> Topology {
        // Every edge as (low vertex, high vertex) in one u64, sorted: a run of equal keys is
        // one edge and its length the triangles that use it.
        let mut keys: Vec<u64> = tris
            .par_iter()
            .flat_map_iter(|t| {
                (0..3).map(move |k| {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
                })
            })
            .collect();
        keys.par_sort_unstable();
        let mut open: Vec<(u32, u32)> = Vec::new();
        let mut shared_edges = 0;
        for run in keys.chunk_by(|a, b| a == b) {
            match run.len() {
                1 => open.push(((run[0] >> 32) as u32, run[0] as u32)),
                2 => {}
                _ => shared_edges += 1,
            }
        }
        // Union-find over the open edges' vertices.
        let mut parent: HashMap<u32, u32> = HashMap::new();
        fn root(parent: &mut HashMap<u32, u32>, x: u32) -> u32 {
            let mut r = x;
            while let Some(&p) = parent.get(&r).filter(|&&p| p != r) {
                r = p;
            }
            parent.insert(x, r);
            r
        }
        for &(a, b) in &open {
            parent.entry(a).or_insert(a);
            parent.entry(b).or_insert(b);
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            if ra != rb {
                parent.insert(ra, rb);
            }
        }
        let mut boxes: HashMap<u32, ([f64; 3], [f64; 3])> = HashMap::new();
        let vertices: Vec<u32> = parent.keys().copied().collect();
        for x in vertices {
            let r = root(&mut parent, x);
            let p = v[x as usize];
            let b = boxes.entry(r).or_insert((p, p));
            for (a, x) in p.iter().enumerate() {
                b.0[a] = b.0[a].min(*x);
                b.1[a] = b.1[a].max(*x);
            }
        }
        let mut t = Topology {
            open_edges: open.len(),
            holes: boxes.len(),
            shared_edges,
            ..Default::default()
        };
        for (lo, hi) in boxes.values() {
            let d = (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum::<f64>().sqrt();
            if d > t.largest_hole {
                t.largest_hole = d;
                t.hole_at = std::array::from_fn(|a| 0.5 * (lo[a] + hi[a]));
            }
        }
        t
    }
}
