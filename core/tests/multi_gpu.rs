//! Several GPUs (`backend::Layout::Gpus`, `run --gpus N`; `backend/cuda/nccl.rs`): one
//! subdomain on each GPU, halos sent through NCCL, equals the one-GPU run bit for bit in
//! every particle, on a 2D dam break (walls, a gate), a 3D dam break and a periodic
//! channel cut along its periodic axis with an inflow band. Needs a machine with 2 GPUs
//! and NCCL on the loader path (libnccl.so or libnccl.so.13): ignored everywhere else, run
//! with `--ignored` there (one-GPU machines and CI have no second GPU to test with).
#![cfg(feature = "nccl")]

mod common;

use meshfree_core::backend::{self, BackendChoice};
use meshfree_core::physics::particle::Particle;
use meshfree_core::scene::Scene;

use common::edited_scene as scene;
use meshfree_core::solver::{Setup, Solver};

/// `setup` on one GPU (`gpus` = 0) or on `gpus` GPUs, gates opened, `steps` steps.
fn run(setup: &Setup, gates: &[u32], gpus: usize, steps: u64) -> Box<dyn Solver> {
    let mut s = if gpus == 0 {
        backend::create(BackendChoice::Cuda, backend::Layout::One, setup.clone())
    } else {
        backend::create(
            BackendChoice::Cuda,
            backend::Layout::Gpus(gpus),
            setup.clone(),
        )
    }
    .unwrap_or_else(|e| panic!("this test needs {gpus} GPUs and NCCL: {e}"));
    for &g in gates {
        s.remove_group(g);
    }
    s.advance(steps);
    s
}

fn bits(q: &Particle) -> Vec<u32> {
    let mut v: Vec<u32> = q.position.iter().map(|x| x.to_bits()).collect();
    v.extend(q.velocity.iter().map(|x| x.to_bits()));
    v.extend([q.density.to_bits(), q.pressure.to_bits()]);
    v.extend(q.stress.iter().map(|x| x.to_bits()));
    v
}

fn two_gpus_equal_one(name: &str, sc: &Scene, steps: u64) {
    let setup = sc.setup().unwrap();
    let gates: Vec<u32> = sc.gates().iter().map(|g| g.0).collect();
    let mut one = run(&setup, &gates, 0, steps);
    let mut two = run(&setup, &gates, 2, steps);
    assert!(
        two.info().device.contains("2 subdomains"),
        "{:?}",
        two.info()
    );
    let (a, b) = (one.particles(), two.particles());
    assert_eq!(a.len(), b.len());
    let moved = a
        .iter()
        .zip(&setup.particles)
        .any(|(p, q)| p.position != q.position);
    assert!(moved, "{name}: nothing moved");
    for (p, q) in a.iter().zip(&b) {
        assert_eq!(p.id, q.id);
        assert!(
            bits(p) == bits(q),
            "{name}: particle {} differs:\n{p:?}\n{q:?}",
            p.id
        );
    }
    assert_eq!(one.time().to_bits(), two.time().to_bits(), "{name}: clocks");
    let cost = two.exchange_cost().expect("a decomposed solver");
    assert!(cost.bytes > 0 && cost.fills >= steps, "{cost:?}");
}

#[test]
#[ignore = "needs 2 GPUs and NCCL: run with --ignored on a multi-GPU machine"]
fn a_2d_dam_break_on_two_gpus_equals_one_gpu() {
    let sc = scene("dam-break-2d", &[("spacing = 0.02", "spacing = 0.01")]);
    two_gpus_equal_one("dam-break-2d", &sc, 200);
}

#[test]
#[ignore = "needs 2 GPUs and NCCL: run with --ignored on a multi-GPU machine"]
fn a_3d_dam_break_on_two_gpus_equals_one_gpu() {
    let sc = scene("dam-break-3d", &[("spacing = 0.04", "spacing = 0.02")]);
    two_gpus_equal_one("dam-break-3d", &sc, 100);
}

#[test]
#[ignore = "needs 2 GPUs and NCCL: run with --ignored on a multi-GPU machine"]
fn a_periodic_channel_on_two_gpus_equals_one_gpu() {
    let sc = scene("vortex-street-re105", &[]);
    two_gpus_equal_one("vortex-street-re105", &sc, 200);
}
