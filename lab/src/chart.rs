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
//! all backends asked for.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Context;
use serde::{Deserialize, Serialize};

use crate::plot::{plot, Figure, Series};
use crate::stability::cases;
use crate::stability::sweep::Base;
use crate::validate::{cylinder, taylor_green, Ctx, Tier};
use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::Scene;
use meshfree_core::scheme::{DensityForm, DiffusionForm, IntegratorChoice, KernelChoice};

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
    /// None: the run blew up (`failure` says how).
    pub error: Option<f64>,
    pub failure: Option<String>,
    pub pareto: bool,
}

/// A variant: a name and a change to the case's scene.
struct Variant {
    name: &'static str,
    edit: fn(&mut Scene),
}

fn variants(quick: bool) -> Vec<Variant> {
    let all = vec![
        Variant {
            name: "default",
            edit: |_| {},
        },
        Variant {
            name: "Wendland C2",
            edit: |s| s.file.discretisation.kernel = KernelChoice::WendlandC2,
        },
        Variant {
            name: "summation density",
            edit: |s| s.file.fluid.density_form = DensityForm::Summation,
        },
        Variant {
            name: "forward Euler",
            edit: |s| s.file.time.integrator = IntegratorChoice::Euler,
        },
        Variant {
            name: "delta-SPH 0.1",
            edit: |s| s.file.fluid.density_diffusion = 0.1,
        },
        Variant {
            name: "delta-SPH 0.1, Fourtakas",
            edit: |s| {
                s.file.fluid.density_diffusion = 0.1;
                s.file.fluid.density_diffusion_form = DiffusionForm::Fourtakas;
            },
        },
        Variant {
            name: "delta-SPH 0.1, Antuono",
            edit: |s| {
                s.file.fluid.density_diffusion = 0.1;
                s.file.fluid.density_diffusion_form = DiffusionForm::Antuono;
            },
        },
        Variant {
            name: "shifting 0.2",
            edit: |s| s.file.fluid.shifting = 0.2,
        },
        Variant {
            name: "Courant 0.4",
            edit: |s| s.file.time.courant = Some(0.4),
        },
    ];
    if quick {
        all.into_iter().take(2).collect()
    } else {
        all
    }
}

/// The dam break's viscosity variant: alpha 0.05 instead of 0.02; the Taylor-Green
/// vortex's: artificial viscosity with the same nu = alpha h c0 / 8 (Monaghan 1992, 2D)
/// instead of the laminar term.
fn viscosity_variant(base: &str) -> Variant {
    if base == "dam-break" {
        Variant {
            name: "alpha 0.05",
            edit: |s| s.file.fluid.alpha = 0.05,
        }
    } else {
        Variant {
            name: "artificial viscosity",
            edit: |s| {
                let f = &mut s.file;
                let h = f.discretisation.h_factor * f.discretisation.spacing;
                f.fluid.alpha = 8.0 * f.fluid.viscosity / (h * f.fluid.sound_speed);
                f.fluid.viscosity = 0.0;
            },
        }
    }
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
        let mut points = Vec::new();
        for &backend in &options.backends {
            let ctx = Ctx {
                tier: options.tier,
                backend,
                courant: None,
                integrator: None,
                out_dir: &options.out_dir,
                verbose: options.verbose,
                edit: None,
            };
            // Resolutions with the default scheme, then each variant at the middle one.
            let (resolutions, middle): (Vec<f64>, f64) = match (case, quick) {
                ("dam-break", true) => (vec![0.1, 0.05], 0.1),
                ("dam-break", false) => (vec![0.1, 0.05, 0.04, 0.025], 0.05),
                ("cylinder", _) => (vec![5.0, 8.0, 10.0], 5.0),
                (_, true) => (vec![16.0, 24.0], 16.0),
                (_, false) => (vec![20.0, 30.0, 40.0, 60.0], 30.0),
            };
            let mut runs: Vec<(f64, Variant)> = resolutions
                .iter()
                .map(|&r| {
                    (
                        r,
                        Variant {
                            name: "default",
                            edit: |_| {},
                        },
                    )
                })
                .collect();
            let mut vs = variants(quick);
            if !quick {
                vs.push(viscosity_variant(case));
            }
            if case == "cylinder" {
                // The validate case's scheme (issue #23: the wake without voids).
                vs.push(Variant {
                    name: "shifting 0.2, background pressure 2 q, Morris walls, ramped start",
                    edit: cylinder::confined,
                });
            }
            runs.extend(
                vs.into_iter()
                    .filter(|v| v.name != "default")
                    .map(|v| (middle, v)),
            );
            for (r, v) in runs {
                let p = if case == "dam-break" {
                    let mut scene = cases::base_scene(Base::DamBreak, r);
                    (v.edit)(&mut scene);
                    scene.revalidate()?;
                    let m = cases::measure(Base::DamBreak, &scene, backend, 2.5)?;
                    Point {
                        case: case.into(),
                        variant: v.name.into(),
                        resolution: format!("dx = {r}"),
                        backend: m.info.backend,
                        device: m.info.device,
                        particles: m.particles,
                        wall_seconds: m.wall_seconds,
                        error: m.result.as_ref().ok().copied(),
                        failure: m.result.as_ref().err().map(|f| f.to_string()),
                        pareto: false,
                    }
                } else {
                    let (measured, label) = if case == "cylinder" {
                        (
                            cylinder::strouhal_error(&ctx, r, CYLINDER_T_END_UD, &|s| (v.edit)(s)),
                            format!("D / dx = {r}"),
                        )
                    } else {
                        let n = r as usize;
                        (
                            taylor_green::decay_rate_error(&ctx, n, &|s| (v.edit)(s)),
                            format!("{n} x {n}"),
                        )
                    };
                    match measured {
                        Ok((e, run)) => Point {
                            case: case.into(),
                            variant: v.name.into(),
                            resolution: run.resolution,
                            backend: run.info.backend,
                            device: run.info.device,
                            particles: run.particles,
                            wall_seconds: run.wall_seconds,
                            error: Some(e),
                            failure: None,
                            pareto: false,
                        },
                        Err(e) => Point {
                            case: case.into(),
                            variant: v.name.into(),
                            resolution: label,
                            backend: format!("{backend:?}").to_lowercase(),
                            device: String::new(),
                            particles: 0,
                            wall_seconds: f64::NAN,
                            error: None,
                            failure: Some(format!("{e:#}")),
                            pareto: false,
                        },
                    }
                };
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

/// The points as CSV (error empty for a failed run; text fields quoted).
pub fn to_csv(points: &[Point]) -> String {
    let mut s = String::from(
        "case,variant,resolution,backend,device,particles,wall_seconds,error,pareto,failure\n",
    );
    for p in points {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{:.3},{},{},{}",
            quoted(&p.case),
            quoted(&p.variant),
            quoted(&p.resolution),
            quoted(&p.backend),
            quoted(&p.device),
            p.particles,
            p.wall_seconds,
            p.error.map(|e| format!("{e:.5}")).unwrap_or_default(),
            p.pareto,
            quoted(p.failure.as_deref().unwrap_or_default())
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
