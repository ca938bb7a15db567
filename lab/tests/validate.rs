//! `meshfree validate --quick` through the library: every quick-tier check passes, the
//! report files and plots are written and the JSON report reads back.

use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::scheme::IntegratorChoice;
use meshfree_lab::validate::{self, Options, Report, Tier};

#[test]
fn quick_validation_passes_and_writes_reports() {
    let dir = tempfile::tempdir().unwrap();
    let report = validate::run(&Options {
        tier: Tier::Quick,
        backend: BackendChoice::Cpu,
        out_dir: dir.path().to_path_buf(),
        cases: Vec::new(),
        verbose: false,
        courant: None,
        integrator: None,
        sets: Vec::new(),
    })
    .expect("validation runs");
    for c in &report.checks {
        println!(
            "{} {}: measured {:.4}, error {:.4}, tolerance {} ({}), {}",
            c.case,
            c.quantity,
            c.measured,
            c.error,
            c.tolerance,
            c.basis,
            if c.pass { "pass" } else { "FAIL" }
        );
    }
    let failed: Vec<String> = report
        .checks
        .iter()
        .filter(|c| !c.pass)
        .map(|c| {
            format!(
                "{} / {}: error {} > tolerance {} ({})",
                c.case, c.quantity, c.error, c.tolerance, c.note
            )
        })
        .collect();
    assert!(
        failed.is_empty(),
        "quick-tier checks failed:\n{}",
        failed.join("\n")
    );
    for case in validate::CASES.iter().filter(|c| c.quick) {
        assert!(
            report.checks.iter().any(|c| c.case == case.name),
            "no row for {}",
            case.name
        );
    }
    for case in validate::CASES.iter().filter(|c| !c.quick) {
        assert!(
            !report.checks.iter().any(|c| c.case == case.name),
            "{} is full tier only but ran in the quick tier",
            case.name
        );
    }
    let json = std::fs::read_to_string(dir.path().join("report.json")).unwrap();
    let back: Report = serde_json::from_str(&json).expect("report.json reads back");
    assert_eq!(back.checks.len(), report.checks.len());
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(md.contains("| quantity |"));
    for png in [
        "hydrostatic-tank.png",
        "dam-break-front.png",
        "dam-break-height.png",
        "poiseuille.png",
        "taylor-green.png",
        "plate-tip.png",
        "cantilever-tip-jaumann.png",
        "cantilever-tip-total-lagrangian.png",
        "gate-x.png",
        "gate-y.png",
    ] {
        let bytes = std::fs::read(dir.path().join(png)).unwrap_or_else(|e| panic!("{png}: {e}"));
        assert!(bytes.starts_with(b"\x89PNG"), "{png} is not a PNG");
    }
}

#[test]
fn unknown_case_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let err = validate::run(&Options {
        tier: Tier::Quick,
        backend: BackendChoice::Cpu,
        out_dir: dir.path().to_path_buf(),
        cases: vec!["no-such-case".into()],
        verbose: false,
        courant: None,
        integrator: None,
        sets: Vec::new(),
    })
    .unwrap_err();
    assert!(err.to_string().contains("taylor-green"), "{err}");
}

/// `--courant` and `--integrator`: every case at another Courant number and with another
/// integrator, both said in the report; a number that is no Courant number is refused.
#[test]
fn a_courant_and_integrator_override_runs_and_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let options = |c: f64| Options {
        tier: Tier::Quick,
        backend: BackendChoice::Cpu,
        out_dir: dir.path().to_path_buf(),
        cases: vec!["taylor-green".into()],
        verbose: false,
        courant: Some(c),
        integrator: Some(IntegratorChoice::Leapfrog),
        sets: Vec::new(),
    };
    let r = validate::run(&options(0.3)).unwrap();
    assert_eq!(r.courant, Some(0.3));
    assert_eq!(r.integrator, Some(IntegratorChoice::Leapfrog));
    assert!(!r.checks.is_empty());
    let md = validate::markdown(&r);
    assert!(md.contains("Courant number 0.3"));
    assert!(md.contains("with the leapfrog integrator"));
    for bad in [0.0, -1.0, f64::NAN] {
        let e = validate::run(&options(bad)).unwrap_err().to_string();
        assert!(e.contains("--courant"), "{e}");
    }
}

#[test]
fn a_scheme_key_set_for_every_case_changes_the_runs_and_is_reported() {
    let dir = tempfile::tempdir().unwrap();
    let options = |sets: &[&str]| Options {
        tier: Tier::Quick,
        backend: BackendChoice::Cpu,
        out_dir: dir.path().to_path_buf(),
        cases: vec!["taylor-green".into()],
        verbose: false,
        courant: None,
        integrator: None,
        sets: sets.iter().map(|s| s.parse().unwrap()).collect(),
    };
    let own = validate::run(&options(&[])).unwrap();
    // Artificial viscosity where the case has none (alpha = 0); the [solid] key concerns no scene of the
    // case (no bodies) and changes nothing.
    let set = validate::run(&options(&[
        "fluid.alpha=0.5",
        "solid.fluid_pressure=extrapolated",
    ]))
    .unwrap();
    assert_eq!(
        set.sets,
        [
            "fluid.alpha = 0.5",
            "solid.fluid_pressure = \"extrapolated\""
        ]
    );
    assert!(validate::markdown(&set).contains("`fluid.alpha = 0.5`"));
    assert!(own.sets.is_empty());
    let errors = |r: &validate::Report| r.checks.iter().map(|c| c.error).collect::<Vec<_>>();
    assert_eq!(errors(&own).len(), errors(&set).len());
    assert_ne!(
        errors(&own),
        errors(&set),
        "the set reached the case's scene"
    );
}

#[test]
fn quick_chart_writes_error_vs_time_with_a_pareto_front() {
    use meshfree_lab::chart;
    let dir = tempfile::tempdir().unwrap();
    let points = chart::run(&chart::Options {
        tier: Tier::Quick,
        backends: vec![BackendChoice::Cpu],
        out_dir: dir.path().to_path_buf(),
        verbose: false,
    })
    .expect("chart runs");
    for case in ["dam-break", "taylor-green"] {
        let ps: Vec<_> = points.iter().filter(|p| p.case == case).collect();
        assert_eq!(ps.len(), 3, "{case}: {ps:?}");
        assert!(
            ps.iter()
                .all(|p| p.error.is_some_and(|e| e.is_finite()) && p.wall_seconds > 0.0),
            "{ps:?}"
        );
        // The fastest run is always on the front, and so is the most accurate.
        let fastest = ps
            .iter()
            .min_by(|a, b| a.wall_seconds.total_cmp(&b.wall_seconds))
            .unwrap();
        let best = ps
            .iter()
            .min_by(|a, b| a.error.unwrap().total_cmp(&b.error.unwrap()))
            .unwrap();
        assert!(fastest.pareto && best.pareto, "{ps:?}");
        let png = dir.path().join(format!("chart-{case}.png"));
        assert!(std::fs::metadata(&png).is_ok_and(|m| m.len() > 5_000));
    }
    let csv = std::fs::read_to_string(dir.path().join("chart.csv")).unwrap();
    assert_eq!(csv.lines().count(), points.len() + 1);
}
