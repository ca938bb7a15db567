//! The whole validation's result, `Report` (the tier, the machine, the build, every case's
//! `Check` rows), and its two files: `report.json` (the report itself, read back by `docs`)
//! and `report.md` (a Markdown table per case, in the registry's order).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Context;
use serde::{Deserialize, Serialize};

use meshfree_core::named::Named;
use meshfree_core::scene::scheme::IntegratorChoice;

use super::check::Check;
use super::ctx::Tier;
use super::registry::CASES;

/// The whole validation result.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Report {
    pub tier: Tier,
    pub machine: String,
    /// The day of the run, `YYYY-MM-DD` (UTC).
    #[serde(default)]
    pub date: String,
    /// The build's commit (`meshfree_core::build_info::COMMIT`).
    #[serde(default)]
    pub commit: String,
    /// The Courant number every case ran at instead of its own (`Options::courant`).
    #[serde(default)]
    pub courant: Option<f64>,
    /// The integrator every case ran with instead of its own (`Options::integrator`).
    #[serde(default)]
    pub integrator: Option<IntegratorChoice>,
    /// The scheme keys every case's scenes ran with (`Options::sets`), `TABLE.KEY = VALUE`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sets: Vec<String>,
    pub wall_seconds: f64,
    pub pass: bool,
    pub checks: Vec<Check>,
}

impl Report {
    /// (checks that pass, checks, informational rows): informational rows are no checks.
    pub fn counts(&self) -> (usize, usize, usize) {
        let info = self
            .checks
            .iter()
            .filter(|c| c.comparison == "informational")
            .count();
        let checks = self.checks.len() - info;
        let pass = self
            .checks
            .iter()
            .filter(|c| c.pass && c.comparison != "informational")
            .count();
        (pass, checks, info)
    }

    /// Write `report.json` and `report.md` into `dir`.
    pub fn write(&self, dir: &Path) -> anyhow::Result<()> {
        let json = dir.join("report.json");
        std::fs::write(&json, serde_json::to_string_pretty(self)? + "\n")
            .with_context(|| format!("writing {}", json.display()))?;
        let md = dir.join("report.md");
        std::fs::write(&md, markdown(self)).with_context(|| format!("writing {}", md.display()))?;
        Ok(())
    }
}

/// The CPU model and core count, for the report.
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string());
    format!(
        "{cpu}, {} threads ({} build)",
        rayon::current_num_threads(),
        if cfg!(debug_assertions) {
            "debug"
        } else {
            "release"
        }
    )
}

fn num(x: Option<f64>) -> String {
    match x {
        Some(x) if x.is_finite() => format!("{x:.4}"),
        Some(_) => "-".into(),
        None => "curve".into(),
    }
}

/// The report as a Markdown table per case.
pub fn markdown(r: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# meshfree validation report ({:?} tier)\n", r.tier);
    let _ = writeln!(
        s,
        "Machine: {}. Build {}, run {}. Total wall time {:.1} s. Result: **{}** ({} of {} checks pass; \
         {} more rows informational).\n",
        r.machine,
        r.commit,
        r.date,
        r.wall_seconds,
        if r.pass { "PASS" } else { "FAIL" },
        r.counts().0,
        r.counts().1,
        r.counts().2
    );
    if let Some(c) = r.courant {
        let _ = writeln!(
            s,
            "Every case ran at Courant number {c} instead of its own.\n"
        );
    }
    if let Some(i) = r.integrator {
        let _ = writeln!(
            s,
            "Every case ran with the {} integrator instead of its own.\n",
            i.name()
        );
    }
    if !r.sets.is_empty() {
        let _ = writeln!(
            s,
            "Every scene with the key's table ran with {} instead of its own.\n",
            r.sets
                .iter()
                .map(|a| format!("`{a}`"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let _ = writeln!(
        s,
        "Basis: *literature* = tolerance from the publications or the reference file's \
         recommendation; *regression* = looser quick-tier bound that catches breakage; \
         *convergence* = observed order, must be positive. Rows marked *info:* are \
         informational: reported, never failing; each row's note says why.\n"
    );
    for case in CASES {
        let rows: Vec<&Check> = r.checks.iter().filter(|c| c.case == case.name).collect();
        if rows.is_empty() {
            continue;
        }
        let _ = writeln!(s, "## {}\n\n{}\n", case.name, case.description);
        let _ = writeln!(
            s,
            "| quantity | reference | measured | error | tolerance | pass | basis | resolution | particles | wall s | backend | device |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|");
        for c in &rows {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} {} | {} | {} | {} | {} | {:.1} | {} | {} |",
                c.quantity,
                num(c.reference),
                num(Some(c.measured)),
                num(Some(c.error)),
                match c.comparison.as_str() {
                    "error > tolerance" => ">",
                    "informational" => "info:",
                    _ => "<=",
                },
                c.tolerance,
                if c.pass { "yes" } else { "**NO**" },
                c.basis,
                c.resolution,
                c.particles,
                c.wall_seconds,
                c.backend,
                c.device
            );
        }
        let _ = writeln!(s);
        for c in &rows {
            if !c.note.is_empty() || !c.source.is_empty() {
                let _ = writeln!(s, "- *{}*: reference: {}. {}", c.quantity, c.source, c.note);
            }
        }
        let mut plots: Vec<&str> = rows.iter().filter_map(|c| c.plot.as_deref()).collect();
        plots.dedup();
        for p in plots {
            let _ = writeln!(s, "\n![{p}]({p})");
        }
        let _ = writeln!(s);
    }
    s
}
