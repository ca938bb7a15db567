//! The registry of the scheme's keys (`meshfree_core::scene::scheme`, issue #18): every field of the
//! parameter struct is a key's or listed as set from the scene or derived; every key writes
//! the field it declares and reads its declared default; every switch has a paper value and
//! `--paper-exact` sets every one of them; the committed reference is current.

use std::collections::{BTreeMap, BTreeSet};

use meshfree_core::physics::params::SphParams;
use meshfree_core::scene::paper_exact::{ALPHA_MIN, DT_FRACTION};
use meshfree_core::scene::scheme::{
    self, reference, Key, KeyDefault, Paper, Param, DERIVED, FROM_RUN, FROM_SCENE,
};
use meshfree_core::scene::{builtin_names, Overrides, Scene, SceneFile, SceneSource};

/// The fields of the parameter struct with their values, from its `Debug` form
/// (`SphParams { dim: 2, periodic: [0, 0, 0], ... }`).
fn fields(p: &SphParams) -> BTreeMap<String, String> {
    let text = format!("{p:?}");
    let body = text
        .strip_prefix("SphParams {")
        .and_then(|t| t.strip_suffix('}'))
        .expect("SphParams { .. }");
    let mut out = BTreeMap::new();
    let (mut depth, mut start) = (0, 0);
    let bytes = body.as_bytes();
    for (i, &b) in bytes.iter().enumerate() {
        match b {
            b'[' => depth += 1,
            b']' => depth -= 1,
            b',' if depth == 0 => {
                let (name, value) = body[start..i].split_once(':').expect("name: value");
                out.insert(name.trim().to_string(), value.trim().to_string());
                start = i + 1;
            }
            _ => {}
        }
    }
    if let Some((name, value)) = body[start..].split_once(':') {
        out.insert(name.trim().to_string(), value.trim().to_string());
    }
    out
}

/// The example of the reference, which has every table.
fn example() -> Scene {
    let text = reference::STRUCTURE;
    let start = text.find("```toml\n").expect("an example") + "```toml\n".len();
    let end = start + text[start..].find("```").expect("its end");
    Scene::from_toml(&text[start..end], "the reference's example").expect("the example parses")
}

/// A scene of `file` as it is, unvalidated (the test sets values no scene would combine).
fn scene_of(file: SceneFile) -> Scene {
    Scene {
        file,
        source: SceneSource::Text("test".into()),
        text: String::new(),
    }
}

/// Another value of key `k` than `v` (absent: a number).
fn other(k: &Key, v: Option<toml::Value>) -> toml::Value {
    use toml::Value;
    match v {
        None => Value::Float(0.05),
        Some(Value::Float(x)) => Value::Float(if x == 0.0 { 0.05 } else { 0.5 * x }),
        Some(Value::Integer(i)) => Value::Integer(i + 1),
        Some(Value::Boolean(b)) => Value::Boolean(!b),
        Some(Value::String(s)) => {
            let choices = (k.choices)();
            let n = choices
                .iter()
                .find(|(n, _)| *n != s)
                .unwrap_or_else(|| panic!("{}: one choice only", k.path));
            Value::String(n.0.to_string())
        }
        Some(Value::Array(mut a)) => {
            a.push(Value::Float(9.0));
            Value::Array(a)
        }
        Some(v) => panic!("{}: no other value for {v}", k.path),
    }
}

#[test]
fn every_header_field_is_a_keys_or_set_from_the_scene_or_derived() {
    let header: BTreeSet<String> = fields(&SphParams::default()).into_keys().collect();
    let mut claimed: BTreeMap<&str, String> = BTreeMap::new();
    let mut claim = |field: &'static str, by: String| {
        if let Some(old) = claimed.insert(field, by.clone()) {
            panic!("{field} is claimed twice: by {old} and by {by}");
        }
    };
    for k in scheme::keys() {
        if let Param::Field(f) = k.param {
            claim(f, format!("key {}", k.path));
        }
    }
    for (f, from) in FROM_SCENE {
        claim(f, format!("the scene ({from})"));
    }
    for f in DERIVED {
        claim(f, "params::derive".into());
    }
    for f in FROM_RUN {
        claim(f, "the run's decomposition".into());
    }
    let claimed_set: BTreeSet<String> = claimed.keys().map(|f| f.to_string()).collect();
    let uncovered: Vec<&String> = header.difference(&claimed_set).collect();
    assert!(
        uncovered.is_empty(),
        "header fields no key writes and neither scheme::FROM_SCENE nor scheme::DERIVED lists: \
         {uncovered:?}"
    );
    let unknown: Vec<&String> = claimed_set.difference(&header).collect();
    assert!(unknown.is_empty(), "not fields of SphParams: {unknown:?}");

    // DERIVED is what the header marks "derived".
    let h = include_str!("../cuda/sph_params.h");
    let marked: BTreeSet<String> = h
        .lines()
        .filter(|l| l.contains("/* derived"))
        .filter_map(|l| {
            let decl = l.split(';').next()?;
            let name = decl.split_whitespace().last()?;
            Some(name.split('[').next()?.to_string())
        })
        .collect();
    let listed: BTreeSet<String> = DERIVED.iter().map(|s| s.to_string()).collect();
    assert_eq!(
        marked, listed,
        "scheme::DERIVED against the header's \"derived\" fields"
    );
}

#[test]
fn every_key_writes_the_field_it_declares() {
    let base = example();
    let before = fields(&base.params());
    for k in scheme::keys() {
        let Param::Field(field) = k.param else {
            continue;
        };
        let mut s = base.clone();
        let v = other(k, (k.get)(&s.file));
        (k.set)(&mut s.file, v.clone()).unwrap_or_else(|e| panic!("{}: {e}", k.path));
        assert_eq!((k.get)(&s.file), Some(v), "{}: set then get", k.path);
        let after = fields(&s.params());
        assert_ne!(
            before[field], after[field],
            "{}: changing it leaves SphParams::{field} as it was",
            k.path
        );
    }
}

#[test]
fn absent_keys_read_as_their_declared_defaults() {
    // A scene with every table and only the required keys.
    let text = r#"
dimension = 2
name = "minimal"
[domain]
min = [0.0, 0.0]
max = [1.0, 1.0]
[discretisation]
spacing = 0.1
[time]
end = 1.0
output_interval = 0.1
[fluid]
density = 1.0
sound_speed = 10.0
[solid]
density = 1.0
sound_speed = 10.0
shear_modulus = 1.0
[boundary]
strength = 1.0
[[fluid_blocks]]
min = [0.0, 0.0]
max = [0.5, 0.5]
"#;
    let s = Scene::from_toml(text, "minimal").unwrap();
    for k in scheme::keys() {
        let got = (k.get)(&s.file);
        match &k.default {
            KeyDefault::Required => assert!(got.is_some(), "{}", k.path),
            KeyDefault::Absent(_) => assert_eq!(got, None, "{}", k.path),
            KeyDefault::Value { value, why } => {
                assert_eq!(got, Some(value()), "{}", k.path);
                assert!(!why.is_empty(), "{}: a default needs its reason", k.path);
                let n = value().as_float();
                k.check.rule.check(n).unwrap_or_else(|r| {
                    panic!("{}: its default fails its check: {}", k.path, r.reason)
                });
            }
        }
        assert!(!k.doc.is_empty(), "{}: no doc", k.path);
    }
}

#[test]
fn an_absent_courant_number_is_the_integrators_own() {
    // Each integrator at the Courant number it was validated at when the scene gives none
    // (the leapfrog 0.4, the Euler schemes 0.2); a scene's own number always wins.
    let scene = |time: &str| {
        let text = format!(
            "dimension = 2\nname = \"c\"\n[domain]\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n\
             [discretisation]\nspacing = 0.1\n[time]\nend = 1.0\noutput_interval = 0.1\n{time}\n\
             [fluid]\ndensity = 1.0\nsound_speed = 10.0\n\
             [[fluid_blocks]]\nmin = [0.0, 0.0]\nmax = [0.5, 0.5]\n"
        );
        Scene::from_toml(&text, "courant").unwrap().params().courant
    };
    assert_eq!(scene(""), 0.4);
    assert_eq!(scene("integrator = \"leapfrog\""), 0.4);
    assert_eq!(scene("integrator = \"symplectic-euler\""), 0.2);
    assert_eq!(scene("integrator = \"euler\""), 0.2);
    assert_eq!(
        scene("integrator = \"symplectic-euler\"\ncourant = 0.3"),
        0.3
    );
    assert_eq!(scene("courant = 0.25"), 0.25);
}

#[test]
fn a_missing_required_key_is_named_as_serde_names_it() {
    let e = Scene::from_toml(
        "dimension = 2\nname = \"x\"\n[domain]\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n\
         [discretisation]\nspacing = 0.1\n[time]\nend = 1.0\noutput_interval = 0.1\n\
         [fluid]\ndensity = 1.0\n",
        "x.toml",
    )
    .unwrap_err();
    assert_eq!(e.field(), Some("fluid"), "{e}");
    assert!(e.to_string().contains("missing field `sound_speed`"), "{e}");
}

#[test]
fn every_switch_has_a_paper_value_and_every_value_a_reason_to_stay() {
    let mut switches = 0;
    for k in scheme::keys() {
        match &k.paper {
            Paper::Is { value, why } => {
                switches += 1;
                assert!(!why.is_empty(), "{}", k.path);
                k.check.rule.check(value().as_float()).unwrap_or_else(|r| {
                    panic!("{}: its paper value fails its check: {}", k.path, r.reason)
                });
            }
            Paper::From(how) | Paper::Scene(how) => assert!(!how.is_empty(), "{}", k.path),
        }
    }
    assert!(switches >= 20, "{switches} switches");
}

/// Every switch of `s` (in the tables it has) reads its paper value after `--paper-exact`,
/// and the two computed ones are the paper's.
fn assert_paper_exact(s: &Scene, what: &str) {
    let p = s
        .with_paper_exact()
        .unwrap_or_else(|e| panic!("{what}: --paper-exact refused: {e}"));
    for k in scheme::keys() {
        match &k.paper {
            Paper::Is { value, .. } if (k.get)(&s.file).is_some() => {
                assert_eq!((k.get)(&p.file), Some(value()), "{what}: {}", k.path)
            }
            Paper::Scene(_) => {
                assert_eq!((k.get)(&p.file), (k.get)(&s.file), "{what}: {}", k.path)
            }
            _ => {}
        }
    }
    let f = &s.file;
    let h = f.discretisation.h();
    let c = f.solid.as_ref().map_or(f.fluid.sound_speed, |m| {
        m.sound_speed.max(f.fluid.sound_speed)
    });
    assert_eq!(p.file.time.dt, Some(DT_FRACTION * h / c), "{what}: time.dt");
    assert!(p.file.fluid.alpha >= ALPHA_MIN, "{what}: fluid.alpha");
    assert!(p.file.fluid.alpha >= f.fluid.alpha, "{what}: fluid.alpha");
}

#[test]
fn paper_exact_sets_every_switch() {
    for name in builtin_names() {
        let s = Scene::builtin(name).unwrap();
        // The paper's forward Euler has no kick before the drift: a scene that moves a wall
        // by a law (a rolling tank, a wave maker) is refused, and says why.
        if ["sloshing-2d", "flume-2d", "beach-2d"].contains(&name) {
            let e = s.with_paper_exact().expect_err(name).to_string();
            assert!(
                e.contains("motion") && e.contains("kick before the drift"),
                "{e}"
            );
            continue;
        }
        // Nor can fluid enter through an inlet's buffer.
        if ["channel-open-2d", "nozzle-open"].contains(&name) {
            let e = s.with_paper_exact().expect_err(name).to_string();
            assert!(
                e.contains("open boundaries") && e.contains("kick before the drift"),
                "{e}"
            );
            continue;
        }
        // Nor can a body float under it.
        if name == "floating-box-2d" {
            let e = s.with_paper_exact().expect_err(name).to_string();
            assert!(
                e.contains("floating") && e.contains("kicks before it drifts"),
                "{e}"
            );
            continue;
        }
        assert_paper_exact(&s, name);
    }
    // Every switch away from its paper value, in a scene with every table.
    let mut s = example();
    for k in scheme::keys() {
        if let Paper::Is { value, .. } = &k.paper {
            let v = other(k, Some(value()));
            (k.set)(&mut s.file, v).unwrap_or_else(|e| panic!("{}: {e}", k.path));
        }
    }
    assert_paper_exact(&scene_of(s.file), "every switch off the paper's value");
}

#[test]
fn the_nozzle_under_paper_exact_has_no_cohesion() {
    let nozzle = Scene::builtin("nozzle").unwrap();
    assert!(nozzle.file.fluid.cohesion > 0.0);
    let p = nozzle.with_paper_exact().unwrap();
    assert_eq!(p.file.fluid.cohesion, 0.0);
    assert_eq!(p.params().cohesion, 0.0);
}

#[test]
fn a_solid_density_diffusion_is_mapped_under_paper_exact_not_refused() {
    let mut s = example();
    s.file.solid.as_mut().unwrap().density_diffusion = 0.02;
    s.revalidate().unwrap();
    let p = s.with_paper_exact().unwrap();
    assert_eq!(p.file.solid.unwrap().density_diffusion, 0.0);
}

#[test]
fn the_committed_reference_is_current() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(reference::PATH);
    let fresh = reference::markdown();
    if std::env::var("MESHFREE_WRITE_REFERENCE").as_deref() == Ok("1") {
        std::fs::write(&path, &fresh).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == fresh,
        "{} is stale: run `meshfree scenes --reference > {}` (or this test with \
         MESHFREE_WRITE_REFERENCE=1)",
        reference::PATH,
        reference::PATH
    );
}

/// The README's "What it cannot do yet" is the reference's list, word for word.
#[test]
fn the_readme_lists_what_a_scene_cannot_express_yet() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md");
    let readme = std::fs::read_to_string(path).unwrap();
    assert!(
        readme.contains("## What it cannot do yet") && readme.contains(reference::CANNOT_YET),
        "README.md's \"What it cannot do yet\" differs from core/src/scene/scheme/reference.rs's \
         CANNOT_YET: copy it there"
    );
}

#[test]
fn total_lagrangian_refuses_the_artificial_stress() {
    let mut s = example();
    let solid = s.file.solid.as_mut().unwrap();
    solid.formulation = meshfree_core::scene::scheme::SolidFormulation::TotalLagrangian;
    solid.artificial_stress = 0.3;
    let e = format!("{:#}", s.revalidate().unwrap_err());
    assert!(e.contains("solid.formulation"), "{e}");
    s.file.solid.as_mut().unwrap().artificial_stress = 0.0;
    s.revalidate().unwrap();
}

/// A run's copy of its scene says what ran: the command line's --t-end and
/// --output-interval are written into the text, comments kept (issue #51).
#[test]
fn overrides_are_written_into_the_scenes_text() {
    let s = Scene::builtin("tank-2d").unwrap();
    let o = s
        .with_overrides(&Overrides {
            t_end: Some(0.5),
            output_interval: Some(0.01),
        })
        .unwrap();
    let back = Scene::from_toml(&o.text, "the copy").unwrap();
    assert_eq!(back.file, o.file);
    assert_eq!(
        (back.file.time.end, back.file.time.output_interval),
        (0.5, 0.01)
    );
    assert!(o.text.contains("# several acoustic periods"), "{}", o.text);
    // Nothing overridden, or overridden to the same value: the scene's own text.
    assert_eq!(
        s.with_overrides(&Overrides::default()).unwrap().text,
        s.text
    );
    let same = Overrides {
        t_end: Some(s.file.time.end),
        output_interval: None,
    };
    assert_eq!(s.with_overrides(&same).unwrap().text, s.text);
}
