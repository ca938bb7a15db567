//! Open boundaries (`cuda/open.cu`, `launch/open.rs`) against the CPU's
//! (`backend/cpu/open.rs`) over whole steps: a channel between an inlet and an outlet, in 2D
//! and in 3D (a duct periodic across), makes the same particles with the same ids, removes
//! the same ones, tallies them alike and moves them alike; a GPU run resumed from a
//! checkpoint steps on bit for bit across creations and removals. The 3D duct's inlet is
//! parabolic across y (`profile`; uniform across z, its periodic axis), the 2D channel's
//! uniform.

use super::*;
use meshfree_core::scene::Scene;
use meshfree_core::solver::{Persist, Readback};

/// `common::open_channel` (a 2D channel or a 3D duct periodic across), its inlet started
/// over 0.02 s; the duct's parabolic.
fn channel(dim: usize) -> Setup {
    let profile = if dim == 3 {
        "\nprofile = \"parabolic\""
    } else {
        ""
    };
    let text = super::common::open_channel(dim).replacen(
        "kind = \"inlet\"",
        &format!("kind = \"inlet\"\nramp = 0.02{profile}"),
        1,
    );
    Scene::from_toml(&text, "channel-open")
        .unwrap()
        .setup()
        .unwrap()
}

fn by_id(mut v: Vec<Particle>) -> Vec<Particle> {
    v.sort_by_key(|q| q.id);
    v
}

/// `channel(dim)` with its inlet's velocity scaled by a series (issue #55): cubic through
/// 1, 1.4 and 0.6 over the first 0.04 s, then held.
fn pulsing_channel(dim: usize) -> Setup {
    let mut setup = channel(dim);
    let o = &mut setup.params.open[0];
    (o.series_first, o.series_count, o.series_cubic) = (0, 4, 1);
    setup.motion_series = vec![
        0.0, 1.0, 0.0, 0.0, 0.0, 0.015, 1.4, 0.0, 0.0, 0.0, 0.03, 0.6, 0.0, 0.0, 0.0, 10.0, 0.6,
        0.0, 0.0, 0.0,
    ];
    setup
}

fn same_channel<D: Dim>(label: &str, setup: Setup) {
    let n0 = setup.particles.len();
    let mut g = gpu::<D>(&setup);
    let again = setup.clone();
    let mut c = CpuSolver::<D>::new(setup);
    for _ in 0..30 {
        c.advance(10);
        g.advance(10);
    }
    let (tc, tg) = (c.open_tally(), g.open_tally());
    let (pc, pg) = (by_id(c.particles()), by_id(g.particles()));
    let ids = |v: &[Particle]| v.iter().map(|q| (q.id, q.group)).collect::<Vec<_>>();
    let dx = c.params().dx;
    let mut worst = 0.0f32;
    for (a, b) in pc.iter().zip(&pg) {
        for d in 0..D::D {
            worst = worst.max((a.position[d] - b.position[d]).abs());
        }
    }
    eprintln!(
        "{label}: after 300 steps (t = {:.4}) {} particles on the CPU, {} on the GPU ({n0} at \
         the start); tally CPU {tc:?} GPU {tg:?}; positions up to {worst:.3e} apart",
        c.time(),
        pc.len(),
        pg.len()
    );
    assert!(tc[0].count_in > 0 && tc[1].count_out > 0, "{tc:?}");
    assert_eq!(
        tc.iter()
            .map(|t| (t.count_in, t.count_out))
            .collect::<Vec<_>>(),
        tg.iter()
            .map(|t| (t.count_in, t.count_out))
            .collect::<Vec<_>>()
    );
    assert_eq!(
        ids(&pc),
        ids(&pg),
        "other particles or groups on the two backends"
    );
    assert!(
        worst < 0.01 * dx,
        "a particle is {worst} apart on the two backends"
    );
    // A GPU run resumed from its checkpoint steps on as the run itself, bit for bit.
    let saved = g.save();
    let mut r = gpu::<D>(&again);
    r.restore(&saved).unwrap();
    g.advance(100);
    r.advance(100);
    let bits = |v: Vec<Particle>| {
        by_id(v)
            .into_iter()
            .map(|q| (q.id, q.position.map(f32::to_bits), q.density.to_bits()))
            .collect::<Vec<_>>()
    };
    assert_eq!(g.open_tally(), r.open_tally());
    assert_eq!(
        bits(g.particles()),
        bits(r.particles()),
        "the resumed run differs"
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_2d_channel_makes_and_removes_the_same_particles_on_both_backends() {
    same_channel::<D2>("2D open channel", channel(2));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_2d_channel_with_a_pulsing_inlet_makes_the_same_particles_on_both_backends() {
    same_channel::<D2>("2D open channel, inlet on a series", pulsing_channel(2));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_3d_duct_makes_and_removes_the_same_particles_on_both_backends() {
    same_channel::<D3>("3D open duct, parabolic inlet", channel(3));
}
