//! Post-processing a finished run (issue #51): our VTU files read back as written (raw and
//! zlib, 2D and 3D), a run's directory listed as its frames, and `meshfree render DIR`
//! drawing a CPU run's frames headless, refusing a run without frames and naming a field
//! the run did not write.
//!
//! The test that draws needs EGL: `#[ignore]`d unless the build had
//! `MESHFREE_REQUIRE_EGL=1` (CI; `build.rs` turns it into the cfg `meshfree_require_egl`),
//! as the viewer's headless tests are; `-- --include-ignored` runs it too, and it fails
//! without an EGL device: it never passes by skipping.

use std::path::Path;
use std::process::{Command, Output};

use meshfree::output::frames::{read_frame_csv, values};
use meshfree::output::{read_vtu, write_particles_csv, write_vtu, Compression, RecordedRun};

const COMPRESSIONS: [Compression; 3] = [Compression::Raw, Compression::Zlib, Compression::Lz4];
use meshfree_core::solver::frame::{Field, Fields, FrameData};

fn meshfree() -> Command {
    Command::new(env!("CARGO_BIN_EXE_meshfree"))
}

fn run_ok(args: &[&str]) -> Output {
    let out = meshfree().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "meshfree {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A frame of `n` particles in `dim` dimensions with every field, values varied per
/// particle (z = 0 in 2D, as the solver writes them).
fn frame(n: usize, dim: usize) -> FrameData {
    let f = |i: usize, k: f32| (i as f32 * 0.37 + k).sin() * 10.0;
    let z = |i: usize, k: f32| if dim == 3 { f(i, k) } else { 0.0 };
    FrameData {
        step: 0,
        time: 0.0,
        len: n,
        position: (0..n).map(|i| [f(i, 0.1), f(i, 0.2), z(i, 0.3)]).collect(),
        velocity: (0..n).map(|i| [f(i, 1.1), f(i, 1.2), z(i, 1.3)]).collect(),
        density: (0..n).map(|i| 1000.0 + f(i, 2.0)).collect(),
        pressure: (0..n).map(|i| f(i, 3.0) * 100.0).collect(),
        kind: (0..n).map(|i| (i % 3) as u8).collect(),
        id: (0..n).map(|i| (n - i) as u32).collect(),
        // Up to 4 n: groups written as UInt8 (n = 1), UInt16 (n < 16,384) and UInt32.
        group: (0..n).map(|i| (i % 5 * n) as u32).collect(),
        stress: (0..n)
            .map(|i| std::array::from_fn(|c| f(i, 4.0 + c as f32)))
            .collect(),
    }
}

#[test]
fn the_vtu_reader_gives_back_what_write_vtu_wrote() {
    let dir = tempfile::tempdir().unwrap();
    // 100 000 particles: the positions (1.2 MB) take two compressed blocks of 1 MiB.
    for (n, dim) in [(1, 2), (257, 2), (1000, 3), (100_000, 3)] {
        let f = frame(n, dim);
        for c in COMPRESSIONS {
            let path = dir.path().join(format!("f{n}-{dim}d-{c:?}.vtu"));
            write_vtu(&path, &f, Fields::all(), c).unwrap();
            let back = read_vtu(&path).unwrap();
            assert_eq!(back, f, "{n} particles, {dim}D, {c:?}");
        }
    }
}

#[test]
fn the_vtu_reader_leaves_out_the_fields_the_run_did_not_write() {
    let dir = tempfile::tempdir().unwrap();
    let f = frame(50, 2);
    let fields = Fields::of(&[Field::Position, Field::Velocity]);
    for c in COMPRESSIONS {
        let path = dir.path().join(format!("f-{c:?}.vtu"));
        write_vtu(&path, &f, fields, c).unwrap();
        let back = read_vtu(&path).unwrap();
        assert_eq!(back.fields(), fields);
        assert_eq!(
            (back.position, back.velocity),
            (f.position.clone(), f.velocity.clone())
        );
        // Pressure is not there: the error names it and the fields the frame has.
        let e = values(
            &read_vtu(&path).unwrap(),
            meshfree_core::solver::Shown::Pressure,
            "the frame",
        )
        .unwrap_err()
        .0;
        assert!(
            e.contains("`pressure`") && e.contains("it has: position, velocity"),
            "{e}"
        );
    }
}

#[test]
fn the_vtu_reader_refuses_a_truncated_file_and_another_format() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("f.vtu");
    write_vtu(&path, &frame(100, 3), Fields::all(), Compression::Raw).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(&path, &bytes[..bytes.len() - 2000]).unwrap();
    let e = read_vtu(&path).unwrap_err();
    assert!(e.contains("truncated") || e.contains("holds"), "{e}");
    std::fs::write(
        &path,
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"/>\n",
    )
    .unwrap();
    let e = read_vtu(&path).unwrap_err();
    assert!(e.contains("f.vtu") && e.contains("AppendedData"), "{e}");
}

#[test]
fn the_csv_frame_reader_gives_back_the_columns_written() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("particles_00000.csv");
    let mut f = frame(40, 3);
    // The CSV is ordered by id.
    let order: Vec<usize> = (0..f.len).rev().collect();
    write_particles_csv(&path, &f, Fields::all()).unwrap();
    let back = read_frame_csv(&path).unwrap();
    f.position = order.iter().map(|&i| f.position[i]).collect();
    f.id = order.iter().map(|&i| f.id[i]).collect();
    f.kind = order.iter().map(|&i| f.kind[i]).collect();
    assert_eq!(back.fields(), Fields::all());
    assert_eq!(
        (back.position, back.id, back.kind),
        (f.position, f.id, f.kind)
    );
}

/// A short CPU run of tank-2d into `dir` with the further arguments `extra`.
fn tank_run(dir: &Path, extra: &[&str]) {
    run_ok(
        &[
            &[
                "run",
                "tank-2d",
                "--backend",
                "cpu",
                "--quiet",
                "--t-end",
                "0.02",
                "--output-interval",
                "0.005",
                "--out",
                dir.to_str().unwrap(),
            ][..],
            extra,
        ]
        .concat(),
    );
}

#[test]
fn a_run_directory_lists_its_frames_in_time_order() {
    let tmp = tempfile::tempdir().unwrap();
    for format in ["vtu", "vtu-zlib", "vtu-lz4", "csv"] {
        let dir = tmp.path().join(format);
        tank_run(&dir, &["--format", format]);
        let run = RecordedRun::open(&dir).unwrap();
        assert_eq!(run.scene.name(), "tank-2d");
        assert_eq!(run.frames.len(), 5, "{format}: {:?}", run.frames);
        assert_eq!(run.frames[0].time, 0.0);
        assert!(
            run.frames.windows(2).all(|w| w[0].time < w[1].time),
            "{format}"
        );
        assert_eq!(run.nearest(0.0051), 1);
        assert_eq!(run.evenly(2), vec![0, 4]);
        assert_eq!(run.evenly(3), vec![0, 2, 4]);
        let last = run.read(4).unwrap();
        assert_eq!(last.len, 2026, "{format}");
        assert_eq!(last.time, run.frames[4].time);
        assert!(
            last.velocity.iter().any(|v| v[1] != 0.0),
            "{format}: it moved"
        );
    }
}

#[test]
#[cfg(feature = "viewer")]
fn render_refuses_a_run_without_frames() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("none");
    tank_run(&dir, &["--format", "none"]);
    let png = tmp.path().join("x.png");
    let out = meshfree()
        .args([
            "render",
            dir.to_str().unwrap(),
            "--out",
            png.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("nothing to render") && err.contains("format `none`"),
        "{err}"
    );
    assert!(!png.exists());
    // A directory that is no run's: named as such.
    let out = meshfree()
        .args([
            "render",
            tmp.path().to_str().unwrap(),
            "--out",
            png.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("holds no scene.toml"), "{err}");
}

#[test]
#[cfg(feature = "viewer")]
fn render_names_a_field_the_run_did_not_write() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("tank.toml");
    let text = meshfree_core::scene::Scene::builtin("tank-2d")
        .unwrap()
        .text;
    std::fs::write(
        &scene,
        format!("{text}\n[output]\nfields = [\"position\", \"velocity\"]\n"),
    )
    .unwrap();
    let dir = tmp.path().join("run");
    run_ok(&[
        "run",
        scene.to_str().unwrap(),
        "--backend",
        "cpu",
        "--quiet",
        "--steps",
        "3",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let png = tmp.path().join("x.png");
    let out = meshfree()
        .args(["render", dir.to_str().unwrap(), "--field", "pressure"])
        .args(["--out", png.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("no `pressure` field") && err.contains("it has: position, velocity"),
        "{err}"
    );
    // Flags that re-simulate do not apply.
    let out = meshfree()
        .args(["render", dir.to_str().unwrap(), "--t-end", "1"])
        .args(["--out", png.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("--t-end applies to a scene"), "{err}");
}

#[cfg(feature = "viewer")]
/// How many pixels of `png` are unlike its corner (the background).
fn lit_pixels(png: &Path) -> usize {
    let img = meshfree_viewer::Image::load_png(png).unwrap();
    let bg = img.rgba[..4].to_vec();
    img.rgba
        .chunks_exact(4)
        .filter(|p| *p != bg.as_slice())
        .count()
}

#[test]
#[cfg(feature = "viewer")]
#[cfg_attr(
    not(meshfree_require_egl),
    ignore = "needs EGL: build with MESHFREE_REQUIRE_EGL=1, or run with --include-ignored"
)]
fn render_draws_the_frames_of_a_finished_cpu_run() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("tank");
    tank_run(&dir, &[]);
    let stem = tmp.path().join("f.png");
    let started = std::time::Instant::now();
    let out = run_ok(&[
        "render",
        dir.to_str().unwrap(),
        "--frames",
        "2",
        "--size",
        "320x200",
        "--out",
        stem.to_str().unwrap(),
    ]);
    println!(
        "render --frames 2 of a run: {:.2} s; {}",
        started.elapsed().as_secs_f64(),
        String::from_utf8_lossy(&out.stderr).trim()
    );
    let said = String::from_utf8_lossy(&out.stdout);
    let (a, b) = (tmp.path().join("f_0000.png"), tmp.path().join("f_0001.png"));
    assert!(
        said.contains("particles_00000.vtu") && said.contains("particles_00004.vtu"),
        "{said}"
    );
    for png in [&a, &b] {
        let lit = lit_pixels(png);
        assert!(lit > 2000, "{}: {lit} pixels drawn", png.display());
    }
    // The first frame is at rest, the last has moved: the colours differ.
    let (ia, ib) = (
        meshfree_viewer::Image::load_png(&a).unwrap(),
        meshfree_viewer::Image::load_png(&b).unwrap(),
    );
    assert_eq!((ia.width, ia.height), (320, 200));
    assert_ne!(ia.rgba, ib.rgba);
    assert!(!tmp.path().join("f_0002.png").exists());
}

#[test]
#[cfg(feature = "viewer")]
fn render_movie_without_ffmpeg_says_what_to_install() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("tank");
    tank_run(&dir, &[]);
    let empty = tmp.path().join("bin");
    std::fs::create_dir(&empty).unwrap();
    let video = tmp.path().join("tank.mp4");
    let out = meshfree()
        .args([
            "render",
            dir.to_str().unwrap(),
            "--movie",
            video.to_str().unwrap(),
        ])
        .env("PATH", &empty)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(
        err.contains("needs `ffmpeg`")
            && err.contains("install ffmpeg")
            && err.contains("--frames N"),
        "{err}"
    );
    assert!(!video.exists());
    // A scene is simulated, not encoded: refused with the way on.
    let out = meshfree()
        .args(["render", "tank-2d", "--movie", video.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("render DIR --movie"), "{err}");
}

/// A stand-in for ffmpeg: answers `-version`, else saves its arguments and copies its
/// standard input to the file named last.
#[cfg(all(feature = "viewer", unix))]
fn fake_ffmpeg(bin: &Path) {
    use std::os::unix::fs::PermissionsExt as _;
    let path = bin.join("ffmpeg");
    std::fs::write(
        &path,
        "#!/bin/sh\n[ \"$1\" = -version ] && exit 0\nfor last; do :; done\necho \"$@\" > \"$last.args\"\ncat > \"$last\"\n",
    )
    .unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
}

#[test]
#[cfg(all(feature = "viewer", unix))]
#[cfg_attr(
    not(meshfree_require_egl),
    ignore = "needs EGL: build with MESHFREE_REQUIRE_EGL=1, or run with --include-ignored"
)]
fn render_movie_pipes_every_frame_to_ffmpeg() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("tank");
    tank_run(&dir, &[]);
    let bin = tmp.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    fake_ffmpeg(&bin);
    let video = tmp.path().join("movie").join("tank.mp4");
    let path = format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = meshfree()
        .args([
            "render",
            dir.to_str().unwrap(),
            "--size",
            "320x200",
            "--fps",
            "12",
        ])
        .args(["--movie", video.to_str().unwrap()])
        .env("PATH", path)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    // All 5 frames of the run, 320 x 200 RGBA each; no PNG without --out.
    let bytes = std::fs::read(&video).unwrap();
    assert_eq!(bytes.len(), 5 * 320 * 200 * 4);
    let args = std::fs::read_to_string(tmp.path().join("movie").join("tank.mp4.args")).unwrap();
    assert!(
        args.contains("-f rawvideo -pix_fmt rgba -s 320x200 -r 12 -i -")
            && args.contains("yuv420p"),
        "{args}"
    );
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains("5 frames at 12 frames/s") && !said.contains(".png"),
        "{said}"
    );
    // The frames differ (the water moves) and are not blank.
    let frame = 320 * 200 * 4;
    assert_ne!(bytes[..frame], bytes[4 * frame..]);
    assert!(
        bytes[..frame]
            .chunks_exact(4)
            .filter(|p| p != &&bytes[..4])
            .count()
            > 2000
    );
}

#[test]
#[cfg(feature = "viewer")]
#[cfg_attr(
    not(all(meshfree_require_egl, meshfree_require_ffmpeg)),
    ignore = "needs EGL and ffmpeg: build with MESHFREE_REQUIRE_EGL=1 MESHFREE_REQUIRE_FFMPEG=1, or run with --include-ignored"
)]
fn render_movie_encodes_a_video_that_ffprobe_reads() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("tank");
    tank_run(&dir, &[]);
    let video = tmp.path().join("tank.mp4");
    let out = run_ok(&[
        "render",
        dir.to_str().unwrap(),
        "--size",
        "320x200",
        "--fps",
        "12",
        "--movie",
        video.to_str().unwrap(),
    ]);
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.contains("5 frames at 12 frames/s"), "{said}");
    let probe = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            "stream=codec_name,width,height,nb_read_frames,r_frame_rate",
        ])
        .args(["-of", "csv=p=0"])
        .arg(&video)
        .output()
        .expect("ffprobe, which comes with ffmpeg, is on the PATH");
    let info = String::from_utf8_lossy(&probe.stdout).trim().to_string();
    assert!(
        probe.status.success(),
        "ffprobe: {}",
        String::from_utf8_lossy(&probe.stderr)
    );
    // Every frame of the run, at the size and rate asked, as H.264.
    assert_eq!(info, "h264,320,200,12/1,5", "ffprobe says {info}");
}

#[test]
#[cfg(feature = "viewer")]
#[cfg_attr(
    not(meshfree_require_xvfb),
    ignore = "needs Xvfb: build with MESHFREE_REQUIRE_XVFB=1, or run with --include-ignored"
)]
fn view_plays_a_finished_run_in_a_window_under_xvfb() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("tank");
    tank_run(&dir, &[]);
    let shot = tmp.path().join("view.png");
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1400x900x24"])
        .arg(env!("CARGO_BIN_EXE_meshfree"))
        .args(["view", dir.to_str().unwrap(), "--field", "pressure"])
        .args(["--capture", shot.to_str().unwrap(), "--capture-after", "8"])
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("xvfb-run, which comes with Xvfb, is on the PATH");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "view DIR under xvfb-run: {err}");
    assert!(err.contains(&format!("saved {}", shot.display())), "{err}");
    let img = meshfree_viewer::Image::load_png(&shot).unwrap();
    assert_eq!((img.width, img.height), (1280, 800));
    assert!(lit_pixels(&shot) > 5000, "the particles were drawn");
    // Eight drawn frames played the 5 frames to the last: the slider's track is blue to its
    // end (x = 28 .. 1280 - 192 - 28 px at ui scale 2, the colour bar's 192 px at the right),
    // and the panel says so.
    let px = |x: u32, y: u32| {
        let i = ((y * img.width + x) * 4) as usize;
        (img.rgba[i], img.rgba[i + 1], img.rgba[i + 2])
    };
    let blue = |(r, g, b): (u8, u8, u8)| b > 150 && b > r + 60 && g > 80;
    let track_y = 800 - 24 + 4;
    let end = 1280 - 192 - 28 - 12;
    assert!(
        blue(px(40, track_y)) && blue(px(end, track_y)),
        "the slider played to the end: {:?} {:?}",
        px(40, track_y),
        px(end, track_y)
    );
}
