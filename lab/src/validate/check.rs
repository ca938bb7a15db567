//! A case's result rows: `Check` (a measured quantity, its reference, the error, a stated
//! tolerance, its basis and pass/fail), `RunInfo` (the run's bookkeeping that each row
//! carries), and the observed order of convergence (`convergence`, a row of its own, fitted
//! by `line_fit`).
//!
//! Every row says its `basis`: "literature" (tolerance from the publications or the
//! reference file's recommendation), "regression" (a looser quick-tier bound that catches
//! breakage, not a claim of accuracy) or "convergence" (observed order, must be positive).
//! A row the tier's resolution cannot make a check of is `informational`: reported, never
//! failing.

use serde::{Deserialize, Serialize};

use meshfree_core::solver::BackendInfo;

/// One measured quantity against its reference.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Check {
    pub case: String,
    pub quantity: String,
    /// The reference and where it comes from.
    pub source: String,
    /// The reference value (null where the reference is a whole curve).
    pub reference: Option<f64>,
    pub measured: f64,
    /// The number compared with `tolerance` (see `comparison`).
    pub error: f64,
    pub tolerance: f64,
    /// "error <= tolerance" or "error > tolerance" (orders of convergence).
    pub comparison: String,
    pub pass: bool,
    /// "literature", "regression" or "convergence" (see the module docs).
    pub basis: String,
    /// e.g. "dx = 0.05" or "dx = 0.05, 0.025, 0.0125".
    pub resolution: String,
    pub particles: usize,
    pub wall_seconds: f64,
    pub backend: String,
    pub device: String,
    pub plot: Option<String>,
    pub note: String,
}

/// A finished simulation's bookkeeping, for the `Check` rows.
#[derive(Clone, Debug)]
pub struct RunInfo {
    pub resolution: String,
    pub particles: usize,
    pub wall_seconds: f64,
    pub info: BackendInfo,
}

impl Check {
    /// A row with `error <= tolerance`.
    #[allow(clippy::too_many_arguments)]
    pub fn within(
        case: &str,
        quantity: &str,
        source: &str,
        reference: Option<f64>,
        measured: f64,
        error: f64,
        tolerance: f64,
        basis: &str,
        run: &RunInfo,
    ) -> Check {
        Check {
            case: case.into(),
            quantity: quantity.into(),
            source: source.into(),
            reference,
            measured,
            error,
            tolerance,
            comparison: "error <= tolerance".into(),
            pass: error.is_finite() && error <= tolerance,
            basis: basis.into(),
            resolution: run.resolution.clone(),
            particles: run.particles,
            wall_seconds: run.wall_seconds,
            backend: run.info.backend.clone(),
            device: run.info.device.clone(),
            plot: None,
            note: String::new(),
        }
    }

    /// The one row of a case whose run returned an error (`note`, after `wall_seconds`): it
    /// did not complete, and fails.
    pub fn did_not_complete(case: &str, wall_seconds: f64, note: String) -> Check {
        Check {
            case: case.into(),
            quantity: "run".into(),
            source: String::new(),
            reference: None,
            measured: f64::NAN,
            error: f64::NAN,
            tolerance: 0.0,
            comparison: "completes".into(),
            pass: false,
            basis: "regression".into(),
            resolution: String::new(),
            particles: 0,
            wall_seconds,
            backend: String::new(),
            device: String::new(),
            plot: None,
            note,
        }
    }

    pub fn with_plot(mut self, plot: &str) -> Check {
        self.plot = Some(plot.into());
        self
    }

    /// Reported, never failing (e.g. an order of convergence against an experiment).
    pub fn informational(mut self) -> Check {
        self.pass = true;
        self.comparison = "informational".into();
        self
    }

    /// Passes when `error > tolerance` instead (e.g. a quantity that must exceed a threshold).
    pub fn must_exceed(mut self) -> Check {
        self.comparison = "error > tolerance".into();
        self.pass = self.error.is_finite() && self.error > self.tolerance;
        self
    }

    pub fn with_note(mut self, note: impl Into<String>) -> Check {
        self.note = note.into();
        self
    }
}

/// The least-squares line y = slope x + intercept through `pts`: (slope, intercept), None
/// with fewer than two distinct x.
pub fn line_fit(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    (pts.len() >= 2 && sxx > 0.0).then(|| (sxy / sxx, my - sxy / sxx * mx))
}

/// The observed order of convergence: the least-squares slope of log(error) against
/// log(dx), as a row that passes when it is positive (the error shrinks with dx).
pub fn convergence(
    case: &str,
    quantity: &str,
    dx: &[f64],
    errors: &[f64],
    runs: &[RunInfo],
) -> Check {
    let pts: Vec<(f64, f64)> = dx
        .iter()
        .zip(errors)
        .filter(|(_, e)| **e > 0.0 && e.is_finite())
        .map(|(d, e)| (d.ln(), e.ln()))
        .collect();
    let order = line_fit(&pts).map_or(f64::NAN, |(slope, _)| slope);
    let last = runs.last().expect("at least one run");
    let resolution = dx
        .iter()
        .map(|d| format!("{d}"))
        .collect::<Vec<_>>()
        .join(", ");
    let errs = errors
        .iter()
        .map(|e| format!("{e:.4}"))
        .collect::<Vec<_>>()
        .join(", ");
    Check {
        case: case.into(),
        quantity: format!("observed order of convergence of {quantity}"),
        source: "slope of log(error) vs log(dx)".into(),
        reference: None,
        measured: order,
        error: order,
        tolerance: 0.0,
        comparison: "error > tolerance".into(),
        pass: order.is_finite() && order > 0.0,
        basis: "convergence".into(),
        resolution: format!("dx = {resolution}"),
        particles: runs.iter().map(|r| r.particles).sum(),
        wall_seconds: runs.iter().map(|r| r.wall_seconds).sum(),
        backend: last.info.backend.clone(),
        device: last.info.device.clone(),
        plot: None,
        note: format!("errors {errs}"),
    }
}
