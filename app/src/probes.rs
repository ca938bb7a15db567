//! The scene's probes and free-surface gauges during a run (`[[probes]]`, `[[gauges]]`):
//! when each samples next, and its rows of `probes.csv` and `gauges.csv`. The values come
//! from `Solver::sample_points` (interpolated on the device on the GPU: no particle
//! read-back); a gauge's surface from the colours of its line's points,
//! `meshfree_core::measure::probe::surface`.
//!
//! Both files are long ("tidy") CSV, one row per point (probes) or gauge per sample, in the
//! scene's order; a cell is empty where the value is not a number (a probe with no fluid
//! particle within the support, a dry gauge), which pandas reads as NaN:
//!
//! - `probes.csv`: `time,step,probe,point,x,y[,z]` then, for each field that any probe
//!   samples, `pressure`, `velocity_x,velocity_y[,velocity_z]`, `density` (a probe's other
//!   fields' cells are empty). `point` is the index in the probe's `points`; x, y, z its
//!   position. `df.pivot_table(index="time", columns=["probe", "point"], values="pressure")`
//!   gives one column per point.
//! - `gauges.csv`: `time,step,gauge,x,y[,z],distance`: the surface point on the line and
//!   its distance from `start`.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use meshfree_core::measure::probe::{gauge_points, surface};
use meshfree_core::scene::format::{Gauge, Probe, ProbeField};
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::reached;
use meshfree_core::solver::{PointSample, Solver};
use serde::{Deserialize, Serialize};

type IoResult = Result<(), (PathBuf, std::io::Error)>;

/// The probes' part of a checkpoint: each probe's and gauge's next sample time \[T\], and
/// the length of each CSV.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct ProbesState {
    pub probes: Vec<f64>,
    pub gauges: Vec<f64>,
    /// (file name in the run directory, bytes).
    pub files: Vec<(String, u64)>,
}

/// The scene's probes and gauges during a run.
pub struct Probes {
    probes: Vec<ActiveProbe>,
    gauges: Vec<ActiveGauge>,
    probes_csv: Option<Csv>,
    gauges_csv: Option<Csv>,
    /// The fields of `probes.csv`'s columns: those any probe samples, in `ProbeField::ALL`
    /// order.
    columns: Vec<ProbeField>,
    dim: usize,
    /// Scratch for `Solver::sample_points`.
    points: Vec<[f32; 3]>,
    samples: Vec<PointSample>,
}

struct ActiveProbe {
    spec: Probe,
    points: Vec<[f32; 3]>,
    next: f64,
}

struct ActiveGauge {
    spec: Gauge,
    /// [L] the line's points.
    line: Vec<[f64; 3]>,
    next: f64,
}

struct Csv {
    w: BufWriter<File>,
    path: PathBuf,
}

impl Csv {
    fn open(path: PathBuf, header: &str, append: bool) -> Result<Csv, (PathBuf, std::io::Error)> {
        let w = crate::output::open_csv(&path, header, append).map_err(|e| (path.clone(), e))?;
        Ok(Csv { w, path })
    }
    fn err(&self) -> impl FnOnce(std::io::Error) -> (PathBuf, std::io::Error) + '_ {
        move |e| (self.path.clone(), e)
    }
}

/// A CSV cell: empty where not a number (f32 values print in their shortest form).
fn cell<T: Into<f64> + std::fmt::Display + Copy>(x: T) -> String {
    if x.into().is_finite() {
        format!("{x}")
    } else {
        String::new()
    }
}

/// The next sample time after `t` on a grid of `interval`.
fn next_after(t: f64, interval: f64) -> f64 {
    ((t / interval + 1e-9).floor() + 1.0) * interval
}

impl Probes {
    /// Open `probes.csv` (if the scene has probes) and `gauges.csv` (if it has gauges) in
    /// `dir` and write their headers.
    ///
    /// Continuing a run from a checkpoint (`resume`), the files are opened at their ends and
    /// the sample times carried on.
    pub fn create(
        scene: &Scene,
        dir: &Path,
        resume: Option<&ProbesState>,
    ) -> Result<Probes, (PathBuf, std::io::Error)> {
        let append = resume.is_some();
        let f = &scene.file;
        let dim = f.dimension as usize;
        let axes = ["x", "y", "z"];
        let columns: Vec<ProbeField> = ProbeField::ALL
            .into_iter()
            .filter(|c| f.probes.iter().any(|p| p.fields.contains(c)))
            .collect();
        let probes_csv = if f.probes.is_empty() {
            None
        } else {
            let mut header = String::from("time,step,probe,point");
            for a in &axes[..dim] {
                header += &format!(",{a}");
            }
            for c in &columns {
                match c {
                    ProbeField::Velocity => {
                        for a in &axes[..dim] {
                            header += &format!(",velocity_{a}");
                        }
                    }
                    _ => header += &format!(",{}", c.name()),
                }
            }
            Some(Csv::open(
                dir.join(crate::output::files::PROBES),
                &header,
                append,
            )?)
        };
        let gauges_csv = if f.gauges.is_empty() {
            None
        } else {
            let header = format!("time,step,gauge,{},distance", axes[..dim].join(","));
            Some(Csv::open(
                dir.join(crate::output::files::GAUGES),
                &header,
                append,
            )?)
        };
        let mut probes: Vec<ActiveProbe> = f
            .probes
            .iter()
            .map(|p| ActiveProbe {
                spec: p.clone(),
                points: p
                    .points
                    .iter()
                    .map(|x| [0, 1, 2].map(|a| x.get(a).copied().unwrap_or(0.0) as f32))
                    .collect(),
                next: 0.0,
            })
            .collect();
        let mut gauges: Vec<ActiveGauge> = f
            .gauges
            .iter()
            .map(|g| ActiveGauge {
                spec: g.clone(),
                line: gauge_points(g, f.discretisation.spacing, dim),
                next: 0.0,
            })
            .collect();
        if let Some(r) = resume {
            for (p, &t) in probes.iter_mut().zip(&r.probes) {
                p.next = t;
            }
            for (g, &t) in gauges.iter_mut().zip(&r.gauges) {
                g.next = t;
            }
        }
        Ok(Probes {
            probes,
            gauges,
            probes_csv,
            gauges_csv,
            columns,
            dim,
            points: Vec::new(),
            samples: Vec::new(),
        })
    }

    /// The files they write into the run's directory.
    pub fn file_names(&self) -> Vec<String> {
        let csv = [&self.probes_csv, &self.gauges_csv].into_iter().flatten();
        csv.map(|c| {
            c.path
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned()
        })
        .collect()
    }

    /// The probes' part of a checkpoint (every row so far flushed).
    pub fn state(&self) -> Result<ProbesState, (PathBuf, std::io::Error)> {
        let mut files = Vec::new();
        for csv in [&self.probes_csv, &self.gauges_csv].into_iter().flatten() {
            let len = std::fs::metadata(&csv.path).map_err(csv.err())?.len();
            let name = csv.path.file_name().unwrap_or_default().to_string_lossy();
            files.push((name.into_owned(), len));
        }
        Ok(ProbesState {
            probes: self.probes.iter().map(|p| p.next).collect(),
            gauges: self.gauges.iter().map(|g| g.next).collect(),
            files,
        })
    }

    /// The time of the next sample, if there is a probe or a gauge.
    pub fn next_time(&self) -> Option<f64> {
        (self.probes.iter().map(|p| p.next))
            .chain(self.gauges.iter().map(|g| g.next))
            .min_by(f64::total_cmp)
    }

    /// Sample every probe and gauge whose time the clock reached (`step::reached`): one
    /// `sample_points` for the gauges and the probes without walls, one for those with.
    pub fn sample_due(&mut self, solver: &mut dyn Solver) -> IoResult {
        let t = solver.time();
        if self.next_time().is_none_or(|n| !reached(t, n)) {
            return Ok(());
        }
        let step = solver.steps();
        for walls in [false, true] {
            self.points.clear();
            let probes =
                (self.probes.iter()).filter(|p| p.spec.walls == walls && reached(t, p.next));
            for p in probes {
                self.points.extend_from_slice(&p.points);
            }
            if !walls {
                for g in self.gauges.iter().filter(|g| reached(t, g.next)) {
                    (self.points).extend(g.line.iter().map(|x| x.map(|c| c as f32)));
                }
            }
            if self.points.is_empty() {
                continue;
            }
            solver.sample_points(&self.points, walls, &mut self.samples);
            let mut at = 0;
            for k in 0..self.probes.len() {
                let p = &self.probes[k];
                if p.spec.walls != walls || !reached(t, p.next) {
                    continue;
                }
                let n = p.points.len();
                self.write_probe(k, t, step, at)?;
                at += n;
            }
            if !walls {
                for k in 0..self.gauges.len() {
                    if !reached(t, self.gauges[k].next) {
                        continue;
                    }
                    let n = self.gauges[k].line.len();
                    self.write_gauge(k, t, step, at)?;
                    at += n;
                }
            }
        }
        for p in self.probes.iter_mut().filter(|p| reached(t, p.next)) {
            p.next = next_after(t, p.spec.interval);
        }
        for g in self.gauges.iter_mut().filter(|g| reached(t, g.next)) {
            g.next = next_after(t, g.spec.interval);
        }
        for csv in [&mut self.probes_csv, &mut self.gauges_csv]
            .into_iter()
            .flatten()
        {
            csv.w.flush().map_err(|e| (csv.path.clone(), e))?;
        }
        Ok(())
    }

    /// Probe `k`'s rows from `self.samples[at..]`.
    fn write_probe(&mut self, k: usize, t: f64, step: u64, at: usize) -> IoResult {
        let (p, dim) = (&self.probes[k], self.dim);
        let csv = self.probes_csv.as_mut().expect("probes.csv is open");
        for (i, (x, s)) in p.points.iter().zip(&self.samples[at..]).enumerate() {
            let mut row = format!("{t},{step},{},{i}", p.spec.name);
            for c in &x[..dim] {
                row += &format!(",{c}");
            }
            for c in &self.columns {
                let on = p.spec.fields.contains(c);
                let values: &[f32] = match c {
                    ProbeField::Pressure => std::slice::from_ref(&s.pressure),
                    ProbeField::Velocity => &s.velocity[..dim],
                    ProbeField::Density => std::slice::from_ref(&s.density),
                };
                for v in values {
                    row.push(',');
                    if on {
                        row += &cell(*v);
                    }
                }
            }
            writeln!(csv.w, "{row}").map_err(csv.err())?;
        }
        Ok(())
    }

    /// Gauge `k`'s row from the colours in `self.samples[at..]`.
    fn write_gauge(&mut self, k: usize, t: f64, step: u64, at: usize) -> IoResult {
        let (g, dim) = (&self.gauges[k], self.dim);
        let n = g.line.len();
        let colour: Vec<f32> = self.samples[at..at + n].iter().map(|s| s.colour).collect();
        let found = surface(&g.line, &colour);
        let csv = self.gauges_csv.as_mut().expect("gauges.csv is open");
        let mut row = format!("{t},{step},{}", g.spec.name);
        for a in 0..dim {
            row.push(',');
            row += &cell(found.map_or(f64::NAN, |s| s.position[a]));
        }
        row.push(',');
        row += &cell(found.map_or(f64::NAN, |s| s.distance));
        writeln!(csv.w, "{row}").map_err(csv.err())
    }
}
