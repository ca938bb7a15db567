//! `meshfree chart`: error against wall time with the Pareto front (`meshfree_lab::chart`).

use std::path::PathBuf;

use super::named;
use meshfree_core::backend::BackendChoice;

#[derive(Debug, clap::Args)]
pub struct ChartArgs {
    /// The quick tier: two coarse resolutions and one variant per case (seconds).
    /// Without it: four resolutions and nine variants per case (minutes in a release build),
    /// and the cylinder at Re 100 (three resolutions, ten variants: for the GPU). A variant
    /// that does not apply to a case's scheme or changes nothing in it is skipped, with
    /// its reason on stderr and in chart.csv.
    #[arg(long)]
    pub quick: bool,
    /// Where to run (repeatable: `--backend cpu --backend cuda` puts both on the charts).
    #[arg(long, value_parser = named::<BackendChoice>(), default_values = ["auto"])]
    pub backend: Vec<BackendChoice>,
    /// Output directory for `chart-<case>.png`, `chart.csv` and `chart.json`.
    #[arg(long, value_name = "DIR", default_value = "out/chart")]
    pub out: PathBuf,
}

pub(super) fn chart(a: ChartArgs) -> anyhow::Result<()> {
    use meshfree_lab::chart;
    use meshfree_lab::validate::Tier;
    let points = chart::run(&chart::Options {
        tier: if a.quick { Tier::Quick } else { Tier::Full },
        backends: a.backend,
        out_dir: a.out.clone(),
        verbose: true,
    })?;
    let skipped = points.iter().filter(|p| p.skipped.is_some()).count();
    let failed = points
        .iter()
        .filter(|p| p.error.is_none() && p.skipped.is_none())
        .count();
    crate::outln!(
        "chart: {} runs ({failed} failed, {} on the Pareto front), {skipped} variants skipped \
         (see chart.csv); charts in {}",
        points.len() - skipped,
        points.iter().filter(|p| p.pareto).count(),
        a.out.display()
    )?;
    Ok(())
}
