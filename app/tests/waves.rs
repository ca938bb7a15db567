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

/// An irregular sea's run directory: flume-2d's wave maker making a JONSWAP sea (H_m0 0.04,
/// T_p 1.2) and gauges at x = 1 and 2 reading that sea's first-order surface for 200 peak
/// periods, every 0.02.
fn sea_dir(dir: &Path) {
    let (_, text) = (meshfree_core::scene::BUILTIN.iter())
        .find(|(n, _)| *n == "flume-2d")
        .unwrap();
    let text = text.replace(
        "wave = { paddle = \"piston\", height = 0.05, period = 1.2, depth = 0.3 }",
        "wave = { paddle = \"piston\", height = 0.04, period = 1.2, depth = 0.3, \
         spectrum = { shape = \"jonswap\", seed = 5, components = 512 } }",
    );
    std::fs::write(dir.join("scene.toml"), &text).unwrap();
    let scene = meshfree_core::scene::Scene::from_toml(&text, "sea").unwrap();
    let meshfree_core::scene::format::Motion::Law(l) = scene.file.walls[1].motion().unwrap() else {
        panic!()
    };
    let parts = l.wave.as_ref().unwrap().components(9.81, 0.1);
    let mut csv = String::from("time,step,gauge,x,y,distance\n");
    for i in 0..12_000 {
        let t = 0.02 * i as f64;
        for (name, x) in [("x1", 1.0), ("x2", 2.0)] {
            // The gauge further down sees the sea later (a plain delay: enough here).
            let eta = meshfree_core::scene::wave_spectrum::elevation_at(&parts, t - x);
            writeln!(csv, "{t},{i},{name},{x},{},{}", 0.3 + eta, 0.2 + eta).unwrap();
        }
    }
    std::fs::write(dir.join("gauges.csv"), csv).unwrap();
}

#[test]
fn an_irregular_sea_gives_back_its_height_and_peak_period() {
    let dir = tempfile::tempdir().unwrap();
    sea_dir(dir.path());
    let d = dir.path().to_str().unwrap();
    let o = meshfree(&["waves", d, "--json", "--from", "0"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let j: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    assert_eq!((f(&j["target_hm0"]), f(&j["target_tp"])), (0.04, 1.2));
    let gauges = j["gauges"].as_array().unwrap();
    assert_eq!(gauges.len(), 2);
    for g in gauges {
        assert!((f(&g["hm0"]) / 0.04 - 1.0).abs() < 0.05, "{g}");
        assert!((f(&g["tp"]) / 1.2 - 1.0).abs() < 0.05, "{g}");
        assert!((f(&g["mean"]) - 0.3).abs() < 1e-3, "{g}");
    }
    // The table names the columns; a dry gap in the window is refused.
    let o = meshfree(&["waves", d]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("H_m0") && out.contains("T_p"), "{out}");
    let csv = std::fs::read_to_string(dir.path().join("gauges.csv")).unwrap();
    let gap = csv.replace("\n100,5000,x1,1,", "\n100,5000,x1,,,\nskip,");
    let gap: String = gap
        .lines()
        .filter(|l| !l.starts_with("skip,"))
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(dir.path().join("gauges.csv"), gap).unwrap();
    let o = meshfree(&["waves", d, "--from", "0"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("gauge \"x1\"") && err.contains("dry gap"),
        "{err}"
    );
}
