//! Rigid-body measures of elastic bodies (`analysis::bodies`) and the run driver's
//! `bodies.csv` and `summary.json` entries.

use meshfree::analysis::bodies::{body, BodyTracker};
use meshfree::output::bodies_csv::BODIES_HEADER;
use meshfree::run::{self, Progress, RunOptions};
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::Scene;

/// A lattice body of group 1 (n[a] particles along each axis at spacing 0.5), moving
/// rigidly: velocity v + omega x (x - c) about its centroid c.
fn rigid(n: [usize; 3], v: [f32; 3], omega: [f32; 3]) -> Vec<Particle> {
    let mut out = Vec::new();
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                out.push([
                    3.0 + 0.5 * i as f32,
                    2.0 + 0.5 * j as f32,
                    1.0 + 0.5 * k as f32,
                ]);
            }
        }
    }
    let m = out.len() as f32;
    let cm = [0, 1, 2].map(|a| out.iter().map(|x| x[a]).sum::<f32>() / m);
    out.iter()
        .enumerate()
        .map(|(id, x)| {
            let d = [x[0] - cm[0], x[1] - cm[1], x[2] - cm[2]];
            let w = omega;
            let u = [
                w[1] * d[2] - w[2] * d[1],
                w[2] * d[0] - w[0] * d[2],
                w[0] * d[1] - w[1] * d[0],
            ];
            Particle {
                id: id as u32,
                kind: Kind::Solid,
                group: 1,
                position: *x,
                velocity: [v[0] + u[0], v[1] + u[1], v[2] + u[2]],
                density: 0.6,
                pressure: 0.0,
                mass: 0.15,
                stress: [0.0; 6],
            }
        })
        .collect()
}

fn close(a: [f32; 3], b: [f32; 3], tol: f32) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= tol)
}

#[test]
fn rigid_motion_is_measured_exactly() {
    // 2D: a 6 x 4 plate (z = const) spinning at 0.7 about z.
    let mut ps = rigid([6, 4, 1], [1.0, -2.0, 0.0], [0.0, 0.0, 0.7]);
    ps.push(Particle {
        group: 0,
        kind: Kind::Fluid,
        ..ps[0]
    });
    let b = body(&ps, 1, 2).unwrap();
    assert_eq!(b.n, 24);
    assert!(
        close(b.velocity, [1.0, -2.0, 0.0], 1e-5),
        "{:?}",
        b.velocity
    );
    assert!(close(b.omega, [0.0, 0.0, 0.7], 1e-5), "{:?}", b.omega);
    assert!((b.size - 24.0 * 0.15 / 0.6).abs() < 1e-4, "{}", b.size);
    assert!(body(&ps, 7, 2).is_none());
    // 3D: a 3 x 4 x 5 block spinning about a tilted axis: omega = I^-1 L exactly.
    let w = [0.3, -0.2, 0.5];
    let b = body(&rigid([3, 4, 5], [0.0, 0.5, 0.0], w), 1, 3).unwrap();
    assert!(close(b.omega, w, 1e-5), "{:?}", b.omega);
    assert!(close(b.velocity, [0.0, 0.5, 0.0], 1e-5));
}

#[test]
fn tracker_reports_spread_and_size_against_the_start() {
    let ps = rigid([4, 4, 1], [0.0; 3], [0.0, 0.0, 0.0]);
    let mut tr = BodyTracker::new(&ps, 2);
    let c = body(&ps, 1, 2).unwrap().centroid;
    // Spread to twice the distance from the centroid, at 0.9 x the density.
    let apart: Vec<Particle> = ps
        .iter()
        .map(|p| Particle {
            position: [0, 1, 2].map(|a| c[a] + 2.0 * (p.position[a] - c[a])),
            density: 0.54,
            velocity: [0.0, 0.0, 0.0],
            ..*p
        })
        .collect();
    let rows = tr.sample(&apart);
    assert_eq!(rows.len(), 1);
    assert!((rows[0].rg_ratio - 2.0).abs() < 1e-5);
    assert!((rows[0].size_ratio - 1.0 / 0.9).abs() < 1e-5);
    let s = &tr.summaries()[0];
    assert_eq!((s.group, s.particles), (1, 16));
    assert!((s.worst_rg_change - 1.0).abs() < 1e-5);
    assert!((s.worst_size_change - (1.0 / 0.9 - 1.0)).abs() < 1e-5);
}

/// The driver writes one `bodies.csv` row per body and output, and each body's extremes
/// to `summary.json`; a scene without solids has no `bodies.csv`.
#[test]
fn run_writes_bodies_csv_and_summary() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("impinging");
    let scene = Scene::builtin("impinging-2d")
        .unwrap()
        .with_spacing(1.5)
        .unwrap();
    let options = RunOptions {
        out_dir: Some(out.clone()),
        t_end: Some(0.2),
        output_interval: Some(0.1),
        progress: Progress::Quiet,
        ..Default::default()
    };
    let summary = run::run(&scene, &options).unwrap();
    let csv = std::fs::read_to_string(out.join("bodies.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(BODIES_HEADER));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2 * summary.outputs, "two bodies per output");
    assert_eq!(rows[0][2], 1.0); // the square's group
    assert_eq!(rows[1][2], 2.0); // the disc's
    for r in &rows {
        // Free fall at g = 1 before the water arrives: vy = -t, no spin, no deformation.
        assert!((r[7] + r[1]).abs() < 0.01, "{r:?}");
        assert!(r[11].abs() < 1e-3 && (r[12] - 1.0).abs() < 0.01 && (r[13] - 1.0).abs() < 0.01);
    }
    assert_eq!(summary.bodies.len(), 2);
    assert!(summary.bodies.iter().all(|b| b.worst_rg_change < 0.01));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["bodies"][0]["group"], 1);

    let fluid_only = dir.path().join("tank");
    let options = RunOptions {
        out_dir: Some(fluid_only.clone()),
        max_steps: Some(2),
        progress: Progress::Quiet,
        ..Default::default()
    };
    let summary = run::run(&Scene::builtin("tank-2d").unwrap(), &options).unwrap();
    assert!(summary.bodies.is_empty());
    assert!(!fluid_only.join("bodies.csv").exists());
}
