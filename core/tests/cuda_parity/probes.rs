//! Probes (`Readback::sample_points`, `cuda/probes.cu`) against the CPU's at points over the
//! domain, and sampling that leaves the GPU's stepping unchanged, bit for bit.

use super::*;
use meshfree_core::solver::Readback;

/// A lattice of points over the parity scene's domain, offset from the cells' corners: in
/// the fluid, in the body, among the walls and above the fluid out of every particle's reach.
fn probe_points(p: &SphParams) -> Vec<[f32; 3]> {
    let dim = p.dim as usize;
    let n = [9, 13, if dim == 3 { 5 } else { 1 }];
    let mut out = Vec::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let c = [i, j, k];
                let mut x = [0.0f32; 3];
                for a in 0..dim {
                    let (lo, hi) = (p.domain_min[a], p.domain_max[a]);
                    x[a] = lo + (hi - lo) * (c[a] as f32 + 0.37) / n[a] as f32;
                }
                out.push(x);
            }
        }
    }
    out
}

/// The CPU's and the GPU's samples at the same points: NaN at the same points, the same
/// neighbours (to one at the support's edge, where |r|^2 may round either way), values
/// within the density stage's tolerances times `scale` (1 from one state; more where the
/// two stepped apart).
fn cmp_samples(what: &str, p: &SphParams, c: &[PointSample], g: &[PointSample], scale: f32) {
    assert_eq!(c.len(), g.len(), "{what}: sample counts differ");
    let dim = p.dim as usize;
    for (k, (a, b)) in c.iter().zip(g).enumerate() {
        assert!(
            a.neighbours.abs_diff(b.neighbours) <= 1,
            "{what}: point {k}: cpu {} gpu {} neighbours",
            a.neighbours,
            b.neighbours
        );
        assert_eq!(
            (
                a.pressure.is_nan(),
                a.density.is_nan(),
                a.velocity[0].is_nan()
            ),
            (
                b.pressure.is_nan(),
                b.density.is_nan(),
                b.velocity[0].is_nan()
            ),
            "{what}: point {k}: NaN on one side only (cpu {a:?}, gpu {b:?})"
        );
    }
    let ids: Vec<u32> = (0..c.len() as u32).collect();
    let num = |v: f32| if v.is_nan() { 0.0 } else { v };
    let col = |s: &[PointSample], f: &dyn Fn(&PointSample) -> Vec<f32>| -> Vec<f32> {
        s.iter().flat_map(f).map(num).collect()
    };
    let (pc, pg) = (col(c, &|q| vec![q.pressure]), col(g, &|q| vec![q.pressure]));
    let tol_p = 2e-5 * scale * p.tait_b * p.tait_gamma;
    close(
        &format!("{what} pressure"),
        &ids,
        1,
        &pc,
        &pg,
        1e-4 * scale,
        tol_p,
    );
    let (rc, rg) = (col(c, &|q| vec![q.density]), col(g, &|q| vec![q.density]));
    close(
        &format!("{what} density"),
        &ids,
        1,
        &rc,
        &rg,
        2e-5 * scale,
        0.0,
    );
    let vel = |q: &PointSample| q.velocity[..dim].to_vec();
    let (vc, vg) = (col(c, &vel), col(g, &vel));
    let tol_v = 1e-4 * scale * max_abs(&vc);
    close(
        &format!("{what} velocity"),
        &ids,
        dim,
        &vc,
        &vg,
        1e-4 * scale,
        tol_v,
    );
    let (cc, cg) = (col(c, &|q| vec![q.colour]), col(g, &|q| vec![q.colour]));
    close(
        &format!("{what} colour"),
        &ids,
        1,
        &cc,
        &cg,
        2e-5 * scale,
        1e-6 * scale,
    );
    let dry = c.iter().filter(|q| q.neighbours == 0).count();
    eprintln!("  {what}: {} points, {dry} with no particle near", c.len());
}

/// Probes (`Readback::sample_points`: `cuda/probes.cu` against `cpu/probes.rs`) on a parity
/// scene, with and without the walls: at the start (no grid built yet on either), after
/// the CPU's state moved by steps is uploaded (the GPU's grid then stale, as the CPU's after
/// its drift), and after both stepped on (the GPU by graphs) from that one state.
fn probes_on<D: Dim>(what: &str, setup: Setup) {
    let p = setup.params;
    let mut g = gpu::<D>(&setup);
    let mut c = CpuSolver::<D>::new(setup);
    let pts = probe_points(&p);
    eprintln!(
        "{}D probes {what}: {} points, {} particles, on {}",
        p.dim,
        pts.len(),
        c.len(),
        g.info().device
    );
    let (mut sc, mut sg) = (Vec::new(), Vec::new());
    let mut both = |c: &mut CpuSolver<D>, g: &mut CudaSolver<D>, when: &str, scale: f32| {
        for walls in [false, true] {
            c.sample_points(&pts, walls, &mut sc);
            g.sample_points(&pts, walls, &mut sg);
            cmp_samples(&format!("{when}, walls {walls}"), &p, &sc, &sg, scale);
        }
    };
    both(&mut c, &mut g, "at the start", 1.0);
    c.advance(3);
    g.upload_state(c.state());
    both(&mut c, &mut g, "after 3 CPU steps, uploaded", 1.0);
    c.advance(6);
    g.advance(6);
    both(&mut c, &mut g, "after 6 more steps each", 50.0);
}

/// Sampling between batches changes nothing of the GPU's stepping (the grid it rebuilds is
/// the one the next step builds; a replayed graph takes a single step first): bit for bit
/// the states of a solver sampled every other batch and one never sampled.
fn sampling_leaves_gpu_stepping_unchanged<D: Dim>(setup: Setup) {
    let pts = probe_points(&setup.params);
    let mut a = gpu::<D>(&setup);
    let mut b = gpu::<D>(&setup);
    let mut out = Vec::new();
    for k in 0..6 {
        a.advance(5);
        b.advance(5);
        if k % 2 == 0 {
            b.sample_points(&pts, k % 4 == 0, &mut out);
        }
    }
    let (sa, sb) = (a.download_state(), b.download_state());
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<u32>>();
    assert_eq!(sa.id, sb.id, "storage orders differ");
    assert_eq!(
        bits(&flat_v::<D>(&sa.pos)),
        bits(&flat_v::<D>(&sb.pos)),
        "positions"
    );
    assert_eq!(
        bits(&flat_v::<D>(&sa.vel)),
        bits(&flat_v::<D>(&sb.vel)),
        "velocities"
    );
    assert_eq!(bits(&sa.rho), bits(&sb.rho), "densities");
    assert_eq!(bits(&sa.p), bits(&sb.p), "pressures");
    assert_eq!(a.time(), b.time());
    eprintln!(
        "  {}D: 30 steps with and without samples between batches: identical states",
        setup.params.dim
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn probes_2d() {
    probes_on::<D2>("V_2D_A (summation, dynamic walls)", scene(2, V_2D_A));
    probes_on::<D2>("V_2D_B (continuity, Lennard-Jones walls)", scene(2, V_2D_B));
    sampling_leaves_gpu_stepping_unchanged::<D2>(scene_with(2, V_2D_B, 0.05));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn probes_3d() {
    probes_on::<D3>("V_3D_A (continuity, Lennard-Jones walls)", scene(3, V_3D_A));
    probes_on::<D3>("V_3D_B (continuity, dynamic walls)", scene(3, V_3D_B));
    sampling_leaves_gpu_stepping_unchanged::<D3>(scene_with(3, V_3D_B, 0.05));
}
