//! Build script: test cfgs only. `MESHFREE_REQUIRE_EGL=1` sets `meshfree_require_egl` and
//! `MESHFREE_REQUIRE_XVFB=1` sets `meshfree_require_xvfb`: the headless (EGL) and live window
//! (Xvfb) tests are `#[ignore]`d without them, and fail without EGL or Xvfb with them (CI).

fn main() {
    for (var, cfg) in [
        ("MESHFREE_REQUIRE_EGL", "meshfree_require_egl"),
        ("MESHFREE_REQUIRE_XVFB", "meshfree_require_xvfb"),
    ] {
        println!("cargo:rerun-if-env-changed={var}");
        println!("cargo::rustc-check-cfg=cfg({cfg})");
        if std::env::var(var).is_ok_and(|v| v == "1") {
            println!("cargo:rustc-cfg={cfg}");
        }
    }
}
