//! What a decomposed run asks of each rank: `Call`, the rank's `Reply`, and the `Status`
//! every reply carries. `Decomposed` speaks to its ranks in these words only, so that a
//! rank may be a thread of the same process (`Threads`) or another process (`meshfree run
//! --mpi`, where a call and its reply travel serialised).

use serde::{Deserialize, Serialize};

use crate::exchange::{ExchangeStats, Rank, Slab, Subdomain, Transport};
use crate::physics::particle::Particle;
use crate::solver::checkpoint::{Piece, SolverCheckpoint};
use crate::solver::frame::{FrameData, PendingFrame};
use crate::solver::{
    BackendInfo, Diagnostics, Fault, Persist, PointSample, Readback, Shown, Snapshot, Solver, Stage,
};

/// One thing every rank does at once (the ranks meet in the transport's collective calls
/// where the work needs the others: the halo of a grid build, the step size).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum Call {
    /// `Solver::info`.
    Info,
    /// Run a stage of `Solver` (`Stage::run`; a rank adds its exchange to three of them).
    Stage(Stage),
    Step,
    Advance(u64),
    Time,
    Check,
    Diagnostics,
    Particles,
    Capture(crate::solver::frame::Fields),
    Snapshot(Shown),
    SamplePoints {
        points: Vec<[f32; 3]>,
        include_walls: bool,
    },
    Save,
    SavePiece,
    /// Take these particles (`Subdomain::replace`): this rank's part of a restore.
    Restore(SolverCheckpoint),
    /// Own `slabs[rank]` from now on, holding `part` (a move of the cuts, or a restore of
    /// per-rank pieces).
    Recut {
        slabs: Vec<Slab>,
        part: SolverCheckpoint,
    },
    RemoveGroup(u32),
    WallForces(Vec<u32>),
    /// The end of the run: a rank in another process stops serving (`Threads` ignores it).
    Stop,
}

/// A rank's answer to a `Call`.
#[derive(Serialize, Deserialize)]
pub enum Reply {
    Done,
    Info(BackendInfo),
    Time(f64),
    Checked(Result<(), Fault>),
    Diagnostics(Diagnostics),
    Particles(Vec<Particle>),
    /// A frame delivered (`Reply::delivered` turns `Pending` into this where the reply
    /// leaves the process).
    Frame(FrameData),
    /// A frame the device could not deliver, and why.
    Failed(String),
    Snapshot(Snapshot),
    Samples(Vec<PointSample>),
    State(SolverCheckpoint),
    Piece(Piece),
    Restored(Result<(), String>),
    Removed(usize),
    Forces(Vec<[f64; 3]>),
    /// A frame on its way (a GPU's copies in flight); in the same process only. Last: a
    /// variant serde skips must not shift the others' indices.
    #[serde(skip)]
    Pending(Box<dyn PendingFrame>),
}

impl Reply {
    /// The same reply with any frame waited for: what can be serialised.
    pub fn delivered(self) -> Reply {
        match self {
            Reply::Pending(p) => p.wait().map_or_else(Reply::Failed, Reply::Frame),
            r => r,
        }
    }

    /// The frame of a `Capture`, pending or delivered.
    pub(crate) fn into_frame(self) -> Box<dyn PendingFrame> {
        match self {
            Reply::Pending(p) => p,
            Reply::Frame(f) => Box::new(Ready(Ok(f))),
            Reply::Failed(why) => Box::new(Ready(Err(why))),
            _ => unexpected("a frame"),
        }
    }
}

/// A frame already delivered (or failed).
struct Ready(Result<FrameData, String>);

impl PendingFrame for Ready {
    fn wait(self: Box<Self>) -> Result<FrameData, String> {
        self.0
    }
}

/// A reply of another kind than the call asks for: a rank out of step with the others,
/// which is a bug, not bad input.
pub(crate) fn unexpected(what: &str) -> ! {
    panic!("a rank answered a call with something other than {what}")
}

/// What the caller keeps of each rank after every call, for the `Solver` queries that take
/// `&self` (a rank in another process cannot be asked then).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Status {
    /// Particles it holds.
    pub len: usize,
    pub steps: u64,
    pub has_solids: bool,
    pub stats: ExchangeStats,
    /// `Subdomain::device_bytes`.
    pub device_bytes: usize,
}

impl<S: Subdomain, T: Transport<S::Halo>> Rank<S, T> {
    /// Carry out `call`; the reply, and this rank's status after it.
    pub fn serve(&mut self, call: Call) -> (Reply, Status) {
        let reply = match call {
            Call::Stop => Reply::Done,
            Call::Info => Reply::Info(self.info()),
            Call::Stage(stage) => {
                stage.run(self);
                Reply::Done
            }
            Call::Step => {
                self.step();
                Reply::Done
            }
            Call::Advance(n) => {
                self.advance(n);
                Reply::Done
            }
            Call::Time => Reply::Time(self.time()),
            Call::Check => Reply::Checked(self.check()),
            Call::Diagnostics => Reply::Diagnostics(self.diagnostics()),
            Call::Particles => Reply::Particles(self.particles()),
            Call::Capture(fields) => Reply::Pending(self.capture(fields)),
            Call::Snapshot(shown) => {
                let mut s = Snapshot::default();
                self.snapshot(shown, &mut s);
                Reply::Snapshot(s)
            }
            Call::SamplePoints {
                points,
                include_walls,
            } => {
                let mut o = Vec::new();
                self.sample_points(&points, include_walls, &mut o);
                Reply::Samples(o)
            }
            Call::Save => Reply::State(self.save()),
            Call::SavePiece => Reply::Piece(Piece {
                slab: self.slab(),
                state: self.save(),
            }),
            Call::Restore(part) => Reply::Restored(self.restore(&part)),
            Call::Recut { slabs, part } => {
                self.set_slabs(slabs);
                Reply::Restored(self.restore(&part))
            }
            Call::RemoveGroup(g) => Reply::Removed(self.remove_group(g)),
            Call::WallForces(groups) => Reply::Forces(self.wall_forces(&groups)),
        };
        (reply, self.status())
    }

    /// Its particle count, clock and exchange costs now.
    pub fn status(&self) -> Status {
        Status {
            len: self.len(),
            steps: self.steps(),
            has_solids: self.has_solids(),
            stats: self.stats,
            device_bytes: self.device_bytes(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A decomposed run sends a stage to its ranks as data (serialised between processes):
    /// every stage survives the trip.
    #[test]
    fn every_stage_is_a_call_that_travels() {
        for &stage in Stage::ALL {
            let call = Call::Stage(stage);
            let text = serde_json::to_string(&call).expect("serialise");
            let back: Call = serde_json::from_str(&text).expect("deserialise");
            assert!(matches!(back, Call::Stage(s) if s == stage));
        }
    }
}
