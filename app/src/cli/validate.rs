//! `meshfree validate`: the accuracy cases against published references
//! (`meshfree_lab::validate`).

use std::path::PathBuf;

use super::named;
use meshfree_core::backend::BackendChoice;
use meshfree_core::scene::scheme::{Assignment, IntegratorChoice};

#[derive(Debug, clap::Args)]
pub struct ValidateArgs {
    /// The quick tier: one coarse resolution per case, robust checks (what the tests run).
    /// Without it: the full tier, three resolutions, literature tolerances, convergence order.
    #[arg(long)]
    pub quick: bool,
    /// Where to run: `auto` takes CUDA where a driver and a device answer, else the CPU.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// Output directory for report.md, report.json and the plots.
    #[arg(long, value_name = "DIR", default_value = "out/validate")]
    pub out: PathBuf,
    /// Run only this case (repeatable): hydrostatic-tank, dam-break, poiseuille, open-channel,
    /// taylor-green, cylinder, cylinder-onset, plate, cantilever, standing-wave, flume, gate
    /// (cylinder-onset and flume are full tier only: the quick tier skips them).
    #[arg(long, value_name = "NAME")]
    pub case: Vec<String>,
    /// Run every case at this Courant number (eq. (19)) instead of its own (its integrator's
    /// default: 0.4 for the leapfrog): what a larger step costs in accuracy.
    #[arg(long, value_name = "C")]
    pub courant: Option<f64>,
    /// Run every case with this integrator instead of its own (`symplectic-euler`,
    /// `leapfrog`, `euler`), at that integrator's default Courant number (0.2 for the Euler
    /// schemes) unless --courant gives one: what another scheme gives on the same cases.
    #[arg(long, value_parser = named::<IntegratorChoice>())]
    pub integrator: Option<IntegratorChoice>,
    /// Set a scheme key in every case's scenes that have its table (repeatable), e.g.
    /// `--set solid.fluid_pressure=extrapolated --set boundary.wall_density_floor=true`:
    /// what another scheme gives on the same cases. The keys are those of the scene files
    /// (`meshfree scenes --reference`); the value is TOML, or a bare word for a choice.
    #[arg(long = "set", value_name = "TABLE.KEY=VALUE")]
    pub set: Vec<Assignment>,
}

pub(super) fn validate(a: ValidateArgs) -> anyhow::Result<()> {
    let report = meshfree_lab::validate::run(&meshfree_lab::validate::Options {
        tier: if a.quick {
            meshfree_lab::validate::Tier::Quick
        } else {
            meshfree_lab::validate::Tier::Full
        },
        backend: a.backend,
        out_dir: a.out.clone(),
        cases: a.case,
        verbose: true,
        courant: a.courant,
        integrator: a.integrator,
        sets: a.set,
    })?;
    let failed = report.checks.iter().filter(|c| !c.pass).count();
    let (pass, checks, info) = report.counts();
    crate::outln!(
        "validate ({:?} tier): {pass} of {checks} checks pass ({info} more rows informational) in {:.1} s; report in {}",
        report.tier,
        report.wall_seconds,
        a.out.join("report.md").display()
    )?;
    anyhow::ensure!(failed == 0, "{failed} validation check(s) failed");
    Ok(())
}
