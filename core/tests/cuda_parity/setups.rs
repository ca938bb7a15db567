//! The scenes the parity tests run: `Variant` (what a scene switches on), the stage scenes
//! in 2D and 3D (`scene`, `scene_with`), and what turns one into another (an inflow band,
//! a ramped start, fluid only, driven and cohesive, bodies in contact, a clamp, no periodic
//! axis, the leapfrog, Morris's no-slip walls).

use super::*;

pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    pub(crate) fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
    pub(crate) fn sym(&mut self, a: f32) -> f32 {
        a * (2.0 * self.next() - 1.0)
    }
}

/// What a parity scene switches on.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Variant {
    /// Dynamic walls (`wall_coupling`): boundary particles carry density and pressure.
    pub(crate) dynamic_walls: bool,
    pub(crate) continuity: bool,
    pub(crate) symplectic: bool,
    pub(crate) art_stress: bool,
    pub(crate) laminar: bool,
    /// Density diffusion (delta-SPH, `density_diffusion` = 0.1) with a perturbed initial fluid
    /// density, so that the diffusive term is not zero from the first step.
    pub(crate) density_diffusion: bool,
    /// The fluid diffusion's form (`density_diffusion_form`, `MF_DIFFUSION_*`): Fourtakas et al. 2019's
    /// hydrostatic one, or Antuono et al. 2010's with renormalised gradients.
    pub(crate) density_diffusion_form: u32,
    /// Density diffusion within the solid body (`solid_density_diffusion` = 0.1) with a perturbed
    /// initial solid density.
    pub(crate) solid_delta: bool,
}

/// 2D: summation, dynamic walls, forward Euler, artificial stress, laminar viscosity.
pub(crate) const V_2D_A: Variant = Variant {
    dynamic_walls: true,
    continuity: false,
    symplectic: false,
    art_stress: true,
    laminar: true,
    density_diffusion: false,
    density_diffusion_form: MF_DIFFUSION_MOLTENI,
    solid_delta: false,
};

/// 2D: continuity, Lennard-Jones-only walls, symplectic Euler, artificial stress.
pub(crate) const V_2D_B: Variant = Variant {
    dynamic_walls: false,
    continuity: true,
    symplectic: true,
    art_stress: true,
    laminar: false,
    density_diffusion: false,
    density_diffusion_form: MF_DIFFUSION_MOLTENI,
    solid_delta: false,
};

/// 3D: continuity, Lennard-Jones-only walls, symplectic Euler, no artificial stress.
pub(crate) const V_3D_A: Variant = Variant {
    dynamic_walls: false,
    continuity: true,
    symplectic: true,
    art_stress: false,
    laminar: false,
    density_diffusion: false,
    density_diffusion_form: MF_DIFFUSION_MOLTENI,
    solid_delta: false,
};

/// 3D: continuity with dynamic walls (wall d rho/dt), forward Euler, artificial stress,
/// laminar viscosity.
pub(crate) const V_3D_B: Variant = Variant {
    dynamic_walls: true,
    continuity: true,
    symplectic: false,
    art_stress: true,
    laminar: true,
    density_diffusion: false,
    density_diffusion_form: MF_DIFFUSION_MOLTENI,
    solid_delta: false,
};

/// 2D and 3D: `V_2D_B` / `V_3D_B` with density diffusion.
pub(crate) const V_2D_DELTA: Variant = Variant {
    density_diffusion: true,
    ..V_2D_B
};

pub(crate) const V_3D_DELTA: Variant = Variant {
    density_diffusion: true,
    ..V_3D_B
};

/// `V_2D_DELTA` / `V_3D_DELTA` with the diffusion's hydrostatic form.
pub(crate) const V_2D_FOURTAKAS: Variant = Variant {
    density_diffusion_form: MF_DIFFUSION_FOURTAKAS,
    ..V_2D_DELTA
};

pub(crate) const V_3D_FOURTAKAS: Variant = Variant {
    density_diffusion_form: MF_DIFFUSION_FOURTAKAS,
    ..V_3D_DELTA
};

/// `V_2D_DELTA` / `V_3D_DELTA` with the diffusion in Antuono et al.'s form (the fluid's
/// density gradients: `sph_grad_rho`).
pub(crate) const V_2D_ANTUONO: Variant = Variant {
    density_diffusion_form: MF_DIFFUSION_ANTUONO,
    ..V_2D_DELTA
};

pub(crate) const V_3D_ANTUONO: Variant = Variant {
    density_diffusion_form: MF_DIFFUSION_ANTUONO,
    ..V_3D_DELTA
};

/// `V_2D_B` / `V_3D_B` (artificial stress) with density diffusion within the solid body.
pub(crate) const V_2D_SOLID_DELTA: Variant = Variant {
    solid_delta: true,
    ..V_2D_B
};

pub(crate) const V_3D_SOLID_DELTA: Variant = Variant {
    solid_delta: true,
    ..V_3D_B
};

/// 2D and 3D: dynamic walls, continuity, forward Euler and nothing beyond the paper's fluid
/// scheme: as fluid-only scenes, the lean kernels' cases (`params::lean_scheme`), the
/// scheme `meshfree bench` times.
pub(crate) const V_2D_LEAN: Variant = Variant {
    dynamic_walls: true,
    symplectic: false,
    ..V_2D_B
};

pub(crate) const V_3D_LEAN: Variant = Variant {
    laminar: false,
    ..V_3D_B
};

/// A fluid lattice over a wall (3 layers, bottom; in 3D also the two z faces), periodic in
/// x, with an elastic disc / sphere inside; jittered positions, random velocities and
/// initial solid stress so that every term is exercised.
pub(crate) fn scene(dim: usize, v: Variant) -> Setup {
    scene_with(dim, v, 0.3)
}

/// `scene` with random initial velocities of amplitude `vel_amp` [L/T].
pub(crate) fn scene_with(dim: usize, v: Variant, vel_amp: f32) -> Setup {
    let dx = 0.1f32;
    let d3 = dim == 3;
    let nx = if d3 { 12 } else { 40 };
    let lx = nx as f32 * dx;
    let (fy, fz) = if d3 { (8, 12) } else { (15, 1) };
    let lz = fz as f32 * dx;
    let mut p = SphParams {
        dim: dim as i32,
        periodic: [1, 0, 0],
        domain_min: [0.0, -3.0 * dx, if d3 { -3.0 * dx } else { 0.0 }],
        domain_max: [lx, 3.0, if d3 { lz + 3.0 * dx } else { 0.0 }],
        kernel: 0,
        dx,
        h: 1.3 * dx,
        density_form: if v.continuity {
            MF_DENSITY_CONTINUITY
        } else {
            MF_DENSITY_SUMMATION
        } as i32,
        rho0: 1.0,
        c0: 15.0,
        tait_gamma: 7.0,
        alpha: 0.1,
        beta: 0.1,
        viscosity: if v.laminar { 0.005 } else { 0.0 },
        xsph: 0.3,
        density_diffusion: if v.density_diffusion { 0.1 } else { 0.0 },
        density_diffusion_form: v.density_diffusion_form as i32,
        solid_density_diffusion: if v.solid_delta { 0.1 } else { 0.0 },
        solid_rho0: 0.8,
        solid_c0: 15.0,
        shear_modulus: 50.0,
        artificial_stress: if v.art_stress { 0.3 } else { 0.0 },
        artificial_stress_exponent: 4.0,
        lj_c0: 2.0,
        lj_r0: dx,
        lj_p1: 12,
        lj_p2: 6,
        attractive: 0,
        wall_contact: 1,
        wall_coupling: v.dynamic_walls as i32,
        gravity: [0.0, -1.0, 0.0],
        integrator: if v.symplectic {
            MF_INTEGRATOR_SYMPLECTIC_EULER
        } else {
            MF_INTEGRATOR_EULER
        } as i32,
        courant: 0.25,
        dt: 0.0,
        ..Default::default()
    };
    params::derive(&mut p);
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let mut out: Vec<Particle> = Vec::new();
    let centre = [0.5 * lx, 0.5 * fy as f32 * dx, 0.5 * lz];
    let radius = if d3 { 0.25 } else { 0.35 };
    let push = |out: &mut Vec<Particle>, x: [f32; 3], kind: Kind, group: u32, rng: &mut Rng| {
        let rho = if kind == Kind::Solid {
            p.solid_rho0
        } else {
            p.rho0
        };
        let mut q = Particle {
            id: out.len() as u32,
            kind,
            group,
            position: x,
            density: rho,
            mass: rho * dx.powi(dim as i32),
            ..Default::default()
        };
        if kind != Kind::Boundary {
            for a in 0..dim {
                q.position[a] += rng.sym(0.1 * dx);
                q.velocity[a] = rng.sym(vel_amp);
            }
        }
        if (v.density_diffusion && kind == Kind::Fluid) || (v.solid_delta && kind == Kind::Solid) {
            q.density *= 1.0 + rng.sym(0.01);
        }
        if kind == Kind::Solid {
            for c in 0..6 {
                q.stress[c] = rng.sym(0.5);
            }
        }
        out.push(q);
    };
    let zs: Vec<i32> = if d3 { (-3..fz + 3).collect() } else { vec![0] };
    for &k in &zs {
        for j in -3..fy.max(12) {
            for i in 0..nx {
                let x = [
                    (i as f32 + 0.5) * dx,
                    (j as f32 + 0.5) * dx,
                    if d3 { (k as f32 + 0.5) * dx } else { 0.0 },
                ];
                let wall = j < 0 || (d3 && (k < 0 || k >= fz));
                if wall {
                    push(&mut out, x, Kind::Boundary, 0, &mut rng);
                } else if j < fy {
                    let r2: f32 = (0..dim).map(|a| (x[a] - centre[a]).powi(2)).sum();
                    if r2 < radius * radius {
                        push(&mut out, x, Kind::Solid, 2, &mut rng);
                    } else {
                        push(&mut out, x, Kind::Fluid, 1, &mut rng);
                    }
                }
            }
        }
    }
    Setup {
        params: p,
        particles: out,
        wall_surface: Vec::new(),
        bodies: Vec::new(),
        motion_series: Vec::new(),
    }
}

/// `scene(dim, v)` with an inflow band across the periodic x axis: fluid in
/// 0.4 <= x < 0.8 moves at (1.5, -0.5, 0.25) (src/backend/cpu/integrate.rs::kick).
pub(crate) fn with_inflow_band(dim: usize, v: Variant) -> Setup {
    let mut setup = scene(dim, v);
    let p = &mut setup.params;
    p.inflow = 1;
    p.inflow_axis = 0;
    p.inflow_lo = 0.4;
    p.inflow_hi = 0.8;
    p.inflow_velocity = [1.5, -0.5, 0.25];
    setup
}

/// `setup` (with an inflow band) under a ramped start (`inflow_ramp`) of 8 of its first
/// steps, so that the stage tests' four rounds all kick inside the ramp: the band at its
/// share r(t) of the inflow velocity and the rest accelerated by its increase
/// (src/backend/cpu/integrate.rs::kick, `ramp_share`, `kick_end`).
pub(crate) fn ramped<D: Dim>(mut setup: Setup) -> Setup {
    let mut c = CpuSolver::<D>::new(setup.clone());
    c.step();
    setup.params.inflow_ramp = 8.0 * c.dt();
    setup
}

/// `scene(dim, v)` with the solid body turned into fluid (rest density, no stress): the only
/// scenes that take the fluid-only entries of forces and rates (`sph_forces_fluid_*`,
/// `sph_rates_fluid_*`: batches of 8 candidates at one lane, and the neighbour's kind read
/// from the sign of its vel.w, `vel_load` in cuda/device/packing.cuh).
pub(crate) fn fluid_only(dim: usize, v: Variant) -> Setup {
    fluid_only_of(scene(dim, v))
}

/// `setup` with its solid body turned into fluid.
pub(crate) fn fluid_only_of(mut setup: Setup) -> Setup {
    let dim = setup.params.dim;
    let (rho0, dx) = (setup.params.rho0, setup.params.dx);
    for q in setup.particles.iter_mut().filter(|q| q.kind == Kind::Solid) {
        q.kind = Kind::Fluid;
        q.group = 1;
        q.density = rho0;
        q.mass = rho0 * dx.powi(dim);
        q.stress = Default::default();
    }
    setup
}

/// `scene(dim, v)` with a driven group (`group` 0: the wall, moving as a piston; 2: the
/// elastic body, a moving clamp) and fluid cohesion (Akinci et al. 2013) switched on.
pub(crate) fn driven_cohesive(dim: usize, v: Variant, group: i32, u: [f32; 3]) -> Setup {
    let mut setup = scene(dim, v);
    let p = &mut setup.params;
    p.driven = 1;
    p.driven_motion[0].group = group;
    p.driven_motion[0].velocity = u;
    p.cohesion = 2.0;
    setup
}

/// `scene(dim, v)` where elastic bodies touch each other and the wall: the disc / sphere
/// split in two bodies at its centre plane (group 3 the +x half), and a layer of solid
/// (group 4, with stress) on the wall under the left part of the fluid. Pairs across two
/// objects take the pressure part of the stress only, or with `whole` the whole stress
/// (`interface`, `whole_stress_pair` in forces.rs / forces.cu).
pub(crate) fn bodies_in_contact(dim: usize, v: Variant, whole: bool) -> Setup {
    let mut setup = scene(dim, v);
    setup.params.interface = whole as i32;
    // The paper's whole stress comes with the body's own pressure (`scheme`'s check); the
    // pressure part alone with the fluid's pressure extrapolated to the bodies (the interface
    // stage, `pairs::extrapolated_pair`), which the other setups (the default) leave out.
    setup.params.solid_fluid_pressure = if whole {
        MF_SOLID_FLUID_PRESSURE_OWN
    } else {
        MF_SOLID_FLUID_PRESSURE_EXTRAPOLATED
    } as i32;
    let p = setup.params;
    let xc = 0.5 * p.domain_max[0];
    let vol = p.dx.powi(dim as i32);
    for (k, q) in setup.particles.iter_mut().enumerate() {
        if q.kind == Kind::Solid && q.position[0] > xc {
            q.group = 3;
        } else if q.kind == Kind::Fluid && q.position[1] < 1.5 * p.dx && q.position[0] < xc {
            q.kind = Kind::Solid;
            q.group = 4;
            q.density = p.solid_rho0;
            q.mass = p.solid_rho0 * vol;
            for c in 0..6 {
                q.stress[c] = 0.1 * ((k * 7 + c * 3) % 11) as f32 - 0.5;
            }
        }
    }
    setup
}

/// `scene(dim, v)` with its elastic body cut in two across x at its centre: the half with
/// x below the mean a clamp (group 2, driven, held fixed), the rest a free body (group 3)
/// bonded to it (`same_body`): XSPH, the velocity gradient and the artificial stress cross
/// the cut.
pub(crate) fn clamped_body(dim: usize, v: Variant) -> Setup {
    clamped_of(scene(dim, v))
}

/// `setup`'s elastic body cut in two across x at its centre, as `clamped_body`.
pub(crate) fn clamped_of(mut setup: Setup) -> Setup {
    let solid: Vec<f32> = (setup.particles.iter())
        .filter(|q| q.kind == Kind::Solid)
        .map(|q| q.position[0])
        .collect();
    let mid = solid.iter().sum::<f32>() / solid.len() as f32;
    for q in setup.particles.iter_mut() {
        if q.kind == Kind::Solid && q.position[0] >= mid {
            q.group = 3;
        }
    }
    let p = &mut setup.params;
    p.driven = 1;
    p.driven_motion[0].group = 2;
    p.driven_motion[0].velocity = [0.0; 3];
    setup
}

/// `setup` with no periodic axis: the neighbour loops' other specialisation (the minimum
/// image compiled out, `neighbour_loop` in cuda/device/neighbours.cuh). Particles at the
/// open x ends just have fewer neighbours.
pub(crate) fn not_periodic(mut setup: Setup) -> Setup {
    setup.params.periodic = [0; 3];
    params::derive(&mut setup.params);
    setup
}

/// `driven_cohesive` with the driven group on a motion law (issue #54): a steady velocity,
/// an oscillation and a turn (steady and oscillating) about a tilted axis through the
/// box's middle, ramped over a few steps, so that the kick's velocity and the drift's move
/// take every term of `MfMotion` (cuda/device/motion.cuh against physics/motion.rs).
pub(crate) fn driven_law(dim: usize, v: Variant, group: i32) -> Setup {
    let mut setup = driven_cohesive(dim, v, group, [0.3, -0.2, 0.1]);
    let p = &mut setup.params;
    let m = &mut p.driven_motion[0];
    m.amplitude = [0.05, 0.02, 0.01];
    (m.period, m.phase) = (0.3, 0.4);
    let mid = |a: usize| 0.5 * (p.domain_min[a] + p.domain_max[a]);
    m.pivot = [mid(0), mid(1), if dim == 3 { mid(2) } else { 0.0 }];
    let n = (0.3f32 * 0.3 + 0.4 * 0.4 + 0.866 * 0.866).sqrt();
    m.axis = [0.3 / n, 0.4 / n, 0.866 / n];
    (m.rate, m.angle, m.angle_period, m.angle_phase) = (0.7, 0.2, 0.5, 0.3);
    m.ramp = 0.004;
    setup
}

/// `driven_cohesive` with the driven group on a time series (issue #54) beside a steady
/// velocity: a recorded translation (x, y, z) and a turn about a tilted axis through the
/// box's middle, knots 2 ms apart from before t = 0, interpolated linearly or (`cubic`) by
/// cubic Hermite, so that the kick's velocity and the drift's move take every term of
/// `motion_series_at` (cuda/device/motion.cuh against physics/motion.rs).
pub(crate) fn driven_series(dim: usize, v: Variant, group: i32, cubic: bool) -> Setup {
    let mut setup = driven_cohesive(dim, v, group, [0.1, 0.0, 0.0]);
    let mut knots = Vec::new();
    for j in 0..200 {
        let t = -0.004 + 0.002 * j as f64;
        knots.extend([
            t,
            0.03 * (25.0 * t).sin(),
            0.5 * t * t,
            -0.01 * (40.0 * t).sin(),
            0.3 * (18.0 * t).sin() + 0.2 * t,
        ]);
    }
    let p = &mut setup.params;
    let m = &mut p.driven_motion[0];
    (m.series_first, m.series_count, m.series_cubic) = (0, 200, cubic as i32);
    let mid = |a: usize| 0.5 * (p.domain_min[a] + p.domain_max[a]);
    m.pivot = [mid(0), mid(1), if dim == 3 { mid(2) } else { 0.0 }];
    let n = (0.3f32 * 0.3 + 0.4 * 0.4 + 0.866 * 0.866).sqrt();
    m.axis = [0.3 / n, 0.4 / n, 0.866 / n];
    setup.motion_series = knots;
    setup
}

/// `setup` with a damping zone along x over the domain's second half (issue #57): the
/// kick's factor on the fluid, exp(-rate r^2 dt), rising from the middle.
pub(crate) fn with_damping(mut setup: Setup) -> Setup {
    let p = &mut setup.params;
    (p.damping, p.damping_axis) = (1, 0);
    p.damping_start = 0.5 * (p.domain_min[0] + p.domain_max[0]);
    p.damping_end = p.domain_max[0];
    p.damping_rate = 50.0;
    setup
}

/// `setup` under the leapfrog: the symplectic Euler's stages with the kick spanning
/// (dt_prev + dt) / 2 and the rates at the drift's midpoint.
pub(crate) fn leapfrog(mut setup: Setup) -> Setup {
    setup.params.integrator = MF_INTEGRATOR_LEAPFROG as i32;
    setup
}

/// `setup` with the no-slip walls of Morris, Fox & Zhu 1997 (`no_slip`, cap `beta_max`):
/// the wall surface of the parity scenes is the fluid's box, y >= 0 (and 0 <= z <= lz in
/// 3D), so each wall particle faces the nearest point of it (diagonally at the 3D edges).
/// The parity scenes number walls among the fluid, so `wall_surface` spans the smallest to
/// the largest wall id with unused entries between.
pub(crate) fn with_no_slip(mut setup: Setup, beta_max: f32) -> Setup {
    let p = &mut setup.params;
    p.no_slip = params::MF_NO_SLIP_MORRIS as i32;
    p.no_slip_beta_max = beta_max;
    with_wall_surface(setup)
}

/// `setup` with mDBC walls (`MF_WALL_COUPLING_MDBC`), their surface as `with_no_slip`'s.
pub(crate) fn with_mdbc(mut setup: Setup) -> Setup {
    setup.params.wall_coupling = params::MF_WALL_COUPLING_MDBC as i32;
    with_wall_surface(setup)
}

/// `Setup::wall_surface` of `scene_with`'s walls: the floor at y = 0 and, in 3D, the lid of
/// z at lz; each wall particle's normal toward the nearest point of the fluid's slab.
fn with_wall_surface(mut setup: Setup) -> Setup {
    let p = &setup.params;
    let d3 = p.dim == 3;
    let lz = p.domain_max[2] - 3.0 * p.dx; // `scene_with`: the domain's z runs to lz + 3 dx
    let lo = [f32::NEG_INFINITY, 0.0, 0.0];
    let hi = [f32::INFINITY, f32::INFINITY, if d3 { lz } else { 0.0 }];
    let walls = || setup.particles.iter().filter(|q| q.kind == Kind::Boundary);
    let first = walls().map(|q| q.id).min().expect("walls");
    let last = walls().map(|q| q.id).max().expect("walls");
    let mut surface = vec![[0.0f32; 4]; (last - first) as usize + 1];
    for q in walls() {
        let x = q.position;
        let v: [f32; 3] = std::array::from_fn(|a| x[a].clamp(lo[a], hi[a]) - x[a]);
        let d = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        surface[(q.id - first) as usize] = [v[0] / d, v[1] / d, v[2] / d, d];
    }
    setup.params.wall_first_id = first;
    setup.wall_surface = surface;
    setup
}
