//! `meshfree waves DIR` on a run directory whose `gauges.csv` holds a known incident and
//! reflected wave (flume-2d's wave maker: T = 1.2, depth 0.3): the heights and the
//! reflection coefficient come back, and bad input is refused with exit status 2.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

fn meshfree(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_meshfree"))
        .args(args)
        .output()
        .unwrap()
}

/// A run directory: flume-2d's scene and gauges at x = 1, 1.4 and 2.1 reading an incident
/// wave of height `hi` and a reflected one of `hr` about the still level 0.3, sampled every
/// 0.02 from t = 0 to 12; the first gauge dry (no surface point) before t = 0.5.
fn run_dir(dir: &Path, hi: f64, hr: f64) {
    run_dir_at(dir, hi, hr, 1.0)
}

/// The same with the waves' wave number `stretch` times linear theory's.
fn run_dir_at(dir: &Path, hi: f64, hr: f64, stretch: f64) {
    let (_, text) = (meshfree_core::scene::BUILTIN.iter())
        .find(|(n, _)| *n == "flume-2d")
        .unwrap();
    std::fs::write(dir.join("scene.toml"), text).unwrap();
    let (t_wave, d) = (1.2, 0.3);
    let k = stretch * meshfree_core::scene::wave::wave_number(9.81, t_wave, d);
    let w = 2.0 * std::f64::consts::PI / t_wave;
    let mut csv = String::from("time,step,gauge,x,y,distance\n");
    for i in 0..=600 {
        let t = 0.02 * i as f64;
        for (name, x) in [("x1", 1.0), ("x2", 1.4), ("x3", 2.1)] {
            let eta =
                0.5 * hi * (w * t - k * x + 0.4).cos() + 0.5 * hr * (w * t + k * x + 1.3).cos();
            if name == "x1" && t < 0.5 {
                writeln!(csv, "{t},{i},{name},,,").unwrap();
            } else {
                writeln!(csv, "{t},{i},{name},{x},{},{}", 0.3 + eta, 0.2 + eta).unwrap();
            }
        }
    }
    std::fs::write(dir.join("gauges.csv"), csv).unwrap();
}

#[test]
fn incident_and_reflected_heights_come_back() {
    let dir = tempfile::tempdir().unwrap();
    run_dir(dir.path(), 0.05, 0.012);
    let d = dir.path().to_str().unwrap();
    let o = meshfree(&["waves", d, "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let s = &j["separation"];
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    assert!((f(&s["incident"]) - 0.05).abs() < 1e-9, "{s}");
    assert!((f(&s["reflected"]) - 0.012).abs() < 1e-9, "{s}");
    assert!((f(&s["coefficient"]) - 0.24).abs() < 1e-8, "{s}");
    // Whole periods from the middle of the record to its end: 5 of them.
    assert!(
        (f(&j["to"]) - 12.0).abs() < 1e-9 && (f(&j["from"]) - 6.0).abs() < 1e-9,
        "{j}"
    );
    for g in j["gauges"].as_array().unwrap() {
        assert!((f(&g["mean"]) - 0.3).abs() < 1e-6, "{g}");
    }
    // The table names the coefficient.
    let o = meshfree(&["waves", d, "--gauges", "x1,x3", "--from", "1"]);
    assert!(o.status.success());
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("reflection coefficient 0.24"), "{out}");
}

#[test]
fn bad_input_is_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    run_dir(dir.path(), 0.05, 0.0);
    let d = dir.path().to_str().unwrap();
    for (args, why) in [
        (vec!["waves", d, "--gauges", "x1,x7"], "no gauge \"x7\""),
        (vec!["waves", d, "--from", "11.5"], "no whole period"),
        (
            vec!["waves", d, "--period=-1"],
            "--period: must be a positive number",
        ),
        (
            vec!["waves", "/nonexistent-run"],
            "output directory of `meshfree run`",
        ),
    ] {
        let o = meshfree(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains(why), "{args:?}: {e}");
    }
}

/// Waves 10 % longer than linear theory's (as the plain pressure gradient makes them): the
/// theory's wave number misreads them, `--wavelength` with the measured one reads them right.
#[test]
fn a_measured_wavelength_replaces_the_theory() {
    let dir = tempfile::tempdir().unwrap();
    let stretch = 1.0 / 1.1;
    run_dir_at(dir.path(), 0.05, 0.012, stretch);
    let d = dir.path().to_str().unwrap();
    let k = stretch * meshfree_core::scene::wave::wave_number(9.81, 1.2, 0.3);
    let coefficient = |extra: &[&str]| {
        let mut args = vec!["waves", d, "--json"];
        args.extend(extra);
        let o = meshfree(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        j["separation"]["coefficient"].as_f64().unwrap()
    };
    let theory = coefficient(&[]);
    let measured = coefficient(&[
        "--wavelength",
        &format!("{}", 2.0 * std::f64::consts::PI / k),
    ]);
    assert!((measured - 0.24).abs() < 1e-8, "{measured}");
    assert!((theory - 0.24).abs() > 0.01, "{theory}");
}
