//! The scene's force monitors during a run (`[[monitors]]`): when each samples next, its
//! samples and its `<name>.csv`. The force itself is `Solver::wall_forces` (on the solver's
//! own state; summed on the device by the CUDA backend), whose sum is
//! `meshfree_core::measure::monitor::wall_force`'s. With them, the floating bodies'
//! `floating.csv`, a row per body every output interval (`Solver::bodies`), and the open
//! boundaries' `open_boundaries.csv`, a row per boundary likewise (`Readback::open_tally`).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use meshfree_core::measure::monitor::{BluffBody, ForceSample, MonitorSummary};
use meshfree_core::scene::{format, Scene};
use meshfree_core::solver::step::reached;
use meshfree_core::solver::Solver;

use crate::output::{FloatingCsv, ForcesCsv, OpenCsv};

/// The scene's monitors during a run: when each samples next, its samples and its CSV.
pub struct Monitors {
    list: Vec<Active>,
    /// [M L^-d] rho0 of the coefficients.
    rho0: f64,
    dim: i32,
    /// [L] domain extent along y, for the blockage ratio.
    height: f64,
    /// The floating bodies' CSV, where the scene has any.
    floating: Option<Floating>,
    /// The open boundaries' CSV, where the scene has any.
    open: Option<Open>,
}

/// `open_boundaries.csv` and when it takes its next rows.
struct Open {
    csv: OpenCsv,
    path: PathBuf,
    /// \[T\] every output interval.
    interval: f64,
    next: f64,
}

/// `floating.csv` and when it takes its next rows.
struct Floating {
    csv: FloatingCsv,
    path: PathBuf,
    /// \[T\] every output interval.
    interval: f64,
    next: f64,
    gravity: [f32; 3],
}

struct Active {
    spec: format::Monitor,
    group: u32,
    next: f64,
    samples: Vec<ForceSample>,
    csv: ForcesCsv,
    path: PathBuf,
}

/// The monitors' part of a checkpoint: per monitor, the next sample time \[T\] and the
/// samples so far (the summary's statistics take them all), and the length of each CSV.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct MonitorsState {
    pub next: Vec<f64>,
    pub samples: Vec<Vec<ForceSample>>,
    /// (file name in the run directory, bytes).
    pub files: Vec<(String, u64)>,
    /// \[T\] the next rows of `floating.csv` (none without floating bodies).
    #[serde(default)]
    pub floating_next: Option<f64>,
    /// \[T\] the next rows of `open_boundaries.csv` (none without open boundaries).
    #[serde(default)]
    pub open_next: Option<f64>,
}

impl Monitors {
    /// Open `<name>.csv` in `dir` for each of the scene's monitors; continuing a run from a
    /// checkpoint (`resume`), open them at their ends and carry on from its state.
    pub fn create(
        scene: &Scene,
        dir: &Path,
        resume: Option<&MonitorsState>,
    ) -> Result<Monitors, (PathBuf, std::io::Error)> {
        let f = &scene.file;
        let mut list = Vec::new();
        for (k, m) in f.monitors.iter().enumerate() {
            let path = dir.join(crate::output::files::monitor_file(&m.name));
            let coefficients = m.reference_velocity.is_some();
            let csv = ForcesCsv::open(&path, resume.is_some(), coefficients)
                .map_err(|e| (path.clone(), e))?;
            list.push(Active {
                spec: m.clone(),
                group: scene.wall_group(m.wall),
                next: resume.and_then(|r| r.next.get(k).copied()).unwrap_or(0.0),
                samples: resume
                    .and_then(|r| r.samples.get(k).cloned())
                    .unwrap_or_default(),
                csv,
                path,
            });
        }
        let floating = if f.walls.iter().any(|w| w.floating().is_some()) {
            let path = dir.join(crate::output::files::FLOATING);
            let csv = FloatingCsv::open(&path, resume.is_some()).map_err(|e| (path.clone(), e))?;
            let p = scene.params();
            Some(Floating {
                csv,
                path,
                interval: f.time.output_interval,
                next: resume.and_then(|r| r.floating_next).unwrap_or(0.0),
                gravity: p.gravity,
            })
        } else {
            None
        };
        let open = if f.open_boundaries.is_empty() {
            None
        } else {
            let path = dir.join(crate::output::files::OPEN_BOUNDARIES);
            let csv = OpenCsv::open(&path, resume.is_some()).map_err(|e| (path.clone(), e))?;
            Some(Open {
                csv,
                path,
                interval: f.time.output_interval,
                next: resume.and_then(|r| r.open_next).unwrap_or(0.0),
            })
        };
        Ok(Monitors {
            list,
            floating,
            open,
            rho0: f.fluid.density,
            dim: f.dimension as i32,
            height: f.domain.max[1] - f.domain.min[1],
        })
    }

    /// The files they write into the run's directory.
    pub fn file_names(&self) -> Vec<String> {
        (self.list.iter())
            .map(|m| crate::output::files::monitor_file(&m.spec.name))
            .chain(
                self.floating
                    .as_ref()
                    .map(|_| crate::output::files::FLOATING.to_string()),
            )
            .chain(
                self.open
                    .as_ref()
                    .map(|_| crate::output::files::OPEN_BOUNDARIES.to_string()),
            )
            .collect()
    }

    /// The monitors' part of a checkpoint (every row so far flushed).
    pub fn state(&self) -> Result<MonitorsState, (PathBuf, std::io::Error)> {
        let mut files = Vec::new();
        let paths = (self.list.iter().map(|m| &m.path))
            .chain(self.floating.as_ref().map(|f| &f.path))
            .chain(self.open.as_ref().map(|o| &o.path));
        for path in paths {
            let len = std::fs::metadata(path)
                .map_err(|e| (path.clone(), e))?
                .len();
            let name = path.file_name().unwrap_or_default().to_string_lossy();
            files.push((name.into_owned(), len));
        }
        Ok(MonitorsState {
            next: self.list.iter().map(|m| m.next).collect(),
            samples: self.list.iter().map(|m| m.samples.clone()).collect(),
            files,
            floating_next: self.floating.as_ref().map(|f| f.next),
            open_next: self.open.as_ref().map(|o| o.next),
        })
    }

    /// The time of the next sample, if there is a monitor.
    pub fn next_time(&self) -> Option<f64> {
        (self.list.iter().map(|m| m.next))
            .chain(self.floating.as_ref().map(|f| f.next))
            .chain(self.open.as_ref().map(|o| o.next))
            .min_by(f64::total_cmp)
    }

    /// Sample every monitor whose time the clock reached (`step::reached`): one call of
    /// `Solver::wall_forces` for all of them.
    pub fn sample_due(&mut self, solver: &mut dyn Solver) -> Result<(), (PathBuf, std::io::Error)> {
        let t = solver.time();
        if self.next_time().is_none_or(|n| !reached(t, n)) {
            return Ok(());
        }
        if let Some(f) = self.floating.as_mut().filter(|f| reached(t, f.next)) {
            let bodies = solver.bodies();
            f.csv
                .write(t, f.gravity, &bodies)
                .map_err(|e| (f.path.clone(), e))?;
            f.next = ((t / f.interval + 1e-9).floor() + 1.0) * f.interval;
        }
        if let Some(o) = self.open.as_mut().filter(|o| reached(t, o.next)) {
            let tally = solver.open_tally();
            o.csv.write(t, &tally).map_err(|e| (o.path.clone(), e))?;
            o.next = ((t / o.interval + 1e-9).floor() + 1.0) * o.interval;
        }
        let due: Vec<usize> = (0..self.list.len())
            .filter(|&k| reached(t, self.list[k].next))
            .collect();
        let groups: Vec<u32> = due.iter().map(|&k| self.list[k].group).collect();
        let forces = solver.wall_forces(&groups);
        for (&k, force) in due.iter().zip(forces) {
            let m = &mut self.list[k];
            // The coefficients' dynamic pressure times area, where the monitor has scales.
            let q = (m.spec.reference_velocity.zip(m.spec.reference_length))
                .map(|(u, d)| 0.5 * self.rho0 * u * u * d.powi(self.dim - 1));
            let s = ForceSample {
                t,
                force,
                cd: q.map_or(0.0, |q| force[0] / q),
                cl: q.map_or(0.0, |q| force[1] / q),
            };
            m.csv.write(&s).map_err(|e| (m.path.clone(), e))?;
            m.samples.push(s);
            m.next = ((t / m.spec.interval + 1e-9).floor() + 1.0) * m.spec.interval;
        }
        Ok(())
    }

    /// The statistics of every monitor (`MonitorSummary::of`).
    pub fn summaries(&self) -> Vec<MonitorSummary> {
        self.list
            .iter()
            .map(|m| {
                let body = (m.spec.reference_velocity.zip(m.spec.reference_length)).map(
                    |(velocity, length)| BluffBody {
                        velocity,
                        length,
                        blockage_ratio: length / self.height,
                    },
                );
                MonitorSummary::of(&m.spec.name, m.spec.wall, &m.samples, body)
            })
            .collect()
    }
}
