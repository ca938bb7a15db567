//! The stages, CPU against CUDA, on the scenes' variants: driven walls and bodies with
//! cohesion, bodies in contact, clamps, dynamic and Lennard-Jones walls, inflow bands and ramps,
//! fluid only, no periodic axis.

use super::*;
use meshfree_core::solver::Readback;

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_driven_wall_cohesion_continuity_symplectic() {
    let setup = driven_cohesive(2, V_2D_B, 0, [0.5, 0.0, 0.0]);
    stages_on::<D2>("V_2D_B + driven wall + cohesion", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_driven_solid_cohesion_summation_euler() {
    let setup = driven_cohesive(2, V_2D_A, 2, [0.0, 0.0, 0.0]);
    stages_on::<D2>("V_2D_A + clamped disc + cohesion", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_driven_solid_cohesion_continuity_euler() {
    let setup = driven_cohesive(3, V_3D_B, 2, [0.2, -0.3, 0.1]);
    stages_on::<D3>("V_3D_B + driven sphere + cohesion", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_wall_on_a_motion_law_symplectic() {
    let setup = with_damping(driven_law(2, V_2D_B, 0));
    stages_on::<D2>(
        "V_2D_B + wall oscillating and turning + damping zone",
        setup,
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_body_on_a_motion_law_leapfrog() {
    let setup = leapfrog(driven_law(3, V_3D_B, 2));
    stages_on::<D3>("V_3D_B leapfrog + sphere oscillating and turning", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_wall_on_a_cubic_series_symplectic() {
    let setup = driven_series(2, V_2D_B, 0, true);
    stages_on::<D2>("V_2D_B + wall on a cubic time series", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_body_on_a_linear_series_leapfrog() {
    let setup = leapfrog(driven_series(3, V_3D_B, 2, false));
    stages_on::<D3>("V_3D_B leapfrog + sphere on a linear time series", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_bodies_in_contact_dynamic_walls() {
    stages_on::<D2>(
        "V_2D_A + bodies in contact",
        bodies_in_contact(2, V_2D_A, false),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_bodies_in_contact_dynamic_walls() {
    stages_on::<D3>(
        "V_3D_B + bodies in contact",
        bodies_in_contact(3, V_3D_B, false),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_bodies_in_contact_lj_walls_whole_stress() {
    let setup = bodies_in_contact(2, V_2D_B, true);
    stages_on::<D2>("V_2D_B + bodies in contact, whole stress", setup);
}

/// `bodies_in_contact` where bodies and walls skip each other (`[solid] wall_contact =
/// false`, `wall_contact`; `meets` in src/physics/pairs.rs / pairs.cuh): the solid layer on
/// the wall feels no Lennard-Jones force or wall pressure, and neither enters the other's
/// density (summation in V_2D_A, the walls' continuity in V_3D_B).
fn bodies_skipping_walls(dim: usize, v: Variant) -> Setup {
    let mut setup = bodies_in_contact(dim, v, false);
    setup.params.wall_contact = 0;
    setup
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_bodies_skipping_walls_summation() {
    let setup = bodies_skipping_walls(2, V_2D_A);
    stages_on::<D2>("V_2D_A + bodies in contact, skipping the walls", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_bodies_skipping_walls_continuity() {
    let setup = bodies_skipping_walls(3, V_3D_B);
    stages_on::<D3>("V_3D_B + bodies in contact, skipping the walls", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_clamp_bonded_to_its_body() {
    stages_on::<D2>(
        "V_2D_A + clamp holding half the disc",
        clamped_body(2, V_2D_A),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_clamp_bonded_to_its_body() {
    stages_on::<D3>(
        "V_3D_B + clamp holding half the sphere",
        clamped_body(3, V_3D_B),
    );
}

/// `clamped_body` with the artificial stress taken from the deviatoric stress alone
/// (`[solid] artificial_stress_from = "deviatoric"`, `artificial_stress_from`; `art_pressure`
/// in stress.rs, `artificial_stress` in density.cu).
#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_clamp_deviatoric_artificial_stress() {
    let mut setup = clamped_body(2, V_2D_B);
    setup.params.artificial_stress_from = 1;
    stages_on::<D2>("V_2D_B + clamp, deviatoric artificial stress", setup);
}

/// `clamped_body` made stiff: a solid sound speed of 1e6 (and shear modulus to match), so
/// that a step's change of a solid's density, dt d rho/dt, lies below f32's resolution of
/// rho and only the departure `rho_dev` (`SolidState::rho_dev`) carries it; the pressure
/// c_s^2 rho_dev must agree between the density pass, the continuity scheme's reorder
/// (no artificial stress) and the CPU.
fn stiff_clamp(dim: usize, v: Variant) -> Setup {
    let mut setup = clamped_body(dim, v);
    let p = &mut setup.params;
    p.solid_c0 = 1e6;
    p.shear_modulus = 0.3 * p.solid_rho0 * p.solid_c0 * p.solid_c0;
    params::derive(p);
    setup
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_stiff_clamp_continuity_eos_in_the_reorder() {
    let v = Variant {
        art_stress: false,
        ..V_2D_B
    };
    stages_on::<D2>("V_2D_B without R + stiff clamp", stiff_clamp(2, v));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_stiff_clamp_continuity_euler() {
    stages_on::<D3>("V_3D_B + stiff clamp", stiff_clamp(3, V_3D_B));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_dynamic_walls_summation_euler() {
    stages::<D2>(2, V_2D_A);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_lj_walls_continuity_symplectic() {
    stages::<D2>(2, V_2D_B);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_lj_walls_continuity_symplectic() {
    stages::<D3>(3, V_3D_A);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_dynamic_walls_continuity_euler() {
    stages::<D3>(3, V_3D_B);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_inflow_band_symplectic() {
    stages_on::<D2>("V_2D_B + inflow band", with_inflow_band(2, V_2D_B));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_inflow_band_euler() {
    stages_on::<D3>("V_3D_B + inflow band", with_inflow_band(3, V_3D_B));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_inflow_ramp_symplectic() {
    let setup = ramped::<D2>(with_inflow_band(2, V_2D_B));
    stages_on::<D2>("V_2D_B + inflow band, ramped", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_inflow_ramp_leapfrog() {
    let setup = ramped::<D3>(leapfrog(with_inflow_band(3, V_3D_A)));
    stages_on::<D3>("V_3D_A leapfrog + inflow band, ramped", setup);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn diagnostics_after_200_steps_2d_inflow_ramp() {
    // The ramp ends inside the run (at 100 of its first steps): graphs, the clock and the
    // ramp's end together.
    let mut setup = scene_with(2, V_2D_B, 0.05);
    let p = &mut setup.params;
    (p.inflow, p.inflow_axis, p.inflow_lo, p.inflow_hi) = (1, 0, 0.4, 0.8);
    p.inflow_velocity = [0.5, -0.2, 0.0];
    let mut c = CpuSolver::<D2>::new(setup.clone());
    c.step();
    setup.params.inflow_ramp = 100.0 * c.dt();
    long_run_on::<D2>("V_2D_B + inflow band, ramped", setup, 200);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_fluid_only_dynamic_walls_summation_euler() {
    stages_on::<D2>("V_2D_A fluid only", fluid_only(2, V_2D_A));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_lj_walls_continuity_symplectic() {
    stages_on::<D3>("V_3D_A fluid only", fluid_only(3, V_3D_A));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_dynamic_walls_continuity_euler() {
    stages_on::<D3>("V_3D_B fluid only", fluid_only(3, V_3D_B));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_no_periodic_axis_with_a_body_symplectic() {
    stages_on::<D2>("V_2D_B, no periodic axis", not_periodic(scene(2, V_2D_B)));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_no_periodic_axis_euler() {
    stages_on::<D3>(
        "V_3D_B fluid only, no periodic axis",
        not_periodic(fluid_only(3, V_3D_B)),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_2d_fluid_only_no_periodic_axis_symplectic() {
    stages_on::<D2>(
        "V_2D_B fluid only, no periodic axis",
        not_periodic(fluid_only(2, V_2D_B)),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn stages_3d_fluid_only_no_periodic_axis_symplectic() {
    stages_on::<D3>(
        "V_3D_A fluid only, no periodic axis",
        not_periodic(fluid_only(3, V_3D_A)),
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_wall_on_a_motion_law_follows_the_same_path_over_whole_steps() {
    same_path_over_whole_steps(driven_law(2, V_2D_B, 0));
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_wall_on_a_time_series_follows_the_same_path_over_whole_steps() {
    same_path_over_whole_steps(driven_series(2, V_2D_B, 0, true));
}

/// The device's clock (time[0], the kick's t0 in time[2]) against the CPU's over 150
/// steps of `Solver::step`: each particle of the driven group 0 where the CPU puts it.
fn same_path_over_whole_steps(setup: Setup) {
    let start: Vec<Particle> = setup.particles.clone();
    let mut g = gpu::<D2>(&setup);
    let mut c = CpuSolver::<D2>::new(setup);
    for _ in 0..150 {
        c.step();
        g.step();
    }
    let by_id = |mut v: Vec<Particle>| {
        v.sort_by_key(|q| q.id);
        v
    };
    let (pc, pg, p0) = (by_id(c.particles()), by_id(g.particles()), by_id(start));
    let (mut n, mut worst, mut moved) = (0, 0.0f32, 0.0f32);
    for ((a, b), s) in pc.iter().zip(&pg).zip(&p0) {
        if a.group != 0 || a.kind != Kind::Boundary {
            continue;
        }
        n += 1;
        for d in 0..2 {
            worst = worst.max((a.position[d] - b.position[d]).abs());
            moved = moved.max((a.position[d] - s.position[d]).abs());
        }
    }
    eprintln!(
        "{n} driven wall particles after 150 steps to t = {:.5} (gpu {:.5}): moved up to {moved}, CPU - GPU up to {worst}",
        c.time(),
        g.time()
    );
    assert!(n > 0 && moved > 1e-3, "the wall did not move ({moved})");
    // Both move by the same double-precision law from the same clock: the difference is
    // float rounding of one pose, not a step's move (~1e-4 here).
    assert!(
        worst < 2e-6,
        "a driven particle is {worst} apart on the two backends"
    );
}
