//! The neighbour passes against each other on the GPU: the fused pass against the two
//! separate ones, the rates pass replaying the forces pass's accepted candidates against one
//! that tests them, and the walls at rest that the passes skip.

use super::*;

/// The fused `forces_and_rates` pass against `rates` then `forces` on the GPU, from one
/// state, at every lane count: each sum runs over the same neighbours in the same order, so
/// rates and the step size agree bit for bit, and the accelerations to `ACC_REL` of their
/// scale.
///
/// Why not the accelerations bit for bit: nvcc's default `-fmad=true` lets ptxas fuse a
/// product and a sum into one FMA where it schedules them, and the two kernels inline the
/// same `ForceSum::add` into different code. Since the extrapolated fluid-body pair (da6ff87)
/// that fusion differs between them in a body's sums, whose terms (the stress and the
/// fluid's pressure) cancel to much less than themselves: on the H100 (2026-12-06), 25 of
/// 2664 particles of the 3D scene, all of the body, 1 ulp apart at one build; 5 more than
/// 2 ulp of their own components at the next (at most 16 ulp of a component near zero;
/// 3e-7 in 1.47 m/s^2). A wrong neighbour, order or term moves an acceleration by a pair's
/// contribution, of the order of g.
fn fused_equals_two_passes<D: Dim>(what: &str, setup: Setup) {
    let mut g = gpu::<D>(&setup);
    g.build_grid();
    g.density();
    g.solid_interface();
    g.density_gradient();
    let start = g.download_state();
    for lanes in [8, 4, 2, 1] {
        g.set_lanes(Some(lanes));
        g.upload_state(&start);
        g.rates();
        g.forces();
        g.time_step();
        let (two, dt2) = (g.download_state(), g.dt());
        g.upload_state(&start);
        g.forces_and_rates();
        g.time_step();
        let (one, dt1) = (g.download_state(), g.dt());
        same_vectors::<D>(
            &format!("{what}, {lanes} lanes: acc"),
            &two,
            (&two.acc, &one.acc),
            (ACC_REL, gravity(&setup)),
        );
        same_vectors::<D>(
            &format!("{what}, {lanes} lanes: xsph"),
            &two,
            (&two.xsph, &one.xsph),
            (0.0, 0.0),
        );
        assert_eq!(two.drho, one.drho, "{what}, {lanes} lanes: drho");
        if let (Some(a), Some(b)) = (&two.solid, &one.solid) {
            assert_eq!(
                flat_m::<D>(&a.stress_rate),
                flat_m::<D>(&b.stress_rate),
                "{what}, {lanes} lanes: stress rate"
            );
        }
        assert_eq!(dt2, dt1, "{what}, {lanes} lanes: dt");
    }
    eprintln!("{what}: fused pass = rates + forces at 8, 4, 2 and 1 lanes");
}

/// |g| of a setup [L/T^2].
fn gravity(setup: &Setup) -> f32 {
    setup
        .params
        .gravity
        .iter()
        .map(|g| g * g)
        .sum::<f32>()
        .sqrt()
}

/// How far the fused pass's accelerations may be from the two passes', relative to their
/// scale: the particle's largest component plus |g| (a particle at rest sums terms of g's
/// size to nearly zero). 1e-6 is about 8 ulp of the scale.
const ACC_REL: f32 = 1e-6;

/// Asserts that the per-particle vectors of the two passes and of the fused pass (`ab`)
/// agree to `rel` x (the two passes' largest component + `floor`) in every component (0:
/// bit for bit); else names the first particle that differs by more (slot, id, kind, both
/// values), how many do, and the largest difference over its scale.
fn same_vectors<D: Dim>(
    what: &str,
    st: &State<D>,
    (a, b): (&[D::V], &[D::V]),
    (rel, floor): (f32, f32),
) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    // Each particle's largest difference over its scale; infinite where a value is not
    // finite, 0 where they are bit for bit the same.
    let apart = |i: usize| -> f32 {
        let (x, y) = (D::to3(a[i]), D::to3(b[i]));
        if x.map(f32::to_bits) == y.map(f32::to_bits) {
            return 0.0;
        }
        if !x.iter().chain(&y).all(|v| v.is_finite()) {
            return f32::INFINITY;
        }
        let scale = x.iter().fold(0.0f32, |m, v| m.max(v.abs())) + floor;
        let d = (0..3).fold(0.0f32, |m, c| m.max((x[c] - y[c]).abs()));
        if scale > 0.0 {
            d / scale
        } else {
            f32::INFINITY
        }
    };
    let gaps: Vec<f32> = (0..a.len()).map(apart).collect();
    let most = gaps.iter().copied().fold(0.0f32, f32::max);
    let differ: Vec<usize> = (0..a.len())
        .filter(|&i| gaps[i] > rel || (rel == 0.0 && gaps[i] > 0.0))
        .collect();
    if let Some(&i) = differ.first() {
        panic!(
            "{what}: {} of {} particles differ by more than {rel} of their scale (at most \
             {most:e}); the first, slot {i} (id {}, kind {}): two passes {:?}, fused {:?}",
            differ.len(),
            a.len(),
            st.id[i],
            st.kind[i],
            D::to3(a[i]),
            D::to3(b[i])
        );
    }
    if most > 0.0 {
        eprintln!(
            "{what}: {} particles not bit for bit, within {most:e} of their scale",
            gaps.iter().filter(|&&g| g > 0.0).count()
        );
    }
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn fused_pass_equals_two_passes_2d() {
    fused_equals_two_passes::<D2>("2D V_2D_A", scene(2, V_2D_A));
    fused_equals_two_passes::<D2>("2D V_2D_DELTA fluid only", fluid_only(2, V_2D_DELTA));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn fused_pass_equals_two_passes_3d() {
    fused_equals_two_passes::<D3>("3D V_3D_B", scene(3, V_3D_B));
    fused_equals_two_passes::<D3>("3D V_3D_B fluid only", fluid_only(3, V_3D_B));
    fused_equals_two_passes::<D3>("3D V_3D_A fluid only", fluid_only(3, V_3D_A));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn fused_pass_equals_two_passes_no_slip_walls() {
    let (s2, s3) = (scene(2, V_2D_A), fluid_only(3, V_3D_B));
    fused_equals_two_passes::<D2>("2D V_2D_A + no-slip walls", with_no_slip(s2, 2.0));
    fused_equals_two_passes::<D3>("3D V_3D_B fluid only + no-slip", with_no_slip(s3, 2.0));
}

/// The rates pass of one lane per particle from the forces pass's record of accepted
/// candidates (`PairBits` in cuda/device/neighbours.cuh) against the rates pass that tests
/// every candidate, from one state: the same neighbours in the same order, so d rho/dt, XSPH
/// and the stress rate agree bit for bit. The record holds 256 candidates a particle in 3D
/// and 192 in 2D: at h = 1.3 dx every particle's fit (about 180 and 40); at h = 2 dx in 3D
/// and 4 dx in 2D most particles' overflow it, and the rates pass tests the candidates past
/// it. The rates are taken as a step takes them, after the step size and the kick (under
/// the leapfrog each pair at the drift's midpoint, r + dt/2 (v_i - v_j), from the record of
/// x^n's candidates).
fn replayed_rates_equal_tested<D: Dim>(what: &str, mut setup: Setup, h_over_dx: f32) {
    setup.params.h = h_over_dx * setup.params.dx;
    params::derive(&mut setup.params);
    let mut g = gpu::<D>(&setup);
    g.set_lanes(Some(1));
    g.build_grid();
    g.density();
    g.solid_interface();
    g.density_gradient();
    let start = g.download_state();
    g.forces();
    assert!(
        g.rates_replay_pairs(),
        "{what}: a forces pass of one lane records its candidates"
    );
    g.time_step();
    g.kick();
    assert!(
        g.rates_replay_pairs(),
        "{what}: the record holds across the step size and the kick"
    );
    let kicked = g.download_state();
    // An upload moves the particles: the record goes, and the rates pass tests.
    g.upload_state(&kicked);
    assert!(
        !g.rates_replay_pairs(),
        "{what}: the record outlived an upload"
    );
    g.rates();
    let tested = g.download_state();
    g.upload_state(&start);
    g.forces();
    g.time_step();
    g.kick();
    g.rates();
    let replayed = g.download_state();
    assert_eq!(
        flat_v::<D>(&tested.xsph),
        flat_v::<D>(&replayed.xsph),
        "{what}: xsph"
    );
    assert_eq!(tested.drho, replayed.drho, "{what}: drho");
    if let (Some(a), Some(b)) = (&tested.solid, &replayed.solid) {
        assert_eq!(
            flat_m::<D>(&a.stress_rate),
            flat_m::<D>(&b.stress_rate),
            "{what}: stress rate"
        );
    }
    g.drift();
    assert!(
        !g.rates_replay_pairs(),
        "{what}: the record outlived a drift"
    );
    eprintln!("{what}, h = {h_over_dx} dx: replayed rates = tested rates, bit for bit");
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn replayed_rates_equal_tested_2d() {
    for h in [1.3, 4.0] {
        replayed_rates_equal_tested::<D2>("2D V_2D_A", scene(2, V_2D_A), h);
        replayed_rates_equal_tested::<D2>("2D V_2D_B", scene(2, V_2D_B), h);
        let lean = fluid_only(2, V_2D_LEAN);
        replayed_rates_equal_tested::<D2>("2D V_2D_LEAN fluid only", lean, h);
        let delta = fluid_only(2, V_2D_DELTA);
        replayed_rates_equal_tested::<D2>("2D V_2D_DELTA fluid only", delta, h);
        let b = leapfrog(scene(2, V_2D_B));
        replayed_rates_equal_tested::<D2>("2D V_2D_B leapfrog", b, h);
    }
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn replayed_rates_equal_tested_3d() {
    for h in [1.3, 2.0] {
        replayed_rates_equal_tested::<D3>("3D V_3D_B", scene(3, V_3D_B), h);
        replayed_rates_equal_tested::<D3>("3D V_3D_A fluid only", fluid_only(3, V_3D_A), h);
        let lean = fluid_only(3, V_3D_LEAN);
        replayed_rates_equal_tested::<D3>("3D V_3D_LEAN fluid only", lean, h);
        let delta = leapfrog(fluid_only(3, V_3D_DELTA));
        replayed_rates_equal_tested::<D3>("3D V_3D_DELTA fluid only leapfrog", delta, h);
    }
}

/// In 3D the neighbour passes walk, for a dynamic wall, only the candidate rows that hold a
/// moving particle, and none where all its candidates are walls at rest (`walked_rows` in
/// cuda/device/grid.cuh: a pair of walls at rest adds 0 to eq. (8)'s d rho/dt). From one
/// state, a step's forces, kick and rates after a grid build at one lane (the rows near
/// moving particles stamped, the skip on) and after an upload (no stamps: every wall walks
/// all its candidates) give the same rates. Part of the side walls above the water are given
/// a velocity across themselves (not driven: it stays, a wall that moves nothing), so that
/// they and their wall neighbours have rates that are not zero: a moving wall must walk the
/// rows of walls at rest around it, its neighbours the rows that hold it.
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn walls_at_rest_are_skipped_exactly_3d() {
    let mut setup = scene(3, V_3D_B);
    let dx = setup.params.dx;
    // Fluid below y = 0.8 (+ 0.1 dx of jitter), support 2.6 dx: the side walls' rows at
    // y = 1.15 are out of its reach, those at 1.05 too (0.3 - 0.01 > 0.26).
    let top = |q: &Particle| q.kind == Kind::Boundary && q.position[1] > 1.1;
    let near_side = |q: &Particle| q.position[2] < 0.0;
    for q in setup.particles.iter_mut() {
        if top(q) && near_side(q) {
            q.velocity = [0.0, 0.2, 0.0];
        }
    }
    let mut g = gpu::<D3>(&setup);
    g.set_lanes(Some(1));
    g.build_grid();
    assert!(
        g.skips_walls_at_rest(),
        "a grid build at one lane in 3D stamps"
    );
    g.density();
    g.solid_interface();
    let start = g.download_state();
    let step = |g: &mut CudaSolver<D3>| {
        g.forces();
        g.time_step();
        g.kick();
        g.density_gradient();
        g.rates();
        g.download_state()
    };
    let skipped = step(&mut g);
    g.upload_state(&start);
    assert!(!g.skips_walls_at_rest(), "an upload drops the stamps");
    let walked = step(&mut g);
    assert_eq!(
        skipped.drho, walked.drho,
        "d rho/dt with and without the skip"
    );
    assert_eq!(
        flat_v::<D3>(&skipped.xsph),
        flat_v::<D3>(&walked.xsph),
        "xsph with and without the skip"
    );
    // What the test covers: walls of both sorts above the water.
    let drho = walked.drho.as_ref().expect("continuity density");
    let (mut at_rest, mut beside_moving, mut moving) = (0, 0, 0);
    for (((&k, x), v), &d) in walked
        .kind
        .iter()
        .zip(&walked.pos)
        .zip(&walked.vel)
        .zip(drho)
    {
        let wall = k as u32 == MF_KIND_BOUNDARY;
        let (y, z) = (x[1], x[2]);
        if wall && y > 1.0 && z > 2.0 * dx {
            at_rest += (d == 0.0) as usize;
        }
        if wall && y > 1.0 && y < 1.1 && z < 0.0 && d != 0.0 {
            beside_moving += 1;
        }
        if wall && v[1] != 0.0 && d != 0.0 {
            moving += 1;
        }
    }
    assert!(
        at_rest > 0,
        "no wall at rest among walls at rest above the water"
    );
    assert!(
        beside_moving > 0,
        "no wall at rest with a non-zero rate beside the moving walls"
    );
    assert!(moving > 0, "no moving wall with a non-zero rate");
    eprintln!(
        "walls at rest skipped: {at_rest} with rate 0 far from motion, {beside_moving} beside moving walls and {moving} moving walls with a rate, as when walking every row"
    );
}
