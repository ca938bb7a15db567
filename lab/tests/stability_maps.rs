//! `meshfree stability --quick` through the library: every map is written with its cells
//! classified, the known failures show up where they must (forward Euler at Courant 1.2
//! blows up with a time; the leapfrog and the symplectic Euler run the dam break at Courant
//! 0.4; the stretched strip without artificial stress is not stable, with it at Courant 0.4
//! under the leapfrog it is), and the report files read back.

use meshfree_core::backend::BackendChoice;
use meshfree_lab::stability::{self, Class, Options, Report, Tier};

#[test]
fn quick_stability_maps_classify_the_known_cases() {
    let dir = tempfile::tempdir().unwrap();
    let report = stability::run(&Options {
        tier: Tier::Quick,
        backend: BackendChoice::Cpu,
        out_dir: dir.path().to_path_buf(),
        maps: Vec::new(),
        verbose: false,
    })
    .expect("stability sweep runs");
    let cell = |map: &str, x: f64, y: f64| {
        let m = report
            .maps
            .iter()
            .find(|m| m.def.name == map)
            .unwrap_or_else(|| panic!("no map {map}"));
        m.cells
            .iter()
            .find(|c| c.x == x && c.y == y)
            .unwrap_or_else(|| panic!("no cell ({x}, {y}) in {map}"))
            .clone()
    };
    // Forward Euler past its CFL limit fails, with the time of the blow-up and the fault.
    let c = cell("dam-break-euler-continuity", 1.2, 0.05);
    assert_eq!(c.class, Class::Failed, "{c:?}");
    assert!(c.blow_up_time.is_some_and(|t| t > 0.0), "{c:?}");
    assert!(
        c.fault.as_ref().is_some_and(|f| f.contains("blow-up")),
        "{c:?}"
    );
    // The default scheme at the default Courant number runs and measures a front error.
    for map in [
        "dam-break-leapfrog-continuity",
        "dam-break-symplectic-continuity",
    ] {
        let c = cell(map, 0.4, 0.05);
        assert_ne!(c.class, Class::Failed, "{c:?}");
        assert!(c.error.is_some_and(|e| e > 0.0), "{c:?}");
    }
    // Tensile instability: without artificial stress the strip clumps, with it it holds.
    let without = cell("elastic-strip-leapfrog", 0.4, 0.0);
    let with = cell("elastic-strip-leapfrog", 0.4, 0.3);
    assert_ne!(without.class, Class::Stable, "{without:?}");
    assert_eq!(with.class, Class::Stable, "{with:?}");
    for m in &report.maps {
        assert_eq!(
            m.cells.len(),
            m.def.x.values.len() * m.def.y.values.len(),
            "{}",
            m.def.name
        );
        let png = dir.path().join(&m.plot);
        assert!(
            std::fs::metadata(&png).is_ok_and(|f| f.len() > 5_000),
            "{} missing or empty",
            png.display()
        );
    }
    let back: Report =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("report.json")).unwrap())
            .unwrap();
    assert_eq!(back.maps.len(), report.maps.len());
    let md = std::fs::read_to_string(dir.path().join("report.md")).unwrap();
    assert!(md.contains("FAILED t="), "{md}");
    let csv = std::fs::read_to_string(dir.path().join("cells.csv")).unwrap();
    let cells: usize = report.maps.iter().map(|m| m.cells.len()).sum();
    assert_eq!(csv.lines().count(), cells + 1);
}
