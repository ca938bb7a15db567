//! Our VTU files (raw, zlib and LZ4) read by the official VTK Python module, and the raw and
//! zlib ones by meshio (whose reader of raw appended data knows no LZ4): point and cell
//! counts, arrays, values, and ParaView's Threshold on `kind` (one vertex cell per
//! particle, so it selects the fluid alone). Needs Python with `vtk`, `meshio` and `numpy`
//! (`MESHFREE_PYTHON`, default `python3`); ignored unless `MESHFREE_REQUIRE_PYVTK=1` at
//! build time (`app/build.rs`; CI sets it and installs them).

use meshfree::run::{self, Progress, RunOptions};
use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::Scene;

const SCRIPT: &str = r#"
import sys, json
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy
import meshio

path, expect = sys.argv[1], json.loads(sys.argv[2])
n = expect["points"]

r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(path)
r.Update()
g = r.GetOutput()
assert g.GetNumberOfPoints() == n, ("vtk points", g.GetNumberOfPoints(), n)
assert g.GetNumberOfCells() == n, ("vtk cells", g.GetNumberOfCells(), n)
assert g.GetCellType(n - 1) == vtk.VTK_VERTEX
pd = g.GetPointData()
names = sorted(pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays()))
assert names == sorted(expect["arrays"]), ("vtk arrays", names)
p = vtk_to_numpy(pd.GetArray("pressure"))
assert abs(float(p.min()) - expect["p_min"]) <= 1e-6 * max(1.0, abs(expect["p_min"])), (p.min(), expect["p_min"])
assert abs(float(p.max()) - expect["p_max"]) <= 1e-6 * max(1.0, abs(expect["p_max"])), (p.max(), expect["p_max"])
if "id" in expect["arrays"]:
    ids = vtk_to_numpy(pd.GetArray("id"))
    assert sorted(ids.tolist()) == list(range(n))

# ParaView's Threshold on kind: fluid only (kind 0).
t = vtk.vtkThreshold()
t.SetInputData(g)
t.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS, "kind")
t.SetLowerThreshold(0)
t.SetUpperThreshold(0)
t.Update()
assert t.GetOutput().GetNumberOfCells() == expect["fluid"], ("threshold", t.GetOutput().GetNumberOfCells())

if expect["meshio"]:
    m = meshio.read(path)
    assert m.points.shape == (n, 3), m.points.shape
    assert sum(len(c.data) for c in m.cells if c.type == "vertex") == n, [c.type for c in m.cells]
    assert np.allclose(np.sort(np.asarray(m.point_data["pressure"]).ravel()), np.sort(p)), (m.point_data["pressure"].shape, p.shape)
    if "id" in expect["arrays"]:
        assert np.array_equal(np.asarray(m.point_data["id"]).ravel(), ids)
else:
    # meshio's reader of raw appended data knows zlib and LZMA only (meshio 5.3): the docs
    # say so; this fails the day it reads LZ4, so that they can change.
    try:
        meshio.read(path)
        raise SystemExit("meshio now reads LZ4: say so in the docs and check its values here")
    except KeyError as e:
        assert "vtkLZ4DataCompressor" in str(e), e
print("ok", path)
"#;

#[test]
#[cfg_attr(
    not(meshfree_require_pyvtk),
    ignore = "needs Python with vtk, meshio and numpy: build with MESHFREE_REQUIRE_PYVTK=1 (CI does)"
)]
fn vtk_and_meshio_read_our_files() {
    let python = std::env::var("MESHFREE_PYTHON").unwrap_or_else(|_| "python3".into());
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("read.py");
    std::fs::write(&script, SCRIPT).unwrap();
    for format in [
        OutputFormat::Vtu,
        OutputFormat::VtuZlib,
        OutputFormat::VtuLz4,
    ] {
        let out = dir.path().join(format!("{format:?}"));
        let scene = Scene::builtin("tank-2d").unwrap();
        let mut frames = Vec::new();
        run::run_observed(
            &scene,
            &RunOptions {
                backend: meshfree_core::backend::BackendChoice::Cpu,
                out_dir: Some(out.clone()),
                max_steps: Some(4),
                output_interval: Some(1e-3),
                progress: Progress::Quiet,
                format: Some(format),
                ..Default::default()
            },
            &mut |f| frames.push(f.data.clone()),
        )
        .unwrap();
        let last = frames.last().unwrap();
        let i = frames.len() - 1;
        let path = out.join(format!("particles_{i:05}.vtu"));
        let fluid = last
            .kind
            .iter()
            .filter(|&&k| k == Kind::Fluid.code())
            .count();
        let (p_min, p_max) = last
            .pressure
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &p| {
                (a.min(p), b.max(p))
            });
        let expect = serde_json::json!({
            "points": last.len,
            "fluid": fluid,
            // The default fields of a tank: fluid and walls, one object each.
            "arrays": ["kind", "velocity", "density", "pressure"],
            "p_min": p_min,
            "p_max": p_max,
            "meshio": format != OutputFormat::VtuLz4,
        });
        let result = std::process::Command::new(&python)
            .arg(&script)
            .arg(&path)
            .arg(expect.to_string())
            .output()
            .unwrap_or_else(|e| panic!("cannot run {python}: {e}"));
        assert!(
            result.status.success(),
            "{format:?}: {}\n{}",
            String::from_utf8_lossy(&result.stdout),
            String::from_utf8_lossy(&result.stderr)
        );
    }
}

/// The Python reader of `checkpoint.bin` in `docs/reference/checkpoint.md` (its last
/// ```python block, run as it stands) reads a checkpoint of a run with elastic bodies: the
/// time, step count, particle count and mean density the Rust reader reads.
#[test]
#[cfg_attr(
    not(meshfree_require_pyvtk),
    ignore = "needs Python with numpy: build with MESHFREE_REQUIRE_PYVTK=1 (CI does)"
)]
fn the_documented_python_reader_reads_a_checkpoint() {
    let python = std::env::var("MESHFREE_PYTHON").unwrap_or_else(|_| "python3".into());
    let doc = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/reference/checkpoint.md"),
    )
    .unwrap();
    let code = doc
        .rsplit("```python\n")
        .next()
        .and_then(|rest| rest.split("```").next())
        .expect("a ```python block in docs/reference/checkpoint.md");
    let dir = tempfile::tempdir().unwrap();
    let script = dir.path().join("read_checkpoint.py");
    std::fs::write(&script, code).unwrap();
    // One domain's checkpoint, and a decomposed run's index with a piece per rank.
    for decompose in [None, Some(2)] {
        reads_one(&python, &script, &dir.path().join("run"), decompose);
    }
}

fn reads_one(
    python: &str,
    script: &std::path::Path,
    out: &std::path::Path,
    decompose: Option<usize>,
) {
    let summary = run::run(
        &Scene::builtin("impinging-2d").unwrap(),
        &RunOptions {
            backend: meshfree_core::backend::BackendChoice::Cpu,
            out_dir: Some(out.to_path_buf()),
            overwrite: true,
            max_steps: Some(5),
            progress: Progress::Quiet,
            format: Some(OutputFormat::None),
            decompose,
            ..Default::default()
        },
    )
    .unwrap();
    let (saved, _): (meshfree::output::checkpoint::Saved, serde_json::Value) =
        meshfree::output::checkpoint::load(&out.join(meshfree::output::checkpoint::FILE)).unwrap();
    let c = saved.gathered();
    assert_eq!(c.steps, summary.steps);
    let result = std::process::Command::new(python)
        .arg(script)
        .arg(out.join(meshfree::output::checkpoint::FILE))
        .output()
        .unwrap_or_else(|e| panic!("cannot run {python}: {e}"));
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(
        result.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&result.stderr)
    );
    let words: Vec<f64> = stdout
        .split_whitespace()
        .map(|w| w.parse().unwrap())
        .collect();
    let mean = c.rho.iter().map(|&r| r as f64).sum::<f64>() / c.len() as f64;
    assert_eq!(words[0], c.time, "time");
    assert_eq!(words[1], c.steps as f64, "steps");
    assert_eq!(words[2], c.len() as f64, "particles");
    assert!(
        (words[3] - mean).abs() <= 1e-5 * mean,
        "mean density: python {} rust {mean}",
        words[3]
    );
}
