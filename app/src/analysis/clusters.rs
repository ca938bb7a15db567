//! Connected clusters of fluid particles (droplets): two fluid particles are connected
//! when closer than `radius` (1.5 dx by convention, `DEFAULT_FACTOR`); a cluster is a
//! connected component. Union-find over a hash grid of cell size `radius`, O(N).

use std::collections::HashMap;

use meshfree_core::physics::particle::{Kind, Particle};

/// The link radius in units of the particle spacing.
pub const DEFAULT_FACTOR: f32 = 1.5;

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Cluster label (0, 1, ...) of every fluid particle of `particles`, in their order, and
/// the number of clusters. Labels are numbered in order of first appearance.
pub fn fluid_clusters(particles: &[Particle], radius: f32) -> (Vec<usize>, usize) {
    let fluid: Vec<&[f32; 3]> = particles
        .iter()
        .filter(|q| q.kind == Kind::Fluid)
        .map(|q| &q.position)
        .collect();
    let key = |x: &[f32; 3]| x.map(|c| (c / radius).floor() as i64);
    let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, x) in fluid.iter().enumerate() {
        cells.entry(key(x)).or_default().push(i);
    }
    let mut parent: Vec<usize> = (0..fluid.len()).collect();
    let r2 = radius * radius;
    for (i, x) in fluid.iter().enumerate() {
        let k = key(x);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let Some(v) = cells.get(&[k[0] + dx, k[1] + dy, k[2] + dz]) else {
                        continue;
                    };
                    for &j in v {
                        if j <= i {
                            continue;
                        }
                        let y = fluid[j];
                        let d2: f32 = (0..3).map(|a| (x[a] - y[a]).powi(2)).sum();
                        if d2 < r2 {
                            let (a, b) = (find(&mut parent, i), find(&mut parent, j));
                            if a != b {
                                parent[a.max(b)] = a.min(b);
                            }
                        }
                    }
                }
            }
        }
    }
    let mut label = HashMap::new();
    let labels: Vec<usize> = (0..fluid.len())
        .map(|i| {
            let root = find(&mut parent, i);
            let next = label.len();
            *label.entry(root).or_insert(next)
        })
        .collect();
    let n = label.len();
    (labels, n)
}

/// The number of fluid clusters (0 without fluid).
pub fn count_fluid_clusters(particles: &[Particle], radius: f32) -> usize {
    fluid_clusters(particles, radius).1
}
