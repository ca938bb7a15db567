//! `meshfree stability`: maps of two swept parameters, each run stable, inaccurate or failed
//! (`meshfree_lab::stability`).

use std::path::PathBuf;

use super::named;
use meshfree_core::backend::BackendChoice;

#[derive(Debug, clap::Args)]
pub struct StabilityArgs {
    /// The quick tier: two values per axis on coarse scenes (seconds; what the tests run).
    /// Without it: five values per axis, dx = 0.04 dam break (tens of minutes on a CPU).
    #[arg(long)]
    pub quick: bool,
    /// Where to run: `auto` takes CUDA where a driver and a device answer, else the CPU.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// Output directory for report.md, report.json, cells.csv and the heat maps.
    #[arg(long, value_name = "DIR", default_value = "out/stability")]
    pub out: PathBuf,
    /// Run only the maps whose name contains this (repeatable), e.g. `elastic-strip`.
    #[arg(long, value_name = "NAME")]
    pub map: Vec<String>,
}

pub(super) fn stability(a: StabilityArgs) -> anyhow::Result<()> {
    use meshfree_lab::stability::{self, Class};
    let report = stability::run(&stability::Options {
        tier: if a.quick {
            stability::Tier::Quick
        } else {
            stability::Tier::Full
        },
        backend: a.backend,
        out_dir: a.out.clone(),
        maps: a.map,
        verbose: true,
    })?;
    for m in &report.maps {
        let n = |k: Class| m.cells.iter().filter(|c| c.class == k).count();
        crate::outln!(
            "{}: {} stable, {} inaccurate, {} failed",
            m.def.name,
            n(Class::Stable),
            n(Class::Inaccurate),
            n(Class::Failed)
        )?;
    }
    crate::outln!(
        "stability ({:?} tier) in {:.1} s; report in {}",
        report.tier,
        report.wall_seconds,
        a.out.join("report.md").display()
    )?;
    Ok(())
}
