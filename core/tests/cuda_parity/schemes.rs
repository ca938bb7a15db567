//! The stages and long runs under each fluid scheme: the lean kernels, density diffusion in
//! each form, the leapfrog, Morris's no-slip walls, mDBC walls, shifting, background pressure, the walls'
//! density floor, and grids of several scan blocks.

use super::*;

/// Which parity scenes take the lean kernels: pinned, so that the lean and the full
/// fluid-only kernels both stay covered.
#[test]
fn lean_kernels_are_covered() {
    for (dim, v) in [(2, V_2D_LEAN), (3, V_3D_LEAN), (3, V_3D_A), (2, V_2D_B)] {
        assert!(
            params::lean_scheme(&fluid_only(dim, v).params),
            "{dim}D {v:?}"
        );
    }
    for (dim, v) in [(2, V_2D_A), (3, V_3D_B), (2, V_2D_DELTA), (3, V_3D_DELTA)] {
        assert!(
            !params::lean_scheme(&fluid_only(dim, v).params),
            "{dim}D {v:?}"
        );
    }
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_lean_dynamic_walls_euler() {
    stages_on::<D2>("V_2D_LEAN fluid only", fluid_only(2, V_2D_LEAN));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_lean_dynamic_walls_euler() {
    stages_on::<D3>("V_3D_LEAN fluid only", fluid_only(3, V_3D_LEAN));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_lean_no_periodic_axis_euler() {
    stages_on::<D3>(
        "V_3D_LEAN fluid only, no periodic axis",
        not_periodic(fluid_only(3, V_3D_LEAN)),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_lean_euler() {
    let setup = fluid_only_of(scene_with(2, V_2D_LEAN, 0.05));
    long_run_on::<D2>("V_2D_LEAN fluid only", setup, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_lean_euler() {
    let setup = fluid_only_of(scene_with(3, V_3D_LEAN, 0.05));
    long_run_on::<D3>("V_3D_LEAN fluid only", setup, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_density_diffusion() {
    stages::<D2>(2, V_2D_DELTA);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_density_diffusion() {
    stages::<D3>(3, V_3D_DELTA);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_density_diffusion() {
    long_run::<D2>(2, V_2D_DELTA, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_density_diffusion_fourtakas() {
    stages::<D2>(2, V_2D_FOURTAKAS);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_density_diffusion_fourtakas() {
    stages::<D3>(3, V_3D_FOURTAKAS);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_density_diffusion_fourtakas() {
    long_run::<D3>(3, V_3D_FOURTAKAS, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_density_diffusion_antuono() {
    stages::<D2>(2, V_2D_ANTUONO);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_density_diffusion_antuono() {
    stages::<D3>(3, V_3D_ANTUONO);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_density_diffusion_antuono() {
    stages_on::<D3>("V_3D_ANTUONO fluid only", fluid_only(3, V_3D_ANTUONO));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_density_diffusion_antuono() {
    long_run::<D2>(2, V_2D_ANTUONO, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_solid_density_diffusion() {
    stages::<D2>(2, V_2D_SOLID_DELTA);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_solid_density_diffusion() {
    stages::<D3>(3, V_3D_SOLID_DELTA);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_solid_density_diffusion() {
    long_run::<D2>(2, V_2D_SOLID_DELTA, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_dynamic_walls_euler() {
    long_run::<D2>(2, V_2D_A, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_lj_walls_symplectic() {
    long_run::<D2>(2, V_2D_B, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_lj_walls_symplectic() {
    long_run::<D3>(3, V_3D_A, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_dynamic_walls_euler() {
    long_run::<D3>(3, V_3D_B, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_leapfrog_with_a_body() {
    stages_on::<D2>("V_2D_B leapfrog", leapfrog(scene(2, V_2D_B)));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_leapfrog_density_diffusion() {
    stages_on::<D3>(
        "V_3D_DELTA fluid-only leapfrog",
        leapfrog(fluid_only(3, V_3D_DELTA)),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_leapfrog_with_a_body() {
    long_run_on::<D2>(
        "V_2D_B leapfrog",
        leapfrog(scene_with(2, V_2D_B, 0.05)),
        200,
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_fluid_only_leapfrog() {
    long_run_on::<D3>(
        "V_3D_DELTA fluid-only leapfrog",
        leapfrog(fluid_only_of(scene_with(3, V_3D_DELTA, 0.05))),
        200,
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_fluid_only_euler() {
    // Forward Euler without solids: every step through the fused fluid-only kernel.
    let setup = fluid_only_of(scene_with(2, V_2D_A, 0.05));
    long_run_on::<D2>("V_2D_A fluid only", setup, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_fluid_only_euler() {
    let setup = fluid_only_of(scene_with(3, V_3D_B, 0.05));
    long_run_on::<D3>("V_3D_B fluid only", setup, 200);
}

/// Symplectic Euler (the separate forces kernel) with dynamic walls and laminar viscosity.
const V_2D_SYMPLECTIC_LAMINAR: Variant = Variant {
    dynamic_walls: true,
    laminar: true,
    ..V_2D_B
};

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_no_slip_walls_summation_euler() {
    let setup = with_no_slip(scene(2, V_2D_A), 2.0);
    stages_on::<D2>("V_2D_A + Morris no-slip walls", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_no_slip_driven_wall_symplectic() {
    // A moving wall (v_w != 0) under the separate forces kernel.
    let setup = driven_cohesive(2, V_2D_SYMPLECTIC_LAMINAR, 0, [0.5, 0.0, 0.0]);
    let setup = with_no_slip(setup, 2.0);
    stages_on::<D2>("2D symplectic + driven Morris no-slip wall", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_no_slip_walls_continuity_euler() {
    let setup = with_no_slip(scene(3, V_3D_B), 2.0);
    stages_on::<D3>("V_3D_B + Morris no-slip walls", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_no_slip_walls_continuity_euler() {
    let setup = with_no_slip(fluid_only(3, V_3D_B), 2.0);
    stages_on::<D3>("V_3D_B fluid only + Morris no-slip walls", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_fluid_only_no_slip_walls_symplectic() {
    let setup = with_no_slip(fluid_only(2, V_2D_SYMPLECTIC_LAMINAR), 2.0);
    stages_on::<D2>("2D symplectic fluid only + Morris no-slip walls", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_no_slip_walls_euler() {
    let setup = with_no_slip(scene_with(2, V_2D_A, 0.05), 2.0);
    long_run_on::<D2>("V_2D_A + Morris no-slip walls", setup, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_mdbc_walls_summation_euler() {
    // The ghost nodes' density under the summation density (the walls keep theirs).
    stages_on::<D2>("V_2D_A + mDBC walls", with_mdbc(scene(2, V_2D_A)));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_mdbc_walls_continuity_euler() {
    // Under the continuity density, where the grid build applies the equation of state
    // and the density pass launches only the walls' ghost nodes.
    stages_on::<D3>("V_3D_B + mDBC walls", with_mdbc(scene(3, V_3D_B)));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_mdbc_walls_continuity() {
    let setup = with_mdbc(fluid_only_of(scene_with(2, V_2D_DELTA, 0.05)));
    long_run_on::<D2>("V_2D_DELTA fluid only + mDBC walls", setup, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_mdbc_walls_continuity() {
    let setup = with_mdbc(fluid_only_of(scene_with(3, V_3D_B, 0.05)));
    long_run_on::<D3>("V_3D_B fluid only + mDBC walls", setup, 200);
}

/// `setup` with particle shifting (`shifting` = 0.2): the shift velocity joins the XSPH
/// velocity in rates and moves the particles in the drift.
fn shifted(mut setup: Setup) -> Setup {
    setup.params.shifting = 0.2;
    setup
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_shifting_with_a_body() {
    stages_on::<D2>("V_2D_B shifting", shifted(scene(2, V_2D_B)));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_shifting_dynamic_walls() {
    stages_on::<D3>("V_3D_B fluid only shifting", shifted(fluid_only(3, V_3D_B)));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_background_pressure_dynamic_walls() {
    let mut setup = scene(2, V_2D_A);
    setup.params.background_pressure = 2.0;
    stages_on::<D2>("V_2D_A background pressure", setup);
}

/// `setup` with the dynamic walls' continuity density held at >= rho0 (`wall_density_floor`,
/// DualSPHysics' DBC; `wall_density_floor` in src/backend/cpu/integrate.rs): the random
/// velocities dilate some wall particles, so the drift's clamp binds.
fn with_wall_density_floor(mut setup: Setup) -> Setup {
    setup.params.wall_density_floor = 1;
    setup
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_wall_density_floor_continuity_symplectic() {
    let setup = with_wall_density_floor(scene(2, V_2D_SYMPLECTIC_LAMINAR));
    stages_on::<D2>("V_2D_SYMPLECTIC_LAMINAR wall density floor", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_wall_density_floor_continuity_euler() {
    let setup = with_wall_density_floor(scene(3, V_3D_B));
    stages_on::<D3>("V_3D_B wall density floor", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_wall_density_floor() {
    let setup = with_wall_density_floor(scene_with(2, V_2D_SYMPLECTIC_LAMINAR, 0.05));
    long_run_on::<D2>("V_2D_SYMPLECTIC_LAMINAR wall density floor", setup, 200);
}

/// `scene(dim, v)` in a domain reaching `y_max` [L] up, so that its grid has `cells` cells
/// (asserted): more than 3 x 4096, several blocks of the GPU's cell scan (4096 cells each;
/// the other scenes have one), for the scan of the block totals (`sph_scan_top`) and cell
/// ranges that cross blocks; 4097 to 8192, the one block of twice the cells that
/// `sph_scan_one` scans alone.
fn with_tall_domain(mut setup: Setup, y_max: f32, cells: std::ops::RangeInclusive<usize>) -> Setup {
    setup.params.domain_max[1] = y_max;
    params::derive(&mut setup.params);
    assert!(
        cells.contains(&(setup.params.n_cells as usize)),
        "{} cells, not in {cells:?}",
        setup.params.n_cells
    );
    setup
}

const MANY_SCAN_BLOCKS: std::ops::RangeInclusive<usize> = 3 * 4096 + 1..=usize::MAX;

const TWO_SCAN_BLOCKS: std::ops::RangeInclusive<usize> = 4097..=8192;

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_lean_many_scan_blocks() {
    stages_on::<D2>(
        "V_2D_LEAN, tall domain",
        with_tall_domain(scene(2, V_2D_LEAN), 60.0, MANY_SCAN_BLOCKS),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_lean_many_scan_blocks() {
    stages_on::<D3>(
        "V_3D_LEAN, tall domain",
        with_tall_domain(scene(3, V_3D_LEAN), 30.0, MANY_SCAN_BLOCKS),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_many_scan_blocks() {
    let setup = with_tall_domain(scene_with(3, V_3D_LEAN, 0.05), 30.0, MANY_SCAN_BLOCKS);
    long_run_on::<D3>("V_3D_LEAN, tall domain", setup, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_lean_two_scan_blocks() {
    stages_on::<D2>(
        "V_2D_LEAN, two scan blocks",
        with_tall_domain(scene(2, V_2D_LEAN), 30.0, TWO_SCAN_BLOCKS),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_3d_two_scan_blocks() {
    let setup = with_tall_domain(scene_with(3, V_3D_LEAN, 0.05), 6.0, TWO_SCAN_BLOCKS);
    long_run_on::<D3>("V_3D_LEAN, two scan blocks", setup, 200);
}
