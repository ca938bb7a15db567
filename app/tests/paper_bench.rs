//! `meshfree bench paper`: the merge of a CPU and a GPU result gives the right speed-ups
//! (also with a short CPU run, extrapolated per step), the command line parses, and a tiny
//! run writes a valid paper-bench.json.

use clap::Parser;
use meshfree::cli::{BenchMode, Cli, Command};
use meshfree::paper_bench::{
    markdown, merge, read, run_scenes, text_table, PaperBench, PaperBenchOptions, PaperBenchRow,
    Span, PAPER_TABLE1,
};
use meshfree::run::Progress;
use meshfree_core::scene::Counts;

fn row(
    scene: &str,
    backend: &str,
    steps: u64,
    t: f64,
    end: f64,
    wall: f64,
    ms: f64,
) -> PaperBenchRow {
    let short = t < end;
    PaperBenchRow {
        scene: scene.into(),
        dimension: 2,
        particles: Counts {
            fluid: 90,
            solid: 0,
            boundary: 10,
            total: 100,
        },
        backend: backend.into(),
        device: format!("{backend} device"),
        steps,
        simulated_time: t,
        scene_end_time: end,
        wall_s: wall,
        ms_per_step: ms,
        full_run_s: if short {
            wall - 1e-3 * ms * steps as f64 + 1e-3 * ms * steps as f64 * end / t
        } else {
            wall
        },
        extrapolated: short,
        completed: true,
        fault: None,
    }
}

fn bench(backend: &str, rows: Vec<PaperBenchRow>) -> PaperBench {
    PaperBench {
        backend: backend.into(),
        device: format!("{backend} device"),
        paper_exact: false,
        span: "full".into(),
        meshfree_version: "0".into(),
        rows,
        skipped: vec![("nozzle".into(), "not built in".into())],
    }
}

#[test]
fn merging_a_cpu_and_a_gpu_run_gives_the_speed_ups() {
    let dir = tempfile::tempdir().unwrap();
    // impinging-2d: both whole runs. GPU 20 s, CPU 200 s; paper GPU 180 s.
    // impinging-3d: the CPU ran a tenth (1,000 of the GPU's 10,000 steps at 50 ms/step, 2 s
    // set-up): whole-run estimate 2 + 0.05 * 10,000 = 502 s; GPU 100 s; paper GPU 1,731 s.
    let gpu = bench(
        "cuda",
        vec![
            row("impinging-2d", "cuda", 5_000, 12.0, 12.0, 20.0, 3.0),
            row("impinging-3d", "cuda", 10_000, 12.0, 12.0, 100.0, 9.0),
        ],
    );
    let cpu = bench(
        "cpu",
        vec![
            row("impinging-2d", "cpu", 5_000, 12.0, 12.0, 200.0, 39.0),
            row("impinging-3d", "cpu", 1_000, 1.2, 12.0, 52.0, 50.0),
        ],
    );
    // Through files, as the command reads them.
    let (pc, pg) = (dir.path().join("cpu.json"), dir.path().join("gpu.json"));
    std::fs::write(&pc, serde_json::to_string(&cpu).unwrap()).unwrap();
    std::fs::write(&pg, serde_json::to_string(&gpu).unwrap()).unwrap();
    let (cpu, gpu) = (read(&pc).unwrap(), read(&pg).unwrap());
    let rows = merge(Some(&cpu), Some(&gpu));
    assert_eq!(rows.len(), PAPER_TABLE1.len());
    let get = |n: &str| rows.iter().find(|r| r.paper.scene == n).unwrap();

    let r2 = get("impinging-2d");
    assert!((r2.speedup_over_paper_gpu.unwrap() - 180.0 / 20.0).abs() < 1e-9);
    assert!((r2.speedup_over_our_cpu.unwrap() - 200.0 / 20.0).abs() < 1e-9);
    assert_eq!(r2.steps, Some(5_000));

    let r3 = get("impinging-3d");
    assert!((r3.cpu.as_ref().unwrap().full_run_s - 502.0).abs() < 1e-9);
    assert!((r3.speedup_over_our_cpu.unwrap() - 502.0 / 100.0).abs() < 1e-9);
    assert!((r3.speedup_over_paper_gpu.unwrap() - 1731.0 / 100.0).abs() < 1e-9);

    // A run that failed short of its end is extrapolated and says where it failed.
    let mut failed = cpu.clone();
    failed.rows[1].completed = false;
    let text = text_table(&merge(Some(&failed), Some(&gpu)));
    assert!(text.contains("502.0* (failed at t = 1.20)"), "{text}");

    // Scenes without a run have no speed-up.
    let rn = get("nozzle");
    assert!(rn.gpu.is_none() && rn.speedup_over_paper_gpu.is_none());

    // The tables mark the extrapolated time and say so.
    let text = text_table(&rows);
    assert!(
        text.contains("502.0*") && text.contains("extrapolated"),
        "{text}"
    );
    let md = markdown(&rows, Some(&cpu), Some(&gpu));
    assert!(
        md.contains("| 180 | 840 | 20.0 | 200.0 | 9.0 | 10.0 |"),
        "{md}"
    );
    assert!(md.contains("502.0*") && md.contains("cuda device") && md.contains("not run: nozzle"));
}

#[test]
fn the_command_line_parses() {
    let cli = Cli::try_parse_from([
        "meshfree",
        "bench",
        "paper",
        "--backend",
        "cpu",
        "--t-end-fraction",
        "0.1",
        "--scenes",
        "impinging-2d,impinging-3d",
        "--paper-exact",
        "--out",
        "x",
    ])
    .unwrap();
    let Command::Bench(b) = cli.command else {
        panic!()
    };
    let Some(BenchMode::Paper(p)) = b.mode else {
        panic!()
    };
    assert_eq!(p.t_end_fraction, Some(0.1));
    assert_eq!(p.scenes, ["impinging-2d", "impinging-3d"]);
    assert!(p.paper_exact);

    let cli = Cli::try_parse_from([
        "meshfree",
        "bench",
        "paper",
        "--table",
        "a.json",
        "b.json",
        "--markdown",
        "t.md",
    ])
    .unwrap();
    let Command::Bench(b) = cli.command else {
        panic!()
    };
    let Some(BenchMode::Paper(p)) = b.mode else {
        panic!()
    };
    assert_eq!(p.table.len(), 2);
    assert!(Cli::try_parse_from(["meshfree", "bench", "paper", "--table", "cpu.json"]).is_ok());
    // The plain `bench` keeps its flags; a fraction and an end time exclude each other; the
    // table takes one or two files.
    assert!(Cli::try_parse_from(["meshfree", "bench", "--dims", "2"]).is_ok());
    for bad in [
        &[
            "meshfree",
            "bench",
            "paper",
            "--t-end-fraction",
            "0.1",
            "--t-end",
            "1",
        ][..],
        &[
            "meshfree", "bench", "paper", "--table", "a.json", "b.json", "c.json",
        ][..],
        &["meshfree", "bench", "paper", "--markdown", "t.md"][..],
    ] {
        assert!(Cli::try_parse_from(bad).is_err(), "{bad:?}");
    }
    for cmd in [
        &["meshfree", "run", "tank-2d", "--paper-exact"][..],
        &["meshfree", "view", "tank-2d", "--paper-exact"][..],
        &[
            "meshfree",
            "render",
            "tank-2d",
            "--paper-exact",
            "--figures",
            "--out",
            "d",
        ][..],
    ] {
        assert!(Cli::try_parse_from(cmd).is_ok(), "{cmd:?}");
    }
}

#[test]
fn a_tiny_run_writes_valid_json() {
    let dir = tempfile::tempdir().unwrap();
    let o = PaperBenchOptions {
        backend: meshfree_core::backend::BackendChoice::Cpu,
        span: Span::Time(0.02),
        scenes: vec!["impinging-2d".into()],
        paper_exact: false,
        progress: Progress::Quiet,
    };
    let b = run_scenes(&o, dir.path()).unwrap();
    let back = read(&dir.path().join("paper-bench.json")).unwrap();
    // (serde_json reads floats back to within the last bit.)
    assert_eq!((back.rows.len(), &back.skipped), (1, &b.skipped));
    assert_eq!(back.rows[0].steps, b.rows[0].steps);
    assert!((back.rows[0].wall_s - b.rows[0].wall_s).abs() < 1e-9);
    assert!(b.skipped.is_empty(), "{:?}", b.skipped);
    // All five of the paper's scenes are built in now (none would be skipped).
    for name in [
        "nozzle",
        "vortex-street-re140",
        "vortex-street-re105",
        "impinging-2d",
        "impinging-3d",
    ] {
        assert!(
            meshfree_core::scene::builtin_names().contains(&name),
            "{name}"
        );
    }
    let r = &b.rows[0];
    assert_eq!(
        (r.scene.as_str(), r.backend.as_str()),
        ("impinging-2d", "cpu")
    );
    assert!(r.completed && r.steps > 0 && r.ms_per_step > 0.0, "{r:?}");
    assert!((r.simulated_time - 0.02).abs() < 0.01 && r.scene_end_time == 12.0);
    assert!(r.extrapolated && r.full_run_s > r.wall_s);
    assert_eq!(r.particles.total, 5_504);
    // An unknown scene is an error, not a skip.
    let bad = PaperBenchOptions {
        scenes: vec!["tank-2d".into()],
        ..o
    };
    assert!(run_scenes(&bad, dir.path()).is_err());
}
