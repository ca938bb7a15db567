//! A run with open boundaries through the binary (`channel-open-2d`): `summary.json`'s
//! `open_boundaries` and `open_boundaries.csv` count the particles in and out, and a run
//! resumed from its checkpoint half way ends with the same files as the run in one go.

use std::path::Path;
use std::process::Command;

fn meshfree() -> Command {
    Command::new(env!("CARGO_BIN_EXE_meshfree"))
}

fn run(args: &[&str]) {
    let out = meshfree().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "meshfree {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn read(dir: &Path, name: &str) -> String {
    std::fs::read_to_string(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn a_channel_counts_its_particles_and_resumes_alike() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let common = [
        "--backend",
        "cpu",
        "--format",
        "csv",
        "--output-interval",
        "0.05",
        "--quiet",
    ];
    let (sa, sb) = (a.to_str().unwrap(), b.to_str().unwrap());
    let mut one_go = vec!["run", "channel-open-2d", "--t-end", "0.1", "--out", sa];
    one_go.extend(common);
    run(&one_go);
    let mut half = vec!["run", "channel-open-2d", "--t-end", "0.05", "--out", sb];
    half.extend(common);
    run(&half);
    run(&["run", "--resume", sb, "--t-end", "0.1", "--quiet"]);

    let summary: serde_json::Value = serde_json::from_str(&read(&a, "summary.json")).unwrap();
    let open = summary["open_boundaries"]
        .as_array()
        .expect("open_boundaries");
    assert_eq!(open.len(), 2);
    // U t / dx = 0.5 x 0.1 / 0.005 = 10 rows of 20 particles came in.
    let came_in = open[0]["count_in"].as_u64().unwrap();
    assert!((190..=210).contains(&came_in), "{came_in} in");
    assert!(open[1]["count_out"].as_u64().unwrap() > 0, "{open:?}");
    // A row per boundary at t = 0, 0.05 and 0.1, after the header.
    let csv = read(&a, "open_boundaries.csv");
    assert!(csv.starts_with("time,boundary,count_in,mass_in,count_out,mass_out\n"));
    assert_eq!(csv.lines().count(), 1 + 3 * 2, "{csv}");
    let last = csv.lines().nth(5).unwrap();
    assert!(
        last.starts_with("0.1") && last.contains(&format!(",0,{came_in},")),
        "{last}"
    );

    let resumed: serde_json::Value = serde_json::from_str(&read(&b, "summary.json")).unwrap();
    assert_eq!(resumed["open_boundaries"], summary["open_boundaries"]);
    for name in ["open_boundaries.csv", "particles_00002.csv"] {
        assert_eq!(
            read(&a, name),
            read(&b, name),
            "{name} differs after the resume"
        );
    }
}
