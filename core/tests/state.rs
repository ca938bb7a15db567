//! Composite <-> raw arrays round trip (the paper's conversion), and the artificial-stress
//! eigen-decomposition.
mod common;

use meshfree_core::backend::cpu::{artificial_stress, jacobi_eigen};
use meshfree_core::physics::dim::{Dim, D2, D3};
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::physics::state::State;

fn sample(dim: usize) -> Vec<Particle> {
    let mut seed = 7u64;
    let mut r = || common::rand01(&mut seed) * 2.0 - 1.0;
    (0..50)
        .map(|i| {
            let kind = Kind::ALL[i % 3];
            let z = |v: f32| if dim == 3 { v } else { 0.0 };
            let mut stress = [r(), r(), z(r()), r(), z(r()), z(r())];
            if kind != Kind::Solid {
                stress = [0.0; 6];
            }
            Particle {
                id: (49 - i) as u32,
                kind,
                group: (i % 4) as u32,
                position: [r(), r(), z(r())],
                velocity: [r(), r(), z(r())],
                density: 1.0 + r(),
                pressure: r(),
                mass: 0.5 + r().abs(),
                stress,
            }
        })
        .collect()
}

fn round_trip<D: Dim>() {
    let mut ps = sample(D::D);
    let s = State::<D>::from_particles(&ps, true, true, 1.0);
    assert!(s.drho.is_some() && s.solid.is_some());
    let back = s.to_particles();
    ps.sort_by_key(|p| p.id);
    assert_eq!(back, ps, "{}D round trip changed a particle", D::D);
    // Reordering keeps every particle whole.
    let order: Vec<usize> = (0..s.len()).rev().collect();
    let mut t = s.clone();
    t.gather(&order);
    assert_eq!(t.to_particles(), ps);
}

#[test]
fn particles_round_trip_2d() {
    round_trip::<D2>();
}

#[test]
fn particles_round_trip_3d() {
    round_trip::<D3>();
}

#[test]
fn fluid_only_state_allocates_no_stress() {
    let ps: Vec<Particle> = sample(2)
        .into_iter()
        .filter(|p| p.kind != Kind::Solid)
        .collect();
    let s = State::<D2>::from_particles(&ps, false, true, 1.0);
    assert!(s.solid.is_none(), "no solid particles: no stress arrays");
    assert!(s.drho.is_none(), "summation density: no d rho/dt array");
}

#[test]
fn jacobi_diagonalises_symmetric_matrices() {
    let a = [[4.0, 1.0, -2.0], [1.0, 2.0, 0.5], [-2.0, 0.5, -3.0]];
    let (l, v) = jacobi_eigen(a, 3);
    for k in 0..3 {
        for r in 0..3 {
            let av: f32 = (0..3).map(|c| a[r][c] * v[c][k]).sum();
            assert!(
                (av - l[k] * v[r][k]).abs() < 1e-4,
                "A v != lambda v for eigenpair {k}"
            );
        }
    }
    let trace: f32 = l.iter().sum();
    assert!((trace - 3.0).abs() < 1e-4);
}

#[test]
fn artificial_stress_acts_only_on_tension() {
    // Pure compression: no artificial stress. Uniaxial tension along x in 2D: R_xx < 0 only.
    let comp = D2::sym_from6([-1.0, -2.0, 0.0, 0.1, 0.0, 0.0]);
    assert_eq!(
        artificial_stress::<D2>(comp, 1.0, 0.3),
        D2::sym_from6([0.0; 6])
    );
    let tens = D2::sym_from6([2.0, -1.0, 0.0, 0.0, 0.0, 0.0]);
    let r = D2::sym_to6(artificial_stress::<D2>(tens, 2.0, 0.3));
    assert!(
        (r[0] + 0.3 * 2.0 / 4.0).abs() < 1e-6 && r[1].abs() < 1e-6 && r[3].abs() < 1e-6,
        "{r:?}"
    );
    let tens3 = D3::sym_from6([0.0, 3.0, -1.0, 0.0, 0.0, 0.0]);
    let r3 = D3::sym_to6(artificial_stress::<D3>(tens3, 1.0, 0.2));
    assert!(
        (r3[1] + 0.6).abs() < 1e-5 && r3[0].abs() < 1e-5 && r3[2].abs() < 1e-5,
        "{r3:?}"
    );
}
