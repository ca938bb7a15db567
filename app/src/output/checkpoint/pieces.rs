//! A checkpoint in pieces, one per rank of a decomposed run (`Solver::save_pieces`): each
//! piece a checkpoint of the parent module's layout, and `checkpoint.bin` their index (the
//! parent module's docs).

use std::io;
use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use meshfree_core::exchange::Slab;
use meshfree_core::solver::checkpoint::{Piece, SolverCheckpoint};
use meshfree_core::solver::Solver;

use super::{read_file, write, write_file};

/// The index's list of a checkpoint's pieces, one per rank.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct PieceList {
    /// The slabs' axis (0: x, 1: y, 2: z).
    pub axis: usize,
    /// \[L\] the cuts between neighbouring ranks' slabs, ranks - 1 of them (the outer slabs
    /// reach to -inf and +inf).
    pub cuts: Vec<f32>,
    /// Each rank's piece, in rank order.
    pub files: Vec<PieceFile>,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct PieceFile {
    /// Its name in the run's directory.
    pub file: String,
    pub particles: u64,
}

impl PieceList {
    /// Rank `k`'s slab.
    pub fn slab(&self, k: usize) -> Slab {
        let n = self.files.len();
        Slab {
            axis: self.axis,
            lo: if k == 0 {
                f32::NEG_INFINITY
            } else {
                self.cuts[k - 1]
            },
            hi: if k + 1 == n {
                f32::INFINITY
            } else {
                self.cuts[k]
            },
        }
    }
}

/// A piece's own run state: which rank of how many saved it.
#[derive(Serialize, Deserialize, PartialEq)]
struct PieceRun {
    rank: usize,
    ranks: usize,
}

pub use crate::output::files::{is_piece_name, piece_name};

/// A solver's saved state: one checkpoint, or one piece per rank of a decomposed solver.
pub enum Saved {
    Whole(SolverCheckpoint),
    Pieces {
        /// The clock, step count and step size, no particles.
        clock: SolverCheckpoint,
        pieces: Vec<Piece>,
    },
}

impl Saved {
    /// `solver`'s state: in pieces where it is decomposed (`Solver::save_pieces`).
    pub fn of(solver: &mut dyn Solver) -> Saved {
        match solver.save_pieces() {
            Some(pieces) => Saved::Pieces {
                clock: clock_of(&pieces[0].state),
                pieces,
            },
            None => Saved::Whole(solver.save()),
        }
    }

    /// The clock, step count and step size (and the particles of a whole one).
    pub fn clock(&self) -> &SolverCheckpoint {
        match self {
            Saved::Whole(c) | Saved::Pieces { clock: c, .. } => c,
        }
    }

    /// Continue `solver` from it (`Solver::restore`, `Solver::restore_pieces`).
    pub fn restore_into(&self, solver: &mut dyn Solver) -> Result<(), String> {
        match self {
            Saved::Whole(c) => solver.restore(c),
            Saved::Pieces { pieces, .. } => solver.restore_pieces(pieces),
        }
    }

    /// The particles, gathered into one checkpoint where in pieces.
    pub fn gathered(&self) -> SolverCheckpoint {
        match self {
            Saved::Whole(c) => c.clone(),
            Saved::Pieces { pieces, .. } => Piece::gather(pieces),
        }
    }

    /// Write it to `path`: `write`, or each rank's piece (`write` per piece) and then the
    /// index at `path`. Then the pieces of earlier checkpoints are removed. Returns the
    /// bytes written.
    pub fn write<R: Serialize>(&self, path: &Path, run: &R) -> io::Result<u64> {
        let dir = parent(path);
        let (bytes, keep) = match self {
            Saved::Whole(c) => (write(path, c, run)?, Vec::new()),
            Saved::Pieces { clock, pieces } => {
                let ranks = pieces.len();
                let mut bytes = 0;
                let mut files = Vec::with_capacity(ranks);
                for (rank, p) in pieces.iter().enumerate() {
                    let file = piece_name(clock.steps, rank, ranks);
                    bytes += write(&dir.join(&file), &p.state, &PieceRun { rank, ranks })?;
                    files.push(PieceFile {
                        file,
                        particles: p.state.len() as u64,
                    });
                }
                let list = PieceList {
                    axis: pieces[0].slab.axis,
                    cuts: pieces[1..].iter().map(|p| p.slab.lo).collect(),
                    files,
                };
                let keep = list.files.iter().map(|f| f.file.clone()).collect();
                (bytes + write_file(path, clock, run, Some(list))?, keep)
            }
        };
        remove_stale_pieces(dir, &keep)?;
        Ok(bytes)
    }
}

/// The clock, step count and step size of `c`, without its particles.
fn clock_of(c: &SolverCheckpoint) -> SolverCheckpoint {
    SolverCheckpoint {
        dim: c.dim,
        time: c.time,
        steps: c.steps,
        dt: c.dt,
        ..SolverCheckpoint::default()
    }
}

fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Remove the pieces in `dir` that are not in `keep`: those of earlier checkpoints, once
/// the index no longer names them, and those a kill left unnamed.
pub fn remove_stale_pieces(dir: &Path, keep: &[String]) -> io::Result<()> {
    for entry in std::fs::read_dir(dir)? {
        let name = entry?.file_name().to_string_lossy().into_owned();
        if is_piece_name(&name) && !keep.contains(&name) {
            std::fs::remove_file(dir.join(&name))?;
        }
    }
    Ok(())
}

/// Read a checkpoint, whole or in pieces (the index at `path`, each rank's piece beside
/// it): the solver's state and the run's. Err: the file at fault and why it cannot be used
/// (`read`; a piece missing, or not the one the index lists: another rank, particle count
/// or step).
pub fn load<R: DeserializeOwned>(path: &Path) -> Result<(Saved, R), (PathBuf, String)> {
    let (clock, run, list) = read_file::<R>(path).map_err(|e| (path.to_path_buf(), e))?;
    let Some(list) = list else {
        return Ok((Saved::Whole(clock), run));
    };
    let ranks = list.files.len();
    if ranks == 0 || list.cuts.len() + 1 != ranks || list.axis > 2 {
        return Err((
            path.to_path_buf(),
            format!(
                "damaged header: its pieces list {ranks} files, {} cuts, axis {}",
                list.cuts.len(),
                list.axis
            ),
        ));
    }
    let dir = parent(path);
    let mut pieces = Vec::with_capacity(ranks);
    for (rank, f) in list.files.iter().enumerate() {
        let at = dir.join(&f.file);
        let bad = |why: String| (at.clone(), why);
        if f.file.contains(['/', '\\']) || !is_piece_name(&f.file) {
            return Err((path.to_path_buf(), format!("lists `{}` as a piece", f.file)));
        }
        if !at.is_file() {
            return Err(bad(format!(
                "is missing: the checkpoint {} lists it as rank {rank}'s piece of {ranks}",
                path.display()
            )));
        }
        let (state, own, more) = read_file::<PieceRun>(&at).map_err(bad)?;
        if more.is_some() || own != (PieceRun { rank, ranks }) {
            return Err(bad(format!(
                "is not rank {rank}'s piece of {ranks}, which {} lists it as",
                path.display()
            )));
        }
        if state.len() as u64 != f.particles || state.steps != clock.steps {
            return Err(bad(format!(
                "holds {} particles at step {}, and {} lists {} at step {}: a piece of \
                 another checkpoint",
                state.len(),
                state.steps,
                path.display(),
                f.particles,
                clock.steps
            )));
        }
        pieces.push(Piece {
            slab: list.slab(rank),
            state,
        });
    }
    Ok((Saved::Pieces { clock, pieces }, run))
}
