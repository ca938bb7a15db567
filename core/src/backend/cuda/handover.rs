//! What one CUDA launch leaves on the device for a later one of the same step, so that the
//! later one launches less: the six marks of `Mark`, each with who leaves it, who takes or
//! reads it and what clears it, declared once in `Mark::rule`. `Handover` holds them (in
//! `Buffers`); every launch function names itself (`By`) when it leaves, takes or reads a
//! mark, and debug builds check it against the rule, so that a launch reading a mark it has
//! no business with fails the parity tests instead of using stale device data.
//! The CPU backend has no hand-over: its stages recompute what they need.

/// A mark one launch leaves for another.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// The grid build applied the equation of state (continuity density without artificial
    /// stress); the density pass that follows takes it and launches nothing, and a wall-force
    /// sample reads it (its own grid build leaves the pressures current).
    EosApplied,
    /// The drift filed every particle in its cell (`cell`, `count`) for the next grid build;
    /// that build takes it and skips its own filing pass. Whatever changes the slots first
    /// (`Buffers::reserve`, `write_state`, a subdomain's append or compaction) takes it and
    /// zeroes the counts. A graph of whole steps is captured only while it holds.
    CellsFiled,
    /// `Solver::time_step` found the step size due from `red` (the forces pass's maxima); the
    /// kick or the drift-kick that follows takes it (one launch fewer a step); anything else
    /// that reads dt or writes red first runs `sph_step_size` (`launch::settle_step_size`).
    StepSizeDue,
    /// The kick or drift-kick that took the step size from `red` left `red` as it was; the
    /// grid build's scatter zeroes `red` and clears it, and a forces pass that finds it (no
    /// grid build between: a test's order) zeroes `red` first.
    RedStale,
    /// A forces pass of one lane per particle recorded in `alt`'s `vel` and `pos` the
    /// accepted candidates of every particle with rates (`PairBits` in
    /// `cuda/device/neighbours.cuh`); a rates pass of one lane reads them instead of testing
    /// the candidates. Cleared by whatever moves a particle, changes the count or the grid,
    /// or writes `alt` (`Handover::moved`).
    PairsRecorded,
    /// A grid build stamped `Buffers::stamp` (3D, one lane per particle); the neighbour passes
    /// read the stamps only while it holds. Cleared with `PairsRecorded`.
    Stamped,
}

/// Who leaves, takes, reads or clears a mark: the launches of `launch/` and the storage
/// changes of `Buffers` and the subdomain exchange.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum By {
    GridBuild,
    Density,
    WallForces,
    TimeStep,
    /// `launch::step_size`, run where the step size is due and no kick takes it.
    StepSize,
    Kick,
    Drift,
    DriftKick,
    Forces,
    Rates,
    /// The solver between launches (whether to capture or replay a graph; parity tests).
    Solver,
    /// `Buffers::reserve`, `write_state`, a subdomain's append, compaction and unpack.
    Storage,
}

/// Of a mark: who may leave it, and who may take or read it.
pub struct Rule {
    pub leaves: &'static [By],
    pub takes: &'static [By],
}

impl Mark {
    /// The rule of this mark (its doc says why).
    pub const fn rule(self) -> Rule {
        use By::*;
        match self {
            Mark::EosApplied => Rule {
                leaves: &[GridBuild],
                takes: &[Density, WallForces, Storage, Solver],
            },
            Mark::CellsFiled => Rule {
                leaves: &[Drift, DriftKick],
                takes: &[GridBuild, Storage, Solver],
            },
            Mark::StepSizeDue => Rule {
                leaves: &[TimeStep],
                takes: &[StepSize, Kick, DriftKick],
            },
            Mark::RedStale => Rule {
                leaves: &[Kick, DriftKick],
                takes: &[GridBuild, Forces],
            },
            Mark::PairsRecorded => Rule {
                leaves: &[Forces],
                takes: &[Rates, Solver],
            },
            Mark::Stamped => Rule {
                leaves: &[GridBuild],
                takes: &[Forces, Rates, Solver],
            },
        }
    }

    const fn bit(self) -> u8 {
        1 << self as u8
    }
}

/// The marks that hold now.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Handover(u8);

impl Handover {
    /// `by` leaves `mark` (or clears it, where `on` is false: a grid build that applied no
    /// equation of state, stamped nothing).
    pub fn leave(&mut self, mark: Mark, on: bool, by: By) {
        debug_assert!(
            mark.rule().leaves.contains(&by),
            "{by:?} may not leave {mark:?} (handover.rs)"
        );
        if on {
            self.0 |= mark.bit();
        } else {
            self.0 &= !mark.bit();
        }
    }

    /// Whether `mark` holds, for `by` to read (it stays).
    pub fn holds(&self, mark: Mark, by: By) -> bool {
        debug_assert!(
            mark.rule().takes.contains(&by),
            "{by:?} may not read {mark:?} (handover.rs)"
        );
        self.0 & mark.bit() != 0
    }

    /// Whether `mark` held; `by` takes it (it no longer holds).
    pub fn take(&mut self, mark: Mark, by: By) -> bool {
        let held = self.holds(mark, by);
        self.0 &= !mark.bit();
        held
    }

    /// The particles moved, their count or the grid changed, or `alt` was written: the
    /// forces pass's record of pairs and the grid's stamps no longer hold.
    pub fn moved(&mut self) {
        self.0 &= !(Mark::PairsRecorded.bit() | Mark::Stamped.bit());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_mark_is_taken_once_and_moved_clears_the_pairs_and_stamps() {
        let mut h = Handover::default();
        h.leave(Mark::CellsFiled, true, By::Drift);
        h.leave(Mark::PairsRecorded, true, By::Forces);
        h.leave(Mark::Stamped, true, By::GridBuild);
        assert!(h.take(Mark::CellsFiled, By::GridBuild));
        assert!(!h.take(Mark::CellsFiled, By::GridBuild));
        h.moved();
        assert!(!h.holds(Mark::PairsRecorded, By::Rates));
        assert!(!h.holds(Mark::Stamped, By::Forces));
        h.leave(Mark::EosApplied, true, By::GridBuild);
        h.leave(Mark::EosApplied, false, By::GridBuild);
        assert!(!h.holds(Mark::EosApplied, By::Density));
    }

    #[test]
    #[cfg(debug_assertions)]
    #[should_panic(expected = "may not read")]
    fn a_launch_outside_the_rule_is_caught_in_debug_builds() {
        Handover::default().holds(Mark::PairsRecorded, By::Density);
    }
}
