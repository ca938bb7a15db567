//! Total-Lagrangian bodies (`cuda/tlsph.cu`): the stages with `solid_stress`, `solid_forces`
//! and the displacements, and runs of 100-200 steps through captured graphs, one with a body
//! removed halfway.

use super::*;
use meshfree_core::solver::Readback;

/// `setup` with total-Lagrangian bodies (`[solid] formulation = "total-lagrangian"`,
/// `cuda/tlsph.cu`, twin `src/backend/cpu/tlsph.rs`) and the hourglass control at `alpha`;
/// its variant has no artificial stress (the formulation refuses it).
fn total_lagrangian_of(mut setup: Setup, alpha: f32) -> Setup {
    assert_eq!(setup.params.artificial_stress, 0.0);
    setup.params.solid_formulation = MF_SOLID_TOTAL_LAGRANGIAN as i32;
    setup.params.hourglass = alpha;
    setup
}

const V_2D_A_TL: Variant = Variant {
    art_stress: false,
    ..V_2D_A
};

const V_2D_B_TL: Variant = Variant {
    art_stress: false,
    ..V_2D_B
};

const V_3D_B_TL: Variant = Variant {
    art_stress: false,
    ..V_3D_B
};

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_total_lagrangian_clamped_plate_summation_euler() {
    let setup = total_lagrangian_of(clamped_body(2, V_2D_A_TL), 0.1);
    stages_on::<D2>(
        "V_2D_A, total Lagrangian, clamp holding half the disc",
        setup,
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_total_lagrangian_bodies_in_contact_continuity_symplectic() {
    let setup = total_lagrangian_of(bodies_in_contact(2, V_2D_B_TL, false), 0.1);
    stages_on::<D2>("V_2D_B, total Lagrangian, bodies in contact", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_total_lagrangian_clamped_block_continuity_euler() {
    let setup = total_lagrangian_of(clamped_body(3, V_3D_B_TL), 0.1);
    stages_on::<D3>(
        "V_3D_B, total Lagrangian, clamp holding half the sphere",
        setup,
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_total_lagrangian_clamped_block_continuity_symplectic() {
    let setup = total_lagrangian_of(clamped_body(3, V_3D_A), 0.1);
    stages_on::<D3>(
        "V_3D_A, total Lagrangian, clamp holding half the sphere",
        setup,
    );
}

/// A total-Lagrangian run of `steps` steps from a calm start, the GPU's through
/// `Solver::advance` (captured graphs), `remove` (a group) taken away from both halfway:
/// diagnostics as `long_run_on`, and the displacements within `scale` of the largest.
fn tl_long_run<D: Dim>(what: &str, setup: Setup, steps: u64, remove: Option<u32>) {
    let mut g = gpu::<D>(&setup);
    let mut c = CpuSolver::<D>::new(setup);
    let half = steps / 2;
    c.advance(half);
    g.advance(half);
    if let Some(grp) = remove {
        let (rc, rg) = (c.remove_group(grp), g.remove_group(grp));
        assert_eq!(rc, rg, "remove_group({grp}): removed cpu {rc} gpu {rg}");
        assert!(rc > 0, "remove_group({grp}) removed nothing");
    }
    c.advance(steps - half);
    g.advance(steps - half);
    let (dc, dg) = (c.diagnostics(), g.diagnostics());
    let dim = D::D;
    eprintln!("{dim}D {what} after {steps} steps:\n  cpu {dc:?}\n  gpu {dg:?}");
    assert!(c.check().is_ok() && g.check().is_ok(), "a blow-up");
    assert_eq!(
        (dc.fluid, dc.solid, dc.boundary),
        (dg.fluid, dg.solid, dg.boundary)
    );
    let rel = |a: f64, b: f64| (a - b).abs() / a.abs().max(1e-30);
    assert!(
        rel(dc.time, dg.time) < 1e-3,
        "time: cpu {} gpu {}",
        dc.time,
        dg.time
    );
    assert!(
        rel(dc.kinetic_energy, dg.kinetic_energy) < 2e-2,
        "kinetic energy: cpu {} gpu {} (rtol 2e-2)",
        dc.kinetic_energy,
        dg.kinetic_energy
    );
    assert!(
        (dc.density_error - dg.density_error).abs() < 5e-3,
        "density error: cpu {} gpu {} (atol 5e-3)",
        dc.density_error,
        dg.density_error
    );
    cmp_displacement(&c, &mut g, 2e-2);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn long_run_2d_total_lagrangian_clamped_plate_symplectic() {
    let setup = total_lagrangian_of(clamped_of(scene_with(2, V_2D_B_TL, 0.05)), 0.1);
    tl_long_run::<D2>("total Lagrangian clamped plate (V_2D_B)", setup, 200, None);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn long_run_3d_total_lagrangian_clamped_block_symplectic() {
    // The symplectic Euler: under the forward Euler this body's elastic modes grow (as an
    // oscillator's do) and blew the run up on both backends alike by step 200.
    let setup = total_lagrangian_of(clamped_of(scene_with(3, V_3D_A, 0.05)), 0.1);
    tl_long_run::<D3>("total Lagrangian clamped block (V_3D_A)", setup, 200, None);
}

/// The slot map after `remove_group` (`sph_tl_slots`; twin `TlBodies::map_slots`): one of
/// the bodies (the solid layer on the wall, group 4) removed halfway.
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn long_run_2d_total_lagrangian_remove_a_body() {
    let mut setup = bodies_in_contact(2, V_2D_B_TL, false);
    for q in setup.particles.iter_mut() {
        for a in 0..2 {
            q.velocity[a] *= 0.05 / 0.3;
        }
    }
    let setup = total_lagrangian_of(setup, 0.1);
    tl_long_run::<D2>("total Lagrangian bodies, one removed", setup, 100, Some(4));
}
