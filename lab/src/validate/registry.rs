//! The list of cases, in report order: each case's name, description, run function and
//! whether the quick tier runs it. A new case is a file of its own in this folder, declared in
//! `mod.rs` and listed here.

use super::check::Check;
use super::ctx::Ctx;
use super::{
    cantilever, cylinder, cylinder_onset, dam_break, flume, gate, hydrostatic, open_channel, plate,
    poiseuille, standing_wave, taylor_green,
};

/// One validation case.
pub struct Case {
    pub name: &'static str,
    pub description: &'static str,
    pub run: fn(&Ctx) -> anyhow::Result<Vec<Check>>,
    /// false: full tier only (the quick tier skips it, e.g. a run that needs t U / D ~ 100).
    pub quick: bool,
}

/// The registry, in report order.
pub const CASES: &[Case] = &[
    Case {
        name: hydrostatic::NAME,
        description: hydrostatic::DESCRIPTION,
        run: hydrostatic::run,
        quick: true,
    },
    Case {
        name: dam_break::NAME,
        description: dam_break::DESCRIPTION,
        run: dam_break::run,
        quick: true,
    },
    Case {
        name: poiseuille::NAME,
        description: poiseuille::DESCRIPTION,
        run: poiseuille::run,
        quick: true,
    },
    Case {
        name: open_channel::NAME,
        description: open_channel::DESCRIPTION,
        run: open_channel::run,
        quick: true,
    },
    Case {
        name: taylor_green::NAME,
        description: taylor_green::DESCRIPTION,
        run: taylor_green::run,
        quick: true,
    },
    Case {
        name: cylinder::NAME,
        description: cylinder::DESCRIPTION,
        run: cylinder::run,
        quick: true,
    },
    Case {
        name: cylinder_onset::NAME,
        description: cylinder_onset::DESCRIPTION,
        run: cylinder_onset::run,
        quick: false,
    },
    Case {
        name: plate::NAME,
        description: plate::DESCRIPTION,
        run: plate::run,
        quick: true,
    },
    Case {
        name: cantilever::NAME,
        description: cantilever::DESCRIPTION,
        run: cantilever::run,
        quick: true,
    },
    Case {
        name: standing_wave::NAME,
        description: standing_wave::DESCRIPTION,
        run: standing_wave::run,
        quick: true,
    },
    Case {
        name: flume::NAME,
        description: flume::DESCRIPTION,
        run: flume::run,
        quick: false,
    },
    Case {
        name: gate::NAME,
        description: gate::DESCRIPTION,
        run: gate::run,
        quick: true,
    },
];

/// An error naming the known cases unless every name in `names` is one of them.
pub fn ensure_known(names: &[String]) -> anyhow::Result<()> {
    for c in names {
        if !CASES.iter().any(|k| k.name == c) {
            anyhow::bail!(
                "unknown validation case `{c}`; known: {}",
                CASES.iter().map(|k| k.name).collect::<Vec<_>>().join(", ")
            );
        }
    }
    Ok(())
}
