//! Small particle sets built directly (no scene file), for the unit-level tests.
#![allow(dead_code)]

use meshfree_core::physics::params::{
    self, SphParams, MF_DENSITY_CONTINUITY, MF_INTEGRATOR_SYMPLECTIC_EULER,
};
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::scheme::NoSlip;
use meshfree_core::scene::Scene;

/// Parameters for spacing `dx` in `dim` dimensions over the box [lo, hi].
pub fn params(dim: i32, dx: f32, lo: [f32; 3], hi: [f32; 3], periodic: [i32; 3]) -> SphParams {
    let mut p = SphParams {
        dim,
        periodic,
        domain_min: lo,
        domain_max: hi,
        dx,
        h: 1.3 * dx,
        density_form: MF_DENSITY_CONTINUITY as i32,
        rho0: 1000.0,
        c0: 20.0,
        tait_gamma: 7.0,
        alpha: 0.05,
        beta: 0.0,
        xsph: 0.0,
        solid_rho0: 600.0,
        solid_c0: 20.0,
        shear_modulus: 1.0e5,
        artificial_stress_exponent: 4.0,
        lj_c0: 10.0,
        lj_r0: dx,
        lj_p1: 12,
        lj_p2: 6,
        wall_contact: 1,
        wall_coupling: 1,
        integrator: MF_INTEGRATOR_SYMPLECTIC_EULER as i32,
        courant: 0.2,
        ..Default::default()
    };
    params::derive(&mut p);
    p
}

/// Lattice points (i + 0.5) dx inside [lo, hi) on the first `dim` axes.
pub fn lattice(dim: usize, dx: f32, lo: [f32; 3], hi: [f32; 3]) -> Vec<[f32; 3]> {
    let n: Vec<usize> = (0..3)
        .map(|a| {
            if a < dim {
                ((hi[a] - lo[a]) / dx).round() as usize
            } else {
                1
            }
        })
        .collect();
    let mut out = Vec::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let c = [i, j, k];
                let mut x = [0.0; 3];
                for a in 0..dim {
                    x[a] = lo[a] + (c[a] as f32 + 0.5) * dx;
                }
                out.push(x);
            }
        }
    }
    out
}

/// Append particles of `kind` at `points` (mass = rho dx^dim, at rest, density rho).
pub fn add(
    out: &mut Vec<Particle>,
    points: &[[f32; 3]],
    kind: Kind,
    group: u32,
    rho: f32,
    p: &SphParams,
) {
    let m = rho * p.dx.powi(p.dim);
    for x in points {
        out.push(Particle {
            id: out.len() as u32,
            kind,
            group,
            position: *x,
            density: rho,
            mass: m,
            ..Default::default()
        });
    }
}

/// A simple deterministic pseudo-random number in [0, 1) (xorshift).
pub fn rand01(state: &mut u64) -> f32 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    (*state >> 40) as f32 / (1u64 << 24) as f32
}

/// The built-in `tank-2d` at spacing `dx` [L] with laminar viscosity nu = 0.01 [L^2/T] and
/// the no-slip walls of Morris, Fox & Zhu 1997 (`[boundary] no_slip = "morris"`).
pub fn tank_2d_morris(dx: f64) -> Scene {
    let mut scene = Scene::builtin("tank-2d").unwrap().with_spacing(dx).unwrap();
    scene.file.fluid.viscosity = 0.01;
    scene.file.boundary.as_mut().unwrap().no_slip = NoSlip::Morris;
    scene.revalidate().unwrap();
    scene
}

/// The built-in scene `name` with text replacements (a coarser spacing, ...); each `from`
/// must be in its text.
pub fn edited_scene(name: &str, edits: &[(&str, &str)]) -> Scene {
    let mut text = Scene::builtin(name).unwrap().text;
    for (from, to) in edits {
        assert!(text.contains(from), "{name} has no {from:?}");
        text = text.replace(from, to);
    }
    Scene::from_toml(&text, name).unwrap()
}

/// The CPU and GPU diagnostics of one scene after a long run agree within the parity
/// tests' long-run tolerances: the same counts and step, time (rtol 1e-3), kinetic energy
/// (rtol 2e-2), max speed (rtol 5e-2), density error (atol 5e-3). SPH is chaotic: the
/// particles themselves diverge.
pub fn assert_long_run_close(
    dc: &meshfree_core::solver::Diagnostics,
    dg: &meshfree_core::solver::Diagnostics,
) {
    assert_eq!(
        (dc.fluid, dc.solid, dc.boundary),
        (dg.fluid, dg.solid, dg.boundary)
    );
    assert_eq!(dc.step, dg.step);
    let rel = |a: f64, b: f64| (a - b).abs() / a.abs().max(1e-30);
    assert!(
        rel(dc.time, dg.time) < 1e-3,
        "time: cpu {} gpu {} (rtol 1e-3)",
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
        rel(dc.max_speed as f64, dg.max_speed as f64) < 5e-2,
        "max speed: cpu {} gpu {} (rtol 5e-2)",
        dc.max_speed,
        dg.max_speed
    );
    assert!(
        (dc.density_error - dg.density_error).abs() < 5e-3,
        "density error: cpu {} gpu {} (atol 5e-3)",
        dc.density_error,
        dg.density_error
    );
}

/// `scene` run on the CPU to time `t`: its particles at the start, at the end (by id) and
/// the time reached.
pub fn run_scene_to(scene: &Scene, t: f64) -> (Vec<Particle>, Vec<Particle>, f64) {
    let setup = scene.setup().unwrap();
    let start = setup.particles.clone();
    let mut s = meshfree_core::backend::cpu_solver(setup);
    meshfree_core::solver::step::Stepper::default()
        .advance_to(s.as_mut(), t)
        .expect("healthy run");
    let t = s.time();
    let mut end = s.particles();
    end.sort_by_key(|q| q.id);
    (start, end, t)
}

/// A plane channel between an inlet and an outlet (`[[open_boundaries]]`), as TOML: H = 0.1
/// high and 0.5 long at dx = 0.01 (10 particles across), water (rho0 = 1000, nu = 0.01),
/// the inlet's buffer x in [-0.03, 0] at U = 0.5, the outlet's x in [0.5, 0.53]; in 3D a duct
/// 0.08 deep across z, periodic there. For `tests/open.rs` and the parity tests.
pub fn open_channel(dim: usize) -> String {
    let (z, zmax, zp) = if dim == 3 {
        (", 0.0", ", 0.08", ", true")
    } else {
        ("", "", "")
    };
    format!(
        r#"
dimension = {dim}
name = "channel-open"
[domain]
min = [-0.05, -0.04{z}]
max = [0.60, 0.14{zmax}]
periodic = [false, false{zp}]
[discretisation]
spacing = 0.01
[time]
end = 1.5
output_interval = 0.25
[fluid]
density = 1000.0
sound_speed = 10.0
viscosity = 0.01
alpha = 0.0
xsph = 0.0
[boundary]
strength = 1.0
wall_coupling = "dynamic"
wall_density_floor = true
[[fluid_blocks]]
min = [0.0, 0.0{z}]
max = [0.5, 0.1{zmax}]
velocity = [0.5, 0.0{z}]
[[walls]]
shape = "box"
min = [-0.05, -0.03{z}]
max = [0.60, 0.0{zmax}]
[[walls]]
shape = "box"
min = [-0.05, 0.1{z}]
max = [0.60, 0.13{zmax}]
[[open_boundaries]]
kind = "inlet"
min = [-0.03, 0.0{z}]
max = [0.0, 0.1{zmax}]
normal = [1.0, 0.0{z}]
velocity = [0.5, 0.0{z}]
[[open_boundaries]]
kind = "outlet"
min = [0.5, 0.0{z}]
max = [0.53, 0.1{zmax}]
normal = [-1.0, 0.0{z}]
"#
    )
}
