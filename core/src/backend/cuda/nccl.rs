//! `Transport` between GPUs through NCCL (`run --gpus N`): one rank per GPU, each on its
//! own thread of one process (`exchange::Decomposed`), one communicator per GPU made by
//! `ncclCommInitAll` on the ranks' own streams, so that a halo's send follows its packing
//! and its unpacking follows the receive on the same stream, and nothing is staged
//! through the host: a halo travels as the one flat device buffer its subdomain packed
//! (`Words`). Per exchange the halo sizes go first (an all-gather of one row of the
//! N x N size matrix per rank, 16 N bytes), then one grouped send/receive per neighbour.
//! The step size's maxima are an all-reduce of 3 floats.
//!
//! NCCL is loaded at run time (cudarc's dynamic loading): `libnccl.so` (or
//! `libnccl.so.13`) must be on the loader path; `available` says whether it is.

use std::marker::PhantomData;
use std::sync::Arc;

use cudarc::driver::{CudaSlice, CudaStream};
use cudarc::nccl::{Comm, ReduceOp};

use crate::backend::error::BackendError;
use crate::exchange::{Decomposed, Transport};
use crate::physics::dim::{Dim, D2, D3};
use crate::solver::{Setup, Solver};

use super::{CudaHalo, CudaSolver};

/// A halo that travels as one flat device buffer of 32-bit words.
pub trait Words: Sized + Send {
    /// Particles it holds.
    fn particles(&self) -> usize;
    /// Its words on the device.
    fn words(&self) -> &CudaSlice<u32>;
    /// The halo of `particles` particles received as `words`.
    fn from_words(particles: usize, words: CudaSlice<u32>) -> Self;
}

impl Words for CudaHalo {
    fn particles(&self) -> usize {
        self.n
    }
    fn words(&self) -> &CudaSlice<u32> {
        &self.words
    }
    fn from_words(particles: usize, words: CudaSlice<u32>) -> Self {
        CudaHalo {
            n: particles,
            words,
        }
    }
}

/// `n` subdomains of `setup`, rank k on GPU k, talking through NCCL (`run --gpus N`):
/// the particles of one domain, bit for bit, as `backend::Layout::Threads` on one GPU.
pub fn multi_gpu(setup: Setup, n: usize) -> Result<Box<dyn Solver>, BackendError> {
    available()?;
    if setup.params.dim == 2 {
        multi::<D2>(setup, n)
    } else {
        multi::<D3>(setup, n)
    }
}

fn multi<D: Dim>(setup: Setup, n: usize) -> Result<Box<dyn Solver>, BackendError> {
    let whole = setup.particles.len();
    let d = Decomposed::build(
        setup,
        n,
        |k, s| CudaSolver::<D>::new_subdomain(s, whole, k),
        |subs: &mut [CudaSolver<D>]| Nccl::group(subs.iter().map(|s| s.stream()).collect()),
    )?;
    Ok(Box::new(d))
}

/// A new communicator's id, which one process makes and hands to the others
/// (`Nccl::joined`).
pub fn new_id() -> Result<[std::ffi::c_char; 128], BackendError> {
    available()?;
    let id = cudarc::nccl::Id::new().map_err(|e| err("unique id", e))?;
    Ok(*id.internal())
}

/// Whether NCCL loads here; the error says why not.
pub fn available() -> Result<(), BackendError> {
    // SAFETY: only probes whether the library file loads (cudarc's dynamic loading).
    if unsafe { cudarc::nccl::sys::is_culib_present() } {
        Ok(())
    } else {
        Err(BackendError::CudaUnavailable(
            "NCCL is not on the loader path (libnccl.so or libnccl.so.13: put the directory \
             of NCCL's library, e.g. the nvidia-nccl Python package's nvidia/nccl/lib, in \
             LD_LIBRARY_PATH, with a libnccl.so link to libnccl.so.2)"
                .into(),
        ))
    }
}

fn err(what: &str, e: impl std::fmt::Debug) -> BackendError {
    BackendError::Cuda(format!("NCCL {what}: {e:?}"))
}

/// One rank's end: its communicator and the small device buffers of the collectives.
pub struct Nccl<H> {
    comm: Comm,
    stream: Arc<CudaStream>,
    /// The step size's maxima (3 floats).
    maxima: CudaSlice<f32>,
    /// This rank's row of the size matrix: (particles, words) per receiving rank.
    sizes: CudaSlice<u64>,
    /// Every rank's row, gathered.
    all_sizes: CudaSlice<u64>,
    _halo: PhantomData<H>,
}

// SAFETY: a communicator is used by the one thread that drives its rank at a time
// (`Threads::call_each` moves each rank to its own thread); NCCL allows a communicator to
// be used from any thread, one at a time.
unsafe impl<H: Send> Send for Nccl<H> {}

impl<H: Words> Nccl<H> {
    /// One end per stream, in rank order (rank k on `streams[k]`, one GPU each).
    pub fn group(streams: Vec<Arc<CudaStream>>) -> Result<Vec<Nccl<H>>, BackendError> {
        available()?;
        let comms = Comm::from_devices(streams.clone()).map_err(|e| err("init", e))?;
        comms
            .into_iter()
            .zip(streams)
            .map(|(comm, stream)| Self::end(comm, stream))
            .collect()
    }

    /// This process's end of a communicator of `ranks` processes, rank `rank` on `stream`'s
    /// GPU (`meshfree run --mpi`): every process passes the same `id`, made by one of them
    /// (`new_id`) and handed to the others.
    pub fn joined(
        stream: Arc<CudaStream>,
        rank: usize,
        ranks: usize,
        id: [std::ffi::c_char; 128],
    ) -> Result<Nccl<H>, BackendError> {
        available()?;
        let comm = Comm::from_rank(stream.clone(), rank, ranks, cudarc::nccl::Id::uninit(id))
            .map_err(|e| err("init", e))?;
        Self::end(comm, stream)
    }

    /// The end of `comm` on `stream`, with its collectives' buffers.
    fn end(comm: Comm, stream: Arc<CudaStream>) -> Result<Nccl<H>, BackendError> {
        let n = comm.world_size();
        let alloc = |k| stream.alloc_zeros::<u64>(k);
        Ok(Nccl {
            maxima: stream.alloc_zeros::<f32>(3).map_err(|e| err("alloc", e))?,
            sizes: alloc(2 * n).map_err(|e| err("alloc", e))?,
            all_sizes: alloc(2 * n * n).map_err(|e| err("alloc", e))?,
            comm,
            stream,
            _halo: PhantomData,
        })
    }

    fn fail(&self, what: &str, e: impl std::fmt::Debug) -> ! {
        panic!(
            "NCCL {what} failed on rank {} of {}: {e:?}",
            self.comm.rank(),
            self.comm.world_size()
        )
    }
}

impl<H: Words> Transport<H> for Nccl<H> {
    fn rank(&self) -> usize {
        self.comm.rank()
    }
    fn ranks(&self) -> usize {
        self.comm.world_size()
    }
    fn max(&mut self, v: &mut [f32]) {
        assert!(v.len() <= 3, "Nccl::max takes at most 3 values");
        let s = self.stream.clone();
        let r = (|| {
            let mut view = self.maxima.slice_mut(..v.len());
            s.memcpy_htod(&*v, &mut view)
                .map_err(|e| format!("{e:?}"))?;
            self.comm
                .all_reduce_in_place(&mut view, &ReduceOp::Max)
                .map_err(|e| format!("{e:?}"))?;
            s.memcpy_dtoh(&view, v).map_err(|e| format!("{e:?}"))?;
            s.synchronize().map_err(|e| format!("{e:?}"))
        })();
        if let Err(e) = r {
            self.fail("all-reduce of the step size", e)
        }
    }
    fn exchange(&mut self, out: Vec<Option<H>>) -> Vec<Option<H>> {
        let (me, n) = (self.rank(), self.ranks());
        let s = self.stream.clone();
        // Sizes first: every rank's row of (particles, words) per receiver.
        let mut row = vec![0u64; 2 * n];
        for (to, h) in out.iter().enumerate() {
            if let (true, Some(h)) = (to != me, h) {
                row[2 * to] = h.particles() as u64;
                row[2 * to + 1] = h.words().len() as u64;
            }
        }
        let sizes = (|| {
            s.memcpy_htod(&row, &mut self.sizes)
                .map_err(|e| format!("{e:?}"))?;
            self.comm
                .all_gather(&self.sizes, &mut self.all_sizes)
                .map_err(|e| format!("{e:?}"))?;
            s.clone_dtoh(&self.all_sizes).map_err(|e| format!("{e:?}"))
        })();
        let all = sizes.unwrap_or_else(|e| self.fail("all-gather of the halo sizes", e));
        // What each rank sends here: row `from`, column `me`.
        let incoming: Vec<(usize, usize)> = (0..n)
            .map(|from| {
                let at = from * 2 * n + 2 * me;
                (all[at] as usize, all[at + 1] as usize)
            })
            .collect();
        let mut bufs: Vec<Option<CudaSlice<u32>>> = incoming
            .iter()
            .enumerate()
            .map(|(from, &(_, words))| {
                (from != me && words > 0).then(|| {
                    s.alloc_zeros::<u32>(words)
                        .unwrap_or_else(|e| self.fail("allocating a halo", e))
                })
            })
            .collect();
        let sent = (|| {
            let mut g = self.comm.group();
            for (to, h) in out.iter().enumerate() {
                if let (true, Some(h)) = (to != me, h) {
                    if !h.words().is_empty() {
                        g.send(h.words().slice(..), to as i32)
                            .map_err(|e| format!("{e:?}"))?;
                    }
                }
            }
            for (from, b) in bufs.iter_mut().enumerate() {
                if let Some(b) = b {
                    g.recv(b.slice_mut(..), from as i32)
                        .map_err(|e| format!("{e:?}"))?;
                }
            }
            Ok::<(), String>(())
        })();
        if let Err(e) = sent {
            self.fail("halo send/receive", e)
        }
        // The sent buffers may be freed only after the sends complete.
        if let Err(e) = s.synchronize() {
            self.fail("waiting for the halo exchange", e)
        }
        drop(out);
        bufs.into_iter()
            .zip(incoming)
            .map(|(b, (particles, _))| b.map(|w| H::from_words(particles, w)))
            .collect()
    }
}
