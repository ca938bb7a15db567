//! `meshfree waves DIR`: the regular waves at a run's gauges (`gauges.csv`): each gauge's mean
//! level and height over whole periods, and the incident and reflected heights from two or
//! more gauges (`meshfree_core::measure::reflection`, Mansard & Funke 1980); or, where the
//! scene's wave maker makes an irregular sea (`wave.spectrum`), each gauge's significant
//! height and periods (`meshfree_core::measure::sea_state`) beside the target's.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use meshfree_core::measure::reflection::{harmonic, separate, Harmonic, Separation};
use meshfree_core::measure::sea_state::{sea_state, SeaState};
use meshfree_core::scene::format::{Motion, WaveMaker};
use meshfree_core::scene::Scene;

use crate::bad_input::BadInput;

#[derive(Debug, clap::Args)]
#[command(
    after_help = "Example: meshfree run flume-2d, then meshfree waves out/flume-2d \
--gauges x1,x2,x3. The gauges must stand in water of one depth, along x (the \
wave maker's direction), away from multiples of half a wavelength apart (the report's \
conditioning, 1 at best, says how far: Mansard & Funke advise x12 = L/10 and x13 between L/6 \
and L/3, not L/5 or 3L/10); the window should start after the ramp and the \
first waves' arrival and end before reflections of the reflections return. Where the \
scene's wave maker makes an irregular sea (wave.spectrum), each gauge's significant height \
H_m0 = 4 sqrt(m0), peak period T_p (Read's, from the band-averaged spectrum) and mean period \
T_m01 come instead, beside the target's; a record of 200 peak periods or more gives H_m0 and \
T_p within a few per cent."
)]
pub struct WavesArgs {
    /// A run's output directory (its `gauges.csv` and `scene.toml`).
    pub dir: PathBuf,
    /// The gauges to analyse, by name (default all); two or more are separated.
    #[arg(long, value_delimiter = ',')]
    pub gauges: Option<Vec<String>>,
    /// The wave period, in the scene's unit of time (default: the wave maker's, `motion`'s
    /// `wave`).
    #[arg(long)]
    pub period: Option<f64>,
    /// The still-water depth at the gauges, in the scene's unit of length (default: the wave
    /// maker's `depth`).
    #[arg(long)]
    pub depth: Option<f64>,
    /// The wavelength, in the scene's unit of length (default: linear theory's at the period
    /// and depth); give the measured one where the scheme's waves run at another speed.
    #[arg(long)]
    pub wavelength: Option<f64>,
    /// The window's start time (default: the middle of the record); it ends at `--to`, the
    /// whole periods that fit taken back from there.
    #[arg(long)]
    pub from: Option<f64>,
    /// The window's end time (default: the record's last sample).
    #[arg(long)]
    pub to: Option<f64>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// What `waves` reports.
#[derive(Debug, serde::Serialize)]
pub struct WavesReport {
    pub period: f64,
    pub depth: f64,
    /// \[L\] the wavelength 2 pi / k.
    pub wavelength: f64,
    /// \[T\] the window (whole periods).
    pub from: f64,
    pub to: f64,
    pub gauges: Vec<GaugeWaves>,
    /// With two or more gauges.
    pub separation: Option<Separation>,
}

#[derive(Debug, serde::Serialize)]
pub struct GaugeWaves {
    pub name: String,
    /// \[L\] along the waves.
    pub x: f64,
    pub samples: usize,
    #[serde(flatten)]
    pub harmonic: Harmonic,
}

fn bad(s: String) -> anyhow::Error {
    BadInput(s).into()
}

/// What `waves` reports on an irregular sea.
#[derive(Debug, serde::Serialize)]
pub struct SeaReport {
    /// \[L\] the wave maker's significant height H_m0.
    pub target_hm0: f64,
    /// \[T\] its peak period.
    pub target_tp: f64,
    /// \[T\] the window.
    pub from: f64,
    pub to: f64,
    pub gauges: Vec<GaugeSea>,
}

#[derive(Debug, serde::Serialize)]
pub struct GaugeSea {
    pub name: String,
    /// \[L\] along the waves.
    pub x: f64,
    pub samples: usize,
    #[serde(flatten)]
    pub sea: SeaState,
}

pub(super) fn waves(a: WavesArgs) -> anyhow::Result<()> {
    if let Some(r) = sea_report(&a)? {
        if a.json {
            crate::outln!("{}", serde_json::to_string_pretty(&r)?)?;
            return Ok(());
        }
        crate::outln!(
            "irregular sea: target H_m0 {} T_p {}; window t = {:.4} to {:.4}",
            r.target_hm0,
            r.target_tp,
            r.from,
            r.to
        )?;
        crate::outln!(
            "{:<12} {:>10} {:>8} {:>10} {:>10} {:>10} {:>10}",
            "gauge",
            "x",
            "samples",
            "mean",
            "H_m0",
            "T_p",
            "T_m01"
        )?;
        for g in &r.gauges {
            crate::outln!(
                "{:<12} {:>10.4} {:>8} {:>10.5} {:>10.5} {:>10.4} {:>10.4}",
                g.name,
                g.x,
                g.samples,
                g.sea.mean,
                g.sea.hm0,
                g.sea.tp,
                g.sea.tm01
            )?;
        }
        return Ok(());
    }
    let r = report(&a)?;
    if a.json {
        crate::outln!("{}", serde_json::to_string_pretty(&r)?)?;
        return Ok(());
    }
    crate::outln!(
        "T = {} s, depth {}, wavelength {:.4}; window t = {:.4} to {:.4} ({} periods)",
        r.period,
        r.depth,
        r.wavelength,
        r.from,
        r.to,
        ((r.to - r.from) / r.period).round()
    )?;
    crate::outln!(
        "{:<12} {:>10} {:>8} {:>10} {:>10} {:>10}",
        "gauge",
        "x",
        "samples",
        "mean",
        "H1",
        "range"
    )?;
    for g in &r.gauges {
        crate::outln!(
            "{:<12} {:>10.4} {:>8} {:>10.5} {:>10.5} {:>10.5}",
            g.name,
            g.x,
            g.samples,
            g.harmonic.mean,
            g.harmonic.height,
            g.harmonic.range
        )?;
    }
    if let Some(s) = &r.separation {
        crate::outln!(
            "incident H {:.5}, reflected H {:.5}, reflection coefficient {:.4} \
             (conditioning {:.3}, residual {:.2e})",
            s.incident,
            s.reflected,
            s.coefficient,
            s.conditioning,
            s.residual
        )?;
        if s.conditioning < 0.1 {
            crate::outln!(
                "warning: the gauges stand near multiples of half a wavelength apart: the \
                 separation is ill-conditioned; space them otherwise"
            )?;
        }
    }
    Ok(())
}

/// The run's scene (`scene.toml` in `a.dir`) and its path.
fn run_scene(a: &WavesArgs) -> anyhow::Result<(Scene, PathBuf)> {
    let scene_path = a.dir.join(meshfree_core::run_files::SCENE);
    let scene = Scene::from_file(&scene_path).map_err(|e| {
        bad(format!(
            "{}: {e} (waves takes the output directory of `meshfree run`)",
            a.dir.display()
        ))
    })?;
    Ok((scene, scene_path))
}

/// The scene's first wave maker.
fn wave_maker(scene: &Scene) -> Option<&WaveMaker> {
    scene
        .file
        .walls
        .iter()
        .filter_map(|w| match w.motion() {
            Some(Motion::Law(l)) => l.wave.as_deref(),
            _ => None,
        })
        .next()
}

/// The elevation along `up`: gravity's opposite in `scene` (Err where it has none).
fn up_of(scene: &Scene, scene_path: &Path) -> anyhow::Result<(f64, Vec<f64>)> {
    let gravity = scene.file.gravity.clone().unwrap_or_default();
    let g = gravity.iter().map(|x| x * x).sum::<f64>().sqrt();
    if g <= 0.0 {
        return Err(bad(format!(
            "{}: the scene has no gravity: no gravity waves",
            scene_path.display()
        )));
    }
    Ok((g, gravity.iter().map(|x| -x / g).collect()))
}

/// The gauges `a` names (all by default), each checked against the record.
fn chosen(a: &WavesArgs, series: &BTreeMap<String, Samples>) -> anyhow::Result<Vec<String>> {
    match &a.gauges {
        Some(list) => {
            for n in list {
                if !series.contains_key(n) {
                    return Err(bad(format!(
                        "--gauges: no gauge {n:?} in gauges.csv (it has {})",
                        series.keys().cloned().collect::<Vec<_>>().join(", ")
                    )));
                }
            }
            Ok(list.clone())
        }
        None => Ok(series.keys().cloned().collect()),
    }
}

/// The record's first and last times over the gauges `names`.
fn span(names: &[String], series: &BTreeMap<String, Samples>) -> (f64, f64) {
    let last = (names.iter())
        .filter_map(|n| series[n].last().map(|s| s.0))
        .fold(f64::MIN, f64::max);
    let first = (names.iter())
        .filter_map(|n| series[n].first().map(|s| s.0))
        .fold(f64::MAX, f64::min);
    (first, last)
}

/// The sea-state report of `a` where the scene's wave maker makes an irregular sea, None
/// where it makes regular waves (or there is none): each gauge's H_m0, T_p and T_m01 over
/// the window (`--from`, default the record's middle, to `--to`, default its end).
pub fn sea_report(a: &WavesArgs) -> anyhow::Result<Option<SeaReport>> {
    let (scene, scene_path) = run_scene(a)?;
    let Some(w) = wave_maker(&scene).filter(|w| w.spectrum.is_some()) else {
        return Ok(None);
    };
    let (_, up) = up_of(&scene, &scene_path)?;
    let series = read_gauges(&a.dir.join("gauges.csv"), &up)?;
    let names = chosen(a, &series)?;
    let (first, last) = span(&names, &series);
    let to = a.to.unwrap_or(last).min(last);
    let from = a.from.unwrap_or(0.5 * (first + last)).max(first);
    let mut gauges = Vec::new();
    for n in &names {
        let rows: Vec<&(f64, f64, f64)> = (series[n].iter())
            .filter(|s| s.0 >= from - 1e-9 && s.0 <= to + 1e-9)
            .collect();
        let times: Vec<f64> = rows.iter().map(|s| s.0).collect();
        let eta: Vec<f64> = rows.iter().map(|s| s.2).collect();
        let sea = sea_state(&times, &eta, 4.0 / w.period).ok_or_else(|| {
            bad(format!(
                "gauge {n:?}: {} wet samples in the window t = {from} to {to}: too few, or a \
                 dry gap, for a spectrum (give a window where the gauge stays wet)",
                times.len()
            ))
        })?;
        let x = rows.iter().map(|s| s.1).sum::<f64>() / rows.len() as f64;
        gauges.push(GaugeSea {
            name: n.clone(),
            x,
            samples: times.len(),
            sea,
        });
    }
    Ok(Some(SeaReport {
        target_hm0: w.height,
        target_tp: w.period,
        from,
        to,
        gauges,
    }))
}

/// The report of `a` (the errors are `BadInput`: exit status 2).
pub fn report(a: &WavesArgs) -> anyhow::Result<WavesReport> {
    let (scene, scene_path) = run_scene(a)?;
    let wave = wave_maker(&scene);
    let period = a.period.or(wave.map(|w| w.period)).ok_or_else(|| {
        bad(format!(
            "{}: the scene has no wave maker: give --period",
            scene_path.display()
        ))
    })?;
    let depth = a.depth.or(wave.map(|w| w.depth)).ok_or_else(|| {
        bad(format!(
            "{}: the scene has no wave maker: give --depth",
            scene_path.display()
        ))
    })?;
    let given = [
        ("--period", Some(period)),
        ("--depth", Some(depth)),
        ("--wavelength", a.wavelength),
    ];
    for (name, v) in given.iter().filter_map(|(n, v)| v.map(|v| (n, v))) {
        if !(v.is_finite() && v > 0.0) {
            return Err(bad(format!("{name}: must be a positive number, found {v}")));
        }
    }
    let (g, up) = up_of(&scene, &scene_path)?;
    let series = read_gauges(&a.dir.join("gauges.csv"), &up)?;
    let names = chosen(a, &series)?;
    let (first, last) = span(&names, &series);
    let to = a.to.unwrap_or(last).min(last);
    let start = a.from.unwrap_or(0.5 * (first + last));
    let whole = ((to - start) / period + 1e-9).floor();
    if whole < 1.0 {
        return Err(bad(format!(
            "the window t = {start} to {to} holds no whole period of {period} (the record runs from {first} to {last})"
        )));
    }
    let from = to - whole * period;
    let omega = 2.0 * std::f64::consts::PI / period;
    let mut gauges = Vec::new();
    for n in &names {
        let rows: Vec<&(f64, f64, f64)> = (series[n].iter())
            .filter(|s| s.0 >= from - 1e-9 && s.0 <= to + 1e-9)
            .collect();
        let times: Vec<f64> = rows.iter().map(|s| s.0).collect();
        let eta: Vec<f64> = rows.iter().map(|s| s.2).collect();
        let h = harmonic(&times, &eta, omega).ok_or_else(|| {
            bad(format!(
                "gauge {n:?}: {} wet samples in the window, too few for a harmonic",
                times.len()
            ))
        })?;
        let x = rows.iter().map(|s| s.1).sum::<f64>() / rows.len() as f64;
        gauges.push(GaugeWaves {
            name: n.clone(),
            x,
            samples: times.len(),
            harmonic: h,
        });
    }
    let k = match a.wavelength {
        Some(l) => 2.0 * std::f64::consts::PI / l,
        None => meshfree_core::scene::wave::wave_number(g, period, depth),
    };
    let separation = if gauges.len() >= 2 {
        let xs: Vec<f64> = gauges.iter().map(|g| g.x).collect();
        let bs: Vec<_> = gauges.iter().map(|g| g.harmonic.amplitude).collect();
        Some(separate(&xs, &bs, k).ok_or_else(|| {
            bad(format!(
                "the gauges at x = {xs:?} stand multiples of half a wavelength ({}) apart: \
                 they cannot tell the incident wave from the reflected one",
                std::f64::consts::PI / k
            ))
        })?)
    } else {
        None
    };
    Ok(WavesReport {
        period,
        depth,
        wavelength: 2.0 * std::f64::consts::PI / k,
        from,
        to,
        gauges,
        separation,
    })
}

/// A gauge's wet samples: (time \[T\], x \[L\], elevation \[L\]), in time order.
type Samples = Vec<(f64, f64, f64)>;

/// Each gauge's wet samples from `gauges.csv` (`time,step,gauge,x,y[,z],distance`), the
/// elevation along `up`.
fn read_gauges(path: &Path, up: &[f64]) -> anyhow::Result<BTreeMap<String, Samples>> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| bad(format!("{}: cannot read it: {e}", path.display())))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let dim = up.len();
    let want = 4 + dim;
    if header.len() != want || header[0] != "time" || header[2] != "gauge" {
        return Err(bad(format!(
            "{}: expected the header time,step,gauge,<{dim} axes>,distance, found {:?}",
            path.display(),
            header.join(",")
        )));
    }
    let mut out: BTreeMap<String, Samples> = BTreeMap::new();
    for (i, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        if cells.len() != want {
            return Err(bad(format!(
                "{}: line {}: {} cells, expected {want}",
                path.display(),
                i + 2,
                cells.len()
            )));
        }
        let num = |c: &str| c.trim().parse::<f64>().ok().filter(|v| v.is_finite());
        let name = cells[2].to_string();
        let series = out.entry(name).or_default();
        // A dry gauge's row has no surface point: skipped.
        let (Some(t), Some(p)) = (
            num(cells[0]),
            (3..3 + dim)
                .map(|c| num(cells[c]))
                .collect::<Option<Vec<f64>>>(),
        ) else {
            continue;
        };
        let elevation = p.iter().zip(up).map(|(a, b)| a * b).sum();
        series.push((t, p[0], elevation));
    }
    if out.is_empty() {
        return Err(bad(format!("{}: no gauge rows", path.display())));
    }
    Ok(out)
}
