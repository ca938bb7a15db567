//! The built-in scenes: they parse, generate the documented particle counts, equal the
//! files in `scenes/`, and start with the right masses, spacing and hydrostatic pressure.

use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::{self, Counts, Scene};

fn counts(name: &str) -> Counts {
    Counts::of(&Scene::builtin(name).unwrap().setup().unwrap().particles)
}

#[test]
fn builtin_files_equal_scene_directory() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    for (name, text) in scene::BUILTIN {
        let file = std::fs::read_to_string(dir.join(format!("{name}.toml"))).unwrap();
        assert_eq!(&file, text, "scenes/{name}.toml differs from the built-in");
        let s = Scene::from_file(dir.join(format!("{name}.toml"))).unwrap();
        assert_eq!(
            s.name(),
            *name,
            "the file's `name` must equal its built-in name"
        );
    }
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter_map(|f| f.strip_suffix(".toml").map(str::to_string))
        .collect();
    on_disk.sort();
    let mut built: Vec<String> = scene::builtin_names()
        .iter()
        .map(|s| s.to_string())
        .collect();
    built.sort();
    assert_eq!(on_disk, built, "every scenes/*.toml is a built-in");
}

#[test]
fn documented_counts() {
    let c = counts("dam-break-2d");
    assert_eq!((c.fluid, c.solid, c.boundary), (2500, 0, 2061)); // tank 1836 + gate 225
    let c = counts("dam-break-3d");
    assert_eq!((c.fluid, c.solid, c.boundary), (7500, 0, 20336)); // tank 19616 + gate 720
    assert!(c.total < 30_000);
    let c = counts("impinging-2d");
    assert_eq!((c.fluid, c.solid, c.boundary), (3384, 116, 2004)); // square 64 + disc 52; tank 1710 + gate 294
    let c = counts("impinging-3d");
    assert_eq!((c.fluid, c.solid, c.boundary), (5376, 56, 22352)); // tank 21520 + gate 832
    let c = counts("tank-2d");
    assert_eq!((c.fluid, c.solid, c.boundary), (1600, 0, 426));
    let c = counts("tank-3d");
    assert_eq!((c.fluid, c.solid, c.boundary), (8000, 0, 5376));
    let c = counts("vortex-street-re140");
    assert_eq!((c.fluid, c.solid, c.boundary), (15684, 0, 160)); // paper 16,000
    let c = counts("vortex-street-re105");
    assert_eq!((c.fluid, c.solid, c.boundary), (33626, 0, 286)); // paper 34,000
}

fn min_distance(ps: &[Particle]) -> f32 {
    let mut best = f32::INFINITY;
    for (i, a) in ps.iter().enumerate() {
        for b in &ps[i + 1..] {
            let d: f32 = (0..3)
                .map(|k| (a.position[k] - b.position[k]).powi(2))
                .sum::<f32>()
                .sqrt();
            best = best.min(d);
        }
    }
    best
}

/// `[boundary] hydrostatic_walls` is off by default: the dam break's walls start at rho0,
/// p = 0 under its hydrostatic column (with it, the walls the water leaves keep the column's
/// pressure: docs/reference/accuracy.md); the still tank opts in (`tank_2d_particles`).
#[test]
fn dam_break_walls_start_at_rest() {
    let setup = Scene::builtin("dam-break-2d").unwrap().setup().unwrap();
    let walls: Vec<&Particle> = setup
        .particles
        .iter()
        .filter(|q| q.kind == Kind::Boundary)
        .collect();
    assert!(!walls.is_empty());
    for q in walls {
        assert_eq!(
            (q.density, q.pressure),
            (setup.params.rho0, 0.0),
            "wall particle {}",
            q.id
        );
    }
}

/// `[boundary] wall_density_floor` is off by default and on in the dam break (docs/reference/accuracy.md:
/// unclamped, the walls the water leaves fall to 0.73 rho0 and the column rings).
#[test]
fn wall_density_floor_only_where_asked() {
    let dam = Scene::builtin("dam-break-2d").unwrap().setup().unwrap();
    assert_eq!(dam.params.wall_density_floor, 1);
    let tank = Scene::builtin("tank-2d").unwrap().setup().unwrap();
    assert_eq!(tank.params.wall_density_floor, 0);
}

#[test]
fn tank_2d_particles() {
    let s = Scene::builtin("tank-2d").unwrap();
    let setup = s.setup().unwrap();
    let p = &setup.params;
    let dx = 0.025f32;
    assert_eq!(p.dim, 2);
    assert!((p.dx - dx).abs() < 1e-7 && (p.h - 1.3 * dx).abs() < 1e-6);
    assert_eq!(p.wall_coupling, 1);
    assert!((p.lj_r0 - dx).abs() < 1e-7);
    assert!(p.n_cells > 0 && (p.support - 2.0 * p.h).abs() < 1e-7);
    for (i, q) in setup.particles.iter().enumerate() {
        assert_eq!(q.id as usize, i);
        let expect_group = if q.kind == Kind::Fluid { 0 } else { 1 };
        assert_eq!(q.group, expect_group);
        assert!((q.mass - 1000.0 * dx * dx).abs() < 1e-4, "mass {}", q.mass);
        assert_eq!(q.position[2], 0.0);
        assert_eq!(q.velocity, [0.0; 3]);
    }
    // Lattice spacing: no two particles closer than dx (walls sit dx from the fluid).
    let d = min_distance(&setup.particles);
    assert!((d - dx).abs() < 1e-5, "closest pair {d}");
    // Hydrostatic start, eq. (9): p = rho0 g (H - y), rho = rho0 (1 + p / B)^(1/7).
    let b = 1000.0 * 45.0f32 * 45.0 / 7.0;
    for q in setup.particles.iter().filter(|q| q.kind == Kind::Fluid) {
        let expect = 1000.0 * 9.81 * (1.0 - q.position[1]);
        assert!(
            (q.pressure - expect).abs() < 1e-2 * expect.max(1.0),
            "p {} vs {expect}",
            q.pressure
        );
        let rho = 1000.0 * (1.0 + expect / b).powf(1.0 / 7.0);
        assert!((q.density - rho).abs() < 1e-3, "rho {} vs {rho}", q.density);
    }
    let fluid: Vec<[f32; 3]> = setup
        .particles
        .iter()
        .filter(|q| q.kind == Kind::Fluid)
        .map(|q| q.position)
        .collect();
    for q in setup.particles.iter().filter(|q| q.kind == Kind::Boundary) {
        // Dynamic walls within a support (2h) of the hydrostatic column start at its
        // pressure at their own depth (not below 0); the others at rho0, p = 0.
        let near = fluid.iter().any(|f| {
            let (ddx, ddy) = (f[0] - q.position[0], f[1] - q.position[1]);
            (ddx * ddx + ddy * ddy).sqrt() < p.support
        });
        if near {
            let expect = (1000.0 * 9.81 * (1.0 - q.position[1])).max(0.0);
            assert!(
                (q.pressure - expect).abs() < 1e-2 * expect.max(1.0),
                "wall p {} vs {expect}",
                q.pressure
            );
            let rho = 1000.0 * (1.0 + expect / b).powf(1.0 / 7.0);
            assert!(
                (q.density - rho).abs() < 1e-3,
                "wall rho {} vs {rho}",
                q.density
            );
        } else {
            assert_eq!((q.density, q.pressure), (1000.0, 0.0));
        }
        // Just outside the tank [0, 1] x [0, 1.2], open at the top.
        let [x, y, _] = q.position;
        assert!(
            !(0.0..=1.0).contains(&x) || y < 0.0,
            "wall particle inside the tank at {x}, {y}"
        );
        assert!(y < 1.2 && x > -0.075 && x < 1.075 && y > -0.075);
    }
}

#[test]
fn dam_break_gate() {
    let s = Scene::builtin("dam-break-2d").unwrap();
    assert_eq!(s.gates(), vec![(2, 0.0)]);
    let setup = s.setup().unwrap();
    let gate: Vec<_> = setup.particles.iter().filter(|p| p.group == 2).collect();
    assert_eq!(gate.len(), 225);
    assert!(gate
        .iter()
        .all(|p| p.kind == Kind::Boundary && p.position[0] > 1.0 && p.position[0] < 1.06));
    // Closest fluid-gate distance is dx.
    assert!((min_distance(&setup.particles[..]) - 0.02).abs() < 1e-5);
}

#[test]
fn dam_break_3d_masses() {
    let setup = Scene::builtin("dam-break-3d").unwrap().setup().unwrap();
    let m = 1000.0 * 0.04f32.powi(3);
    assert!(setup.particles.iter().all(|p| (p.mass - m).abs() < 1e-5));
    let zs: Vec<f32> = setup
        .particles
        .iter()
        .filter(|p| p.kind == Kind::Fluid)
        .map(|p| p.position[2])
        .collect();
    assert!(zs.iter().all(|&z| z > 0.0 && z < 0.48));
}

const SOLIDS: &str = r#"
dimension = 2
name = "solids"

[domain]
min = [0.0, 0.0]
max = [2.0, 2.0]

[discretisation]
spacing = 0.05

[time]
end = 1.0
output_interval = 0.1

[fluid]
density = 1.0
sound_speed = 10.0

[solid]
density = 0.6
sound_speed = 10.0
shear_modulus = 5.0

[boundary]
strength = 1.0

[[fluid_blocks]]
min = [0.0, 0.0]
max = [2.0, 2.0]

[[solids]]
shape = "disc"
center = [0.5, 0.5]
radius = 0.25
velocity = [1.0, 0.0]

[[solids]]
shape = "box"
min = [1.2, 1.2]
max = [1.5, 1.5]

[[walls]]
shape = "cylinder"
center = [1.5, 0.5]
radius = 0.2
layers = 2
"#;

#[test]
fn solids_and_cylinder_displace_fluid() {
    let s = Scene::from_toml(SOLIDS, "solids.toml").unwrap();
    let setup = s.setup().unwrap();
    let ps = &setup.particles;
    let group = |g: u32| ps.iter().filter(|p| p.group == g).collect::<Vec<_>>();
    let disc = group(1);
    let area = std::f32::consts::PI * 0.25 * 0.25 / (0.05 * 0.05);
    assert!(
        (disc.len() as f32 - area).abs() < 0.1 * area,
        "disc {} vs {area}",
        disc.len()
    );
    assert!(disc
        .iter()
        .all(|p| p.kind == Kind::Solid && p.velocity == [1.0, 0.0, 0.0]));
    assert!(disc
        .iter()
        .all(|p| (p.mass - 0.6 * 0.0025).abs() < 1e-6 && p.density == 0.6));
    assert_eq!(group(2).len(), 36);
    let rings = group(3);
    // Rings at r = 0.175 and 0.125: round(2 pi r / dx) points each.
    assert_eq!(rings.len(), 22 + 16);
    // No two particles closer than half a spacing.
    let mut min = f32::INFINITY;
    for (i, a) in ps.iter().enumerate() {
        for b in &ps[i + 1..] {
            let d = ((a.position[0] - b.position[0]).powi(2)
                + (a.position[1] - b.position[1]).powi(2))
            .sqrt();
            min = min.min(d);
        }
    }
    assert!(min >= 0.025, "closest pair {min}");
    // Fluid yields: none inside the disc, the box or the cylinder.
    for p in ps.iter().filter(|p| p.kind == Kind::Fluid) {
        let [x, y, _] = p.position;
        assert!(((x - 0.5).powi(2) + (y - 0.5).powi(2)).sqrt() > 0.25);
        assert!(((x - 1.5).powi(2) + (y - 0.5).powi(2)).sqrt() > 0.2);
        assert!(!(x > 1.2 && x < 1.5 && y > 1.2 && y < 1.5));
    }
    assert!(setup.has_solids());
    assert!((setup.params.solid_rho0 - 0.6).abs() < 1e-7);
}

/// GPUSPH's dam breaks in our format (`scenes/peers/`, `meshfree bench peers`) parse and
/// validate (generating them takes too long for a test: up to 13.5 M particles).
#[test]
fn peer_scenes_validate() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/peers");
    let mut n = 0;
    for e in std::fs::read_dir(&dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "toml") {
            let s = Scene::from_file(&path).unwrap_or_else(|e| panic!("{e}"));
            assert!(s.name().starts_with("gpusph-"), "{}", path.display());
            n += 1;
        }
    }
    assert_eq!(n, 3, "db3d-ppH70, db3d-ppH180, db2d-ppH670");
}

/// The default output fields follow what the scene holds: kind only with more than one kind,
/// group only where a kind holds more than one object, stress only with solids, id never; a
/// listed set is kept as listed (position always added).
#[test]
fn default_output_fields_weigh_what_the_scene_needs() {
    use meshfree_core::scene::format::Output;
    use meshfree_core::solver::frame::{Field, Fields};
    let p = |kind, group| Particle {
        kind,
        group,
        ..Default::default()
    };
    let base = Fields::of(&[
        Field::Position,
        Field::Velocity,
        Field::Density,
        Field::Pressure,
    ]);
    let out = Output::default();
    let fluid = [p(Kind::Fluid, 0), p(Kind::Fluid, 0)];
    assert_eq!(out.fields(&fluid), base);
    let tank = [p(Kind::Fluid, 1), p(Kind::Boundary, 0), p(Kind::Fluid, 1)];
    assert_eq!(out.fields(&tank), base.with(Field::Kind));
    // Two wall objects (a tank and an obstacle), stored apart.
    let obstacle = [
        p(Kind::Boundary, 0),
        p(Kind::Fluid, 1),
        p(Kind::Boundary, 2),
        p(Kind::Boundary, 0),
    ];
    assert_eq!(
        out.fields(&obstacle),
        base.with(Field::Kind).with(Field::Group)
    );
    let body = [p(Kind::Solid, 3), p(Kind::Solid, 3)];
    assert_eq!(out.fields(&body), base.with(Field::Stress));
    let listed = Output {
        fields: Some(vec![Field::Id, Field::Pressure]),
        ..Default::default()
    };
    assert_eq!(
        listed.fields(&obstacle),
        Fields::of(&[Field::Position, Field::Id, Field::Pressure])
    );
    // The built-in tank: fluid and walls, one object each.
    let tank = Scene::builtin("tank-2d").unwrap();
    let ps = tank.setup().unwrap().particles;
    assert_eq!(tank.file.output.fields(&ps), base.with(Field::Kind));
}
