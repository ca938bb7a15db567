//! A driven object on a time series from a file (`motion.series`, issue #54): a piston whose
//! recorded stroke samples a sinusoid moves the fluid as the same sinusoid's law does; a
//! flap's recorded angle turns it about its pivot; and the file's faults are refused with
//! the field and the reason before anything runs.

use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::scene::Scene;

mod common;
use common::run_scene_to;

/// A 2D tank with a piston at its left end, on `motion` (a TOML inline table).
fn piston(motion: &str, end: f64) -> String {
    format!(
        r#"
dimension = 2
name = "series-piston"

[domain]
min = [-0.2, -0.2]
max = [2.2, 0.7]

[discretisation]
spacing = 0.05

[time]
end = {end}
output_interval = 0.1
integrator = "symplectic-euler"

[fluid]
density = 1000.0
sound_speed = 20.0
alpha = 0.05

[boundary]
strength = 10.0

[[fluid_blocks]]
min = [0.25, 0.0]
max = [1.5, 0.4]

[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [2.0, 0.6]

[[walls]]
shape = "box"
min = [0.05, 0.0]
max = [0.2, 0.5]
motion = {motion}
"#
    )
}

/// Writes `scene` and the series `csv` into a fresh directory and reads the scene there.
fn load(scene: &str, csv: &str) -> Result<Scene, String> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("stroke.csv"), csv).unwrap();
    let path = dir.path().join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    Scene::from_file(&path).map_err(|e| e.to_string())
}

/// The stroke x = a sin(2 pi t / period) sampled every `h` over [-h, t_end].
fn stroke(a: f64, period: f64, h: f64, t_end: f64) -> String {
    let mut csv = String::from("# a piston's recorded stroke [m]\nt,x\n");
    let n = (t_end / h).ceil() as usize + 1;
    for j in 0..=n + 1 {
        let t = -h + j as f64 * h;
        let x = a * (2.0 * std::f64::consts::PI * t / period).sin();
        csv.push_str(&format!("{t},{x}\n"));
    }
    csv
}

#[test]
fn a_recorded_stroke_moves_the_piston_and_the_fluid_as_its_law_does() {
    let end = 0.3;
    let law = Scene::from_toml(
        &piston(
            "{ oscillation = { amplitude = [0.04, 0.0], period = 0.4 } }",
            end,
        ),
        "law",
    )
    .unwrap();
    let series = load(
        &piston(
            r#"{ series = { file = "stroke.csv", interpolation = "cubic" } }"#,
            end,
        ),
        &stroke(0.04, 0.4, 0.002, end),
    )
    .unwrap();
    let p = series.params();
    assert_eq!(p.driven, 1);
    assert_eq!(p.driven_motion[0].series_count, 153);
    assert_eq!(series.setup().unwrap().motion_series.len(), 153 * 5);
    let (start, a, ta) = run_scene_to(&law, end);
    let (_, b, tb) = run_scene_to(&series, end);
    // The step sizes follow the flow: the runs end within a step of each other.
    assert!((ta - tb).abs() < 1e-6, "{ta} vs {tb}");
    let (mut piston_worst, mut fluid_worst, mut moved) = (0.0f32, 0.0f32, 0.0f32);
    for ((s, a), b) in start.iter().zip(&a).zip(&b) {
        let gap = (a.position[0] - b.position[0])
            .abs()
            .max((a.position[1] - b.position[1]).abs());
        if a.kind == Kind::Boundary && a.group == 2 {
            piston_worst = piston_worst.max(gap);
            moved = moved.max((a.position[0] - s.position[0]).abs());
        } else if a.kind == Kind::Fluid {
            fluid_worst = fluid_worst.max(gap);
        }
    }
    eprintln!("piston moved {moved}; series - law: piston {piston_worst}, fluid {fluid_worst}");
    assert!(moved > 0.02, "the piston moved {moved}");
    // The cubic's error on a 2 ms sampling of this stroke is ~1e-8 m, the runs' ends differ
    // by a few ns (4e-7 m apart on the CPU); the fluid follows through its pressure (4e-6 m
    // apart), where a wrong wall velocity in the kick would move it by millimetres.
    assert!(
        piston_worst < 2.0e-6,
        "the piston is {piston_worst} off its law"
    );
    assert!(
        fluid_worst < 5.0e-5,
        "the fluid is {fluid_worst} off the law's run"
    );
}

#[test]
fn a_recorded_angle_turns_the_flap_about_its_pivot() {
    // theta(t) = -0.5 t [rad] about the flap's foot (0.125, 0): its top moves towards +x.
    let csv = "t,angle\n0,0\n0.5,-0.25\n";
    let scene = load(
        &piston(
            r#"{ series = { file = "stroke.csv", pivot = [0.125, 0.0] } }"#,
            0.1,
        ),
        csv,
    )
    .unwrap();
    let (start, end, t) = run_scene_to(&scene, 0.1);
    let (mut n, mut worst) = (0, 0.0f64);
    for (s, e) in start.iter().zip(&end) {
        if s.kind != Kind::Boundary || s.group != 2 {
            continue;
        }
        n += 1;
        let q = -0.5 * t;
        let (x, y) = (s.position[0] as f64 - 0.125, s.position[1] as f64);
        let want = [0.125 + x * q.cos() - y * q.sin(), x * q.sin() + y * q.cos()];
        for (got, want) in e.position.iter().zip(want) {
            worst = worst.max((*got as f64 - want).abs());
        }
    }
    assert!(n > 10, "{n} flap particles");
    assert!(worst < 1.0e-6, "a flap particle is {worst} off its turn");
}

#[test]
fn a_series_that_does_not_fit_the_scene_is_refused_with_its_field() {
    let f = "walls[1].motion.series";
    let ok = "t,x\n0,0\n1,0.1\n";
    for (motion, csv, field, why) in [
        (
            r#"{ series = { file = "stroke.csv" } }"#,
            "t,x\n0,0\n0.2,0.1\n",
            format!("{f}.file"),
            "ends at t = 0.2, before the run does (time.end = 0.5)",
        ),
        (
            r#"{ series = { file = "missing.csv" } }"#,
            ok,
            format!("{f}.file"),
            "cannot read the file",
        ),
        (
            r#"{ series = { file = "stroke.csv" } }"#,
            "t,x\n0,0\n1,oops\n",
            format!("{f}.file"),
            "line 3: \"oops\" is not a number",
        ),
        (
            r#"{ series = { file = "stroke.csv" } }"#,
            "t,angle\n0,0\n1,0.1\n",
            format!("{f}.pivot"),
            "give it",
        ),
        (
            r#"{ series = { file = "stroke.csv", pivot = [0.1, 0.0] } }"#,
            ok,
            f.to_string(),
            "the file has none",
        ),
        (
            r#"{ series = { file = "stroke.csv", pivot = [0.1, 0.0] }, rotation = { pivot = [0.1, 0.0], rate = 1.0 } }"#,
            "t,angle\n0,0\n1,0.1\n",
            f.to_string(),
            "put the turn in one of them",
        ),
        (
            r#"{ series = { file = "stroke.csv", pivot = [0.1, 0.0], axis = [0, 0, 1] } }"#,
            "t,angle\n0,0\n1,0.1\n",
            format!("{f}.axis"),
            "a 2D scene turns about z",
        ),
        (
            r#"{ series = { file = "stroke.csv" }, wave = { paddle = "piston", height = 0.05, period = 1.0, depth = 0.4 } }"#,
            ok,
            "walls[1].motion.wave".to_string(),
            "leave out velocity, oscillation, rotation and series",
        ),
        (
            r#"{ series = { file = "stroke.csv", interpolation = "spline" } }"#,
            ok,
            "walls[1]".to_string(),
            "unknown variant `spline`, expected `linear` or `cubic`",
        ),
    ] {
        let e = load(&piston(motion, 0.5), csv).unwrap_err();
        assert!(e.contains(&field) && e.contains(why), "{motion}: {e}");
    }
    // The forward Euler has no kick before its drift: a series is refused there too.
    let euler =
        piston(r#"{ series = { file = "stroke.csv" } }"#, 0.5).replace("symplectic-euler", "euler");
    let e = load(&euler, ok).unwrap_err();
    assert!(e.contains("needs a kick before the drift"), "{e}");
}

/// flume-2d's regular wave maker made an irregular sea's, over `end` \[T\].
fn irregular_flume(spectrum: &str, end: f64) -> Result<Scene, String> {
    let text = Scene::builtin("flume-2d").unwrap().text;
    let regular = "wave = { paddle = \"piston\", height = 0.05, period = 1.2, depth = 0.3 }";
    assert!(text.contains(regular));
    let text = text
        .replace(
            regular,
            &format!(
                "wave = {{ paddle = \"piston\", height = 0.04, period = 1.2, depth = 0.3, \
                 spectrum = {spectrum} }}"
            ),
        )
        .replace("end = 12.0 ", &format!("end = {end} "));
    Scene::from_toml(&text, "irregular").map_err(|e| e.to_string())
}

#[test]
fn an_irregular_sea_drives_the_paddle_along_its_record() {
    use meshfree_core::scene::format::{Motion, Paddle};
    let scene = irregular_flume("{ shape = \"jonswap\", seed = 4 }", 0.1).unwrap();
    let p = scene.params();
    let m = p.driven_motion[0];
    // Knots a 40th of the shortest kept period (2.5 Hz) apart, 0.01 s, from -0.01 to past
    // the end.
    assert!(
        (12..=14).contains(&m.series_count) && m.series_cubic == 1,
        "{m:?}"
    );
    let setup = scene.setup().unwrap();
    assert_eq!(setup.motion_series.len(), m.series_count as usize * 5);
    // The record reaches the run's end; a longer run makes a longer one of the same sea.
    let last = setup.motion_series[setup.motion_series.len() - 5];
    assert!(last >= 0.1, "{last}");
    let longer = scene
        .with_overrides(&meshfree_core::scene::Overrides {
            t_end: Some(0.3),
            output_interval: None,
        })
        .unwrap();
    let more = longer.setup().unwrap().motion_series;
    assert!(more.len() > setup.motion_series.len());
    assert_eq!(more[..setup.motion_series.len()], setup.motion_series[..]);
    // The paddle's particles move by the record's displacement (ramped over 2.4 s: small).
    let Motion::Law(l) = scene.file.walls[1].motion().unwrap() else {
        panic!()
    };
    let w = l.wave.as_ref().unwrap();
    assert_eq!(w.paddle, Paddle::Piston);
    let (start, end, t) = run_scene_to(&scene, 0.1);
    let want = m.at(&setup.motion_series, t).s[0];
    let group = scene.wall_group(1);
    let (mut n, mut worst) = (0, 0.0f64);
    for (a, b) in start.iter().zip(&end) {
        if a.group == group && a.kind == Kind::Boundary {
            n += 1;
            worst = worst.max(((b.position[0] - a.position[0]) as f64 - want).abs());
        }
    }
    assert!(n > 10 && want.abs() > 1e-6, "{n} particles, moved {want}");
    assert!(
        worst < 1e-6,
        "a paddle particle is {worst} off the record's {want}"
    );
}

#[test]
fn an_irregular_sea_the_flume_cannot_make_is_refused() {
    for (spectrum, field, why) in [
        (
            "{ shape = \"jonswap\", gamma = 0.5 }",
            "walls[1].motion.wave.spectrum.gamma",
            "from 1 to 10",
        ),
        (
            "{ shape = \"jonswap\", components = 8 }",
            "walls[1].motion.wave.spectrum.components",
            "from 16 to 4096",
        ),
        (
            "{ shape = \"choppy\" }",
            "walls[1]",
            "expected `jonswap` or `pierson-moskowitz`",
        ),
    ] {
        let e = irregular_flume(spectrum, 1.0).unwrap_err();
        assert!(e.contains(field) && e.contains(why), "{spectrum}: {e}");
    }
    // A sea whose paddle would leave the domain: flume-2d's paddle has 0.22 behind it.
    let text = Scene::builtin("flume-2d").unwrap().text.replace(
        "wave = { paddle = \"piston\", height = 0.05, period = 1.2, depth = 0.3 }",
        "wave = { paddle = \"piston\", height = 0.24, period = 2.5, depth = 0.3, spectrum = { shape = \"pierson-moskowitz\" } }",
    );
    let e = Scene::from_toml(&text, "big").unwrap_err().to_string();
    assert!(
        e.contains("walls[1].motion.wave") && e.contains("leaves the domain"),
        "{e}"
    );
}

/// `common::open_channel` in 2D with its inlet's velocity scaled by `scale.csv` = `csv`.
fn channel_with_series(series: &str, csv: &str) -> Result<Scene, String> {
    let text = common::open_channel(2).replacen(
        "velocity = [0.5, 0.0]\n[[open",
        &format!("velocity = [0.5, 0.0]\nseries = {series}\n[[open"),
        1,
    );
    assert!(text.contains("series = "));
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scale.csv"), csv).unwrap();
    let path = dir.path().join("channel.toml");
    std::fs::write(&path, text).unwrap();
    Scene::from_file(&path).map_err(|e| e.to_string())
}

#[test]
fn an_inlets_series_scales_the_flow_it_brings() {
    use meshfree_core::backend::{self, BackendChoice, Layout};
    // Full speed to t = 0.25, then down to 0.4 of it by t = 0.5 (linearly), held after.
    let csv = "t,scale\n0,1\n0.25,1\n0.5,0.4\n2,0.4\n";
    let scene = channel_with_series(r#"{ file = "scale.csv" }"#, csv).unwrap();
    let p = scene.params();
    assert_eq!((p.open[0].series_first, p.open[0].series_count), (0, 4));
    // A run's directory holds the file as `inflow-0.csv`, and its scene names it there.
    let (copy, files) = scene.with_surface_copies().unwrap();
    assert_eq!(files.len(), 1);
    assert_eq!(
        (files[0].name.as_str(), files[0].bytes.as_slice()),
        ("inflow-0.csv", csv.as_bytes())
    );
    assert!(
        copy.text.contains(r#"series = { file = "inflow-0.csv" }"#),
        "{}",
        copy.text
    );
    assert_eq!(p.open[1].series_count, 0);
    let mut s = backend::create(BackendChoice::Cpu, Layout::One, scene.setup().unwrap()).unwrap();
    while s.time() < 0.5 {
        s.advance(10);
    }
    let t = s.time();
    // The inlet's rows cross at U a(t): U (0.25 + 0.175 + 0.4 (t - 0.5)) / dx rows of 10.
    let crossed = 0.5 * (0.25 + 0.175 + 0.4 * (t - 0.5)) / 0.01 * 10.0;
    let inlet = s.open_tally()[0];
    eprintln!(
        "to t = {t:.4}: {} in, {crossed:.1} expected (250 at full speed)",
        inlet.count_in
    );
    assert!(
        (inlet.count_in as f64 - crossed).abs() <= 10.0,
        "{} particles came in, {crossed:.1} expected",
        inlet.count_in
    );
    // The buffer moves at U a(t) = 0.2 (group 3: the inlet's buffer).
    let buffer: Vec<Particle> = s.particles().into_iter().filter(|q| q.group == 3).collect();
    assert!(buffer.len() >= 20);
    for q in &buffer {
        assert!((q.velocity[0] - 0.2).abs() < 1e-3, "{:?}", q.velocity);
    }
}

#[test]
fn an_inlets_series_that_does_not_fit_is_refused() {
    let f = "open_boundaries[0].series";
    for (series, csv, field, why) in [
        (
            r#"{ file = "scale.csv" }"#,
            "t,scale\n0,1\n1,1\n",
            format!("{f}.file"),
            "ends at t = 1, before the run does (time.end = 1.5)",
        ),
        (
            r#"{ file = "scale.csv" }"#,
            "t,scale\n0,1\n1,-0.5\n2,1\n",
            format!("{f}.file"),
            "line 3: the scale -0.5 is negative",
        ),
        (
            r#"{ file = "scale.csv" }"#,
            "t,x\n0,1\n2,1\n",
            format!("{f}.file"),
            "column \"x\" is none of t and scale",
        ),
        (
            r#"{ file = "scale.csv", pivot = [0.0, 0.0] }"#,
            "t,scale\n0,1\n2,1\n",
            f.to_string(),
            "an inlet's series scales its velocity",
        ),
    ] {
        let e = channel_with_series(series, csv).unwrap_err();
        assert!(
            e.contains(&field) && e.contains(why),
            "{series} {csv:?}: {e}"
        );
    }
}

#[test]
fn a_focused_group_is_made_and_its_focus_checked() {
    let scene = irregular_flume(
        "{ shape = \"jonswap\", focus = { distance = 2.0, time = 8.0 } }",
        0.1,
    )
    .unwrap();
    assert!(scene.params().driven_motion[0].series_count > 10);
    for (focus, field, why) in [
        (
            "{ distance = -1.0, time = 8.0 }",
            "focus.distance",
            "positive",
        ),
        ("{ distance = 2.0, time = 0.0 }", "focus.time", "positive"),
        (
            "{ distance = 9.0, time = 8.0 }",
            "focus.distance",
            "beyond the domain's end",
        ),
    ] {
        let e = irregular_flume(&format!("{{ shape = \"jonswap\", focus = {focus} }}"), 0.1)
            .unwrap_err();
        assert!(
            e.contains(&format!("walls[1].motion.wave.spectrum.{field}")) && e.contains(why),
            "{focus}: {e}"
        );
    }
}
