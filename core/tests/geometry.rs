//! Surfaces from files (issue #53): a sphere written as STL (binary and ASCII), OBJ and PLY
//! (ASCII and binary) fills to its volume, its wall particles get radial normals and their
//! distance to it, a small hole and an inside-out winding change nothing, and a built-in
//! scene whose tank is a polygon makes the particles of its box-container.

use std::f64::consts::PI;
use std::path::Path;

use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::{Counts, Scene};

/// An icosphere of radius `r` about the origin, `level` times subdivided (20 * 4^level
/// triangles), wound outward.
fn icosphere(r: f64, level: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    let norm = |p: [f64; 3]| {
        let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        p.map(|x| x / l)
    };
    for p in v.iter_mut() {
        *p = norm(*p);
    }
    for _ in 0..level {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::new();
        for t in &f {
            let mut m = [0u32; 3];
            for k in 0..3 {
                let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
                m[k] = *mid.entry((a, b)).or_insert_with(|| {
                    let (pa, pb) = (v[a as usize], v[b as usize]);
                    v.push(norm(std::array::from_fn(|i| pa[i] + pb[i])));
                    v.len() as u32 - 1
                });
            }
            next.extend([
                [t[0], m[0], m[2]],
                [t[1], m[1], m[0]],
                [t[2], m[2], m[1]],
                m,
            ]);
        }
        f = next;
    }
    (v.into_iter().map(|p| p.map(|x| x * r)).collect(), f)
}

/// The sphere written in `format` into `dir`; the file's name.
fn write(dir: &Path, format: &str, v: &[[f64; 3]], f: &[[u32; 3]]) -> String {
    use std::fmt::Write as _;
    use std::io::Write as _;
    let name = format!("sphere-{format}");
    let mut text = String::new();
    let mut bytes: Vec<u8> = Vec::new();
    let ext = match format {
        "stl-binary" => {
            let tris: Vec<stl_io::Triangle> = f
                .iter()
                .map(|t| stl_io::Triangle {
                    normal: stl_io::Normal::new([0.0; 3]),
                    vertices: t.map(|i| stl_io::Vertex::new(v[i as usize].map(|x| x as f32))),
                })
                .collect();
            stl_io::write_stl(&mut bytes, tris.iter()).unwrap();
            "stl"
        }
        "stl-ascii" => {
            writeln!(text, "solid sphere").unwrap();
            for t in f {
                writeln!(text, "facet normal 0 0 0\nouter loop").unwrap();
                for &i in t {
                    let p = v[i as usize];
                    writeln!(text, "vertex {} {} {}", p[0], p[1], p[2]).unwrap();
                }
                writeln!(text, "endloop\nendfacet").unwrap();
            }
            writeln!(text, "endsolid sphere").unwrap();
            "stl"
        }
        "obj" => {
            for p in v {
                writeln!(text, "v {} {} {}", p[0], p[1], p[2]).unwrap();
            }
            for t in f {
                writeln!(text, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).unwrap();
            }
            "obj"
        }
        "ply-ascii" | "ply-binary" => {
            let binary = format == "ply-binary";
            let head = format!(
                "ply\nformat {} 1.0\nelement vertex {}\nproperty double x\nproperty double y\n\
                 property double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
                if binary { "binary_little_endian" } else { "ascii" },
                v.len(),
                f.len()
            );
            bytes.extend(head.as_bytes());
            for p in v {
                if binary {
                    p.iter().for_each(|x| bytes.extend(x.to_le_bytes()));
                } else {
                    bytes.extend(format!("{} {} {}\n", p[0], p[1], p[2]).as_bytes());
                }
            }
            for t in f {
                if binary {
                    bytes.push(3);
                    t.iter()
                        .for_each(|&i| bytes.extend((i as i32).to_le_bytes()));
                } else {
                    bytes.extend(format!("3 {} {} {}\n", t[0], t[1], t[2]).as_bytes());
                }
            }
            "ply"
        }
        _ => unreachable!(),
    };
    bytes.extend(text.as_bytes());
    let file = format!("{name}.{ext}");
    std::fs::File::create(dir.join(&file))
        .and_then(|mut o| o.write_all(&bytes))
        .unwrap();
    file
}

/// A 3D scene at spacing `dx` in [-1.5, 1.5]^3 holding `objects` (TOML tables).
fn scene3(dx: f64, objects: &str) -> String {
    format!(
        r#"dimension = 3
name = "geometry"
[domain]
min = [-1.5, -1.5, -1.5]
max = [1.5, 1.5, 1.5]
[discretisation]
spacing = {dx}
[time]
end = 0.1
output_interval = 0.1
[fluid]
density = 1000.0
sound_speed = 20.0
[boundary]
strength = 10.0
{objects}"#
    )
}

fn fluid_in(dx: f64, file: &str) -> String {
    scene3(
        dx,
        &format!(
            "[[fluid_blocks]]\nmin = [-1.2, -1.2, -1.2]\nmax = [1.2, 1.2, 1.2]\ninside = {{ file = \"{file}\" }}\n"
        ),
    )
}

#[test]
fn a_sphere_in_every_format_fills_to_its_volume() {
    let dir = tempfile::tempdir().unwrap();
    let (v, f) = icosphere(1.0, 4);
    let dx = 0.05; // R / dx = 20
    let exact = 4.0 / 3.0 * PI;
    for format in ["stl-binary", "stl-ascii", "obj", "ply-ascii", "ply-binary"] {
        let file = write(dir.path(), format, &v, &f);
        let text = fluid_in(dx, &file);
        let scene = Scene::from_toml_in(
            &text,
            format,
            &meshfree_core::scene::geometry::base_of(&dir.path().join("s.toml")),
        )
        .unwrap();
        let n = Counts::of(&scene.particles()).fluid;
        let volume = n as f64 * dx.powi(3);
        eprintln!(
            "{format}: {n} particles, volume {:+.3} % of the sphere's",
            100.0 * (volume / exact - 1.0)
        );
        assert!(
            (volume / exact - 1.0).abs() < 0.01,
            "{format}: {n} particles, volume {volume} against {exact}"
        );
    }
}

fn base(dir: &Path) -> meshfree_core::scene::geometry::Base {
    meshfree_core::scene::geometry::base_of(&dir.join("scene.toml"))
}

#[test]
fn a_sphere_wall_gets_radial_normals_and_its_distance() {
    let dir = tempfile::tempdir().unwrap();
    let (v, f) = icosphere(1.0, 5);
    let file = write(dir.path(), "stl-binary", &v, &f);
    let dx = 0.05;
    // Morris's walls ask for each wall particle's surface (normal into the fluid, d_B).
    let text = scene3(
        dx,
        &format!(
            "[[walls]]\nshape = \"mesh\"\nmesh = {{ file = \"{file}\" }}\nsolid = \"inside\"\nlayers = 3\n\
             [[fluid_blocks]]\nmin = [-1.4, -1.4, -1.4]\nmax = [1.4, 1.4, 1.4]\n"
        ),
    )
    .replace(
        "strength = 10.0",
        "strength = 10.0\nwall_coupling = \"dynamic\"\nno_slip = \"morris\"",
    )
    .replace("sound_speed = 20.0", "sound_speed = 20.0\nviscosity = 0.01");
    let scene = Scene::from_toml_in(&text, "sphere-wall", &base(dir.path())).unwrap();
    let setup = scene.setup().unwrap();
    let first = setup.params.wall_first_id;
    let (mut worst_angle, mut worst_d, mut n) = (0.0f64, 0.0f64, 0);
    for p in setup.particles.iter().filter(|p| p.kind == Kind::Boundary) {
        let x = p.position.map(f64::from);
        let r = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
        assert!(
            r < 1.0 && r > 1.0 - 3.0 * dx - 1e-9,
            "a wall particle at r = {r}"
        );
        let s = setup.wall_surface[(p.id - first) as usize].map(f64::from);
        let cos = (s[0] * x[0] + s[1] * x[1] + s[2] * x[2]) / r;
        worst_angle = worst_angle.max(cos.clamp(-1.0, 1.0).acos().to_degrees());
        worst_d = worst_d.max((s[3] - (1.0 - r)).abs() / dx);
        n += 1;
    }
    eprintln!("{n} wall particles: normals within {worst_angle:.3} deg of radial, distances within {worst_d:.4} dx");
    assert!(n > 1000, "{n} wall particles");
    assert!(
        worst_angle < 2.0,
        "normals within {worst_angle} degrees of radial"
    );
    assert!(worst_d < 0.05, "distances within {worst_d} dx");
    // No fluid inside the sphere, and fluid up to about one spacing from it.
    let fluid: Vec<f64> = (setup.particles.iter())
        .filter(|p| p.kind == Kind::Fluid)
        .map(|p| {
            p.position
                .map(f64::from)
                .iter()
                .map(|x| x * x)
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    let nearest = fluid.iter().cloned().fold(f64::MAX, f64::min);
    assert!(
        nearest > 1.0 && nearest < 1.0 + 1.5 * dx,
        "nearest fluid at r = {nearest}"
    );
}

#[test]
fn a_small_hole_and_an_inside_out_winding_fill_the_same() {
    let dir = tempfile::tempdir().unwrap();
    let (v, f) = icosphere(1.0, 4);
    let dx = 0.05;
    let count = |f: &[[u32; 3]], name: &str| {
        let file = write(dir.path(), "obj", &v, f);
        let renamed = format!("{name}.obj");
        std::fs::rename(dir.path().join(&file), dir.path().join(&renamed)).unwrap();
        let scene = Scene::from_toml_in(&fluid_in(dx, &renamed), name, &base(dir.path())).unwrap();
        Counts::of(&scene.particles()).fluid
    };
    let whole = count(&f, "whole");
    let mut holed = f.clone();
    holed.drain(100..103); // three triangles gone: a hole about 0.1 across
    assert_eq!(count(&holed, "holed"), whole);
    let inverted: Vec<[u32; 3]> = f.iter().map(|t| [t[0], t[2], t[1]]).collect();
    assert_eq!(count(&inverted, "inverted"), whole);
}

#[test]
fn a_polygon_tank_makes_the_box_containers_particles() {
    // dam-break-2d's tank as a closed polygon with the rows outside it, and a lid as the
    // box-container has (open_top = false).
    let base_scene = Scene::builtin("dam-break-2d").unwrap();
    let text = base_scene.text.replace(
        "shape = \"box-container\"\nmin = [0.0, 0.0]\nmax = [4.0, 2.0]",
        "shape = \"polygon\"\npolygon = { points = [[0.0, 0.0], [4.0, 0.0], [4.0, 2.0], [0.0, 2.0]] }\nsolid = \"outside\"",
    )
    .replacen("open_top = false", "# closed", 1);
    assert_ne!(text, base_scene.text);
    let poly = Scene::from_toml(&text, "polygon-tank").unwrap();
    let (a, b) = (base_scene.particles(), poly.particles());
    let (ca, cb) = (Counts::of(&a), Counts::of(&b));
    assert_eq!(ca.fluid, cb.fluid);
    // The rows are the same but for the corners: a box-container fills the square 3 x 3
    // corner, the band of the polygon keeps only the points within 3 dx of its corner.
    let missing = ca.boundary - cb.boundary;
    assert!(
        cb.boundary < ca.boundary && missing <= 4 * 3,
        "{ca:?} {cb:?}"
    );
    let key = |p: &meshfree_core::physics::particle::Particle| {
        p.position.map(|x| (x * 1e4).round() as i64)
    };
    let rows: std::collections::HashSet<_> = a
        .iter()
        .filter(|p| p.kind == Kind::Boundary)
        .map(key)
        .collect();
    assert!(b
        .iter()
        .filter(|p| p.kind == Kind::Boundary)
        .all(|p| rows.contains(&key(p))));
}

#[test]
fn a_sphere_sliced_through_its_centre_is_a_disc() {
    // The 2D cut of the 3D sphere file: a polygon of radius about 1 (the icosphere's chords
    // make it a little smaller), filled and walled as a disc.
    let dir = tempfile::tempdir().unwrap();
    let (v, f) = icosphere(1.0, 4);
    let file = write(dir.path(), "stl-binary", &v, &f);
    let dx = 0.02;
    let text = format!(
        r#"dimension = 2
name = "slice"
[domain]
min = [-1.5, -1.5]
max = [1.5, 1.5]
[discretisation]
spacing = {dx}
[time]
end = 0.1
output_interval = 0.1
[fluid]
density = 1000.0
sound_speed = 20.0
[boundary]
strength = 10.0
[[fluid_blocks]]
min = [-1.2, -1.2]
max = [1.2, 1.2]
inside = {{ file = "{file}", slice = 0.0, scale = 0.5, translate = [0.2, 0.0] }}
[[walls]]
shape = "polygon"
polygon = {{ file = "{file}", slice = 0.0, scale = 0.5, rotate = [30.0], translate = [0.2, 0.0] }}
solid = "outside"
layers = 2
"#
    );
    let scene = Scene::from_toml_in(&text, "slice", &base(dir.path())).unwrap();
    let p = scene.particles();
    let c = Counts::of(&p);
    let area = c.fluid as f64 * dx * dx;
    let exact = PI * 0.25;
    assert!(
        (area / exact - 1.0).abs() < 0.02,
        "{} fluid: area {area} against {exact}",
        c.fluid
    );
    for q in p.iter() {
        let r = ((q.position[0] as f64 - 0.2).powi(2) + (q.position[1] as f64).powi(2)).sqrt();
        match q.kind {
            Kind::Fluid => assert!(r < 0.5, "fluid at r = {r}"),
            _ => assert!(r > 0.49 && r < 0.5 + 2.0 * dx + 1e-6, "wall at r = {r}"),
        }
    }
    // A plane that misses the mesh, and slice in the wrong place, are refused.
    let missed = text.replace(
        "slice = 0.0, scale = 0.5, translate",
        "slice = 3.0, scale = 0.5, translate",
    );
    let e = Scene::from_toml_in(&missed, "slice", &base(dir.path())).unwrap_err();
    assert!(
        e.to_string().contains("fluid_blocks[0].inside.slice: ")
            && e.to_string().contains("cuts no triangle"),
        "{e}"
    );
    let points = text.replace(
        &format!("polygon = {{ file = \"{file}\", slice = 0.0,"),
        "polygon = { points = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], slice = 0.0,",
    );
    let e = Scene::from_toml_in(&points, "slice", &base(dir.path())).unwrap_err();
    assert!(e.to_string().contains("walls[0].polygon.slice: "), "{e}");
}

/// (count, mean and standard deviation of the distance to the sphere of radius `r` about
/// the origin, in dx, of the particles within one spacing of it; the smallest distance
/// between two particles, in dx).
fn skin(
    p: &[meshfree_core::physics::particle::Particle],
    r: f64,
    dx: f64,
) -> (usize, f64, f64, f64) {
    let x: Vec<[f64; 3]> = p.iter().map(|q| q.position.map(f64::from)).collect();
    let d: Vec<f64> = x
        .iter()
        .map(|q| (r - (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt()) / dx)
        .filter(|&d| d < 1.0)
        .collect();
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    let sd = (d.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / d.len() as f64).sqrt();
    let mut closest = f64::MAX;
    for i in 0..x.len() {
        for j in i + 1..x.len() {
            let s = (0..3)
                .map(|a| (x[i][a] - x[j][a]).powi(2))
                .sum::<f64>()
                .sqrt();
            closest = closest.min(s / dx);
        }
    }
    (d.len(), mean, sd, closest)
}

#[test]
fn packing_lays_the_first_row_half_a_spacing_inside_a_sphere() {
    let dir = tempfile::tempdir().unwrap();
    let (v, f) = icosphere(0.5, 4);
    let file = write(dir.path(), "stl-binary", &v, &f);
    let dx = 0.05; // R / dx = 10
    let text = |pack: bool| {
        scene3(
            dx,
            &format!(
                "[solid]\ndensity = 1000.0\nsound_speed = 20.0\nshear_modulus = 1e5\n\
                 [[solids]]\nshape = \"mesh\"\nmesh = {{ file = \"{file}\", pack = {pack} }}\n"
            ),
        )
    };
    let lattice = Scene::from_toml_in(&text(false), "lattice", &base(dir.path()))
        .unwrap()
        .particles();
    let packed = Scene::from_toml_in(&text(true), "packed", &base(dir.path()))
        .unwrap()
        .particles();
    assert_eq!(lattice.len(), packed.len(), "packing keeps the particles");
    let (n0, m0, s0, c0) = skin(&lattice, 0.5, dx);
    let (n1, m1, s1, c1) = skin(&packed, 0.5, dx);
    eprintln!("lattice: {n0} in the skin, distance {m0:.3} +- {s0:.3} dx, closest pair {c0:.3} dx");
    eprintln!("packed:  {n1} in the skin, distance {m1:.3} +- {s1:.3} dx, closest pair {c1:.3} dx");
    // The stair-stepped lattice spreads its skin over the spacing; packed, it is one row.
    assert!(s0 > 0.2, "{s0}");
    assert!(s1 < 0.12 && (m1 - 0.5).abs() < 0.1, "{m1} +- {s1}");
    // Relaxed in 3D the first row holds a few more particles than the lattice's skin (the
    // closest pair at 0.68 dx on 2026-12-06); a collapse would put two far closer.
    assert!(c1 > 0.6, "no two packed particles closer than 0.6 dx: {c1}");
    assert!(packed.iter().all(|q| {
        let x = q.position.map(f64::from);
        (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt() < 0.5
    }));
}
