//! Output files are well-formed: VTK (.vtu, .pvd), diagnostics CSV, summary JSON; and a
//! short run through `run::run` writes all of them consistently.

use meshfree::output::{self, diagnostics, Compression, PvdSeries};
use meshfree::run::{self, Progress, RunOptions};
use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::Scene;
use meshfree_core::solver::frame::{Field, Fields, FrameData};
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

/// A .vtu file's XML head (up to the appended data) and the appended bytes after `_`.
fn split_vtu(bytes: &[u8]) -> (String, Vec<u8>) {
    let marker = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(marker.len())
        .position(|w| w == marker)
        .expect("appended data");
    let head = String::from_utf8(bytes[..at].to_vec()).unwrap();
    let rest = &bytes[at + marker.len()..];
    let underscore = rest.iter().position(|&b| b == b'_').unwrap();
    let tail = b"\n  </AppendedData>\n</VTKFile>\n";
    assert!(rest.ends_with(tail), "the file ends with the closing tags");
    (head, rest[underscore + 1..rest.len() - tail.len()].to_vec())
}

/// (Name, type, NumberOfComponents, offset) of every DataArray of a .vtu head.
fn arrays(head: &str) -> Vec<(String, String, usize, usize)> {
    head.split("<DataArray ")
        .skip(1)
        .map(|tag| {
            let attr = |k: &str| {
                tag.find(&format!(" {k}=\""))
                    .or_else(|| tag.find(&format!("{k}=\"")).filter(|&i| i == 0))
                    .map(|i| {
                        let s = &tag[tag[i..].find('"').unwrap() + i + 1..];
                        s[..s.find('"').unwrap()].to_string()
                    })
            };
            (
                attr("Name").unwrap_or_else(|| "Points".into()),
                attr("type").unwrap(),
                attr("NumberOfComponents").unwrap().parse().unwrap(),
                attr("offset").unwrap().parse().unwrap(),
            )
        })
        .collect()
}

fn u64_at(b: &[u8], at: usize) -> usize {
    u64::from_le_bytes(b[at..at + 8].try_into().unwrap()) as usize
}

/// The decoded bytes of the array at `offset` of the appended data.
fn array_bytes(data: &[u8], offset: usize, compression: Compression) -> Vec<u8> {
    if compression == Compression::Raw {
        let n = u64_at(data, offset);
        return data[offset + 8..offset + 8 + n].to_vec();
    }
    use std::io::Read;
    let blocks = u64_at(data, offset);
    let (block, last) = (u64_at(data, offset + 8), u64_at(data, offset + 16));
    let mut at = offset + 8 * (3 + blocks);
    let mut out = Vec::new();
    for k in 0..blocks {
        let size = u64_at(data, offset + 8 * (3 + k));
        let chunk = &data[at..at + size];
        if compression == Compression::Zlib {
            let mut d = flate2::read::ZlibDecoder::new(chunk);
            d.read_to_end(&mut out).unwrap();
        } else {
            let len = if k + 1 == blocks && last != 0 {
                last
            } else {
                block
            };
            out.extend(lz4_flex::block::decompress(chunk, len).unwrap());
        }
        at += size;
    }
    let full = if last == 0 {
        blocks * block
    } else {
        (blocks - 1) * block + last
    };
    assert_eq!(out.len(), full, "the header's sizes match the data");
    out
}

fn number_of_points(head: &str) -> usize {
    let s = &head[head.find("NumberOfPoints=\"").unwrap() + 16..];
    s[..s.find('"').unwrap()].parse().unwrap()
}

fn floats(b: &[u8]) -> Vec<f32> {
    b.chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

/// Binary VTU, raw, zlib and LZ4, with and without stress, and a chosen field list: the head
/// names the arrays, the offsets lead to arrays of the right size, and the values are the
/// frame's; one vertex cell per particle.
#[test]
fn vtu_arrays_decode_to_the_frame() {
    let dir = tempfile::tempdir().unwrap();
    let all = Fields::all();
    let few = Fields::of(&[Field::Position, Field::Pressure]);
    // 300 000 particles: more than one compressed block per array.
    for (n, fields, compression) in [
        (7, all, Compression::Raw),
        (40, all, Compression::Zlib),
        (40, all, Compression::Lz4),
        (300_000, few, Compression::Zlib),
        (300_000, all, Compression::Lz4),
        (5, few, Compression::Raw),
    ] {
        let frame = FrameData::from_particles(&particles(n), all, 3, 0.25);
        let path = dir.path().join(format!("p{n}{compression:?}.vtu"));
        let bytes = output::write_vtu(&path, &frame, fields, compression).unwrap();
        let file = std::fs::read(&path).unwrap();
        assert_eq!(bytes, file.len() as u64);
        let (head, data) = split_vtu(&file);
        assert_eq!(
            head.contains("vtkZLibDataCompressor"),
            compression == Compression::Zlib
        );
        assert_eq!(
            head.contains("vtkLZ4DataCompressor"),
            compression == Compression::Lz4
        );
        assert_eq!(number_of_points(&head), n);
        assert!(head.contains(&format!("NumberOfCells=\"{n}\"")));
        let a = arrays(&head);
        let names: Vec<&str> = a.iter().map(|x| x.0.as_str()).collect();
        let mut expect: Vec<&str> = if fields == all {
            vec![
                "id", "kind", "group", "velocity", "density", "pressure", "stress",
            ]
        } else {
            vec!["pressure"]
        };
        expect.extend(["Points", "connectivity", "offsets", "types"]);
        assert_eq!(names, expect);
        for (name, ty, comps, offset) in &a {
            let b = array_bytes(&data, *offset, compression);
            let size = match ty.as_str() {
                "UInt8" => 1,
                "Int64" => 8,
                _ => 4,
            };
            assert_eq!(b.len(), n * comps * size, "{name}");
            match name.as_str() {
                "Points" => assert_eq!(floats(&b)[3 * (n - 1)], (n - 1) as f32 * 0.1),
                "pressure" => assert!(floats(&b).iter().all(|&p| p == 12.5)),
                "velocity" => assert_eq!(floats(&b)[..3], [1.0, -2.0, 0.25]),
                "stress" => assert_eq!(floats(&b)[6..12], [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
                "kind" => assert_eq!(b[..3], [0, 1, 2]),
                "types" => assert!(b.iter().all(|&t| t == 1), "VTK_VERTEX cells"),
                "offsets" => {
                    let last = i32::from_le_bytes(b[b.len() - 4..].try_into().unwrap());
                    assert_eq!(last as usize, n);
                }
                _ => {}
            }
        }
    }
}

/// The particle CSV carries the chosen fields' columns, rows ordered by id, and reads back
/// through `read_particles_csv` (what `meshfree compare` reads).
#[test]
fn particle_csv_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.csv");
    let mut frame = FrameData::from_particles(
        &particles(6),
        Fields::of(&[
            Field::Position,
            Field::Velocity,
            Field::Density,
            Field::Pressure,
            Field::Kind,
            Field::Id,
        ]),
        0,
        0.0,
    );
    // Storage order is not id order.
    frame.id.reverse();
    let fields = frame.fields();
    output::write_particles_csv(&path, &frame, fields).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.starts_with("id,kind,x,y,z,vx,vy,vz,density,pressure\n"),
        "{text}"
    );
    // The kind as its code, as in the VTU files (#51).
    for line in text.lines().skip(1) {
        let cols: Vec<&str> = line.split(',').collect();
        let slot = frame
            .id
            .iter()
            .position(|&i| i.to_string() == cols[0])
            .unwrap();
        assert_eq!(cols[1], frame.kind[slot].to_string(), "{line}");
    }
    let back = output::read_particles_csv(&path).unwrap();
    assert_eq!(back.len(), 6);
    assert!(back.windows(2).all(|w| w[0].id < w[1].id));
    // id 0 sits in the last storage slot, whose position is 0.5.
    assert_eq!(back[0].position[0], 0.5);
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
    let mut csv = output::DiagnosticsCsv::open(&path, false).unwrap();
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
    let mut scene = Scene::builtin("tank-2d").unwrap();
    scene.file.output.clusters = true;
    scene.revalidate().unwrap();
    let options = RunOptions {
        format: None,
        out_dir: Some(out.clone()),
        max_steps: Some(12),
        output_interval: Some(1e-3),
        progress: Progress::Quiet,
        ..Default::default()
    };
    let mut seen = 0;
    let summary = run::run_observed(&scene, &options, &mut |f| {
        assert_eq!(f.index, seen);
        let ps = f.data.particles();
        assert_eq!(ps.len(), 2026);
        assert!(ps.windows(2).all(|w| w[0].id < w[1].id));
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
        let file = std::fs::read(out.join(format!("particles_{i:05}.vtu"))).unwrap();
        let (head, _) = split_vtu(&file);
        assert_eq!(number_of_points(&head), 2026);
        assert!(
            !head.contains("Name=\"stress\""),
            "no stress without solids"
        );
    }
    let t = &summary.timing;
    assert!(t.setup_seconds > 0.0 && t.stepping_seconds > 0.0 && t.writer_seconds > 0.0);
    assert!(t.setup_seconds + t.stepping_seconds + t.output_wait_seconds <= t.total_seconds);
    assert!(summary.output_bytes > 2026 * 30 * summary.outputs as u64);
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

/// A write that fails mid-run (here the second frame's temporary file is a directory: what
/// a full disk or a lost mount does at that point) stops the run with the file and the
/// reason; the first frame stays readable and `particles.pvd` lists it alone.
#[test]
fn a_failed_write_stops_the_run_and_keeps_earlier_frames() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("w");
    let options = RunOptions {
        out_dir: Some(out.clone()),
        max_steps: Some(40),
        output_interval: Some(2e-4),
        progress: Progress::Quiet,
        ..Default::default()
    };
    // Planted once the first frame landed (a fresh run refuses a directory that holds one).
    let blocked = out.join("particles_00001.vtu.tmp");
    let mut plant = |f: &run::Frame| {
        if f.index == 0 {
            std::fs::create_dir_all(&blocked).unwrap();
        }
    };
    let scene = Scene::builtin("tank-2d").unwrap();
    let err = run::run_observed(&scene, &options, &mut plant).unwrap_err();
    let run::RunError::Io { path, reason } = &err else {
        panic!("expected an output error, got {err}")
    };
    assert!(path.ends_with("particles_00001.vtu"), "{err}");
    assert!(!reason.is_empty(), "{err}");
    let (head, _) = split_vtu(&std::fs::read(out.join("particles_00000.vtu")).unwrap());
    assert_eq!(number_of_points(&head), 2026);
    let pvd = std::fs::read_to_string(out.join("particles.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet ").count(), 1);
    assert!(!out.join("particles_00002.vtu").exists(), "the run stopped");
    // The summary says so (issue #52: it stayed `running`).
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "failed");
    assert!(
        json["error"]
            .as_str()
            .unwrap()
            .contains("particles_00001.vtu"),
        "{json}"
    );
}

/// A fixed step far beyond the CFL limit blows up: the run stops with the fault, keeps
/// its output, writes the failing state as its last frame and a failed summary.
#[test]
fn blow_up_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("boom");
    let mut scene = Scene::builtin("tank-2d").unwrap();
    scene.file.time.dt = Some(0.5);
    scene.revalidate().unwrap();
    let options = RunOptions {
        format: None,
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
            // The failing state is the last frame, and the summary names it.
            let k = summary.fault_frame.expect("the failing frame");
            assert_eq!(json["fault_frame"], k);
            assert_eq!(k + 1, summary.outputs);
            let failing = out.join(format!("particles_{k:05}.vtu"));
            assert!(failing.exists(), "{} missing", failing.display());
        }
        other => panic!("expected a blow-up, got {other:?}"),
    }
}

/// A monitor without a bluff body's scales (the tank's walls here, a dam-break obstacle in
/// use) writes the force alone and reports its peak and impulse, no coefficient (#51).
#[test]
fn a_monitor_without_scales_reports_peak_and_impulse() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m");
    let text = format!(
        "{}\n[[monitors]]\nname = \"tank\"\nwall = 0\ninterval = 1e-4\n",
        Scene::builtin("tank-2d").unwrap().text
    );
    let scene = Scene::from_toml(&text, "tank with a monitor").unwrap();
    let options = RunOptions {
        out_dir: Some(out.clone()),
        max_steps: Some(20),
        progress: Progress::Quiet,
        ..Default::default()
    };
    let summary = run::run(&scene, &options).unwrap();
    let csv = std::fs::read_to_string(out.join("tank.csv")).unwrap();
    assert_eq!(csv.lines().next(), Some("time,Fx,Fy,Fz"));
    let m = &summary.monitors[0];
    assert!(m.coefficients.is_none());
    // The water's weight rests on the tank: a downward force, so the peak is positive.
    assert!(m.peak_force > 0.0 && m.impulse[1] < 0.0, "{m}");
    let json = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        json.contains("\"peak_force\"") && !json.contains("mean_cd"),
        "{json}"
    );
}
