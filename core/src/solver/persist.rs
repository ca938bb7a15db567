//! Persistence: the state a restart needs (`crate::solver::checkpoint`), whole or as one piece per
//! rank of a decomposed run.

use crate::solver::checkpoint::{Piece, SolverCheckpoint};

/// Save and restore (`Solver`'s supertrait): `meshfree run --resume` continues bit for bit
/// on the same backend and build.
pub trait Persist {
    /// The state a restart needs (`crate::solver::checkpoint`), at this step boundary (a
    /// read-back on the GPU).
    fn save(&mut self) -> SolverCheckpoint;
    /// Continue from `saved`, taken by `save` from a solver of the same scene on either
    /// backend (this one started afresh, its gates opened as they were): the particles, the
    /// total-Lagrangian displacements, the clock and the step count replaced. On the same
    /// backend and build the steps that follow are those the saved solver would have taken,
    /// bit for bit. Err: why the checkpoint does not fit (`SolverCheckpoint::mismatch`);
    /// the solver is then unchanged.
    fn restore(&mut self, saved: &SolverCheckpoint) -> Result<(), String>;
    /// A decomposed solver's state as one piece per rank (its slab and its particles), in
    /// rank order, for checkpoints written one file per rank; None for one domain (`save`).
    fn save_pieces(&mut self) -> Option<Vec<Piece>> {
        None
    }
    /// Continue from the pieces `save_pieces` gave: a decomposed solver of as many ranks
    /// gives each rank its own piece and slab (the saved run's storage and cuts, so that
    /// it steps on as the saved one would have, bit for bit); any other solver takes them
    /// gathered into one (`restore`: equally exact, the cuts the solver's own). Err as
    /// `restore`, or a piece that is not its rank's (`Piece::mismatch`).
    fn restore_pieces(&mut self, pieces: &[Piece]) -> Result<(), String> {
        self.restore(&Piece::gather(pieces))
    }
}
