//! `meshfree compare`: two particle CSV files, per-field error norms and the worst pairs
//! (`crate::compare`).

use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct CompareArgs {
    /// The particle CSV to check (e.g. the GPU run's).
    pub a: PathBuf,
    /// The reference particle CSV (e.g. the CPU run's).
    pub b: PathBuf,
    /// Pair particles by id (same scene) or by nearest position (different codes).
    #[arg(long = "match", value_enum, default_value_t = crate::compare::MatchBy::Id)]
    pub match_by: crate::compare::MatchBy,
    /// How many of the farthest-apart pairs to list.
    #[arg(long, default_value_t = 5)]
    pub worst: usize,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

pub(super) fn compare(a: CompareArgs) -> anyhow::Result<()> {
    // An unreadable or malformed file is bad input (exit 2), as `--help` lists.
    let c = crate::compare::compare_files(&a.a, &a.b, a.match_by, a.worst)
        .map_err(crate::bad_input::BadInput)?;
    if a.json {
        crate::outln!("{}", serde_json::to_string_pretty(&c)?)?;
        return Ok(());
    }
    crate::outln!(
        "{} pairs matched by {:?}; {} particles only in A, {} only in B",
        c.matched,
        a.match_by,
        c.only_in_a,
        c.only_in_b
    )?;
    crate::outln!(
        "{:<9} {:>12} {:>12} {:>12} {:>9}",
        "field",
        "max |A-B|",
        "rms",
        "rel. L2",
        "worst id"
    )?;
    for f in &c.fields {
        crate::outln!(
            "{:<9} {:>12.4e} {:>12.4e} {:>12.4e} {:>9}",
            f.field,
            f.max_abs,
            f.rms,
            f.rel_l2,
            f.worst_id
        )?;
    }
    crate::outln!("farthest pairs (id in A, id in B, distance):")?;
    for (ia, ib, d) in &c.worst_positions {
        crate::outln!("  {ia:>8} {ib:>8} {d:.4e}")?;
    }
    Ok(())
}
