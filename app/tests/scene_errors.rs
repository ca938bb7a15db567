//! Bad scene files: each error names the file, the field and the reason; nothing panics;
//! no output directory is created.

use std::path::{Path, PathBuf};

use meshfree::run::{self, Progress, RunOptions};
use meshfree_core::scene::{Scene, SceneError};

const BASE: &str = r#"
dimension = 2
name = "tiny"
gravity = [0.0, -9.81]

[domain]
min = [-0.2, -0.2]
max = [1.2, 1.2]

[discretisation]
spacing = 0.05

[time]
end = 0.01
output_interval = 0.005

[fluid]
density = 1000.0
sound_speed = 30.0
alpha = 0.02

[boundary]
strength = 100.0

[[fluid_blocks]]
min = [0.0, 0.0]
max = [0.5, 0.5]
hydrostatic = true

[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [1.0, 1.0]
"#;

/// Write `text` as a scene file in a fresh directory; return (dir, file).
fn write(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad scene.toml");
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

/// Load `text` from a file; it must fail with the file's path, `field` and `reason` in the
/// message. Also runs it through `run::run` and checks that no output directory appears.
fn expect_error(text: &str, field: &str, reason: &str) -> SceneError {
    expect_error_with(&[], text, field, reason)
}

/// `expect_error` with `files` (name, bytes) written beside the scene file: surfaces.
fn expect_error_with(files: &[(&str, &[u8])], text: &str, field: &str, reason: &str) -> SceneError {
    let (dir, path) = write(text);
    for (name, bytes) in files {
        std::fs::write(dir.path().join(name), bytes).unwrap();
    }
    let err = Scene::from_file(&path).expect_err("the scene should be refused");
    let msg = err.to_string();
    assert!(
        msg.starts_with(&path.display().to_string()),
        "no file in `{msg}`"
    );
    assert!(
        msg.contains(&format!(": {field}: ")),
        "no field `{field}` in `{msg}`"
    );
    assert!(msg.contains(reason), "no reason `{reason}` in `{msg}`");
    assert_eq!(err.field(), Some(field));
    // Through the command line: non-zero exit, `error: <file>: <field>: <reason>`, no output.
    let out = dir.path().join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_meshfree"))
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "bad input exits with 2");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.starts_with(&format!("error: {}: {field}: ", path.display())),
        "{stderr}"
    );
    assert!(!out.exists());
    err
}

fn with(old: &str, new: &str) -> String {
    assert!(BASE.contains(old), "BASE lacks `{old}`");
    BASE.replacen(old, new, 1)
}

#[test]
fn base_scene_is_valid() {
    let s = Scene::from_toml(BASE, "base").unwrap();
    let setup = s.setup().unwrap();
    assert_eq!(
        setup
            .particles
            .iter()
            .filter(|p| p.kind == meshfree_core::physics::particle::Kind::Fluid)
            .count(),
        100
    );
}

#[test]
fn unknown_key() {
    let e = expect_error(
        &with("alpha = 0.02", "alpha = 0.02\nalfa = 0.1"),
        "fluid.alfa",
        "unknown field `alfa`, expected one of",
    );
    match e {
        SceneError::Parse { line, column, .. } => assert_eq!((line, column), (21, 1)),
        other => panic!("{other:?}"),
    }
}

#[test]
fn unknown_key_in_array_of_tables() {
    expect_error(
        &with(
            "hydrostatic = true",
            "hydrostatic = true\ncolour = \"blue\"",
        ),
        "fluid_blocks[0].colour",
        "unknown field `colour`",
    );
}

#[test]
fn wrong_type() {
    expect_error(
        &with("spacing = 0.05", "spacing = \"fine\""),
        "discretisation.spacing",
        "invalid type",
    );
}

#[test]
fn wrong_enum_value() {
    expect_error(
        &with("spacing = 0.05", "spacing = 0.05\nkernel = \"gaussian\""),
        "discretisation.kernel",
        "unknown variant `gaussian`",
    );
}

#[test]
fn wrong_array_length() {
    expect_error(
        &with("max = [0.5, 0.5]", "max = [0.5, 0.5, 0.5]"),
        "fluid_blocks[0].max",
        "expected 2 numbers",
    );
}

#[test]
fn min_not_below_max() {
    expect_error(
        &with("max = [0.5, 0.5]", "max = [0.5, -0.5]"),
        "fluid_blocks[0].max",
        "not greater than min[1]",
    );
}

#[test]
fn spacing_not_positive() {
    expect_error(
        &with("spacing = 0.05", "spacing = 0.0"),
        "discretisation.spacing",
        "must be a positive number",
    );
}

#[test]
fn density_diffusion_out_of_range_or_with_summation() {
    expect_error(
        &with("alpha = 0.02", "alpha = 0.02\ndensity_diffusion = 1.5"),
        "fluid.density_diffusion",
        "must lie in [0, 1]",
    );
    expect_error(
        &with(
            "alpha = 0.02",
            "alpha = 0.02\ndensity_diffusion = 0.1\ndensity_form = \"summation\"",
        ),
        "fluid.density_diffusion",
        "acts on the continuity equation",
    );
}

#[test]
fn shifting_and_background_pressure_out_of_range() {
    expect_error(
        &with("alpha = 0.02", "alpha = 0.02\nshifting = 1.5"),
        "fluid.shifting",
        "must lie in [0, 1]",
    );
    expect_error(
        &with("alpha = 0.02", "alpha = 0.02\nbackground_pressure = -1.0"),
        "fluid.background_pressure",
        "",
    );
    expect_error(
        &with("alpha = 0.02", "alpha = 0.02\nbackground_pressure = 1e12"),
        "fluid.background_pressure",
        "must not exceed the Tait stiffness",
    );
}

#[test]
fn object_outside_domain() {
    expect_error(
        &with("max = [0.5, 0.5]", "max = [1.5, 0.5]"),
        "fluid_blocks[0]",
        "beyond domain.max[0]",
    );
}

#[test]
fn wall_layers_outside_domain() {
    let t = with("min = [-0.2, -0.2]", "min = [-0.1, -0.1]")
        .replace("spacing = 0.05", "spacing = 0.05\nh_factor = 1.3");
    let t = t.replacen("max = [1.0, 1.0]", "max = [1.0, 1.0]\nlayers = 3", 1);
    expect_error(&t, "walls[0]", "below domain.min[0]");
}

#[test]
fn solid_without_material() {
    let t = format!("{BASE}\n[[solids]]\nshape = \"disc\"\ncenter = [0.7, 0.7]\nradius = 0.1\n");
    expect_error(&t, "solid", "no [solid] material table");
}

#[test]
fn sphere_in_2d() {
    let t = format!(
        "{BASE}\n[solid]\ndensity = 600.0\nsound_speed = 30.0\nshear_modulus = 1e4\n\n[[solids]]\nshape = \"sphere\"\ncenter = [0.7, 0.7]\nradius = 0.1\n"
    );
    expect_error(&t, "solids[0].shape", "a \"sphere\" is a 3D shape");
}

#[test]
fn wall_contact_is_checked() {
    let solid = "\n[solid]\ndensity = 600.0\nsound_speed = 30.0\nshear_modulus = 1e4\n";
    let body = "\n[[solids]]\nshape = \"disc\"\ncenter = [0.7, 0.7]\nradius = 0.1\n";
    let t = format!("{BASE}{solid}wall_contact = \"no\"\n{body}");
    expect_error(&t, "solid.wall_contact", "invalid type");
    // Without walls there is nothing to skip.
    let walls = BASE.find("[[walls]]").unwrap();
    let t = format!("{}{solid}wall_contact = false\n{body}", &BASE[..walls]);
    expect_error(&t, "solid.wall_contact", "the scene has no [[walls]]");
    // With walls it is accepted and reaches the parameters.
    let t = format!("{BASE}{solid}wall_contact = false\n{body}");
    assert_eq!(Scene::from_toml(&t, "ok").unwrap().params().wall_contact, 0);
    let t = format!("{BASE}{solid}{body}");
    assert_eq!(Scene::from_toml(&t, "ok").unwrap().params().wall_contact, 1);
}

#[test]
fn periodic_axis_too_short() {
    let t = with(
        "max = [1.2, 1.2]",
        "max = [1.2, 1.2]\nperiodic = [false, true]",
    )
    .replace("spacing = 0.05", "spacing = 0.2");
    expect_error(&t, "domain.periodic[1]", "at least 3 neighbour cells");
}

#[test]
fn toml_syntax_error() {
    let e = expect_error(
        &with("density = 1000.0", "density = = 1000.0"),
        // The key of the line (toml itself names none).
        "fluid.density",
        "invalid",
    );
    match e {
        SceneError::Parse { line, column, .. } => {
            assert_eq!(line, 18);
            assert!(column > 1);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn missing_key() {
    expect_error(&with("end = 0.01\n", ""), "time", "missing field `end`");
}

#[test]
fn dimension_out_of_range() {
    expect_error(
        &with("dimension = 2", "dimension = 4"),
        "dimension",
        "must be 2 or 3",
    );
}

#[test]
fn no_particles() {
    // A block thinner than the spacing holds no particle.
    let t = with("max = [0.5, 0.5]", "max = [0.5, 0.01]").replace(
        "[[walls]]\nshape = \"box-container\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n",
        "",
    );
    let s = Scene::from_toml(&t, "thin.toml").unwrap();
    let e = s.setup().unwrap_err();
    assert!(
        e.to_string()
            .starts_with("thin.toml: fluid_blocks: the scene generates no fluid"),
        "{e}"
    );
}

#[test]
fn missing_file() {
    let e = Scene::from_file(Path::new("/nonexistent/scene.toml")).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("/nonexistent/scene.toml: cannot read the file"),
        "{e}"
    );
}

#[test]
fn unknown_builtin() {
    let e = Scene::builtin("dam-brake-2d").unwrap_err();
    let m = e.to_string();
    assert!(
        m.contains("(known: ") && m.contains(" dam-break-2d, "),
        "{e}"
    );
}

#[test]
fn bad_override_creates_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let s = Scene::from_toml(BASE, "base.toml").unwrap();
    let options = RunOptions {
        format: None,
        out_dir: Some(out.clone()),
        t_end: Some(-1.0),
        progress: Progress::Quiet,
        ..Default::default()
    };
    let e = run::run(&s, &options).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("command line: --t-end: must be a positive number"),
        "{e}"
    );
    assert!(!out.exists());
}

#[test]
fn more_driven_objects_than_the_solver_holds() {
    // Eight moving walls (MF_MAX_DRIVEN) are a scene; a ninth is refused at its motion.
    let walls = |n: usize| -> String {
        (0..n)
            .map(|i| {
                let x = 0.1 * i as f64;
                format!(
                    "\n[[walls]]\nshape = \"box\"\nmin = [{x}, 0.7]\nmax = [{}, 0.8]\nmotion = [0.0, {}]\n",
                    x + 0.05,
                    0.1 * i as f64
                )
            })
            .collect()
    };
    let eight = format!("{BASE}{}", walls(8));
    Scene::from_toml(&eight, "eight.toml").expect("eight moving walls");
    expect_error(
        &format!("{BASE}{}", walls(9)),
        "walls[9].motion",
        "at most 8 driven or floating objects",
    );
}

/// A motion table's own checks (issue #54): each names the key inside the table.
#[test]
fn motion_law_errors_name_their_key() {
    let wall = |m: &str| {
        format!("{BASE}\n[[walls]]\nshape = \"box\"\nmin = [0.0, 0.6]\nmax = [0.1, 0.9]\nmotion = {m}\n")
    };
    Scene::from_toml(
        &wall("{ oscillation = { amplitude = [0.1, 0.0], period = 1.0 }, rotation = { pivot = [0.5, 0.5], amplitude = 0.1, period = 2.0 }, ramp = 0.5 }"),
        "law.toml",
    )
    .expect("an oscillating, rocking wall");
    expect_error(&wall("{ ramp = 1.0 }"), "walls[1].motion", "nothing moves");
    expect_error(
        &wall("{ oscillation = { amplitude = [0.1, 0.0], period = 0.0 } }"),
        "walls[1].motion.oscillation.period",
        "positive",
    );
    expect_error(
        &wall("{ oscillation = { amplitude = [0.1], period = 1.0 } }"),
        "walls[1].motion.oscillation.amplitude",
        "expected 2 numbers",
    );
    expect_error(
        &wall("{ rotation = { pivot = [0.5, 0.5], axis = [0, 0, 1], rate = 1.0 } }"),
        "walls[1].motion.rotation.axis",
        "leave out axis",
    );
    expect_error(
        &wall("{ rotation = { pivot = [0.5, 0.5] } }"),
        "walls[1].motion.rotation",
        "turns nothing",
    );
    expect_error(
        &wall("{ rotation = { pivot = [0.5, 0.5], amplitude = 0.2 } }"),
        "walls[1].motion.rotation.period",
        "positive period",
    );
    expect_error(
        &wall("{ velocity = [1.0, 0.0], ramp = -1.0 }"),
        "walls[1].motion.ramp",
        ">= 0",
    );
    expect_error(
        &wall("{ velocity = [1.0, 0.0], spin = 2.0 }"),
        "walls[1].motion",
        "unknown field `spin`",
    );
    // The paper's forward Euler has no kick before the drift: steady velocities only.
    let euler = |m: &str| wall(m).replace("[time]\n", "[time]\nintegrator = \"euler\"\n");
    Scene::from_toml(&euler("[1.0, 0.0]"), "euler.toml").expect("a steady piston under Euler");
    expect_error(
        &euler("{ rotation = { pivot = [0.5, 0.5], rate = 1.0 } }"),
        "walls[1].motion",
        "kick before the drift",
    );
}

/// A wave maker that cannot make its wave, and a damping zone that cannot damp (issue #57).
#[test]
fn wave_makers_and_damping_zones_refuse_what_they_cannot_do() {
    let flume = include_str!("../../scenes/flume-2d.toml");
    let wave = "wave = { paddle = \"piston\", height = 0.05, period = 1.2, depth = 0.3 }";
    assert!(flume.contains(wave));
    let with = |w: &str| flume.replace(wave, w);
    // Miche: H <= 0.142 L tanh(kd) = 0.198 at T = 1.2, d = 0.3.
    expect_error(
        &with("wave = { paddle = \"piston\", height = 0.21, period = 1.2, depth = 0.3 }"),
        "walls[1].motion.wave.height",
        "Miche's limit",
    );
    // A wavelength under 10 spacings (T = 0.2: L = 0.062 < 0.1).
    expect_error(
        &with("wave = { paddle = \"piston\", height = 0.001, period = 0.2, depth = 0.3 }"),
        "walls[1].motion.wave.period",
        "under 10 particle spacings",
    );
    // Longer than the flume (T = 5: L = 8.5 > 6.35).
    expect_error(
        &with("wave = { paddle = \"piston\", height = 0.05, period = 5.0, depth = 0.3 }"),
        "walls[1].motion.wave.period",
        "longer than the domain",
    );
    // A stroke the domain behind the paddle cannot hold (H = 0.19 at T = 3: S = 0.5).
    expect_error(
        &with("wave = { paddle = \"piston\", height = 0.19, period = 3.0, depth = 0.3 }"),
        "walls[1].motion.wave",
        "leaves the domain",
    );
    expect_error(
        &with("wave = { paddle = \"flap\", height = 0.05, period = 1.2, depth = 0.3 }"),
        "walls[1].motion.wave.hinge",
        "needs its hinge",
    );
    expect_error(
        &with("wave = { paddle = \"piston\", height = 0.05, period = 1.2, depth = 0.3, hinge = [0.0, 0.0] }"),
        "walls[1].motion.wave.hinge",
        "no hinge",
    );
    Scene::from_toml(
        &with("wave = { paddle = \"flap\", height = 0.05, period = 1.2, depth = 0.3, hinge = [0.0, 0.0] }"),
        "flap.toml",
    )
    .expect("a flap hinged on the floor");
    expect_error(
        &with(&format!("velocity = [0.1, 0.0], {wave}")),
        "walls[1].motion.wave",
        "follows its wave alone",
    );
    expect_error(
        &flume.replace("gravity = [0.0, -9.81]", "gravity = [-9.81, 0.0]"),
        "walls[1].motion.wave",
        "gravity must point along -y",
    );
    // The damping zone.
    expect_error(
        &flume.replace("end = 6.0\nstrength", "end = 7.0\nstrength"),
        "damping_zone.end",
        "outside the domain",
    );
    expect_error(
        &flume.replace("end = 6.0\nstrength", "end = 4.0\nstrength"),
        "damping_zone.end",
        "needs a length",
    );
    expect_error(
        &flume.replace("strength = 10.0", "strength = -1.0"),
        "damping_zone.strength",
        "",
    );
}

#[test]
fn driven_motion_wrong_length() {
    let bad = format!(
        "{BASE}\n[[walls]]\nshape = \"box\"\nmin = [0.0, 0.6]\nmax = [0.1, 0.9]\nmotion = [1.0]\n"
    );
    expect_error(&bad, "walls[1].motion", "expected 2 numbers");
}

#[test]
fn driven_solid_with_velocity_too() {
    let bad = format!(
        "{BASE}\n[solid]\ndensity = 500.0\nsound_speed = 30.0\nshear_modulus = 1e4\n\n[[solids]]\n\
         shape = \"box\"\nmin = [0.6, 0.6]\nmax = [0.8, 0.8]\nvelocity = [1.0, 0.0]\nmotion = [0.0, 0.0]\n"
    );
    expect_error(
        &bad,
        "solids[0].velocity",
        "give motion or velocity, not both",
    );
}

#[test]
fn clamp_off_the_lattice_of_the_solid_it_holds() {
    // The clamp's min corner is 0.03 from the plate's: not a whole number of spacings 0.05.
    let solids = "\n[solid]\ndensity = 500.0\nsound_speed = 30.0\nshear_modulus = 1e4\n\n\
         [[solids]]\nshape = \"box\"\nmin = [0.57, 0.6]\nmax = [0.7, 0.7]\nmotion = [0.0, 0.0]\n\n\
         [[solids]]\nshape = \"box\"\nmin = [0.6, 0.6]\nmax = [0.9, 0.7]\n";
    expect_error(
        &format!("{BASE}{solids}"),
        "solids[0].min",
        "must sit on its particle lattice: min[0] differs by -0.03",
    );
    // On the lattice (0.55 = 0.6 - 1 dx) it is accepted.
    let ok = format!("{BASE}{}", solids.replace("0.57", "0.55"));
    Scene::from_toml(&ok, "clamp-ok").expect("a clamp on the plate's lattice");
}

#[test]
fn negative_cohesion() {
    expect_error(
        &with("alpha = 0.02", "alpha = 0.02\ncohesion = -1.0"),
        "fluid.cohesion",
        "must be zero or positive",
    );
}

/// BASE with an inflow band `band` (TOML lines of the [inflow] table).
fn with_inflow(band: &str) -> String {
    format!("{BASE}\n[inflow]\n{band}\n")
}

#[test]
fn inflow_band_is_checked() {
    let ok = with_inflow("axis = \"x\"\nmin = 0.0\nmax = 0.2\nvelocity = [1.0, 0.0]");
    let s = Scene::from_toml(&ok, "ok").unwrap();
    let p = s.params();
    assert_eq!(
        (p.inflow, p.inflow_axis, p.inflow_lo, p.inflow_hi),
        (1, 0, 0.0, 0.2)
    );
    assert_eq!(p.inflow_velocity, [1.0, 0.0, 0.0]);
    expect_error(
        &with_inflow("axis = \"z\"\nmin = 0.0\nmax = 0.2\nvelocity = [1.0, 0.0]"),
        "inflow.axis",
        "does not exist in a 2D scene",
    );
    expect_error(
        &with_inflow("axis = \"x\"\nmin = 0.2\nmax = 0.2\nvelocity = [1.0, 0.0]"),
        "inflow.max",
        "needs min < max",
    );
    expect_error(
        &with_inflow("axis = \"y\"\nmin = 0.0\nmax = 2.0\nvelocity = [1.0, 0.0]"),
        "inflow",
        "reaches outside the domain",
    );
    expect_error(
        &with_inflow("axis = \"x\"\nmin = 0.0\nmax = 0.2\nvelocity = [1.0, 0.0, 0.0]"),
        "inflow.velocity",
        "expected 2 numbers",
    );
}

#[test]
fn segment_wall_too_short() {
    let bad =
        format!("{BASE}\n[[walls]]\nshape = \"segment\"\nfrom = [0.2, 0.6]\nto = [0.22, 0.6]\n");
    expect_error(&bad, "walls[1].to", "shorter than one spacing");
}

#[test]
fn monitors_are_checked() {
    let m = |body: &str| format!("{BASE}\n[[monitors]]\n{body}\n");
    let good = "wall = 0\ninterval = 0.01\nreference_velocity = 1.0\nreference_length = 0.2";
    assert!(Scene::from_toml(&m(good), "ok").is_ok());
    expect_error(
        &m(&good.replace("wall = 0", "wall = 1")),
        "monitors[0].wall",
        "wall 1 does not exist: the scene has 1 wall(s)",
    );
    expect_error(
        &m(&good.replace("interval = 0.01", "interval = 0.0")),
        "monitors[0].interval",
        "must be a positive number",
    );
    expect_error(
        &m(&good.replace("reference_length = 0.2", "reference_length = -1.0")),
        "monitors[0].reference_length",
        "must be a positive number",
    );
    // The scales are both or neither (#51): neither is a force record alone.
    assert!(Scene::from_toml(&m("wall = 0\ninterval = 0.01"), "ok").is_ok());
    expect_error(
        &m(&good.replace("reference_length = 0.2", "")),
        "monitors[0].reference_length",
        "need both scales",
    );
    expect_error(
        &m(&format!("{good}\nname = \"a/b\"")),
        "monitors[0].name",
        "file name of letters",
    );
    expect_error(
        &format!("{}\n[[monitors]]\n{good}\n", m(good)),
        "monitors[1].name",
        "names an earlier monitor",
    );
}

#[test]
fn figure_moments_must_increase() {
    expect_error(
        &with(
            "output_interval = 0.005",
            "output_interval = 0.005\nfigures = [0.0, 0.5, 0.5]",
        ),
        "time.figures[2]",
        "must increase",
    );
    expect_error(
        &with(
            "output_interval = 0.005",
            "output_interval = 0.005\nfigures = [-1.0]",
        ),
        "time.figures[0]",
        "zero or positive",
    );
    // Moments past the end time are fine: a shortened run renders the ones it reaches.
    Scene::from_toml(
        &with(
            "output_interval = 0.005",
            "output_interval = 0.005\nfigures = [0.0, 5.0]",
        ),
        "x",
    )
    .unwrap();
}

#[test]
fn solid_density_diffusion_out_of_range_or_with_summation() {
    let solid = "\n[solid]\ndensity = 600.0\nsound_speed = 30.0\nshear_modulus = 1e4\n";
    let body = "\n[[solids]]\nshape = \"disc\"\ncenter = [0.7, 0.7]\nradius = 0.1\n";
    let t = format!("{BASE}{solid}density_diffusion = -0.1\n{body}");
    expect_error(&t, "solid.density_diffusion", "");
    let t = format!("{BASE}{solid}density_diffusion = 1.5\n{body}");
    expect_error(&t, "solid.density_diffusion", "must lie in [0, 1]");
    let t = format!(
        "{}{solid}density_diffusion = 0.02\n{body}",
        with("alpha = 0.02", "alpha = 0.02\ndensity_form = \"summation\"")
    );
    expect_error(
        &t,
        "solid.density_diffusion",
        "acts on the continuity equation",
    );
    // In range with the continuity density it reaches the parameters.
    let t = format!("{BASE}{solid}density_diffusion = 0.02\n{body}");
    let p = Scene::from_toml(&t, "ok").unwrap().setup().unwrap().params;
    assert_eq!(p.solid_density_diffusion, 0.02);
}

/// A probe table of two points and a gauge, valid in `BASE`.
const PROBES: &str = r#"
[[probes]]
name = "p"
points = [[0.5, 0.25], [0.5, 0.4]]
interval = 0.005

[[gauges]]
name = "g"
start = [0.5, 0.0]
end = [0.5, 1.0]
interval = 0.005
"#;

fn with_probes(old: &str, new: &str) -> String {
    assert!(PROBES.contains(old), "PROBES lacks `{old}`");
    BASE.to_string() + &PROBES.replacen(old, new, 1)
}

#[test]
fn probes_and_gauges_are_valid() {
    let s = Scene::from_toml(&(BASE.to_string() + PROBES), "probes").unwrap();
    assert_eq!((s.file.probes.len(), s.file.gauges.len()), (1, 1));
    assert_eq!(s.file.probes[0].fields.len(), 3);
}

#[test]
fn probe_outside_the_domain() {
    expect_error(
        &with_probes("[0.5, 0.4]", "[0.5, 1.5]"),
        "probes[0].points[1]",
        "the point [0.5, 1.5] is outside the domain: x[1] = 1.5 is not within \
         [domain.min[1], domain.max[1]] = [-0.2, 1.2]",
    );
}

#[test]
fn gauge_outside_the_domain() {
    expect_error(
        &with_probes("end = [0.5, 1.0]", "end = [1.3, 1.0]"),
        "gauges[0].end",
        "is outside the domain: x[0] = 1.3",
    );
}

#[test]
fn probe_and_gauge_intervals_must_be_positive() {
    expect_error(
        &with_probes(
            "interval = 0.005\n\n[[gauges]]",
            "interval = 0.0\n\n[[gauges]]",
        ),
        "probes[0].interval",
        "must be a positive number, found 0",
    );
    expect_error(
        &with_probes(
            "end = [0.5, 1.0]\ninterval = 0.005",
            "end = [0.5, 1.0]\ninterval = -1.0",
        ),
        "gauges[0].interval",
        "must be a positive number, found -1",
    );
}

#[test]
fn probe_field_must_be_known_and_listed_once() {
    expect_error(
        &with_probes(
            "interval = 0.005\n\n[[gauges]]",
            "interval = 0.005\nfields = [\"pressure\", \"presure\"]\n\n[[gauges]]",
        ),
        "probes[0].fields[1]",
        "unknown variant `presure`, expected one of `pressure`, `velocity`, `density`",
    );
    expect_error(
        &with_probes(
            "interval = 0.005\n\n[[gauges]]",
            "interval = 0.005\nfields = [\"density\", \"density\"]\n\n[[gauges]]",
        ),
        "probes[0].fields[1]",
        "\"density\" is listed twice",
    );
}

#[test]
fn probe_and_gauge_names_must_be_unique() {
    let twice = BASE.to_string()
        + PROBES
        + "\n[[probes]]\nname = \"p\"\npoints = [[0.1, 0.1]]\ninterval = 0.01\n";
    expect_error(&twice, "probes[1].name", "\"p\" names an earlier entry");
    expect_error(
        &with_probes("name = \"g\"", "name = \"g,1\""),
        "gauges[0].name",
        "must be a non-empty name of letters, digits",
    );
}

/// CR-only line endings (classic Mac OS) gave an empty reason.
#[test]
fn cr_only_line_endings_are_named() {
    let text = BASE.replace('\n', "\r");
    let Err(e) = Scene::from_toml(&text, "mac.toml") else {
        panic!("a CR-only file parsed")
    };
    let s = e.to_string();
    assert!(s.contains("mac.toml") && s.contains("CR-only"), "{s}");
}

/// A TOML syntax error names the key of its line, and NaN / Infinity say why.
#[test]
fn syntax_errors_name_the_key_and_nan_is_explained() {
    let text = BASE.replace("spacing = 0.05", "spacing = NaN");
    let e = Scene::from_toml(&text, "n.toml").unwrap_err();
    assert_eq!(e.field(), Some("discretisation.spacing"), "{e}");
    assert!(e.to_string().contains("finite numbers only"), "{e}");
    let text = BASE.replace("sound_speed = 30.0", "sound_speed = fast");
    let e = Scene::from_toml(&text, "w.toml").unwrap_err();
    assert_eq!(e.field(), Some("fluid.sound_speed"), "{e}");
    assert!(e.to_string().contains("in quotes"), "{e}");
}

#[test]
fn solid_so_stiff_the_step_is_below_a_billionth_of_the_run() {
    // h = 1.3 x 0.05, courant 0.4, end 0.01: dt = 0.026 / c is below 1e-11 where c > 2.6e9.
    let solid = |c: &str, g: &str| {
        format!(
            "{BASE}\n[solid]\ndensity = 500.0\nsound_speed = {c}\nshear_modulus = {g}\n\n\
             [[solids]]\nshape = \"disc\"\ncenter = [0.7, 0.7]\nradius = 0.1\n"
        )
    };
    // A sound speed in mm/s given as m/s, say: the step and the number of steps are named.
    let e = expect_error(&solid("5e9", "1e4"), "solid.sound_speed", "the time step");
    let msg = e.to_string();
    assert!(
        msg.contains("would be 5.200e-12") && msg.contains("1.923e9 steps"),
        "{msg}"
    );
    // A shear modulus that dominates the wave speed names its own field.
    expect_error(
        &solid("30.0", "1e22"),
        "solid.shear_modulus",
        "below 1e-9 of the end time 0.01",
    );
    // Aluminium (c_s = 5100 m/s, G = 26 GPa at rho 2700) runs: about 1e5 steps here.
    Scene::from_toml(&solid("5100.0", "2.6e10").replace("500.0", "2700.0"), "al")
        .expect("a stiff but sane solid");
}

#[test]
fn a_fixed_step_or_a_fluid_sound_speed_that_needs_a_billion_steps_is_refused() {
    // end 0.01: a fixed dt of 1e-12 is 1e10 steps.
    let e = expect_error(
        &with("[time]", "[time]\ndt = 1e-12"),
        "time.dt",
        "below 1e-9 of the end time 0.01",
    );
    assert!(e.to_string().contains("1.000e10 steps"), "{e}");
    // A sound speed in mm/s given as m/s: 3e10 (h = 0.065, courant 0.4: dt 8.7e-13).
    expect_error(
        &BASE.replace("sound_speed = 30.0", "sound_speed = 3e10"),
        "fluid.sound_speed",
        "the time step",
    );
}

/// A wrong type inside a wall (read whole before its shape is known) names the key, not
/// only the wall (issue #51).
#[test]
fn a_wrong_type_inside_a_wall_names_its_key() {
    let text = format!("{BASE}motion = \"fast\"\n");
    expect_error(
        &text,
        "walls[0].motion",
        "a velocity [vx, vy(, vz)] or a table",
    );
    // Inside a motion table, the key of the table.
    let text = format!("{BASE}motion = {{oscillation = {{amplitude = 0.1, period = 1.0}}}}\n");
    expect_error(&text, "walls[0].motion", "invalid type");
}

/// A 3D version of BASE whose walls are `wall` (a TOML table's keys).
fn mesh_scene(wall: &str) -> String {
    format!(
        r#"dimension = 3
name = "mesh"
[domain]
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 1.0]
[discretisation]
spacing = 0.05
[time]
end = 0.01
output_interval = 0.005
[fluid]
density = 1000.0
sound_speed = 30.0
[boundary]
strength = 100.0
[[fluid_blocks]]
min = [0.1, 0.1, 0.1]
max = [0.5, 0.5, 0.5]
[[walls]]
shape = "mesh"
{wall}
"#
    )
}

/// The unit cube's 12 triangles as ASCII STL, scaled by `s` and moved by `t`; without the
/// triangles `drop`.
fn cube_stl(s: f64, t: f64, drop: &[usize]) -> Vec<u8> {
    let v = |i: u32| [(i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64].map(|x| x * s + t);
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut out = String::from("solid cube\n");
    let tris = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]);
    for (k, t) in tris.enumerate().filter(|(k, _)| !drop.contains(k)) {
        out.push_str("facet normal 0 0 0\nouter loop\n");
        for i in t {
            let p = v(i);
            out.push_str(&format!("vertex {} {} {}\n", p[0], p[1], p[2]));
        }
        out.push_str("endloop\nendfacet\n");
        let _ = k;
    }
    out.push_str("endsolid cube\n");
    out.into_bytes()
}

#[test]
fn a_mesh_wall_of_a_good_cube_is_accepted() {
    let (dir, path) = write(&mesh_scene(
        "mesh = { file = \"cube.stl\", scale = 0.2, translate = [0.6, 0.6, 0.6] }",
    ));
    std::fs::write(dir.path().join("cube.stl"), cube_stl(1.0, 0.0, &[])).unwrap();
    let s = Scene::from_file(&path).unwrap();
    assert!(s.setup().is_ok());
}

#[test]
fn mesh_files_that_cannot_be_volumes_are_refused_with_the_reason() {
    let good = cube_stl(0.2, 0.6, &[]);
    // Missing, unreadable, of no triangle, of an unknown format.
    expect_error(
        &mesh_scene("mesh = { file = \"none.stl\" }"),
        "walls[0].mesh.file",
        "cannot read the file",
    );
    expect_error_with(
        &[("bad.stl", b"solid x\nnot an stl")],
        &mesh_scene("mesh = { file = \"bad.stl\" }"),
        "walls[0].mesh.file",
        "not a readable STL file",
    );
    expect_error_with(
        &[("empty.obj", b"v 0 0 0\n")],
        &mesh_scene("mesh = { file = \"empty.obj\" }"),
        "walls[0].mesh.file",
        "holds no triangle",
    );
    expect_error_with(
        &[("cube.step", &good)],
        &mesh_scene("mesh = { file = \"cube.step\" }"),
        "walls[0].mesh.file",
        "not known from its extension",
    );
    // Open: two faces of six gone, a hole across the whole cube.
    let open = cube_stl(0.2, 0.6, &[0, 1, 4, 5]);
    expect_error_with(
        &[("open.stl", &open)],
        &mesh_scene("mesh = { file = \"open.stl\" }"),
        "walls[0].mesh.file",
        "is open: ",
    );
    // Outside the domain, and in millimetres.
    expect_error_with(
        &[("cube.stl", &good)],
        &mesh_scene("mesh = { file = \"cube.stl\", translate = [0.5, 0.0, 0.0] }"),
        "walls[0].mesh",
        "beyond domain.max[0]",
    );
    let mm = cube_stl(200.0, 600.0, &[]);
    expect_error_with(
        &[("mm.stl", &mm)],
        &mesh_scene("mesh = { file = \"mm.stl\" }"),
        "walls[0].mesh",
        "a file in millimetres? scale = 0.001",
    );
    // Keys: a bad scale, a polygon's points in 3D, a mesh in 2D.
    expect_error_with(
        &[("cube.stl", &good)],
        &mesh_scene("mesh = { file = \"cube.stl\", scale = -1.0 }"),
        "walls[0].mesh.scale",
        "must be a positive number",
    );
    expect_error(
        &mesh_scene("mesh = { points = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]] }"),
        "walls[0].mesh.points",
        "points make a 2D polygon",
    );
    expect_error(
        &with(
            "shape = \"box-container\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]",
            "shape = \"mesh\"\nmesh = { file = \"x.stl\" }",
        ),
        "walls[0].shape",
        "use \"polygon\" in a 2D scene",
    );
    expect_error(
        &with(
            "shape = \"box-container\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]",
            "shape = \"polygon\"\npolygon = { points = [[0.0, 0.0], [1.0, 0.0]] }",
        ),
        "walls[0].polygon.points",
        "at least 3 corners",
    );
}
