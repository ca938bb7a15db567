//! Where the ranks of a decomposed run live: `Group`, what `Decomposed` calls them through,
//! and `Threads`, the ranks as threads of this process (`--decompose N`, `--gpus N`). A
//! group of processes (`meshfree run --mpi`) is the app's `mpi` module.

use crate::exchange::{Call, Rank, Reply, Status, Subdomain, Transport};
use crate::solver::BackendInfo;

/// The ranks of a decomposed run, called together.
pub trait Group: Send {
    /// How many ranks.
    fn ranks(&self) -> usize;
    /// Rank k carries out `calls[k]`, every rank at once (they meet in the transport's
    /// collective calls); the replies and the ranks' statuses after them, in rank order.
    fn call_each(&mut self, calls: Vec<Call>) -> Vec<(Reply, Status)>;
    /// What the group runs on, for `Solver::info` ("..., 2 processes").
    fn describe(&self, rank0: &BackendInfo) -> BackendInfo {
        rank0.clone()
    }
}

/// Ranks on threads of this process: each call runs on every rank at once, one thread each.
pub struct Threads<S: Subdomain, T: Transport<S::Halo>> {
    pub ranks: Vec<Rank<S, T>>,
}

impl<S: Subdomain, T: Transport<S::Halo>> Group for Threads<S, T> {
    fn ranks(&self) -> usize {
        self.ranks.len()
    }
    fn call_each(&mut self, calls: Vec<Call>) -> Vec<(Reply, Status)> {
        assert_eq!(calls.len(), self.ranks.len(), "one call per rank");
        if self.ranks.len() == 1 {
            let call = calls.into_iter().next().expect("one call");
            return vec![self.ranks[0].serve(call)];
        }
        std::thread::scope(|s| {
            let handles: Vec<_> = self
                .ranks
                .iter_mut()
                .zip(calls)
                .map(|(r, c)| s.spawn(move || r.serve(c)))
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                .collect()
        })
    }
}
