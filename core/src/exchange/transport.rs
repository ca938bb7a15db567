//! How subdomains talk: the `Transport` trait (a maximum over all ranks, and one round of
//! point-to-point messages), and `InProcess`, its implementation for ranks that are threads
//! of one process (the CPU backend's subdomains, or several subdomains on one GPU, whose
//! messages are then device buffers handed over, never copied through the host).

use std::sync::{Arc, Barrier, Mutex};

/// One rank's end of the communication between the subdomains of a run. Every rank calls
/// the same methods in the same order (collective calls, as MPI's and NCCL's).
pub trait Transport<M>: Send {
    /// This rank's index, 0 .. `ranks()`.
    fn rank(&self) -> usize;
    /// How many ranks take part.
    fn ranks(&self) -> usize;
    /// `v` becomes the element-wise maximum of every rank's `v` (all the same length).
    fn max(&mut self, v: &mut [f32]);
    /// Send `out[j]` to rank j (`None`: nothing; `out[rank()]` is ignored) and return what
    /// each rank sent to this one, indexed by sender (`None` where it sent nothing).
    fn exchange(&mut self, out: Vec<Option<M>>) -> Vec<Option<M>>;
}

/// What the ranks of one process share: a barrier and a mailbox per (sender, receiver), and
/// one slot per rank for the maxima.
struct Shared<M> {
    barrier: Barrier,
    mail: Vec<Mutex<Option<M>>>,
    maxima: Mutex<Vec<Vec<f32>>>,
}

/// `Transport` between threads of one process: messages are moved, not copied.
pub struct InProcess<M> {
    rank: usize,
    ranks: usize,
    shared: Arc<Shared<M>>,
}

impl<M: Send> InProcess<M> {
    /// The ends of `ranks` ranks, in rank order.
    pub fn group(ranks: usize) -> Vec<InProcess<M>> {
        let shared = Arc::new(Shared {
            barrier: Barrier::new(ranks),
            mail: (0..ranks * ranks).map(|_| Mutex::new(None)).collect(),
            maxima: Mutex::new(vec![Vec::new(); ranks]),
        });
        (0..ranks)
            .map(|rank| InProcess {
                rank,
                ranks,
                shared: shared.clone(),
            })
            .collect()
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    // A rank that panicked holding the lock leaves data that is still whole.
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl<M: Send> Transport<M> for InProcess<M> {
    fn rank(&self) -> usize {
        self.rank
    }
    fn ranks(&self) -> usize {
        self.ranks
    }
    fn max(&mut self, v: &mut [f32]) {
        if self.ranks == 1 {
            return;
        }
        lock(&self.shared.maxima)[self.rank] = v.to_vec();
        self.shared.barrier.wait();
        {
            let all = lock(&self.shared.maxima);
            for other in all.iter() {
                for (a, b) in v.iter_mut().zip(other) {
                    *a = a.max(*b);
                }
            }
        }
        // Nobody writes a slot again before everyone has read them all.
        self.shared.barrier.wait();
    }
    fn exchange(&mut self, out: Vec<Option<M>>) -> Vec<Option<M>> {
        let n = self.ranks;
        let mut out = out;
        out.resize_with(n, || None);
        if n == 1 {
            return vec![None];
        }
        for (to, m) in out.into_iter().enumerate() {
            if to != self.rank {
                *lock(&self.shared.mail[self.rank * n + to]) = m;
            }
        }
        self.shared.barrier.wait();
        let got = (0..n)
            .map(|from| {
                if from == self.rank {
                    None
                } else {
                    lock(&self.shared.mail[from * n + self.rank]).take()
                }
            })
            .collect();
        // Every box is emptied before anyone fills it again.
        self.shared.barrier.wait();
        got
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_exchange_and_agree_on_maxima() {
        let ends = InProcess::<String>::group(3);
        let results: Vec<(Vec<f32>, Vec<Option<String>>)> = std::thread::scope(|s| {
            let handles: Vec<_> = ends
                .into_iter()
                .map(|mut t| {
                    s.spawn(move || {
                        let r = t.rank();
                        let mut v = vec![r as f32, -(r as f32)];
                        t.max(&mut v);
                        let out = (0..3)
                            .map(|to| (to != r).then(|| format!("{r}->{to}")))
                            .collect();
                        (v, t.exchange(out))
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for (r, (v, got)) in results.iter().enumerate() {
            assert_eq!(v, &vec![2.0, 0.0]);
            for (from, m) in got.iter().enumerate() {
                let want = (from != r).then(|| format!("{from}->{r}"));
                assert_eq!(m, &want, "rank {r} from {from}");
            }
        }
    }
}
