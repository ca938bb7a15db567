//! `meshfree render` with the CUDA backend draws from device memory (CUDA-OpenGL interop,
//! `Readback::gl_interop`): the frame drawn from vertex buffers filled on the GPU and the frame
//! drawn from a host copy (`--host-copy`) of the same state are the same image, and drawing
//! a frame reads back 8 bytes (the colour range) or none with a fixed `--range`, where the
//! host copy reads back every particle; the spheres of the GPU's visibility splat (from a
//! view's second frame on) are the sprites' image. Needs a CUDA GPU whose driver also gives
//! EGL (ignored elsewhere; `MESHFREE_BIN` names the binary).
#![cfg(feature = "viewer")]

use std::path::Path;
use std::process::Command;

use meshfree_viewer::Image;

fn meshfree() -> Command {
    Command::new(std::env::var_os("MESHFREE_BIN").unwrap_or(env!("CARGO_BIN_EXE_meshfree").into()))
}

/// Runs `meshfree render` with `args`; returns its standard output.
fn render(args: &[&str]) -> String {
    let out = meshfree().arg("render").args(args).output().unwrap();
    assert!(
        out.status.success(),
        "render {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// The share of pixels of `a` and `b` that differ and the largest channel difference, after
/// asserting that `a` is not (almost) empty.
fn compare(a: &Image, b: &Image, what: &str) -> (f64, u8) {
    let lit = a
        .rgba
        .chunks_exact(4)
        .filter(|p| p[..3] != a.rgba[..3])
        .count();
    assert!(lit > 1000, "{what}: the image is (almost) empty");
    difference(a, b)
}

/// The share of pixels that differ, and the largest channel difference.
fn difference(a: &Image, b: &Image) -> (f64, u8) {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let (mut differ, mut most) = (0usize, 0u8);
    for (p, q) in a.rgba.chunks_exact(4).zip(b.rgba.chunks_exact(4)) {
        let d = p.iter().zip(q).map(|(x, y)| x.abs_diff(*y)).max().unwrap();
        differ += usize::from(d > 0);
        most = most.max(d);
    }
    (differ as f64 / (a.width * a.height) as f64, most)
}

/// One scene at one moment drawn both ways (with the further arguments `extra`): the same
/// image.
fn same_image(dir: &Path, scene: &str, at: &str, field: &str, extra: &[&str]) {
    let (dev, host) = (
        dir.join(format!("{scene}-dev.png")),
        dir.join(format!("{scene}-host.png")),
    );
    let common = [
        scene,
        "--backend",
        "cuda",
        "--at",
        at,
        "--field",
        field,
        "--size",
        "640x360",
    ];
    let said = render(&[&common[..], extra, &["--out", dev.to_str().unwrap()]].concat());
    assert!(
        said.contains("drawn from vertex buffers filled on the GPU"),
        "{said}"
    );
    let said = render(
        &[
            &common[..],
            extra,
            &["--host-copy", "--out", host.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(said.contains("drawn from a host copy"), "{said}");
    let (a, b) = (
        Image::load_png(&dev).unwrap(),
        Image::load_png(&host).unwrap(),
    );
    let (share, most) = compare(&a, &b, scene);
    println!(
        "{scene} at t = {at}, {field}: {:.4} % of the pixels differ, by {most} at most",
        100.0 * share
    );
    // The fill computes every value as the host path does, so the images should agree bit
    // for bit; a pixel moved by float rounding is allowed, a different picture is not.
    assert!(
        share < 1e-4,
        "{scene}: {:.4} % of the pixels differ",
        100.0 * share
    );
}

#[test]
#[ignore = "needs a CUDA GPU with EGL: run with --include-ignored there (MESHFREE_BIN names the binary)"]
fn the_interop_frame_and_the_host_copy_frame_are_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    same_image(dir.path(), "dam-break-2d", "0.3", "speed", &[]);
    same_image(dir.path(), "dam-break-3d", "0.2", "speed", &[]);
    same_image(dir.path(), "dam-break-3d", "0.2", "pressure", &[]);
    // All three kinds, each its own part of the vertex buffers (the fluid, the sphere's
    // solid, the walls): drawn as spheres in one span, and with the fluid as a surface.
    let walls = ["--show-boundary"];
    same_image(dir.path(), "impinging-3d", "1.0", "speed", &walls);
    same_image(dir.path(), "impinging-3d", "1.0", "speed", &["--surface"]);
}

/// The `timing-json` line of a timed render.
fn timing(extra: &[&str]) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("t.png");
    let args = [
        "dam-break-3d",
        "--backend",
        "cuda",
        "--frames",
        "4",
        "--steps-per-frame",
        "5",
        "--size",
        "320x180",
        "--out",
        out.to_str().unwrap(),
    ];
    let said = render(&[&args[..], extra].concat());
    let line = said
        .lines()
        .find_map(|l| l.strip_prefix("timing-json: "))
        .unwrap_or_else(|| panic!("no timing-json line in {said}"));
    serde_json::from_str(line).unwrap()
}

#[test]
#[ignore = "needs a CUDA GPU with EGL: run with --include-ignored there (MESHFREE_BIN names the binary)"]
fn drawing_reads_back_nothing_per_particle() {
    let fixed = timing(&["--range", "0,2"]);
    assert_eq!(fixed["path"], "device", "{fixed}");
    assert_eq!(fixed["d2h_bytes_per_frame_drawing"], 0.0, "{fixed}");
    let auto = timing(&[]);
    assert_eq!(auto["path"], "device", "{auto}");
    assert_eq!(auto["d2h_bytes_per_frame_drawing"], 8.0, "{auto}");
    // The host copy reads positions (float4), kinds and velocities (float4) of every particle.
    let host = timing(&["--host-copy"]);
    assert_eq!(host["path"], "host copy", "{host}");
    let n = host["particles"].as_f64().unwrap();
    assert_eq!(host["d2h_bytes_per_frame_drawing"], 33.0 * n, "{host}");
}

#[test]
#[ignore = "needs a CUDA GPU with EGL: run with --include-ignored there (MESHFREE_BIN names the binary)"]
fn the_splat_frame_and_the_sprites_frame_are_the_same_image() {
    // Two frames of one view: the first drawn as sprites, the second from the visibility
    // splat that the first asked of the second's fill; the host copy draws sprites only.
    let dir = tempfile::tempdir().unwrap();
    let shots = |how: &str, extra: &[&str]| {
        let stem = dir.path().join(how);
        let said = render(
            &[
                &[
                    "dam-break-3d",
                    "--backend",
                    "cuda",
                    "--spacing",
                    "0.0156",
                    "--t-end",
                    "0.2",
                    "--frames",
                    "2",
                    "--size",
                    "640x360",
                    "--out",
                    stem.to_str().unwrap(),
                ][..],
                extra,
            ]
            .concat(),
        );
        let last = Image::load_png(dir.path().join(format!("{how}_0001.png"))).unwrap();
        (said, last)
    };
    let (said, splat) = shots("dev", &[]);
    let second = said.lines().find(|l| l.contains("_0001.png")).unwrap_or("");
    assert!(second.contains("visibility splat"), "{said}");
    let (said, sprites) = shots("host", &["--host-copy"]);
    assert!(said.contains("drawn from a host copy"), "{said}");
    let (share, most) = compare(&splat, &sprites, "the splat's frame");
    println!(
        "splat against sprites: {:.4} % of the pixels differ, by {most} at most",
        100.0 * share
    );
    // The same spheres: a pixel at a sphere's rim may go either way by float rounding.
    assert!(share < 1e-4, "{:.4} % of the pixels differ", 100.0 * share);
}
