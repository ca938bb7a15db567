//! The device's own machinery: the `SphParams` layout as nvcc sees it, the state's round
//! trip, graph replay against single steps, captures as snapshots, and the queued health
//! check's first fault.

use super::*;
use meshfree_core::solver::Readback;

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn params_layout_matches_nvcc() {
    let setup = scene(3, V_3D_A);
    let mut g = gpu::<D3>(&setup);
    let l = g.params_layout();
    let rust = [
        std::mem::size_of::<SphParams>() as u32,
        std::mem::offset_of!(SphParams, dt) as u32,
        std::mem::offset_of!(SphParams, gravity) as u32,
        3,
    ];
    assert_eq!(
        l, rust,
        "nvcc (sizeof, offsetof dt, offsetof gravity, dim) vs Rust"
    );
    eprintln!("SphParams layout: nvcc {l:?} == rust {rust:?}");
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn state_round_trip_through_device() {
    let setup = scene(2, V_2D_A);
    let mut g = gpu::<D2>(&setup);
    let s: State<D2> = g.download_state();
    let host = State::<D2>::from_particles(&setup.particles, false, true, setup.params.solid_rho0);
    assert_eq!(s.id, host.id);
    assert_eq!(flat_v::<D2>(&s.pos), flat_v::<D2>(&host.pos));
    let back = g.particles();
    assert_eq!(back.len(), setup.particles.len());
    assert!(back
        .iter()
        .zip(&setup.particles)
        .all(|(a, b)| a.id == b.id && a.position == b.position && a.mass == b.mass));
}

/// `advance` (two steps captured as a CUDA graph, replayed) against the same number of
/// single `step` calls on the GPU: the same kernels on the same inputs, so the same state bit
/// for bit (odd counts end with single steps).
fn graph_replay<D: Dim>(dim: usize, v: Variant) {
    let setup = scene_with(dim, v, 0.05);
    let (mut a, mut b) = (gpu::<D>(&setup), gpu::<D>(&setup));
    for n in [7u64, 10, 1] {
        a.advance(n);
        for _ in 0..n {
            b.step();
        }
    }
    assert_eq!(a.steps(), b.steps());
    assert_eq!(a.time(), b.time(), "simulated time after advance vs step");
    let (pa, pb) = (a.particles(), b.particles());
    for (x, y) in pa.iter().zip(&pb) {
        assert_eq!(x.id, y.id);
        assert_eq!(
            (x.position, x.velocity, x.density),
            (y.position, y.velocity, y.density),
            "particle {} differs between graph replay and single steps",
            x.id
        );
    }
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn graph_replay_matches_single_steps_2d() {
    graph_replay::<D2>(2, V_2D_B);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn graph_replay_matches_single_steps_3d() {
    graph_replay::<D3>(3, V_3D_B);
}

/// Every field of a frame (sorted by id) as `particles()` read it back (mass aside: frames
/// carry none).
fn same_particles(what: &str, frame: &[Particle], read: &[Particle]) {
    assert_eq!(frame.len(), read.len(), "{what}: particle count");
    for (f, r) in frame.iter().zip(read) {
        let r = Particle { mass: 0.0, ..*r };
        assert_eq!(*f, r, "{what}: particle {}", r.id);
    }
}

/// Output frames (`Readback::capture`): the device-side copy taken at a step is what
/// `particles()` reads back at that step, although the solver stepped on before the frame
/// was downloaded; two frames in flight at once; a frame dropped unread gives its staging
/// set back; and the CPU backend's capture likewise.
fn capture_is_a_snapshot<D: Dim>(dim: usize, v: Variant) {
    use meshfree_core::solver::frame::{Field, Fields};
    let all = Fields::all();
    let setup = scene(dim, v);
    let mut g = gpu::<D>(&setup);
    g.advance(3);
    let at_a = g.particles();
    let a = g.capture(all);
    g.advance(5);
    let at_b = g.particles();
    let b = g.capture(all);
    g.advance(2);
    let a = a.wait().unwrap();
    assert_eq!(a.step, 3);
    assert!(
        !a.stress.is_empty(),
        "the scene has a solid: stress is captured"
    );
    same_particles("GPU frame A", &a.particles(), &at_a);
    same_particles("GPU frame B", &b.wait().unwrap().particles(), &at_b);
    // Both staging sets are free again; a frame dropped unread frees its set too.
    for _ in 0..3 {
        drop(g.capture(all));
    }
    let few = Fields::of(&[Field::Position, Field::Pressure]);
    let at_c = g.particles();
    let c = g.capture(few).wait().unwrap();
    assert!(c.velocity.is_empty() && c.id.is_empty());
    let mut pos_c: Vec<[f32; 3]> = c.position.clone();
    let mut pos_r: Vec<[f32; 3]> = at_c.iter().map(|q| q.position).collect();
    pos_c.sort_by(|x, y| x.partial_cmp(y).unwrap());
    pos_r.sort_by(|x, y| x.partial_cmp(y).unwrap());
    assert_eq!(pos_c, pos_r, "the positions of a frame without ids");

    let mut c = CpuSolver::<D>::new(setup);
    c.advance(2);
    let at = c.particles();
    let frame = c.capture(all).wait().unwrap();
    same_particles("CPU frame", &frame.particles(), &at);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn capture_is_a_snapshot_2d() {
    capture_is_a_snapshot::<D2>(2, V_2D_A);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn capture_is_a_snapshot_3d() {
    capture_is_a_snapshot::<D3>(3, V_3D_A);
}

/// A health check queued on the GPU (`Solver::queue_check`, read by `queued_fault` with
/// the clock) reports the fault that the immediate check (`Solver::check`) and the CPU's
/// check report, with the step and time of the queued check; and a later check's fault
/// does not replace the first one's.
fn queued_check_on<D: Dim>(setup: Setup) {
    let mut g = gpu::<D>(&setup);
    let mut c = CpuSolver::<D>::new(setup.clone());
    for _ in 0..3 {
        c.step();
    }
    let mut st = c.state().clone();
    g.upload_state(&st);
    assert!(
        g.queue_check().is_ok() && g.queued_fault().is_ok(),
        "a fault on a healthy state"
    );
    let fluid: Vec<usize> = (0..st.len())
        .filter(|&i| st.kind[i] == Kind::Fluid.code())
        .collect();
    let (a, b) = (fluid[fluid.len() / 2], fluid[fluid.len() / 4]);
    st.rho[a] *= 5.0;
    g.upload_state(&st);
    g.queue_check().expect("queued: nothing read back yet");
    let (step, time) = (g.steps(), g.time());
    // The CPU's check of the same particles.
    let mut faulty = setup;
    faulty.particles = st.to_particles();
    let cpu = CpuSolver::<D>::new(faulty)
        .check()
        .expect_err("the CPU's fault");
    // A second fault, at a lower slot, found by a later check.
    let rho_b = st.rho[b];
    st.rho[b] = f32::NAN;
    g.upload_state(&st);
    g.queue_check().expect("queued");
    let queued = g.queued_fault().expect_err("the queued check's fault");
    st.rho[b] = rho_b;
    g.upload_state(&st);
    let now = g.check().expect_err("the immediate check's fault");
    eprintln!("queued: {queued}\nnow:    {now}\ncpu:    {cpu}");
    assert_eq!((queued.step, queued.time), (step, time));
    for f in [&queued, &now] {
        assert_eq!(f.particle, st.id[a]);
        assert_eq!(
            (&f.kind, &f.quantity, f.value, &f.reason),
            (&cpu.kind, &cpu.quantity, cpu.value, &cpu.reason)
        );
    }
    assert_eq!(cpu.particle, st.id[a]);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn queued_check_reports_the_first_fault_2d() {
    queued_check_on::<D2>(scene_with(2, V_2D_B, 0.05));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn queued_check_reports_the_first_fault_3d() {
    queued_check_on::<D3>(scene_with(3, V_3D_B, 0.05));
}
