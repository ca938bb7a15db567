//! An object whose name becomes a file in the run directory (a force monitor's
//! `<name>.csv`) may not take a name the run writes itself, nor one that is not a plain
//! file name (issue #52: a monitor named `diagnostics` interleaved its rows with the
//! diagnostics').

use meshfree_core::run_files;
use meshfree_core::scene::{Scene, SceneError};

#[test]
fn a_monitor_may_not_be_named_like_a_run_file() {
    let base = Scene::builtin("tank-2d").unwrap().text;
    let with_monitor = |name: &str| {
        let quoted = toml::Value::String(name.to_string()).to_string();
        format!(
            "{base}\n[[monitors]]\nname = {quoted}\nwall = 0\ninterval = 0.01\n\
             reference_velocity = 1.0\nreference_length = 1.0\n"
        )
    };
    assert!(Scene::from_toml(&with_monitor("drag"), "ok.toml").is_ok());
    let mut names: Vec<String> = run_files::FILES
        .iter()
        .map(|f| f.split('.').next().unwrap().to_string())
        .collect();
    names.extend(
        [
            "particles_00000",
            "Diagnostics",
            "PROBES",
            "checkpoint-step10-rank0of2",
            "",
            "..",
            ".hidden",
            "a/b",
            "a\\b",
            "tab\there",
            "nul\0",
        ]
        .map(String::from),
    );
    names.push("x".repeat(run_files::MAX_STEM + 1));
    for name in &names {
        match Scene::from_toml(&with_monitor(name), "m.toml") {
            Err(SceneError::Invalid { field, reason, .. }) => {
                assert_eq!(field, "monitors[0].name", "{name:?}: {reason}");
                assert!(reason.contains(&format!("{name:?}")), "{reason}");
            }
            other => panic!("{name:?} accepted or refused elsewhere: {other:?}"),
        }
    }
    // Two monitors whose files are one on a case-insensitive file system.
    let two = format!(
        "{}[[monitors]]\nname = \"DRAG\"\nwall = 0\ninterval = 0.01\nreference_velocity = 1.0\n\
         reference_length = 1.0\n",
        with_monitor("drag")
    );
    let e = Scene::from_toml(&two, "two.toml").unwrap_err();
    assert_eq!(e.field(), Some("monitors[1].name"), "{e}");
}
