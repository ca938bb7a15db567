//! `analysis::clusters`: connected components of fluid particles (links under a radius).

use meshfree::analysis::clusters::{count_fluid_clusters, fluid_clusters};
use meshfree_core::physics::particle::{Kind, Particle};

fn at(x: f32, y: f32, kind: Kind) -> Particle {
    Particle {
        kind,
        position: [x, y, 0.0],
        ..Default::default()
    }
}

/// A row of `n` fluid particles from `x0`, spacing `dx`, at height `y`.
fn row(x0: f32, n: usize, dx: f32, y: f32) -> Vec<Particle> {
    (0..n)
        .map(|i| at(x0 + i as f32 * dx, y, Kind::Fluid))
        .collect()
}

#[test]
fn separate_blocks_are_separate_clusters() {
    let dx = 0.1;
    let r = 1.5 * dx;
    // Two rows 2 dx apart end to end: two clusters; at dx: one.
    let mut ps = row(0.0, 10, dx, 0.0);
    ps.extend(row(0.9 + 2.0 * dx, 10, dx, 0.0));
    assert_eq!(count_fluid_clusters(&ps, r), 2);
    let mut joined = row(0.0, 10, dx, 0.0);
    joined.extend(row(1.0, 10, dx, 0.0));
    assert_eq!(count_fluid_clusters(&joined, r), 1);
    // Labels: the first row is cluster 0, the second 1.
    let (labels, n) = fluid_clusters(&ps, r);
    assert_eq!(n, 2);
    assert!(labels[..10].iter().all(|&l| l == 0) && labels[10..].iter().all(|&l| l == 1));
    // A diagonal neighbour at sqrt(2) dx < 1.5 dx links; one at 1.6 dx does not.
    let diag = vec![at(0.0, 0.0, Kind::Fluid), at(dx, dx, Kind::Fluid)];
    assert_eq!(count_fluid_clusters(&diag, r), 1);
    let far = vec![at(0.0, 0.0, Kind::Fluid), at(1.6 * dx, 0.0, Kind::Fluid)];
    assert_eq!(count_fluid_clusters(&far, r), 2);
    // Wall particles neither count nor bridge; negative coordinates work; none -> 0.
    let mut bridged = row(-1.0, 5, dx, -0.5);
    bridged.push(at(-0.5, -0.5, Kind::Boundary));
    bridged.extend(row(-0.4, 5, dx, -0.5));
    assert_eq!(count_fluid_clusters(&bridged, r), 2);
    assert_eq!(count_fluid_clusters(&[], r), 0);
    // A U shape whose arms join only at the bottom: one cluster (union-find across cells).
    let mut u = row(0.0, 20, dx, 0.0);
    for k in 1..15 {
        u.push(at(0.0, k as f32 * dx, Kind::Fluid));
        u.push(at(1.9, k as f32 * dx, Kind::Fluid));
    }
    assert_eq!(count_fluid_clusters(&u, r), 1);
}
