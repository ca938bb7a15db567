//! Walls of open surfaces (issue #53): a terrain mesh (3D) and a sea-bed line (2D) with
//! `solid` = "back"/"front" or "left"/"right". The rows must lie on the chosen side within
//! `layers` spacings, every lattice point that close on that side must be one, and the
//! fluid must fill exactly the lattice points on the other side.

use std::path::Path;

use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::Scene;

const DX: f64 = 0.025;
/// The terrain's grid: NX x NY quads over [0, 1] x [0, 0.5].
const NX: usize = 20;
const NY: usize = 10;

/// The terrain's height at its grid node (i, j).
fn node(i: usize, j: usize) -> f64 {
    let (x, y) = (i as f64 / NX as f64, 0.5 * j as f64 / NY as f64);
    0.213 + 0.08 * (2.0 * std::f64::consts::PI * x).sin() * (std::f64::consts::PI * y).cos()
}

/// The piecewise-linear height of the mesh at (x, y): each quad split along its diagonal
/// from (i, j) to (i + 1, j + 1), as `terrain_obj` writes it.
fn height(x: f64, y: f64) -> f64 {
    let (hx, hy) = (1.0 / NX as f64, 0.5 / NY as f64);
    let i = ((x / hx) as usize).min(NX - 1);
    let j = ((y / hy) as usize).min(NY - 1);
    let (u, v) = (x / hx - i as f64, y / hy - j as f64);
    let (h00, h10, h01, h11) = (
        node(i, j),
        node(i + 1, j),
        node(i, j + 1),
        node(i + 1, j + 1),
    );
    if u >= v {
        h00 + u * (h10 - h00) + v * (h11 - h10)
    } else {
        h00 + v * (h01 - h00) + u * (h11 - h01)
    }
}

/// The terrain as an OBJ file in `dir`, its faces' normals up (+z).
fn terrain_obj(dir: &Path) -> String {
    use std::fmt::Write as _;
    let mut t = String::new();
    for j in 0..=NY {
        for i in 0..=NX {
            let (x, y) = (i as f64 / NX as f64, 0.5 * j as f64 / NY as f64);
            writeln!(t, "v {x} {y} {}", node(i, j)).unwrap();
        }
    }
    let at = |i: usize, j: usize| j * (NX + 1) + i + 1;
    for j in 0..NY {
        for i in 0..NX {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            writeln!(t, "f {a} {b} {c}\nf {a} {c} {d}").unwrap();
        }
    }
    std::fs::write(dir.join("terrain.obj"), t).unwrap();
    "terrain.obj".into()
}

fn scene3(solid: &str) -> String {
    format!(
        r#"dimension = 3
name = "terrain"
[domain]
min = [0.0, 0.0, 0.0]
max = [1.0, 0.5, 0.5]
[discretisation]
spacing = {DX}
[time]
end = 0.1
output_interval = 0.1
[fluid]
density = 1000.0
sound_speed = 20.0
viscosity = 0.01
[boundary]
strength = 10.0
wall_coupling = "dynamic"
no_slip = "morris"
[[walls]]
shape = "mesh"
mesh = {{ file = "terrain.obj" }}
solid = "{solid}"
layers = 3
[[fluid_blocks]]
min = [0.0, 0.0, 0.0]
max = [1.0, 0.5, 0.5]
"#
    )
}

/// The lattice points (i + 1/2) dx of the box [0, n * dx] per axis.
fn lattice(n: [usize; 3]) -> impl Iterator<Item = [f64; 3]> {
    let c = |i: usize| (i as f64 + 0.5) * DX;
    (0..n[2])
        .flat_map(move |k| (0..n[1]).flat_map(move |j| (0..n[0]).map(move |i| [c(i), c(j), c(k)])))
}

fn positions(setup: &meshfree_core::solver::Setup, kind: Kind) -> Vec<[f64; 3]> {
    (setup.particles.iter())
        .filter(|p| p.kind == kind)
        .map(|p| p.position.map(f64::from))
        .collect()
}

#[test]
fn a_terrain_sheet_walls_its_back_and_the_fluid_fills_its_front() {
    let dir = tempfile::tempdir().unwrap();
    terrain_obj(dir.path());
    let base = meshfree_core::scene::geometry::base_of(&dir.path().join("scene.toml"));
    // The steepest slope of the terrain is 0.08 * 2 pi: a distance of 3 dx to the surface
    // is at most 3 dx / cos(atan(0.51)) = 3.37 dx below it.
    let steepest = 1.0 / (1.0 + (0.16 * std::f64::consts::PI).powi(2)).sqrt();
    let n = [40, 20, 20];
    for (solid, sign) in [("back", 1.0), ("front", -1.0)] {
        let scene = Scene::from_toml_in(&scene3(solid), solid, &base).unwrap();
        let setup = scene.setup().unwrap();
        // gap > 0: on the wall's side of the surface, by that much along z.
        let gap = |p: &[f64; 3]| sign * (height(p[0], p[1]) - p[2]);
        let walls = positions(&setup, Kind::Boundary);
        let fluid = positions(&setup, Kind::Fluid);
        // The size estimate (refusals before allocation): the fluid block's box (16,000
        // points) and, for the rows, at most 2 (layers + 1) / layers times their band.
        let rows = meshfree_core::scene::estimate::estimate(&scene.file).particles - 16_000.0;
        let made = walls.len() as f64;
        assert!(
            rows >= made && rows <= 3.0 * made,
            "{solid}: the rows estimated {rows}, {made} made"
        );
        let worst = walls.iter().map(gap).fold(f64::MAX, f64::min);
        let deepest = walls.iter().map(gap).fold(0.0, f64::max);
        assert!(
            worst > 0.0,
            "{solid}: a wall particle {worst} on the fluid's side"
        );
        assert!(
            deepest <= 3.0 * DX / steepest + 1e-9,
            "{solid}: a wall particle {} dx deep",
            deepest / DX
        );
        // Every lattice point within 3 dx along z on the wall's side (so within 3 dx of the
        // surface) is a wall particle; every one on the other side is fluid.
        let key = |p: &[f64; 3]| p.map(|x| (x / DX).floor() as i64);
        let wall_keys: std::collections::HashSet<_> = walls.iter().map(key).collect();
        let fluid_keys: std::collections::HashSet<_> = fluid.iter().map(key).collect();
        let (mut band, mut wet) = (0, 0);
        for p in lattice(n) {
            let g = gap(&p);
            if g > 0.0 && g <= 3.0 * DX {
                band += 1;
                assert!(wall_keys.contains(&key(&p)), "{solid}: no wall at {p:?}");
            }
            if g < 0.0 {
                wet += 1;
                assert!(fluid_keys.contains(&key(&p)), "{solid}: no fluid at {p:?}");
            }
        }
        assert_eq!(fluid.len(), wet, "{solid}: fluid beyond the front side");
        eprintln!(
            "{solid}: {} wall particles ({band} within 3 dx vertically), deepest {:.2} dx; {} fluid",
            walls.len(),
            deepest / DX,
            fluid.len()
        );
        // Morris's walls: each wall particle's normal points to the fluid's side, about as
        // the terrain's does, and its distance is at most the rows' depth.
        let first = setup.params.wall_first_id;
        let mut lowest = 1.0f64;
        for p in setup.particles.iter().filter(|p| p.kind == Kind::Boundary) {
            let s = setup.wall_surface[(p.id - first) as usize].map(f64::from);
            assert!(
                sign * s[2] > 0.85,
                "{solid}: normal {s:?} at {:?}",
                p.position
            );
            assert!(
                s[3] > 0.0 && s[3] <= 3.0 * DX + 1e-6,
                "{solid}: distance {}",
                s[3]
            );
            lowest = lowest.min(sign * s[2]);
        }
        eprintln!(
            "{solid}: normals within {:.1} degrees of vertical",
            lowest.acos().to_degrees()
        );
    }
}

fn scene2(solid: &str, points: &str) -> String {
    format!(
        r#"dimension = 2
name = "bed"
[domain]
min = [0.0, 0.0]
max = [1.0, 0.6]
[discretisation]
spacing = {DX}
[time]
end = 0.1
output_interval = 0.1
[fluid]
density = 1000.0
sound_speed = 20.0
[boundary]
strength = 10.0
[[walls]]
shape = "polygon"
polygon = {{ points = {points} }}
solid = "{solid}"
layers = 3
[[fluid_blocks]]
min = [0.0, 0.0]
max = [1.0, 0.4]
"#
    )
}

/// The sea bed: flat at 0.107 to x = 0.5, then a beach up to 0.407 at x = 1.
fn bed(x: f64) -> f64 {
    if x <= 0.5 {
        0.107
    } else {
        0.107 + 0.6 * (x - 0.5)
    }
}

#[test]
fn a_sea_bed_line_walls_the_side_it_is_told() {
    let forward = "[[0.0, 0.107], [0.5, 0.107], [1.0, 0.407]]";
    let backward = "[[1.0, 0.407], [0.5, 0.107], [0.0, 0.107]]";
    // Walked from the paddle to the beach the bed is on the right; walked back, on the left.
    for (solid, points) in [("right", forward), ("left", backward)] {
        let scene = Scene::from_toml(&scene2(solid, points), solid).unwrap();
        let setup = scene.setup().unwrap();
        let walls = positions(&setup, Kind::Boundary);
        let fluid = positions(&setup, Kind::Fluid);
        let depth = |p: &[f64; 3]| bed(p[0]) - p[1];
        let steepest = 1.0 / (1.0f64 + 0.36).sqrt();
        assert!(
            walls.iter().all(|p| depth(p) > 0.0),
            "{solid}: a wall above the bed"
        );
        assert!(
            walls.iter().all(|p| depth(p) <= 3.0 * DX / steepest + 1e-9),
            "{solid}: a wall particle too deep"
        );
        assert!(
            fluid.iter().all(|p| depth(p) < 0.0),
            "{solid}: fluid under the bed"
        );
        let c = |i: usize| (i as f64 + 0.5) * DX;
        let (mut band, mut wet) = (0, 0);
        for j in 0..24 {
            for i in 0..40 {
                let d = bed(c(i)) - c(j);
                band += usize::from(d > 0.0 && d <= 3.0 * DX);
                wet += usize::from(d < 0.0 && c(j) < 0.4);
            }
        }
        assert_eq!(fluid.len(), wet, "{solid}: the fluid above the bed");
        assert!(
            walls.len() >= band,
            "{solid}: {} walls, {band} lattice points within 3 dx above them",
            walls.len()
        );
    }
}

#[test]
fn open_sides_are_refused_where_they_cannot_hold() {
    let err = |text: &str| Scene::from_toml(text, "t").unwrap_err().to_string();
    let line = "[[0.0, 0.107], [1.0, 0.107]]";
    // A 3D side in 2D, and a line of one point.
    let e = err(&scene2("back", line));
    assert!(
        e.contains("walls[0].solid") && e.contains("\"left\""),
        "{e}"
    );
    let e = err(&scene2("left", "[[0.5, 0.1], [0.5, 0.1]]"));
    assert!(
        e.contains("walls[0].polygon.points") && e.contains("2 distinct"),
        "{e}"
    );
    // An open line does not float.
    let floating =
        scene2("right", line).replace("layers = 3", "layers = 3\nfloating = { density = 500.0 }");
    let e = err(&floating);
    assert!(
        e.contains("walls[0].floating") && e.contains("solid"),
        "{e}"
    );
    // A 2D side in 3D.
    let dir = tempfile::tempdir().unwrap();
    terrain_obj(dir.path());
    let base = meshfree_core::scene::geometry::base_of(&dir.path().join("scene.toml"));
    let e = Scene::from_toml_in(&scene3("left"), "t", &base)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("walls[0].solid") && e.contains("\"back\""),
        "{e}"
    );
    // The terrain as a closed obstacle is refused, and the error names the open sides.
    let e = Scene::from_toml_in(&scene3("inside"), "t", &base)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("is open") && e.contains("solid = \"back\""),
        "{e}"
    );
}
