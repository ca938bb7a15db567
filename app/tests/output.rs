//! Output files are well-formed: VTK (.vtu, .pvd), diagnostics CSV, summary JSON; and a
//! short run through `run::run` writes all of them consistently.

use meshfree::output::{self, diagnostics, PvdSeries};
use meshfree::run::{self, Progress, RunOptions};
use meshfree_core::particle::{Kind, Particle};
use meshfree_core::scene::Scene;
use meshfree_core::solver::Diagnostics;

fn particles(n: usize) -> Vec<Particle> {
    (0..n)
        .map(|i| Particle {
            id: i as u32,
            kind: Kind::from_code((i % 3) as u8).unwrap(),
            group: (i % 2) as u32,
            position: [i as f32 * 0.1, 1.0, -0.5],
            velocity: [1.0, -2.0, 0.25],
            density: 1000.0,
            pressure: 12.5,
            mass: 0.4,
            stress: [1.0, 2.0, 3.0, 4.0, 5.0, 6.0],
        })
        .collect()
}

/// (Name, NumberOfComponents, number of values) of every DataArray in a .vtu text.
fn arrays(text: &str) -> Vec<(String, usize, usize)> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("<DataArray ") {
        rest = &rest[i..];
        let head_end = rest.find('>').unwrap();
        let head = &rest[..head_end];
        let attr = |k: &str| {
            let s = &head[head.find(&format!("{k}=\"")).unwrap() + k.len() + 2..];
            s[..s.find('"').unwrap()].to_string()
        };
        let body_end = rest.find("</DataArray>").unwrap();
        let values = rest[head_end + 1..body_end].split_whitespace().count();
        out.push((
            attr("Name"),
            attr("NumberOfComponents").parse().unwrap(),
            values,
        ));
        rest = &rest[body_end..];
    }
    out
}

fn number_of_points(text: &str) -> usize {
    let s = &text[text.find("NumberOfPoints=\"").unwrap() + 16..];
    s[..s.find('"').unwrap()].parse().unwrap()
}

#[test]
fn vtu_counts_match() {
    let dir = tempfile::tempdir().unwrap();
    for (with_stress, n) in [(false, 7), (true, 40)] {
        let path = dir.path().join(format!("p{n}.vtu"));
        output::write_vtu(&path, &particles(n), with_stress).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("<?xml") && text.trim_end().ends_with("</VTKFile>"));
        assert_eq!(number_of_points(&text), n);
        let a = arrays(&text);
        let names: Vec<&str> = a.iter().map(|x| x.0.as_str()).collect();
        let mut expect = vec![
            "id", "kind", "group", "velocity", "speed", "density", "pressure",
        ];
        if with_stress {
            expect.push("stress");
        }
        expect.extend(["Points", "connectivity", "offsets", "types"]);
        assert_eq!(names, expect);
        for (name, comps, values) in &a {
            let want = match name.as_str() {
                "offsets" | "types" => 1,
                _ => n * comps,
            };
            assert_eq!(*values, want, "{name}");
        }
        assert!(
            text.contains(&format!("{}", (1.0f32 + 4.0 + 0.0625).sqrt())),
            "speed written"
        );
    }
}

#[test]
fn pvd_lists_every_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut pvd = PvdSeries::new(dir.path().join("s.pvd"));
    for i in 0..3 {
        pvd.add(i as f64 * 0.5, &format!("f{i}.vtu")).unwrap();
        let text = std::fs::read_to_string(dir.path().join("s.pvd")).unwrap();
        assert_eq!(text.matches("<DataSet ").count(), i + 1);
        assert!(text.trim_end().ends_with("</VTKFile>"));
    }
    let text = std::fs::read_to_string(dir.path().join("s.pvd")).unwrap();
    assert!(text.contains("timestep=\"1\" group=\"\" part=\"0\" file=\"f2.vtu\""));
}

#[test]
fn csv_rows_match_header() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.csv");
    let mut csv = output::DiagnosticsCsv::create(&path).unwrap();
    let d = Diagnostics {
        step: 3,
        time: 0.5,
        momentum: [1.0, 2.0, 3.0],
        fluid: 9,
        ..Default::default()
    };
    csv.write(&d).unwrap();
    csv.write(&d).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], diagnostics::CSV_HEADER);
    assert_eq!(lines.len(), 3);
    let cols = lines[0].split(',').count();
    assert_eq!(cols, 12);
    for l in &lines[1..] {
        let f: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        assert_eq!(f.len(), cols);
        assert_eq!((f[0], f[1], f[8], f[9]), (3.0, 0.5, 3.0, 9.0));
    }
}

/// A short run of the resting tank through the library driver. Needs a working backend.
#[test]
fn run_writes_consistent_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("tank");
    let scene = Scene::builtin("tank-2d").unwrap();
    let options = RunOptions {
        particle_csv: false,
        out_dir: Some(out.clone()),
        max_steps: Some(12),
        output_interval: Some(1e-3),
        progress: Progress::Quiet,
        ..Default::default()
    };
    let mut seen = 0;
    let summary = run::run_observed(&scene, &options, &mut |f| {
        assert_eq!(f.index, seen);
        assert!(f.particles.windows(2).all(|w| w[0].id < w[1].id));
        seen += 1;
    })
    .unwrap();
    assert_eq!(summary.steps, 12);
    assert_eq!(summary.particles.total, 2026);
    assert_eq!(summary.status, output::RunStatus::Completed);
    assert!(summary.outputs >= 2 && summary.outputs == seen);

    let pvd = std::fs::read_to_string(out.join("particles.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet ").count(), summary.outputs);
    for i in 0..summary.outputs {
        let text = std::fs::read_to_string(out.join(format!("particles_{i:05}.vtu"))).unwrap();
        assert_eq!(number_of_points(&text), 2026);
        assert!(
            !text.contains("Name=\"stress\""),
            "no stress without solids"
        );
    }
    let csv = std::fs::read_to_string(out.join("diagnostics.csv")).unwrap();
    assert_eq!(csv.lines().count(), summary.outputs + 1);
    let last: Vec<&str> = csv.lines().last().unwrap().split(',').collect();
    assert_eq!(last[0], "12");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "completed");
    assert_eq!(json["steps"], 12);
    assert_eq!(json["scene_source"], "builtin:tank-2d");
    assert_eq!(json["particles"]["fluid"], 1600);
    assert!(json["fault"].is_null());
    // The tank's water is one connected body: one fluid cluster at every output.
    assert_eq!(json["fluid_clusters"], 1);
    let clusters = std::fs::read_to_string(out.join("clusters.csv")).unwrap();
    assert_eq!(clusters.lines().count(), summary.outputs + 1);
    assert!(
        clusters.lines().skip(1).all(|l| l.ends_with(",1")),
        "{clusters}"
    );
    assert!(out.join("scene.toml").exists());
}

/// A fixed step far beyond the CFL limit blows up: the run stops with the fault, keeps
/// its output and writes a failed summary.
#[test]
fn blow_up_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("boom");
    let mut scene = Scene::builtin("tank-2d").unwrap();
    scene.file.time.dt = Some(0.5);
    scene.revalidate().unwrap();
    let options = RunOptions {
        particle_csv: false,
        out_dir: Some(out.clone()),
        max_steps: Some(50),
        output_interval: Some(0.5),
        progress: Progress::Quiet,
        ..Default::default()
    };
    match run::run(&scene, &options) {
        Err(run::RunError::BlowUp { fault, summary, .. }) => {
            assert_eq!(summary.status, output::RunStatus::Failed);
            assert_eq!(summary.fault.as_ref(), Some(&*fault));
            let json: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                    .unwrap();
            assert_eq!(json["status"], "failed");
            assert_eq!(json["fault"]["step"], fault.step);
            assert!(out.join("particles_00000.vtu").exists());
        }
        other => panic!("expected a blow-up, got {other:?}"),
    }
}
