//! Build script: test cfgs only. `MESHFREE_REQUIRE_PYVTK=1` sets `meshfree_require_pyvtk`:
//! the test that reads our VTU files with the official VTK Python module and with meshio
//! (`tests/python_readers.rs`, Python from `MESHFREE_PYTHON`, default `python3`) is
//! `#[ignore]`d without it and fails without those modules with it (CI installs them).
//! `MESHFREE_REQUIRE_EGL=1` sets `meshfree_require_egl`: the tests that render a run's
//! frames headless (`tests/render_run.rs`) are `#[ignore]`d without it and fail without
//! EGL with it, as the viewer's headless tests are (CI). `MESHFREE_REQUIRE_FFMPEG=1` sets
//! `meshfree_require_ffmpeg`: the test that encodes a run's frames with a real ffmpeg and
//! counts them with ffprobe; `MESHFREE_REQUIRE_XVFB=1` sets `meshfree_require_xvfb`: the
//! test that opens `meshfree view DIR` in a window under `xvfb-run`. Each is `#[ignore]`d
//! without its variable and fails without the program with it (CI installs both).

fn main() {
    for (var, cfg) in [
        ("MESHFREE_REQUIRE_PYVTK", "meshfree_require_pyvtk"),
        ("MESHFREE_REQUIRE_EGL", "meshfree_require_egl"),
        ("MESHFREE_REQUIRE_FFMPEG", "meshfree_require_ffmpeg"),
        ("MESHFREE_REQUIRE_XVFB", "meshfree_require_xvfb"),
    ] {
        println!("cargo:rerun-if-env-changed={var}");
        println!("cargo::rustc-check-cfg=cfg({cfg})");
        if std::env::var(var).is_ok_and(|v| v == "1") {
            println!("cargo:rustc-cfg={cfg}");
        }
    }
}
