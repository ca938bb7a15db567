//! `meshfree stability`: sweeps of the Courant number, artificial viscosity, density form,
//! integrator, Lennard-Jones strength, density diffusion and (for solids) artificial stress,
//! each run classified as stable, inaccurate (error over tolerance) or failed (blow-up
//! found by the health checks, `Solver::check`, with its time), drawn as heat maps.
//!
//! `sweep.rs` defines the maps, `cases.rs` the base scenes and their error measures,
//! `heatmap.rs` the PNGs. `run` writes `report.md`, `report.json`, `cells.csv` and one PNG
//! per map. The quick tier (two values per axis, coarse scenes) takes seconds; the full
//! tier (five values, dx = 0.04 dam break, dx = 0.02 strip) takes tens of minutes on a CPU.

pub mod cases;
pub mod heatmap;
pub mod sweep;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use serde::{Deserialize, Serialize};

use meshfree_core::backend::BackendChoice;
use sweep::{Base, MapDef};

/// Quick (coarse, two values per axis: the tests) or full: the tiers of `validate`.
pub use crate::validate::Tier;

/// What `run` does.
#[derive(Clone, Debug)]
pub struct Options {
    pub tier: Tier,
    pub backend: BackendChoice,
    pub out_dir: PathBuf,
    /// Only the maps whose name contains one of these; empty: all.
    pub maps: Vec<String>,
    /// Progress lines on stderr.
    pub verbose: bool,
}

/// How a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Class {
    /// Ran to the end with the error within tolerance.
    Stable,
    /// Ran to the end with the error over tolerance.
    Inaccurate,
    /// A blow-up (health check fault) before the end.
    Failed,
}

/// One run of a map.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Cell {
    pub map: String,
    pub x: f64,
    pub y: f64,
    pub class: Class,
    /// The error measure (none after a blow-up).
    pub error: Option<f64>,
    pub tolerance: f64,
    /// \[T\] simulated time of the blow-up.
    pub blow_up_time: Option<f64>,
    /// The fault, as `Fault` prints it.
    pub fault: Option<String>,
    pub particles: usize,
    pub wall_seconds: f64,
}

/// A map with its cells (row-major: y outer, x inner).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MapResult {
    pub def: MapDef,
    /// \[L\] the base scene's spacing.
    pub spacing: f64,
    /// What `error` measures.
    pub error_measure: String,
    pub cells: Vec<Cell>,
    pub plot: String,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Report {
    pub tier: Tier,
    pub machine: String,
    pub backend: String,
    pub wall_seconds: f64,
    pub maps: Vec<MapResult>,
}

/// The error measure, its tolerance and the normalised end time of a base per tier.
fn measure_of(base: Base, quick: bool) -> (&'static str, f64, f64) {
    match base {
        // 15 %: published WCSPH fronts lie 10-15 % from Martin & Moyce (validate::dam_break);
        // the quick tier's dx = 0.1 column of 10 x 10 particles gets a regression bound.
        Base::DamBreak => (
            "max relative error of the surge front vs Martin & Moyce 1952, 0.8 <= T <= 2.5",
            if quick { 0.3 } else { 0.15 },
            2.5,
        ),
        // A stretched body's particles move apart: a pair closer than 0.75 dx is clumping,
        // a particle 1.25 dx from all others a crack. Measured: 0.03 with artificial stress
        // 0.3, 0.43 (dx = 0.05) and 0.9 (dx = 0.02) without.
        Base::ElasticStrip => (
            "max |nearest-neighbour distance / dx - 1| over 0.3 T (clumping or fracture)",
            0.25,
            0.0,
        ),
    }
}

/// Run every selected map and write the reports to `options.out_dir`.
pub fn run(options: &Options) -> anyhow::Result<Report> {
    let quick = options.tier == Tier::Quick;
    let maps: Vec<MapDef> = sweep::maps(options.tier)
        .into_iter()
        .filter(|m| options.maps.is_empty() || options.maps.iter().any(|k| m.name.contains(k)))
        .collect();
    anyhow::ensure!(
        !maps.is_empty(),
        "no stability map matches {:?}; known: {}",
        options.maps,
        sweep::maps(options.tier)
            .iter()
            .map(|m| m.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    );
    std::fs::create_dir_all(&options.out_dir)
        .with_context(|| format!("creating {}", options.out_dir.display()))?;
    let started = Instant::now();
    let mut backend_name = String::new();
    let mut out = Vec::new();
    for def in maps {
        let dx = cases::spacing(def.base, quick);
        let (measure, tolerance, t_end) = measure_of(def.base, quick);
        if options.verbose {
            crate::note!("stability: {} (dx = {dx})", def.name);
        }
        let mut cells = Vec::new();
        for &y in &def.y.values {
            for &x in &def.x.values {
                let mut scene = cases::base_scene(def.base, dx);
                sweep::apply_fixed(&mut scene, &def);
                sweep::apply(&mut scene, def.x.param, x);
                sweep::apply(&mut scene, def.y.param, y);
                scene
                    .revalidate()
                    .with_context(|| format!("map {} at ({x}, {y})", def.name))?;
                let m = cases::measure(def.base, &scene, options.backend, t_end)?;
                if backend_name.is_empty() {
                    backend_name = format!("{} ({})", m.info.backend, m.info.device);
                }
                let cell = match m.result {
                    Ok(error) => Cell {
                        map: def.name.clone(),
                        x,
                        y,
                        class: if error <= tolerance {
                            Class::Stable
                        } else {
                            Class::Inaccurate
                        },
                        error: Some(error),
                        tolerance,
                        blow_up_time: None,
                        fault: None,
                        particles: m.particles,
                        wall_seconds: m.wall_seconds,
                    },
                    Err(f) => Cell {
                        map: def.name.clone(),
                        x,
                        y,
                        class: Class::Failed,
                        error: None,
                        tolerance,
                        blow_up_time: Some(f.time),
                        fault: Some(f.to_string()),
                        particles: m.particles,
                        wall_seconds: m.wall_seconds,
                    },
                };
                if options.verbose {
                    crate::note!(
                        "  {} = {x}, {} = {y}: {} {:.1} s",
                        def.x.param.label(),
                        def.y.param.label(),
                        cell_text(&cell),
                        cell.wall_seconds
                    );
                }
                cells.push(cell);
            }
        }
        let plot = format!("{}.png", def.name);
        let result = MapResult {
            def,
            spacing: dx,
            error_measure: measure.into(),
            cells,
            plot: plot.clone(),
        };
        heatmap::draw(&options.out_dir.join(&plot), &result)?;
        out.push(result);
    }
    let report = Report {
        tier: options.tier,
        machine: crate::validate::machine(),
        backend: backend_name,
        wall_seconds: started.elapsed().as_secs_f64(),
        maps: out,
    };
    let write = |name: &str, text: String| -> anyhow::Result<()> {
        let p = options.out_dir.join(name);
        std::fs::write(&p, text).with_context(|| format!("writing {}", p.display()))
    };
    write("report.json", serde_json::to_string_pretty(&report)? + "\n")?;
    write("report.md", markdown(&report))?;
    write("cells.csv", csv(&report))?;
    Ok(report)
}

fn csv(r: &Report) -> String {
    let mut s = String::from(
        "map,x_param,x,y_param,y,class,error,tolerance,blow_up_time,particles,wall_seconds\n",
    );
    for m in &r.maps {
        for c in &m.cells {
            let _ = writeln!(
                s,
                "{},{:?},{},{:?},{},{:?},{},{},{},{},{:.3}",
                m.def.name,
                m.def.x.param,
                c.x,
                m.def.y.param,
                c.y,
                c.class,
                c.error.map(|e| e.to_string()).unwrap_or_default(),
                c.tolerance,
                c.blow_up_time.map(|t| t.to_string()).unwrap_or_default(),
                c.particles,
                c.wall_seconds
            );
        }
    }
    s
}

/// A cell as text: "stable 0.12", "inaccurate 0.41", "FAILED t=0.0123".
pub fn cell_text(c: &Cell) -> String {
    match c.class {
        Class::Stable => format!("stable {:.3}", c.error.unwrap_or(f64::NAN)),
        Class::Inaccurate => format!("inaccurate {:.3}", c.error.unwrap_or(f64::NAN)),
        Class::Failed => format!("FAILED t={:.4}", c.blow_up_time.unwrap_or(f64::NAN)),
    }
}

/// The report: per map, a table with y down and x across.
pub fn markdown(r: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# meshfree stability maps ({:?} tier)\n", r.tier);
    let _ = writeln!(
        s,
        "Machine: {}; backend {}. Total wall time {:.1} s. Cells: stable (error within \
         tolerance), inaccurate (error over tolerance), FAILED (blow-up found by the health \
         check, with the simulated time).\n",
        r.machine, r.backend, r.wall_seconds
    );
    for m in &r.maps {
        let counts = |k: Class| m.cells.iter().filter(|c| c.class == k).count();
        let _ = writeln!(s, "## {}\n", m.def.title);
        let _ = writeln!(
            s,
            "dx = {}; error: {}; tolerance {}. {} stable, {} inaccurate, {} failed.\n",
            m.spacing,
            m.error_measure,
            m.cells.first().map(|c| c.tolerance).unwrap_or(f64::NAN),
            counts(Class::Stable),
            counts(Class::Inaccurate),
            counts(Class::Failed)
        );
        let _ = write!(
            s,
            "| {} \\ {} |",
            m.def.y.param.label(),
            m.def.x.param.label()
        );
        for x in &m.def.x.values {
            let _ = write!(s, " {x} |");
        }
        let _ = writeln!(s);
        let _ = writeln!(s, "|---|{}", "---|".repeat(m.def.x.values.len()));
        for (row, y) in m.def.y.values.iter().enumerate() {
            let _ = write!(s, "| {y} |");
            for col in 0..m.def.x.values.len() {
                let c = &m.cells[row * m.def.x.values.len() + col];
                let _ = write!(s, " {} |", cell_text(c));
            }
            let _ = writeln!(s);
        }
        let _ = writeln!(s, "\n![{}]({})\n", m.def.name, m.plot);
    }
    s
}
