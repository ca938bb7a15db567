//! `meshfree chart`: speed against accuracy. For each case a sweep of variants (resolution,
//! kernel, density form, viscosity, integrator, density diffusion; on each backend asked
//! for), each run's error against the reference and its wall time, drawn log-log with the
//! Pareto front (no other point is both faster and more accurate) marked; one PNG per case,
//! `chart.csv` and `chart.json`.
//!
//! Cases: the square-column dam break (max relative surge-front error vs Martin & Moyce
//! 1952 for 0.8 <= T <= 2.5, measured by `stability::cases::measure`), the Taylor-Green
//! vortex (|decay rate of E_k / exact - 1|, `taylor_green::decay_rate_error`) and, in the
//! full tier only, the cylinder at Re 100 (|St / St_Williamson - 1| over t U / D = 40-80 of
//! a kicked start, `cylinder::strouhal_error`; D / dx = 5, 8, 10, the variants at 5).
//! Every point carries its backend and device (labels, CSV, JSON); one front per case over
//! all backends asked for. A variant that does not apply to a case's scheme, or changes
//! nothing in it, is not run: its row says why (`variants.rs`).

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Context;
use serde::{Deserialize, Serialize};

mod variants;

use crate::plot::{plot, Figure, Series};
use crate::stability::cases;
use crate::stability::sweep::Base;
use crate::validate::{cylinder, taylor_green, Ctx, RunInfo, Tier};
use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::Scene;
use meshfree_core::solver::BackendInfo;
pub use variants::SAME_AS_DEFAULT;
use variants::{case_variants, skip_reason, Variant};

/// The cylinder's run length in D / U: the kicked wake sheds from t U / D ~ 30; the
/// Strouhal number comes from the second half.
const CYLINDER_T_END_UD: f64 = 80.0;

/// What `run` does.
#[derive(Clone, Debug)]
pub struct Options {
    /// Quick: two coarse resolutions and two variants per case (the tests).
    pub tier: Tier,
    pub backends: Vec<BackendChoice>,
    pub out_dir: PathBuf,
    pub verbose: bool,
}

/// One run.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Point {
    pub case: String,
    pub variant: String,
    /// "dx = 0.05" or "30 x 30".
    pub resolution: String,
    pub backend: String,
    pub device: String,
    pub particles: usize,
    pub wall_seconds: f64,
    /// None: the run blew up (`failure` says how), or was not made (`skipped`).
    pub error: Option<f64>,
    pub failure: Option<String>,
    pub pareto: bool,
    /// Some: the variant was not run on this case, and why (it does not apply to the case's
    /// scheme, or changes nothing in it); once per case, whatever the backends, with no
    /// backend, device, particles or wall time.
    #[serde(default)]
    pub skipped: Option<String>,
}

/// Mark the Pareto front among the successful points of one case and backend set: a point
/// is on it when no other is at least as fast and strictly more accurate, or faster and
/// as accurate.
fn mark_pareto(points: &mut [Point]) {
    let ok: Vec<(usize, f64, f64)> = points
        .iter()
        .enumerate()
        .filter_map(|(i, p)| p.error.map(|e| (i, p.wall_seconds, e)))
        .collect();
    for &(i, t, e) in &ok {
        points[i].pareto = !ok
            .iter()
            .any(|&(j, t2, e2)| j != i && t2 <= t && e2 <= e && (t2 < t || e2 < e));
    }
}

/// The resolutions a case runs the default scheme at, and the one its variants run at.
fn resolutions(case: &str, quick: bool) -> (Vec<f64>, f64) {
    match (case, quick) {
        ("dam-break", true) => (vec![0.1, 0.05], 0.1),
        ("dam-break", false) => (vec![0.1, 0.05, 0.04, 0.025], 0.05),
        ("cylinder", _) => (vec![5.0, 8.0, 10.0], 5.0),
        (_, true) => (vec![16.0, 24.0], 16.0),
        (_, false) => (vec![20.0, 30.0, 40.0, 60.0], 30.0),
    }
}

/// The scene a case's run at resolution `r` starts from, before a variant's edit.
fn case_scene(case: &str, r: f64) -> anyhow::Result<Scene> {
    match case {
        "dam-break" => Ok(cases::base_scene(Base::DamBreak, r)),
        "cylinder" => cylinder::scene(r, cylinder::RE, CYLINDER_T_END_UD),
        _ => taylor_green::scene(r as usize),
    }
}

/// The resolution as a row names it where no run reports its own.
fn resolution_label(case: &str, r: f64) -> String {
    match case {
        "dam-break" => format!("dx = {r}"),
        "cylinder" => format!("D / dx = {r}"),
        _ => format!("{n} x {n}", n = r as usize),
    }
}

/// The rows of the variants of `case` not run there (`variants::skip_reason`), and the
/// variants that run.
fn plan(case: &str, quick: bool) -> anyhow::Result<(Vec<Variant>, Vec<Point>)> {
    let middle = resolutions(case, quick).1;
    let default = case_scene(case, middle)?;
    let (mut run, mut skipped) = (Vec::new(), Vec::new());
    for v in case_variants(case, quick) {
        match skip_reason(&default, &v) {
            None => run.push(v),
            Some(reason) => skipped.push(Point {
                case: case.into(),
                variant: v.name.into(),
                resolution: resolution_label(case, middle),
                backend: String::new(),
                device: String::new(),
                particles: 0,
                wall_seconds: f64::NAN,
                error: None,
                failure: None,
                pareto: false,
                skipped: Some(reason),
            }),
        }
    }
    Ok((run, skipped))
}

/// Run `case` at resolution `r` with `v` on `ctx.backend`: its error, or how it failed,
/// and the run. An Err: the run did not start or stopped short (a blow-up, no shedding).
fn measure(
    ctx: &Ctx,
    case: &str,
    r: f64,
    v: &Variant,
) -> anyhow::Result<(Result<f64, String>, RunInfo)> {
    match case {
        "dam-break" => {
            let mut scene = case_scene(case, r)?;
            (v.edit)(&mut scene);
            scene.revalidate()?;
            let m = cases::measure(Base::DamBreak, &scene, ctx.backend, 2.5)?;
            let run = RunInfo {
                resolution: resolution_label(case, r),
                particles: m.particles,
                wall_seconds: m.wall_seconds,
                info: m.info,
            };
            Ok((m.result.map_err(|f| f.to_string()), run))
        }
        "cylinder" => {
            let (e, run) = cylinder::strouhal_error(ctx, r, CYLINDER_T_END_UD, &|s| (v.edit)(s))?;
            Ok((Ok(e), run))
        }
        _ => {
            let (e, run) = taylor_green::decay_rate_error(ctx, r as usize, &|s| (v.edit)(s))?;
            Ok((Ok(e), run))
        }
    }
}

/// The point of one run (`measure`); a run that errors is a point with its failure, never
/// an error of the chart.
fn point(ctx: &Ctx, case: &str, r: f64, v: &Variant) -> Point {
    let (error, failure, run) = match measure(ctx, case, r, v) {
        Ok((result, run)) => (result.as_ref().ok().copied(), result.err(), run),
        Err(e) => {
            let info = BackendInfo {
                backend: format!("{:?}", ctx.backend).to_lowercase(),
                device: String::new(),
            };
            let run = RunInfo {
                resolution: resolution_label(case, r),
                particles: 0,
                wall_seconds: f64::NAN,
                info,
            };
            (None, Some(format!("{e:#}")), run)
        }
    };
    Point {
        case: case.into(),
        variant: v.name.into(),
        resolution: run.resolution,
        backend: run.info.backend,
        device: run.info.device,
        particles: run.particles,
        wall_seconds: run.wall_seconds,
        error,
        failure,
        pareto: false,
        skipped: None,
    }
}

pub fn run(options: &Options) -> anyhow::Result<Vec<Point>> {
    let quick = options.tier == Tier::Quick;
    std::fs::create_dir_all(&options.out_dir)
        .with_context(|| format!("creating {}", options.out_dir.display()))?;
    let mut all = Vec::new();
    let cases: &[&str] = if quick {
        &["dam-break", "taylor-green"]
    } else {
        &["dam-break", "taylor-green", "cylinder"]
    };
    for &case in cases {
        // Resolutions with the default scheme, then each variant that applies at the middle one.
        let (resolutions, middle) = resolutions(case, quick);
        let (variants, skipped) = plan(case, quick)?;
        for p in skipped.iter().filter(|_| options.verbose) {
            crate::note!(
                "chart {case} {} {}: skipped: {}",
                p.variant,
                p.resolution,
                p.skipped.as_deref().unwrap_or_default()
            );
        }
        let runs: Vec<(f64, Variant)> = resolutions
            .iter()
            .map(|&r| (r, Variant::default()))
            .chain(variants.into_iter().map(|v| (middle, v)))
            .collect();
        let mut points = Vec::new();
        for &backend in &options.backends {
            let ctx = Ctx {
                tier: options.tier,
                backend,
                courant: None,
                integrator: None,
                sets: &[],
                out_dir: &options.out_dir,
                verbose: options.verbose,
                edit: None,
            };
            for (r, v) in &runs {
                let p = point(&ctx, case, *r, v);
                if options.verbose {
                    crate::note!(
                        "chart {case} {} {} ({}): {} in {:.2} s",
                        p.variant,
                        p.resolution,
                        p.backend,
                        p.error
                            .map(|e| format!("error {e:.4}"))
                            .unwrap_or_else(|| "FAILED".into()),
                        p.wall_seconds
                    );
                }
                points.push(p);
            }
        }
        mark_pareto(&mut points);
        draw(options, case, &points)?;
        all.extend(points);
        all.extend(skipped);
    }
    let json = options.out_dir.join("chart.json");
    std::fs::write(&json, serde_json::to_string_pretty(&all)? + "\n")
        .with_context(|| format!("writing {}", json.display()))?;
    let csv = options.out_dir.join("chart.csv");
    std::fs::write(&csv, to_csv(&all)).with_context(|| format!("writing {}", csv.display()))?;
    Ok(all)
}

/// A CSV text field, quoted (RFC 4180: a quote inside is doubled), since variant names and
/// resolutions hold commas ("delta-SPH 0.1, Fourtakas", "Re 100, D / dx = 5").
fn quoted(field: &str) -> String {
    format!("\"{}\"", field.replace('"', "\"\""))
}

/// The points as CSV (error empty for a failed or skipped run, the wall time where none
/// was measured; text fields quoted).
pub fn to_csv(points: &[Point]) -> String {
    let mut s = String::from(
        "case,variant,resolution,backend,device,particles,wall_seconds,error,pareto,failure,skipped\n",
    );
    for p in points {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{}",
            quoted(&p.case),
            quoted(&p.variant),
            quoted(&p.resolution),
            quoted(&p.backend),
            quoted(&p.device),
            p.particles,
            Some(p.wall_seconds)
                .filter(|t| t.is_finite())
                .map(|t| format!("{t:.3}"))
                .unwrap_or_default(),
            p.error.map(|e| format!("{e:.5}")).unwrap_or_default(),
            p.pareto,
            quoted(p.failure.as_deref().unwrap_or_default()),
            quoted(p.skipped.as_deref().unwrap_or_default())
        );
    }
    s
}

fn draw(options: &Options, case: &str, points: &[Point]) -> anyhow::Result<()> {
    // One series per variant (and backend), the Pareto front as a line through its points.
    let mut series: Vec<Series> = Vec::new();
    for p in points.iter().filter(|p| p.error.is_some_and(|e| e > 0.0)) {
        let label = format!("{} ({})", p.variant, p.backend);
        let pt = (p.wall_seconds, p.error.unwrap_or(f64::NAN));
        match series.iter_mut().find(|s| s.label == label) {
            Some(s) => s.points.push(pt),
            None => series.push(Series::points(label, vec![pt])),
        }
    }
    let mut front: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.pareto && p.error.is_some_and(|e| e > 0.0))
        .map(|p| (p.wall_seconds, p.error.unwrap_or(f64::NAN)))
        .collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    series.push(Series::line("Pareto front", front));
    let title = format!("{case}: error against wall time");
    plot(
        &options.out_dir.join(format!("chart-{case}.png")),
        &Figure {
            title: &title,
            x_label: "wall time [s]",
            y_label: match case {
                "dam-break" => "max relative surge-front error",
                "cylinder" => "|St / St_Williamson - 1|",
                _ => "|E_k decay rate / exact - 1|",
            },
            log_y: true,
            log_x: true,
        },
        &series,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fields of one CSV line (RFC 4180 quoting).
    fn fields(line: &str) -> Vec<String> {
        let (mut out, mut cur, mut quoted, mut chars) =
            (Vec::new(), String::new(), false, line.chars().peekable());
        while let Some(c) = chars.next() {
            match (c, quoted) {
                ('"', true) if chars.peek() == Some(&'"') => {
                    cur.push('"');
                    chars.next();
                }
                ('"', _) => quoted = !quoted,
                (',', false) => out.push(std::mem::take(&mut cur)),
                _ => cur.push(c),
            }
        }
        out.push(cur);
        out
    }

    /// The names of the variants `plan` runs on `case` (full tier), and its skipped rows as
    /// (variant, reason).
    fn planned(case: &str) -> (Vec<&'static str>, Vec<(String, String)>) {
        let (run, skipped) = plan(case, false).unwrap();
        let skipped = skipped
            .into_iter()
            .map(|p| (p.variant, p.skipped.expect("a skipped row says why")))
            .collect();
        (run.iter().map(|v| v.name).collect(), skipped)
    }

    #[test]
    fn a_summation_case_skips_density_diffusion_and_runs_only_what_its_scene_accepts() {
        // The cylinder has summation density: the three delta-SPH variants were refused by
        // the scene check mid-chart. Now they are skipped, with the reason.
        let (run, skipped) = planned("cylinder");
        let default = case_scene("cylinder", 5.0).unwrap();
        for v in case_variants("cylinder", false)
            .iter()
            .filter(|v| run.contains(&v.name))
        {
            let mut s = default.clone();
            (v.edit)(&mut s);
            assert!(s.revalidate().is_ok(), "{}: {:?}", v.name, s.revalidate());
            assert!(!v.name.starts_with("delta-SPH"), "{}", v.name);
        }
        let diffusion: Vec<_> = skipped
            .iter()
            .filter(|(v, _)| v.starts_with("delta-SPH"))
            .collect();
        assert_eq!(diffusion.len(), 3, "{skipped:?}");
        assert!(
            diffusion
                .iter()
                .all(|(_, r)| r.contains("summation density")),
            "{diffusion:?}"
        );
        // On the continuity cases they run.
        for case in ["dam-break", "taylor-green"] {
            let (run, _) = planned(case);
            assert!(run.contains(&"delta-SPH 0.1, Antuono"), "{case}: {run:?}");
        }
    }

    #[test]
    fn a_variant_that_changes_nothing_is_skipped_as_the_default() {
        let same = |skipped: &[(String, String)], name: &str| {
            skipped
                .iter()
                .any(|(v, r)| v == name && r == SAME_AS_DEFAULT)
        };
        // The cylinder already has summation density; the leapfrog's own Courant number
        // is 0.4 on every case.
        let (run, skipped) = planned("cylinder");
        assert!(same(&skipped, "summation density"), "{skipped:?}");
        assert!(same(&skipped, "Courant 0.4"), "{skipped:?}");
        assert!(run.contains(&"Wendland C2"), "{run:?}");
        // The dam break has the continuity form: its summation variant is a change.
        let (run, skipped) = planned("dam-break");
        assert!(run.contains(&"summation density"), "{run:?}");
        assert!(same(&skipped, "Courant 0.4"), "{skipped:?}");
    }

    #[test]
    fn a_skipped_row_carries_its_reason_in_the_table() {
        let (_, skipped) = plan("cylinder", false).unwrap();
        let csv = to_csv(&skipped);
        let mut lines = csv.lines();
        let header = fields(lines.next().unwrap());
        let col = header.iter().position(|h| h == "skipped").unwrap();
        let rows: Vec<_> = lines.map(fields).collect();
        assert!(
            rows.iter()
                .any(|r| r[1] == "summation density" && r[col] == SAME_AS_DEFAULT),
            "{csv}"
        );
        // No wall time, error or backend where nothing ran.
        assert!(rows
            .iter()
            .all(|r| r[3].is_empty() && r[6].is_empty() && r[7].is_empty()));
    }

    #[test]
    fn csv_rows_keep_their_columns_where_names_hold_commas() {
        let p = Point {
            case: "cylinder".into(),
            variant: "delta-SPH 0.1, Fourtakas".into(),
            resolution: "Re 100, D / dx = 5".into(),
            backend: "cuda".into(),
            device: "NVIDIA H100 80GB HBM3".into(),
            particles: 6004,
            wall_seconds: 3.5,
            error: None,
            failure: Some("fluid.density_diffusion: set \"continuity\"".into()),
            pareto: false,
            skipped: None,
        };
        let csv = to_csv(&[p]);
        let mut lines = csv.lines();
        let header = fields(lines.next().unwrap());
        let row = fields(lines.next().unwrap());
        assert_eq!(row.len(), header.len(), "{row:?}");
        assert_eq!(row[1], "delta-SPH 0.1, Fourtakas");
        assert_eq!(row[2], "Re 100, D / dx = 5");
        assert_eq!(row[9], "fluid.density_diffusion: set \"continuity\"");
    }
}
