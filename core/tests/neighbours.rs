//! Neighbour search against brute force, with and without periodic axes, in 2D and 3D.
mod common;

use meshfree_core::backend::cpu::Grid;
use meshfree_core::physics::dim::{Dim, D2, D3};
use meshfree_core::physics::pairs::separation;
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::physics::state::State;

fn scattered(dim: usize, n: usize, lo: [f32; 3], hi: [f32; 3]) -> Vec<Particle> {
    let mut seed = 0x9e3779b97f4a7c15u64;
    (0..n)
        .map(|i| {
            let mut x = [0.0; 3];
            for a in 0..dim {
                x[a] = lo[a] + (hi[a] - lo[a]) * common::rand01(&mut seed);
            }
            Particle {
                id: i as u32,
                kind: Kind::Fluid,
                position: x,
                mass: 1.0,
                density: 1.0,
                ..Default::default()
            }
        })
        .collect()
}

fn check<D: Dim>(periodic: [i32; 3]) {
    let (lo, hi) = ([0.0; 3], [1.0, 0.8, 0.6]);
    let p = common::params(D::D as i32, 0.05, lo, hi, periodic);
    let particles = scattered(D::D, 600, lo, hi);
    let mut s = State::<D>::from_particles(&particles, false, false, p.solid_rho0);
    let mut grid = Grid::default();
    grid.build(&p, &mut s);
    // Storage is sorted by (cell, id).
    let mut last = (0u32, 0u32);
    for i in 0..s.len() {
        let c = meshfree_core::backend::cpu::cell_index(
            &p,
            meshfree_core::backend::cpu::cell_coords::<D>(&p, s.pos[i]),
        );
        assert!(
            (c, s.id[i]) > last || i == 0,
            "slot {i} not sorted by (cell, id)"
        );
        last = (c, s.id[i]);
    }
    for i in 0..s.len() {
        let mut found: Vec<usize> = Vec::new();
        grid.for_each_neighbor::<D>(&p, &s.pos, s.pos[i], |j, r, r2| {
            assert!((D::length2(r) - r2).abs() < 1e-6);
            found.push(j);
        });
        let mut want: Vec<usize> = (0..s.len())
            .filter(|&j| D::length2(separation::<D>(&p, s.pos[i], s.pos[j])) < p.support2)
            .collect();
        let mut got = found.clone();
        got.sort();
        want.sort();
        assert_eq!(
            got,
            want,
            "{}D periodic {periodic:?}: neighbours of slot {i} differ from brute force",
            D::D
        );
        assert!(found.len() == got.len(), "a neighbour was visited twice");
    }
}

#[test]
fn grid_matches_brute_force_2d() {
    check::<D2>([0, 0, 0]);
}

#[test]
fn grid_matches_brute_force_2d_periodic() {
    check::<D2>([1, 1, 0]);
}

#[test]
fn grid_matches_brute_force_3d() {
    check::<D3>([0, 0, 0]);
}

#[test]
fn grid_matches_brute_force_3d_periodic() {
    check::<D3>([1, 0, 1]);
}
