//! Probes and gauges through a run (`[[probes]]`, `[[gauges]]`: `app/src/probes.rs`): the
//! built-in still tank on the CPU writes `probes.csv` and `gauges.csv` in their documented
//! layout, with the hydrostatic pressure at the probes and the surface at the gauge.

use meshfree::run::{self, Progress, RunOptions};
use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::Scene;

const PROBES: &str = r#"
[[probes]]
name = "column"
points = [[0.5, 0.75], [0.5, 0.5], [0.5, 0.25], [0.5, 1.25]]
interval = 0.01

[[probes]]
name = "corner-v"
points = [[0.05, 0.05]]
interval = 0.02
fields = ["velocity"]
walls = true

[[gauges]]
name = "middle"
start = [0.5, 0.0]
end = [0.5, 1.2]
interval = 0.005

[[gauges]]
name = "dry"
start = [0.2, 1.1]
end = [0.8, 1.25]
interval = 0.01
step = 0.01
"#;

/// The CSV's rows as maps from column name to cell.
fn read(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    for r in &rows {
        assert_eq!(r.len(), header.len(), "{}: row {r:?}", path.display());
    }
    (header, rows)
}

#[test]
fn tank_probes_and_gauges_write_their_csv() {
    let base = Scene::builtin("tank-2d").unwrap();
    let scene = Scene::from_toml(&(base.text.clone() + PROBES), "tank-2d + probes").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let options = RunOptions {
        backend: BackendChoice::Cpu,
        out_dir: Some(out.clone()),
        t_end: Some(0.02),
        output_interval: Some(0.02),
        progress: Progress::Quiet,
        ..Default::default()
    };
    let summary = run::run(&scene, &options).unwrap();

    let (h, rows) = read(&out.join("probes.csv"));
    assert_eq!(
        h.join(","),
        "time,step,probe,point,x,y,pressure,velocity_x,velocity_y,density"
    );
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let times = |probe: &str| -> Vec<f64> {
        let mut t: Vec<f64> = (rows.iter().filter(|r| r[col("probe")] == probe))
            .map(|r| r[0].parse().unwrap())
            .collect();
        t.dedup();
        t
    };
    // At t = 0 and at the first step at or past each multiple of the interval.
    let (tc, tv) = (times("column"), times("corner-v"));
    assert_eq!((tc.len(), tv.len()), (3, 2), "{tc:?} {tv:?}");
    for (t, k) in tc.iter().zip(0..) {
        assert!(
            *t >= 0.01 * k as f64 - 1e-9 && *t < 0.01 * k as f64 + 5e-4,
            "{tc:?}"
        );
    }
    for r in rows.iter().filter(|r| r[col("probe")] == "column") {
        let (point, y): (usize, f64) = (
            r[col("point")].parse().unwrap(),
            r[col("y")].parse().unwrap(),
        );
        if point == 3 {
            // Above the water, beyond the support: empty cells (NaN).
            for c in ["pressure", "velocity_x", "velocity_y", "density"] {
                assert_eq!(r[col(c)], "", "{r:?}");
            }
            continue;
        }
        let p: f64 = r[col("pressure")].parse().unwrap();
        let want = 1000.0 * 9.81 * (1.0 - y);
        assert!((p / want - 1.0).abs() < 0.03, "{r:?}: rho0 g d = {want}");
        let rho: f64 = r[col("density")].parse().unwrap();
        assert!((rho / 1000.0 - 1.0).abs() < 0.01, "{r:?}");
        assert!(r[col("velocity_x")].parse::<f64>().unwrap().abs() < 0.05);
    }
    // The velocity-only probe: its other fields' cells stay empty.
    for r in rows.iter().filter(|r| r[col("probe")] == "corner-v") {
        assert_eq!(
            (r[col("pressure")].as_str(), r[col("density")].as_str()),
            ("", "")
        );
        assert!(
            r[col("velocity_y")].parse::<f64>().unwrap().abs() < 0.05,
            "{r:?}"
        );
    }

    let (h, rows) = read(&out.join("gauges.csv"));
    assert_eq!(h.join(","), "time,step,gauge,x,y,distance");
    let dx = scene.file.discretisation.spacing;
    let middle: Vec<&Vec<String>> = rows.iter().filter(|r| r[2] == "middle").collect();
    assert_eq!(middle.len(), 5, "{rows:?}");
    for r in middle {
        let (x, y, d): (f64, f64, f64) = (
            r[3].parse().unwrap(),
            r[4].parse().unwrap(),
            r[5].parse().unwrap(),
        );
        assert_eq!(x, 0.5);
        assert!(
            (y - 1.0).abs() <= 0.5 * dx && (d - y).abs() < 1e-12,
            "{r:?}"
        );
    }
    for r in rows.iter().filter(|r| r[2] == "dry") {
        assert_eq!(&r[3..], ["", "", ""], "a dry line has no surface: {r:?}");
    }
    assert_eq!(summary.status, meshfree::output::RunStatus::Completed);
}
