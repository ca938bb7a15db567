//! The live window under a virtual X server (Xvfb): opens the window on the
//! demo source, lets it draw a few frames, takes a screenshot through
//! `ViewOptions::screenshot_after_frames` and checks the PNG.
//!
//! Starts its own `Xvfb` from PATH. `#[ignore]`d unless the build had
//! `MESHFREE_REQUIRE_XVFB=1` (CI; `build.rs` turns it into the cfg
//! `meshfree_require_xvfb`); `-- --include-ignored` runs it too. When it runs,
//! a missing or failing Xvfb is a failure: it never passes by skipping.
//! (This file holds one test: winit allows one event loop per process.)

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use meshfree_viewer::demo::DemoSource;
use meshfree_viewer::{run_window, Image, LiveSource, ViewOptions};

/// The Xvfb we started and, once it is up, its display number; stopped (and
/// then its socket and lock file removed) on drop.
struct Xvfb(Child, Option<u32>);

impl Drop for Xvfb {
    fn drop(&mut self) {
        // SIGTERM lets Xvfb remove its socket and lock file; fall back to SIGKILL.
        let terminated = Command::new("kill")
            .arg(self.0.id().to_string())
            .status()
            .map(|s| s.success())
            .unwrap_or(false);
        if terminated {
            let t0 = Instant::now();
            while t0.elapsed() < Duration::from_secs(5) {
                if let Ok(Some(_)) = self.0.try_wait() {
                    break;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
        }
        let _ = self.0.kill();
        let _ = self.0.wait();
        if let Some(n) = self.1 {
            let _ = std::fs::remove_file(format!("/tmp/.X11-unix/X{n}"));
            let _ = std::fs::remove_file(format!("/tmp/.X{n}-lock"));
        }
    }
}

fn on_path(name: &str) -> Option<PathBuf> {
    std::env::var_os("PATH")
        .map(|p| {
            std::env::split_paths(&p)
                .map(|d| d.join(name))
                .find(|f| f.is_file())
        })
        .unwrap_or(None)
}

/// Starts Xvfb on a free display number and waits for its socket.
fn start_xvfb(bin: &Path) -> Result<(Xvfb, String), String> {
    let base = 90 + std::process::id() % 400;
    for n in base..base + 50 {
        let socket = PathBuf::from(format!("/tmp/.X11-unix/X{n}"));
        if socket.exists() || Path::new(&format!("/tmp/.X{n}-lock")).exists() {
            continue;
        }
        let child = Command::new(bin)
            .args([
                &format!(":{n}"),
                "-screen",
                "0",
                "640x480x24",
                "-nolisten",
                "tcp",
                "-noreset",
            ])
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| format!("starting Xvfb: {e}"))?;
        let mut x = Xvfb(child, None);
        let t0 = Instant::now();
        while t0.elapsed() < Duration::from_secs(15) {
            if socket.exists() {
                x.1 = Some(n);
                return Ok((x, format!(":{n}")));
            }
            if let Ok(Some(status)) = x.0.try_wait() {
                eprintln!("Xvfb :{n} exited with {status}, trying the next display");
                break;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
    Err("no Xvfb display could be started".into())
}

#[test]
#[cfg_attr(
    not(meshfree_require_xvfb),
    ignore = "needs Xvfb: build with MESHFREE_REQUIRE_XVFB=1, or run with --include-ignored"
)]
fn live_window_screenshot_under_xvfb() {
    let bin =
        on_path("Xvfb").expect("this test needs Xvfb, which is not on PATH (apt-get install xvfb)");
    let (_xvfb, display) =
        start_xvfb(&bin).unwrap_or_else(|e| panic!("this test needs a running Xvfb: {e}"));
    // This test binary holds only this test, so changing the environment is safe.
    std::env::set_var("DISPLAY", &display);
    std::env::remove_var("WAYLAND_DISPLAY");
    std::env::set_var("LIBGL_ALWAYS_SOFTWARE", "1");

    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer-tests");
    std::fs::create_dir_all(&out).unwrap();
    let shot = out.join("window_xvfb.png");
    let _ = std::fs::remove_file(&shot);

    let mut source = DemoSource::new_2d(40);
    let opts = ViewOptions {
        title: "meshfree viewer test".into(),
        width: 480,
        height: 320,
        steps_per_frame: 3,
        vsync: false,
        show_help: true,
        screenshot_after_frames: Some((6, shot.clone())),
        ..ViewOptions::default()
    };
    let t0 = Instant::now();
    run_window(&mut source, opts).expect("live window under Xvfb");
    eprintln!(
        "window ran {:.2} s, status {:?}",
        t0.elapsed().as_secs_f64(),
        source.status()
    );
    assert!(
        source.status().step >= 6 * 3,
        "the source advanced: {:?}",
        source.status()
    );

    let img = Image::load_png(&shot).expect("screenshot written");
    assert_eq!((img.width, img.height), (480, 320));
    // Coloured (saturated) particle pixels: blue-ish and red-ish ones.
    let (mut coloured, mut red, mut blue) = (0usize, 0usize, 0usize);
    for p in img.rgba.chunks_exact(4) {
        let (r, g, b) = (p[0] as i32, p[1] as i32, p[2] as i32);
        if r.max(g).max(b) - r.min(g).min(b) > 60 {
            coloured += 1;
        }
        if r > 150 && r > b + 60 && r > g + 60 {
            red += 1;
        }
        if b > 150 && b > r + 60 {
            blue += 1;
        }
    }
    let frac = coloured as f64 / (480.0 * 320.0);
    eprintln!("coloured {frac:.3}, red {red}, blue {blue}");
    assert!(frac > 0.1, "coloured pixel fraction {frac}");
    assert!(red > 200 && blue > 200, "red {red}, blue {blue}");
}
