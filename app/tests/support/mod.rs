//! What several of the app's test files share (`mod support;`).

use std::path::{Path, PathBuf};

/// The impinging flow at twice the spacing (a gate opened at t = 0, two elastic bodies),
/// ending at `end` with a frame every `interval`, with a force monitor (wall forces across
/// the cuts of a decomposed run) and a checkpoint every 0.3: written into `dir`, its path.
pub fn coarse_impinging(dir: &Path, end: &str, interval: &str) -> PathBuf {
    let text = meshfree_core::scene::Scene::builtin("impinging-2d")
        .unwrap()
        .text;
    let (end, interval) = (
        format!("end = {end}"),
        format!("output_interval = {interval} "),
    );
    let text = text
        .replace("spacing = 0.375", "spacing = 0.75")
        .replace("layers = 3", "layers = 2")
        .replace("end = 12.0", &end)
        .replace("output_interval = 0.1 ", &interval);
    assert!(text.contains(&end) && text.contains(&interval));
    let text = text
        + r#"
[output]
checkpoint_interval = 0.3

[[monitors]]
wall = 0
interval = 0.1
reference_velocity = 1.0
reference_length = 1.0
"#;
    let path = dir.join("impinging-coarse.toml");
    std::fs::write(&path, text).unwrap();
    path
}
