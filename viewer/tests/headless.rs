//! Headless (EGL, no display) rendering tests.
//!
//! They are `#[ignore]`d unless the build had `MESHFREE_REQUIRE_EGL=1` (CI; `build.rs`
//! turns it into the cfg `meshfree_require_egl`); `-- --include-ignored` runs them too.
//! A test that runs fails without an EGL device: it never passes by skipping.
//! `MESHFREE_UPDATE_REFERENCE=1` rewrites the reference PNG in `tests/data/`.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use meshfree_viewer::{
    colormap, kind, Camera, Field, FrameData, HeadlessRenderer, Image, OrbitCamera, OrthoCamera,
    Outline, RenderOptions, ViewerError,
};

/// One EGL context at a time: the tests run in parallel threads.
static GL: Mutex<()> = Mutex::new(());

fn renderer() -> HeadlessRenderer {
    match HeadlessRenderer::new() {
        Ok(r) => {
            eprintln!("headless GL: {}", r.gl_renderer());
            r
        }
        Err(ViewerError::NoEglDevice(m)) => panic!(
            "this test needs an EGL device for headless rendering: {m} (install Mesa EGL, \
             e.g. apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri)"
        ),
        Err(e) => panic!("headless renderer failed: {e}"),
    }
}

fn out_dir() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer-tests");
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A fixed 2D set: 24 x 14 fluid particles in a vortex, a floor and two walls of
/// boundary particles, and a small solid block.
fn frame_2d() -> FrameData {
    let dx = 0.05f32;
    let mut f = FrameData {
        dim: 2,
        domain_min: [-2.0 * dx, -2.0 * dx, 0.0],
        domain_max: [1.2 + 2.0 * dx, 0.8, 0.0],
        particle_radius: 0.5 * dx,
        ..FrameData::default()
    };
    for i in 0..24 {
        for j in 0..14 {
            let (x, y) = ((i as f32 + 0.5) * dx, (j as f32 + 0.5) * dx);
            let (rx, ry) = (x - 0.6, y - 0.35);
            let r = (rx * rx + ry * ry).sqrt();
            let k = if (0.95..1.1).contains(&x) && y < 0.2 {
                kind::SOLID
            } else {
                kind::FLUID
            };
            f.positions.push([x, y, 0.0]);
            f.values.push(if k == kind::SOLID {
                0.1
            } else {
                r * (-r * r / 0.05).exp() * 10.0
            });
            f.kinds.push(k);
        }
    }
    for i in -2..28 {
        for l in 0..2 {
            let y = -(l as f32 + 0.5) * dx;
            f.positions.push([(i as f32 + 0.5) * dx, y, 0.0]);
            f.values.push(0.0);
            f.kinds.push(kind::BOUNDARY);
        }
    }
    for j in 0..16 {
        for x in [-0.5 * dx, -1.5 * dx, 1.2 + 0.5 * dx, 1.2 + 1.5 * dx] {
            f.positions.push([x, (j as f32 + 0.5) * dx, 0.0]);
            f.values.push(0.0);
            f.kinds.push(kind::BOUNDARY);
        }
    }
    f
}

/// A 3D block of particles whose speed grows with x: fast (red) on the +x side.
fn frame_3d() -> FrameData {
    let dx = 0.1f32;
    let mut f = FrameData {
        dim: 3,
        domain_min: [0.0; 3],
        domain_max: [1.0, 0.6, 0.6],
        particle_radius: 0.5 * dx,
        ..FrameData::default()
    };
    for i in 0..10 {
        for j in 0..6 {
            for k in 0..6 {
                let p = [
                    (i as f32 + 0.5) * dx,
                    (j as f32 + 0.5) * dx,
                    (k as f32 + 0.5) * dx,
                ];
                f.positions.push(p);
                f.values.push(p[0]);
                f.kinds.push(kind::FLUID);
            }
        }
    }
    f
}

/// Mean absolute difference per channel (0..255) and the fraction of pixels
/// where any channel differs by more than 24.
fn compare(a: &Image, b: &Image) -> (f64, f64) {
    assert_eq!(
        (a.width, a.height),
        (b.width, b.height),
        "image sizes differ"
    );
    let mut sum = 0u64;
    let mut bad = 0usize;
    for (p, q) in a.rgba.chunks_exact(4).zip(b.rgba.chunks_exact(4)) {
        let d: Vec<u8> = (0..3).map(|c| p[c].abs_diff(q[c])).collect();
        sum += d.iter().map(|&x| x as u64).sum::<u64>();
        if d.iter().any(|&x| x > 24) {
            bad += 1;
        }
    }
    let n = (a.width * a.height) as f64;
    (sum as f64 / (3.0 * n), bad as f64 / n)
}

fn is_background(p: [u8; 4], bg: [f32; 3]) -> bool {
    (0..3).all(|c| (p[c] as f32 - bg[c] * 255.0).abs() <= 3.0)
}

#[test]
#[cfg_attr(
    not(meshfree_require_egl),
    ignore = "needs EGL: build with MESHFREE_REQUIRE_EGL=1, or run with --include-ignored"
)]
fn reference_2d_speed() {
    let _g = GL.lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer();
    let frame = frame_2d();
    let opts = RenderOptions {
        width: 320,
        height: 200,
        field: Field::Speed,
        overlay: vec!["t 0.125  step 42".into()],
        ..RenderOptions::default()
    };
    let img = r.render(&frame, &opts).unwrap();
    let got = out_dir().join("reference_2d_speed.png");
    img.save_png(&got).unwrap();
    let reference = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/reference_2d_speed.png");
    if std::env::var("MESHFREE_UPDATE_REFERENCE").as_deref() == Ok("1") {
        img.save_png(&reference).unwrap();
        eprintln!("updated {}", reference.display());
        return;
    }
    let want = Image::load_png(&reference).unwrap_or_else(|e| {
        panic!(
            "{e}: regenerate with MESHFREE_UPDATE_REFERENCE=1 (got {})",
            got.display()
        )
    });
    let (mad, frac) = compare(&img, &want);
    eprintln!(
        "mean abs diff {mad:.3}, differing pixels {:.3}%",
        frac * 100.0
    );
    // The comparison is sensitive: a different colour range must fail it.
    let other = r
        .render(
            &frame,
            &RenderOptions {
                range: Some((0.0, 2.0)),
                ..opts.clone()
            },
        )
        .unwrap();
    let (mad2, frac2) = compare(&other, &want);
    assert!(
        mad2 >= 1.5 || frac2 >= 0.01,
        "tolerance too loose: {mad2} {frac2}"
    );
    assert!(
        mad < 1.5 && frac < 0.01,
        "render differs from {}: mean abs diff {mad:.3}, differing pixels {:.2}% (see {})",
        reference.display(),
        frac * 100.0,
        got.display()
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_egl),
    ignore = "needs EGL: build with MESHFREE_REQUIRE_EGL=1, or run with --include-ignored"
)]
fn render_2d_content() {
    let _g = GL.lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer();
    let frame = frame_2d();
    // Camera looking at the domain only (no colour bar): nothing but particles and background.
    let cam = OrthoCamera::fit(frame.domain_min, frame.domain_max, 0.0, 1.6);
    let opts = RenderOptions {
        width: 320,
        height: 200,
        colorbar: false,
        camera: Camera::Ortho(cam),
        ..RenderOptions::default()
    };
    let img = r.render(&frame, &opts).unwrap();
    img.save_png(out_dir().join("content_2d.png")).unwrap();
    let bg = opts.background;
    let fg = img
        .rgba
        .chunks_exact(4)
        .filter(|p| !is_background([p[0], p[1], p[2], p[3]], bg))
        .count();
    let frac = fg as f64 / (320.0 * 200.0);
    assert!(
        (0.3..0.95).contains(&frac),
        "particle pixel fraction {frac}"
    );
    // The slowest fluid particle is near the vortex centre (0.6, 0.35): bluish.
    let c = center_pixel(&img, &cam, 1.6, [0.625, 0.375]);
    assert!(c[2] > c[0], "vortex centre should be blue: {c:?}");
    // Hiding boundary particles removes pixels.
    let hidden = r
        .render(
            &frame,
            &RenderOptions {
                hide_kinds: [false, false, true],
                ..opts.clone()
            },
        )
        .unwrap();
    let fg2 = hidden
        .rgba
        .chunks_exact(4)
        .filter(|p| !is_background([p[0], p[1], p[2], p[3]], bg))
        .count();
    assert!(fg2 < fg, "hiding boundary: {fg2} >= {fg}");
}

fn center_pixel(img: &Image, cam: &OrthoCamera, aspect: f32, p: [f32; 2]) -> [u8; 4] {
    let hw = cam.half_height * aspect;
    let x = ((p[0] - cam.center[0] + hw) / (2.0 * hw) * img.width as f32) as u32;
    let y = ((cam.center[1] + cam.half_height - p[1]) / (2.0 * cam.half_height) * img.height as f32)
        as u32;
    img.pixel(x.min(img.width - 1), y.min(img.height - 1))
}

#[test]
#[cfg_attr(
    not(meshfree_require_egl),
    ignore = "needs EGL: build with MESHFREE_REQUIRE_EGL=1, or run with --include-ignored"
)]
fn render_3d_visible_and_coloured() {
    let _g = GL.lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer();
    let frame = frame_3d();
    let opts = RenderOptions {
        width: 320,
        height: 240,
        field: Field::Speed,
        ..RenderOptions::default()
    };
    let img = r.render(&frame, &opts).unwrap();
    img.save_png(out_dir().join("render_3d.png")).unwrap();
    let bg = opts.background;
    // The particle viewport is left of the colour-bar panel.
    let scene_w = 320 - 96;
    let (mut fg, mut red, mut blue) = (0usize, 0usize, 0usize);
    let mut red_x = 0u64;
    let mut blue_x = 0u64;
    for y in 0..img.height {
        for x in 0..scene_w {
            let p = img.pixel(x, y);
            if is_background(p, bg) {
                continue;
            }
            fg += 1;
            let (r_, g_, b_) = (p[0] as i32, p[1] as i32, p[2] as i32);
            if r_ > 110 && r_ > b_ + 50 && r_ > g_ + 50 {
                red += 1;
                red_x += x as u64;
            }
            if b_ > 110 && b_ > r_ + 50 {
                blue += 1;
                blue_x += x as u64;
            }
        }
    }
    let frac = fg as f64 / (scene_w * img.height) as f64;
    eprintln!("3D: foreground {frac:.3}, red {red}, blue {blue}");
    assert!((0.1..0.9).contains(&frac), "particle pixel fraction {frac}");
    assert!(red > 100 && blue > 100, "red {red}, blue {blue}");
    // Default view looks from +x+z: fast (+x) particles are on the right... in any
    // case on a different side than the slow ones.
    let (rx, bx) = (red_x as f64 / red as f64, blue_x as f64 / blue as f64);
    assert!((rx - bx).abs() > 20.0, "red mean x {rx}, blue mean x {bx}");
    // Colour bar: bottom is the colour map's blue, top its red.
    let top = img.pixel(scene_w + 16, 30);
    let bottom = img.pixel(scene_w + 16, 240 - 18);
    let (cb, ct) = (colormap(0.0), colormap(1.0));
    assert!(
        (bottom[2] as f32 - cb[2] * 255.0).abs() < 20.0,
        "bar bottom {bottom:?}"
    );
    assert!(
        (top[0] as f32 - ct[0] * 255.0).abs() < 20.0 && top[2] < 60,
        "bar top {top:?}"
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_egl),
    ignore = "needs EGL: build with MESHFREE_REQUIRE_EGL=1, or run with --include-ignored"
)]
fn kind_field_and_many_frames_reuse_context() {
    let _g = GL.lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer();
    let mut frame = frame_2d();
    frame.values = frame.kinds.iter().map(|&k| k as f32).collect();
    let opts = RenderOptions {
        width: 160,
        height: 100,
        field: Field::Kind,
        ..RenderOptions::default()
    };
    let a = r.render(&frame, &opts).unwrap();
    let b = r
        .render(
            &frame,
            &RenderOptions {
                width: 200,
                ..opts.clone()
            },
        )
        .unwrap();
    let c = r.render(&frame, &opts).unwrap();
    assert_eq!(a, c, "same input, same pixels");
    assert_eq!((b.width, b.height), (200, 100));
    a.save_png(out_dir().join("kind_2d.png")).unwrap();
}

/// A 3D tank (2 x 1 x 0.5) holding water whose surface is a wave along x, with the tank as
/// an outline.
fn frame_tank() -> FrameData {
    let dx = 0.04f32;
    let tank = Outline {
        min: [0.0, 0.0, 0.0],
        max: [2.0, 1.0, 0.5],
    };
    let mut f = FrameData {
        dim: 3,
        domain_min: [-0.1, -0.1, -0.1],
        domain_max: [2.1, 1.1, 0.6],
        particle_radius: 0.5 * dx,
        outlines: vec![tank],
        ..FrameData::default()
    };
    for i in 0..50 {
        let x = (i as f32 + 0.5) * dx;
        let top = 0.35 + 0.15 * (x * 3.0).sin();
        for j in 0..((top / dx) as usize) {
            for k in 0..12 {
                f.positions
                    .push([x, (j as f32 + 0.5) * dx, (k as f32 + 0.5) * dx]);
                f.values.push(x);
                f.kinds.push(kind::FLUID);
            }
        }
    }
    f
}

/// Connected regions (4-neighbours) of the pixels where `inside` holds: (sizes, largest
/// first; pixels of regions that touch the image's border).
fn regions(img: &Image, inside: impl Fn([u8; 4]) -> bool) -> (Vec<usize>, usize) {
    let (w, h) = (img.width as usize, img.height as usize);
    let mut seen = vec![false; w * h];
    let mut sizes = Vec::new();
    let mut at_border = 0;
    for start in 0..w * h {
        if seen[start] || !inside(img.pixel((start % w) as u32, (start / w) as u32)) {
            continue;
        }
        let (mut size, mut border) = (0, false);
        let mut stack = vec![start];
        seen[start] = true;
        while let Some(i) = stack.pop() {
            size += 1;
            let (x, y) = (i % w, i / w);
            border |= x == 0 || y == 0 || x == w - 1 || y == h - 1;
            let mut push = |j: usize| {
                if !seen[j] && inside(img.pixel((j % w) as u32, (j / w) as u32)) {
                    seen[j] = true;
                    stack.push(j);
                }
            };
            if x > 0 {
                push(i - 1);
            }
            if x + 1 < w {
                push(i + 1);
            }
            if y > 0 {
                push(i - w);
            }
            if y + 1 < h {
                push(i + w);
            }
        }
        if border {
            at_border += size;
        }
        sizes.push(size);
    }
    sizes.sort_unstable_by(|a, b| b.cmp(a));
    (sizes, at_border)
}

fn luminance(p: [u8; 4]) -> f64 {
    0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
}

#[test]
#[cfg_attr(
    not(meshfree_require_egl),
    ignore = "needs EGL: build with MESHFREE_REQUIRE_EGL=1, or run with --include-ignored"
)]
fn surface_is_one_shaded_region() {
    let _g = GL.lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer();
    let frame = frame_tank();
    let opts = RenderOptions {
        width: 360,
        height: 240,
        colorbar: false,
        outlines: false,
        surface: true,
        ..RenderOptions::default()
    };
    let bg = opts.background;
    let fluid = |p: [u8; 4]| !is_background(p, bg);
    let surface = r.render(&frame, &opts).unwrap();
    surface.save_png(out_dir().join("surface_3d.png")).unwrap();
    let spheres = r
        .render(
            &frame,
            &RenderOptions {
                surface: false,
                ..opts.clone()
            },
        )
        .unwrap();
    spheres.save_png(out_dir().join("spheres_3d.png")).unwrap();

    // The fluid: one region, with no holes of background inside it (background regions
    // that do not reach the border).
    let (parts, _) = regions(&surface, fluid);
    let total: usize = parts.iter().sum();
    let frac = total as f64 / (360.0 * 240.0);
    eprintln!(
        "surface: fluid {frac:.3} of the image in {} regions, largest {:?}",
        parts.len(),
        &parts[..parts.len().min(4)]
    );
    assert!((0.08..0.9).contains(&frac), "fluid pixel fraction {frac}");
    assert!(
        parts[0] as f64 >= 0.995 * total as f64,
        "the surface is not one region: {:?}",
        &parts[..parts.len().min(8)]
    );
    // Smooth: neighbouring pixels differ less than over the spheres' shading.
    let roughness = |img: &Image| {
        let (mut sum, mut n) = (0.0, 0usize);
        for y in 0..img.height {
            for x in 0..img.width - 1 {
                let (a, b) = (img.pixel(x, y), img.pixel(x + 1, y));
                if fluid(a) && fluid(b) {
                    sum += (luminance(a) - luminance(b)).abs();
                    n += 1;
                }
            }
        }
        sum / n as f64
    };
    let (rough_surface, rough_spheres) = (roughness(&surface), roughness(&spheres));
    eprintln!("mean luminance step between pixels: surface {rough_surface:.2}, spheres {rough_spheres:.2}");
    assert!(
        rough_surface < 0.5 * rough_spheres,
        "the surface is as rough as the spheres: {rough_surface} vs {rough_spheres}"
    );

    // Shaded: the brightness varies across the water, and it is water (blue over red).
    let mut lum: Vec<f64> = Vec::new();
    let (mut rs, mut bs) = (0.0, 0.0);
    for p in surface.rgba.chunks_exact(4) {
        let p = [p[0], p[1], p[2], p[3]];
        if fluid(p) {
            lum.push(luminance(p));
            rs += p[0] as f64;
            bs += p[2] as f64;
        }
    }
    lum.sort_by(f64::total_cmp);
    let (p5, p95) = (lum[lum.len() / 20], lum[lum.len() * 19 / 20]);
    eprintln!(
        "surface luminance 5 % {p5:.1}, 95 % {p95:.1}; mean red {:.1}, blue {:.1}",
        rs / lum.len() as f64,
        bs / lum.len() as f64
    );
    assert!(
        p95 - p5 > 25.0,
        "flat shading: luminance 5 % {p5}, 95 % {p95}"
    );
    assert!(bs > 1.3 * rs, "not water-coloured: red {rs}, blue {bs}");
}

#[test]
#[cfg_attr(
    not(meshfree_require_egl),
    ignore = "needs EGL: build with MESHFREE_REQUIRE_EGL=1, or run with --include-ignored"
)]
fn container_outline_where_the_box_projects() {
    let _g = GL.lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer();
    let frame = frame_tank();
    let (w, h) = (360u32, 240u32);
    let tank = frame.outlines[0];
    let cam = OrbitCamera::fit(tank.min, tank.max, 0.0, w as f32 / h as f32);
    let opts = RenderOptions {
        width: w,
        height: h,
        colorbar: false,
        surface: true,
        camera: Camera::Orbit(cam),
        ..RenderOptions::default()
    };
    let with = r.render(&frame, &opts).unwrap();
    with.save_png(out_dir().join("outline_3d.png")).unwrap();
    let without = r
        .render(
            &frame,
            &RenderOptions {
                outlines: false,
                ..opts.clone()
            },
        )
        .unwrap();
    // Outline pixels: light grey (the edge colour, or the edge seen through shallow water
    // is excluded: only edges in the open count).
    let edge = |p: [u8; 4]| {
        p[0] > 150 && p[1] > 150 && p[2] > 150 && (p[0] as i32 - p[2] as i32).abs() < 40
    };
    let near_edge = |img: &Image, x: f32, y: f32| {
        let (cx, cy) = (x.round() as i32, y.round() as i32);
        (-2..=2).any(|dy| {
            (-2..=2).any(|dx| {
                let (px, py) = (cx + dx, cy + dy);
                px >= 0
                    && py >= 0
                    && px < w as i32
                    && py < h as i32
                    && edge(img.pixel(px as u32, py as u32))
            })
        })
    };
    let aspect = w as f32 / h as f32;
    let (mut hits, mut hits_without, mut samples) = (0, 0, 0);
    for i in 0..8usize {
        for bit in [1usize, 2, 4] {
            if i & bit != 0 {
                continue;
            }
            let corner = |c: usize| {
                [
                    if c & 1 == 0 { tank.min[0] } else { tank.max[0] },
                    if c & 2 == 0 { tank.min[1] } else { tank.max[1] },
                    if c & 4 == 0 { tank.min[2] } else { tank.max[2] },
                ]
            };
            let (a, b) = (corner(i), corner(i | bit));
            // Points along the edge, away from its ends; those hidden by the water in
            // front of them are skipped by testing the render without outlines there.
            for s in 1..10 {
                let t = s as f32 / 10.0;
                let p = [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * t);
                let ndc = cam.project(p, aspect).expect("in front of the eye");
                let x = (ndc[0] * 0.5 + 0.5) * w as f32;
                let y = (0.5 - ndc[1] * 0.5) * h as f32;
                assert!(
                    (0.0..w as f32).contains(&x) && (0.0..h as f32).contains(&y),
                    "the fitted camera shows the whole box: {p:?} at ({x}, {y})"
                );
                let (xi, yi) = (x as u32, y as u32);
                let behind_water = !is_background(without.pixel(xi, yi), opts.background);
                if behind_water {
                    continue;
                }
                samples += 1;
                hits += near_edge(&with, x, y) as usize;
                hits_without += near_edge(&without, x, y) as usize;
            }
        }
    }
    eprintln!("outline: {hits} of {samples} edge points drawn ({hits_without} without outlines)");
    assert!(samples >= 60, "too few edge points in the open: {samples}");
    assert!(
        hits as f64 >= 0.95 * samples as f64,
        "outline missing: {hits} of {samples}"
    );
    assert!(
        hits_without == 0,
        "edge-coloured pixels without outlines: {hits_without}"
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_egl),
    ignore = "needs EGL: build with MESHFREE_REQUIRE_EGL=1, or run with --include-ignored"
)]
fn surface_closes_the_gaps_of_a_sheet() {
    let _g = GL.lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer();
    // One layer of particles in the plane y = 0, seen from above: touching spheres on a
    // square lattice leave a gap at every fourth corner; the surface has none.
    let dx = 0.04f32;
    let mut frame = FrameData {
        dim: 3,
        domain_min: [0.0, -dx, 0.0],
        domain_max: [1.2, dx, 0.8],
        particle_radius: 0.5 * dx,
        ..FrameData::default()
    };
    for i in 0..30 {
        for k in 0..20 {
            frame
                .positions
                .push([(i as f32 + 0.5) * dx, 0.0, (k as f32 + 0.5) * dx]);
            frame.values.push(0.0);
            frame.kinds.push(kind::FLUID);
        }
    }
    let (w, h) = (360u32, 240u32);
    let mut cam = OrbitCamera::fit(frame.domain_min, frame.domain_max, 0.0, 1.5);
    cam.pitch = 1.5;
    cam.yaw = 0.0;
    let opts = RenderOptions {
        width: w,
        height: h,
        colorbar: false,
        surface: true,
        camera: Camera::Orbit(cam),
        ..RenderOptions::default()
    };
    let bg = opts.background;
    let surface = r.render(&frame, &opts).unwrap();
    surface
        .save_png(out_dir().join("surface_sheet.png"))
        .unwrap();
    let spheres = r
        .render(
            &frame,
            &RenderOptions {
                surface: false,
                ..opts.clone()
            },
        )
        .unwrap();
    spheres
        .save_png(out_dir().join("spheres_sheet.png"))
        .unwrap();
    // Background regions that do not reach the border: gaps inside the fluid.
    let holes = |img: &Image| {
        let (bgs, at_border) = regions(img, |p| is_background(p, bg));
        (bgs.len(), bgs.iter().sum::<usize>() - at_border)
    };
    let ((n_surface, px_surface), (n_spheres, px_spheres)) = (holes(&surface), holes(&spheres));
    eprintln!(
        "gaps: surface {px_surface} pixels in {} regions, spheres {px_spheres} pixels in {} regions",
        n_surface - 1,
        n_spheres - 1
    );
    assert!(
        n_spheres > 100,
        "the spheres should show their gaps ({n_spheres} regions): the test can tell dots apart"
    );
    assert_eq!(px_surface, 0, "the surface has gaps");
    let (parts, _) = regions(&surface, |p| !is_background(p, bg));
    assert_eq!(
        parts.len(),
        1,
        "the sheet is one region: {:?}",
        &parts[..parts.len().min(8)]
    );
}

/// The share of pixels where any channel of `a` and `b` differs by more than 8 of 255.
fn differing(a: &Image, b: &Image) -> f64 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let n = a
        .rgba
        .chunks_exact(4)
        .zip(b.rgba.chunks_exact(4))
        .filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 8))
        .count();
    n as f64 / (a.width * a.height) as f64
}

#[test]
#[cfg_attr(
    not(meshfree_require_egl),
    ignore = "needs EGL: build with MESHFREE_REQUIRE_EGL=1, or run with --include-ignored"
)]
fn points_draw_the_picture_of_quads() {
    let _g = GL.lock().unwrap_or_else(|e| e.into_inner());
    let mut r = renderer();
    let tank = frame_tank();
    // Close enough that the nearest spheres are wider than the widest point (the quads
    // take them), and many sprites' centres lie off screen (the guard band).
    let close = OrbitCamera {
        target: [1.0, 0.2, 0.45],
        distance: 0.15,
        yaw: 0.3,
        pitch: 0.2,
        fov_y: 0.3,
    };
    let cases = [
        ("2d", frame_2d(), Camera::Auto, false),
        ("3d", frame_3d(), Camera::Auto, false),
        ("tank", tank.clone(), Camera::Auto, false),
        ("tank_surface", tank.clone(), Camera::Auto, true),
        ("close", tank.clone(), Camera::Orbit(close), false),
        ("close_surface", tank, Camera::Orbit(close), true),
    ];
    for (name, frame, camera, surface) in cases {
        let opts = RenderOptions {
            width: 360,
            height: 240,
            colorbar: false,
            camera,
            surface,
            ..RenderOptions::default()
        };
        let points = r.render(&frame, &opts).unwrap();
        let quads = r
            .render(
                &frame,
                &RenderOptions {
                    quads_only: true,
                    ..opts.clone()
                },
            )
            .unwrap();
        points
            .save_png(out_dir().join(format!("points_{name}.png")))
            .unwrap();
        quads
            .save_png(out_dir().join(format!("quads_{name}.png")))
            .unwrap();
        let bg = opts.background;
        let drawn = quads
            .rgba
            .chunks_exact(4)
            .filter(|p| !is_background([p[0], p[1], p[2], p[3]], bg))
            .count() as f64
            / (quads.width * quads.height) as f64;
        let (mean, _) = compare(&points, &quads);
        let diff = differing(&points, &quads);
        eprintln!("{name}: drawn {drawn:.3}, mean difference {mean:.4}, differing {diff:.5}");
        assert!(drawn > 0.05, "{name}: only {drawn} of the image drawn");
        // Float rounding moves single pixels at the spheres' edges, no more.
        assert!(
            mean < 0.1 && diff < 0.002,
            "{name}: points and quads differ (mean {mean}, share of pixels {diff})"
        );
    }
}
