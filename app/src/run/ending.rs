//! How a run ended: the stepping's stop (its end, or an interrupt) or a blow-up, the
//! summary's fields it owns (the status and what stopped the run), and what `run` returns.

use std::path::PathBuf;

use meshfree_core::solver::Fault;

use super::RunError;
use crate::output::{RunStatus, RunSummary};

/// Why the stepping stopped short of a blow-up.
pub(super) enum Stop {
    /// The end time or `--steps`.
    End,
    /// The interrupt flag (a signal, or the caller's).
    Interrupted,
}

/// How the run ended.
pub(super) enum Ending {
    Completed,
    /// By this signal (`SIGINT`, `SIGTERM`, `SIGHUP`).
    Interrupted(String),
    /// A blow-up, and the output index of the frame that holds the failing state.
    Failed(Fault, Option<usize>),
}

impl Ending {
    pub fn of(stop: Stop) -> Ending {
        match stop {
            Stop::End => Ending::Completed,
            Stop::Interrupted => Ending::Interrupted(crate::interrupt::signal_name().to_string()),
        }
    }

    /// The summary's status, the fault and its frame, or the signal.
    pub fn summarise(&self, s: &mut RunSummary) {
        match self {
            Ending::Completed => s.status = RunStatus::Completed,
            Ending::Interrupted(signal) => {
                s.status = RunStatus::Interrupted;
                s.interrupted_by = Some(signal.clone());
            }
            Ending::Failed(fault, frame) => {
                s.status = RunStatus::Failed;
                s.fault = Some(fault.clone());
                s.fault_frame = *frame;
            }
        }
    }

    /// What the run returns: the summary, or the interrupt or the blow-up with it.
    pub fn into_result(
        self,
        summary: RunSummary,
        out_dir: PathBuf,
    ) -> Result<RunSummary, RunError> {
        match self {
            Ending::Completed => Ok(summary),
            Ending::Interrupted(signal) => Err(RunError::Interrupted {
                signal,
                out_dir,
                summary: Box::new(summary),
            }),
            Ending::Failed(fault, _) => Err(RunError::BlowUp {
                fault: Box::new(fault),
                out_dir,
                summary: Box::new(summary),
            }),
        }
    }
}
