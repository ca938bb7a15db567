//! `meshfree run SCENE --mpi` under `mpirun -np N`: one process per rank, on one machine
//! or several (the `mpi` cargo feature; OpenMPI or any MPI the `mpi` crate builds with).
//!
//! Rank 0 leads: it runs the driver as any run does (output, checkpoints, progress), with a
//! `Decomposed` solver whose ranks are the processes (`Leader`, a `Group`). It sends the
//! scene to the others (`Start`); each builds the same set-up, cuts the same slabs
//! (`exchange::cut`) and keeps its own (`exchange::part`), then serves the leader's calls
//! (`Call`, `Reply`, serialised with bincode) until `Stop`. The particles travel between
//! GPUs through NCCL (the communicator's id made by rank 0 and broadcast over MPI), and
//! between CPU processes over MPI (`MpiTransport`). MPI starts the ranks, maps them to
//! GPUs, hands out the NCCL id and carries the calls; with GPUs, no particle crosses it
//! per step.
//!
//! The same run as `--decompose N` (or `--gpus N`) on one machine: the particles bit for
//! bit (`tests/mpi.rs`).

use std::marker::PhantomData;
use std::sync::atomic::{AtomicBool, Ordering};

use mpi::collective::SystemOperation;
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use mpi::Tag;
use serde::{de::DeserializeOwned, Deserialize, Serialize};

use meshfree_core::backend::cpu::CpuSolver;
use meshfree_core::backend::{BackendChoice, BackendError};
use meshfree_core::exchange::{
    cut, halo_width, part, Call, Decomposed, Group, Rank, Reply, Slab, Status, Subdomain, Transport,
};
use meshfree_core::physics::dim::{Dim, D2, D3};
use meshfree_core::scene::{Scene, SceneSource};
use meshfree_core::solver::{BackendInfo, Setup, Solver};

/// Message tags: the leader's calls and their replies, the run's start, and the halos
/// between CPU ranks.
const START: Tag = 1;
const CALL: Tag = 2;
const REPLY: Tag = 3;
const HALO: Tag = 4;
const AGREE: Tag = 5;

/// Set once rank 0 has sent the scene (`abort_unstarted` tells the others otherwise).
static STARTED: AtomicBool = AtomicBool::new(false);

/// MPI initialised for this process; finalised when dropped (at the end of `main`'s run).
/// On rank 0 the drop first tells the other ranks that no run comes where none started
/// (`abort_unstarted`): a bad scene, an output directory in use.
pub struct Mpi {
    _universe: Universe,
}

impl Drop for Mpi {
    fn drop(&mut self) {
        abort_unstarted();
    }
}

impl Mpi {
    /// Initialise MPI. The ranks' threads call MPI only from the thread that drives the
    /// solver, but the CUDA backend and the writer run threads of their own: the full
    /// thread support is asked for.
    pub fn init() -> anyhow::Result<Mpi> {
        let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Multiple)
            .ok_or_else(|| anyhow::anyhow!("MPI was initialised twice"))?;
        Ok(Mpi {
            _universe: universe,
        })
    }

    /// This process's rank.
    pub fn rank(&self) -> usize {
        world().rank() as usize
    }

    /// How many processes run.
    pub fn ranks(&self) -> usize {
        world().size() as usize
    }
}

fn world() -> SimpleCommunicator {
    SimpleCommunicator::world()
}

/// What rank 0 sends the others before the run: the scene (its file as JSON, with the
/// command line's overrides in it) and the backend; or that the run will not start.
#[derive(Serialize, Deserialize)]
enum Start {
    Run {
        scene: String,
        backend: BackendChoice,
        /// The leader's set-up, summarised (`fingerprint`): every rank must build the same.
        fingerprint: String,
    },
    Abort,
}

/// Send `bytes` to rank `to` with `tag`: the length, then chunks of at most 1 GiB (MPI
/// counts are 32-bit).
fn send_bytes(to: usize, tag: Tag, bytes: &[u8]) {
    let w = world();
    let p = w.process_at_rank(to as i32);
    p.send_with_tag(&header(bytes)[..], tag);
    for chunk in bytes.chunks(CHUNK) {
        p.send_with_tag(chunk, tag);
    }
}

/// The largest message: MPI counts are 32-bit.
const CHUNK: usize = 1 << 30;

/// The first message of `bytes`: their length, 8 bytes little-endian.
fn header(bytes: &[u8]) -> [u8; 8] {
    (bytes.len() as u64).to_le_bytes()
}

/// What `send_bytes` sent from rank `from` with `tag`.
fn receive_bytes(from: usize, tag: Tag) -> Vec<u8> {
    let w = world();
    let p = w.process_at_rank(from as i32);
    let (head, _) = p.receive_vec_with_tag::<u8>(tag);
    let len = u64::from_le_bytes(head.try_into().expect("an 8-byte length first"));
    let mut out = Vec::with_capacity(len as usize);
    while out.len() < len as usize {
        let (chunk, _) = p.receive_vec_with_tag::<u8>(tag);
        out.extend_from_slice(&chunk);
    }
    out
}

fn encode<T: Serialize>(v: &T) -> Vec<u8> {
    bincode::serialize(v).expect("a call, a reply or a halo serialises")
}

fn decode<T: DeserializeOwned>(bytes: &[u8], what: &str) -> T {
    bincode::deserialize(bytes)
        .unwrap_or_else(|e| panic!("a {what} from another rank does not decode: {e}"))
}

/// Every rank passes its own result; all return the same: Ok where every rank succeeded,
/// else the failures, each naming its rank.
fn agree(mine: Result<(), String>) -> Result<(), String> {
    let (me, n) = (world().rank() as usize, world().size() as usize);
    let why = mine.err().unwrap_or_default();
    let all = if me == 0 {
        let mut failed: Vec<String> = Vec::new();
        if !why.is_empty() {
            failed.push(format!("rank 0: {why}"));
        }
        for k in 1..n {
            let w = String::from_utf8_lossy(&receive_bytes(k, AGREE)).into_owned();
            if !w.is_empty() {
                failed.push(format!("rank {k}: {w}"));
            }
        }
        let all = failed.join("; ");
        for k in 1..n {
            send_bytes(k, AGREE, all.as_bytes());
        }
        all
    } else {
        send_bytes(0, AGREE, why.as_bytes());
        String::from_utf8_lossy(&receive_bytes(0, AGREE)).into_owned()
    };
    if all.is_empty() {
        Ok(())
    } else {
        Err(all)
    }
}

/// What every rank's set-up must agree on: the parameters and the particles' count and
/// positions, summarised.
fn fingerprint(setup: &Setup) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h = (h ^ b as u64).wrapping_mul(0x100000001b3);
        }
    };
    eat(format!("{:?}", setup.params).as_bytes());
    for q in &setup.particles {
        for x in q.position {
            eat(&x.to_bits().to_le_bytes());
        }
        eat(&q.id.to_le_bytes());
    }
    format!("{} particles, {h:016x}", setup.particles.len())
}

/// Rank 0: send the scene to the other ranks, build its own subdomain, and return the run's
/// solver, whose calls the other ranks serve. `setup` is `scene.setup()`.
pub fn lead(
    scene: &Scene,
    setup: Setup,
    backend: BackendChoice,
) -> Result<Box<dyn Solver>, BackendError> {
    let n = world().size() as usize;
    let start = Start::Run {
        scene: serde_json::to_string(&scene.file)
            .map_err(|e| BackendError::Launch(format!("the scene does not serialise: {e}")))?,
        backend,
        fingerprint: fingerprint(&setup),
    };
    let bytes = encode(&start);
    for k in 1..n {
        send_bytes(k, START, &bytes);
    }
    STARTED.store(true, Ordering::SeqCst);
    join(setup, backend)?.ok_or_else(|| BackendError::Launch("rank 0 did not lead".into()))
}

/// Rank 0, where the run stopped before `lead` (bad input): tell the other ranks that no
/// run comes, so that they end.
fn abort_unstarted() {
    if world().rank() == 0 && !STARTED.swap(true, Ordering::SeqCst) {
        let bytes = encode(&Start::Abort);
        for k in 1..world().size() as usize {
            send_bytes(k, START, &bytes);
        }
    }
}

/// Ranks 1..N: wait for rank 0's scene, build this rank's subdomain and serve the leader's
/// calls until the run ends. Err: the scene or the solver could not be built here (rank
/// 0 reports it too).
pub fn follow() -> anyhow::Result<()> {
    let start: Start = decode(&receive_bytes(0, START), "start");
    let Start::Run {
        scene,
        backend,
        fingerprint: theirs,
    } = start
    else {
        return Ok(());
    };
    let setup = (|| {
        let scene = Scene {
            file: serde_json::from_str(&scene).map_err(|e| e.to_string())?,
            source: SceneSource::Text("the scene rank 0 sent".into()),
            text: String::new(),
        };
        scene.revalidate().map_err(|e| e.to_string())?;
        let setup = scene.setup().map_err(|e| e.to_string())?;
        let mine = fingerprint(&setup);
        if mine != theirs {
            return Err(format!(
                "its set-up of the scene ({mine}) is not rank 0's ({theirs})"
            ));
        }
        Ok(setup)
    })();
    let setup = match setup {
        Ok(s) => s,
        Err(why) => {
            // Rank 0 waits for every rank's word before it builds its solver.
            let _ = agree(Err(why.clone()));
            anyhow::bail!("{why}");
        }
    };
    join(setup, backend).map_err(anyhow::Error::from)?;
    Ok(())
}

/// Build this rank's subdomain of `setup` on `backend` and its transport; on rank 0 the
/// run's solver, elsewhere serve until the run ends (None).
fn join(mut setup: Setup, backend: BackendChoice) -> Result<Option<Box<dyn Solver>>, BackendError> {
    setup.params.own_solids = setup.has_solids() as i32;
    let cuda = match backend {
        BackendChoice::Cpu => false,
        BackendChoice::Cuda => true,
        BackendChoice::Auto => meshfree_core::backend::cuda::available().is_ok(),
    };
    // Every rank must take the same backend: a process without a GPU refuses `auto`'s CUDA
    // decision of the others.
    let mut any = [cuda as i32];
    let mut all = [cuda as i32];
    world().all_reduce_into(&[cuda as i32][..], &mut any[..], SystemOperation::max());
    world().all_reduce_into(&[cuda as i32][..], &mut all[..], SystemOperation::min());
    if any != all {
        return Err(BackendError::Launch(
            "some ranks found a usable GPU and some did not: pass --backend cpu or cuda".into(),
        ));
    }
    match (cuda, setup.params.dim) {
        (false, 2) => on_cpu::<D2>(setup),
        (false, _) => on_cpu::<D3>(setup),
        (true, 2) => on_gpu::<D2>(setup),
        (true, _) => on_gpu::<D3>(setup),
    }
}

/// The slabs of every rank and this rank's part of `setup`, or the refusal every rank
/// reaches alike.
fn slabs_and_part(setup: &Setup) -> Result<(Vec<Slab>, Setup), BackendError> {
    let slabs = cut(setup, world().size() as usize)?;
    let mine = part(setup, &slabs[world().rank() as usize]);
    Ok((slabs, mine))
}

fn on_cpu<D: Dim>(setup: Setup) -> Result<Option<Box<dyn Solver>>, BackendError> {
    let (slabs, mine) = slabs_and_part(&setup)?;
    let sub = CpuSolver::<D>::new(mine);
    agree(Ok(())).map_err(BackendError::Launch)?;
    Ok(start(&setup, slabs, sub, MpiTransport::default()))
}

#[cfg(feature = "cuda")]
fn on_gpu<D: Dim>(setup: Setup) -> Result<Option<Box<dyn Solver>>, BackendError> {
    use meshfree_core::backend::cuda::CudaSolver;
    let (slabs, mine) = slabs_and_part(&setup)?;
    let whole = setup.particles.len();
    let built = CudaSolver::<D>::new_subdomain(mine, whole, gpu_of_this_process());
    agree(built.as_ref().map(|_| ()).map_err(|e| e.to_string())).map_err(BackendError::Launch)?;
    let sub = built?;
    let transport = nccl_end(&sub)?;
    Ok(start(&setup, slabs, sub, transport))
}

#[cfg(not(feature = "cuda"))]
fn on_gpu<D: Dim>(_setup: Setup) -> Result<Option<Box<dyn Solver>>, BackendError> {
    Err(BackendError::CudaUnavailable(
        "this build has the `cuda` feature off".into(),
    ))
}

/// This process's GPU: its rank among the processes of its machine (as the launcher
/// numbers them: OpenMPI, MPICH or Slurm), modulo the machine's GPUs.
#[cfg(feature = "cuda")]
fn gpu_of_this_process() -> usize {
    let local = [
        "OMPI_COMM_WORLD_LOCAL_RANK",
        "MPI_LOCALRANKID",
        "SLURM_LOCALID",
    ]
    .iter()
    .find_map(|v| std::env::var(v).ok()?.parse::<usize>().ok())
    .unwrap_or(world().rank() as usize);
    let gpus = meshfree_core::backend::cuda::device_count().max(1);
    local % gpus
}

/// This rank's end of an NCCL communicator of all the processes: rank 0 makes its id and
/// broadcasts it over MPI.
#[cfg(all(feature = "cuda", feature = "nccl"))]
fn nccl_end<D: Dim>(
    sub: &meshfree_core::backend::cuda::CudaSolver<D>,
) -> Result<
    meshfree_core::backend::cuda::nccl::Nccl<meshfree_core::backend::cuda::CudaHalo>,
    BackendError,
> {
    use meshfree_core::backend::cuda::nccl;
    let mut id = [0u8; 128];
    let made = if world().rank() == 0 {
        nccl::new_id().map(|i| {
            for (b, c) in id.iter_mut().zip(i) {
                *b = c as u8;
            }
        })
    } else {
        Ok(())
    };
    agree(made.map_err(|e| e.to_string())).map_err(BackendError::Launch)?;
    world().process_at_rank(0).broadcast_into(&mut id[..]);
    let id = id.map(|b| b as std::ffi::c_char);
    let end = nccl::Nccl::joined(
        sub.stream(),
        world().rank() as usize,
        world().size() as usize,
        id,
    );
    agree(end.as_ref().map(|_| ()).map_err(|e| e.to_string())).map_err(BackendError::Launch)?;
    end
}

#[cfg(all(feature = "cuda", not(feature = "nccl")))]
fn nccl_end<D: Dim>(
    _sub: &meshfree_core::backend::cuda::CudaSolver<D>,
) -> Result<MpiTransport<meshfree_core::backend::cuda::CudaHalo>, BackendError> {
    Err(BackendError::CudaUnavailable(
        "this build has the `nccl` feature off: GPUs in several processes talk through NCCL".into(),
    ))
}

/// Rank 0: the run's solver over every process; the others: serve until `Stop`.
fn start<S: Subdomain + 'static, T: Transport<S::Halo> + 'static>(
    setup: &Setup,
    slabs: Vec<Slab>,
    sub: S,
    transport: T,
) -> Option<Box<dyn Solver>> {
    let rank = Rank::new(sub, transport, slabs.clone(), halo_width(&setup.params));
    if world().rank() == 0 {
        Some(Box::new(Decomposed::with_group(
            setup.params,
            slabs,
            setup.wall_surface.clone(),
            Leader { me: rank },
        )))
    } else {
        serve(rank);
        None
    }
}

/// Carry out rank 0's calls until it says `Stop`.
fn serve<S: Subdomain, T: Transport<S::Halo>>(mut rank: Rank<S, T>) {
    loop {
        let call: Call = decode(&receive_bytes(0, CALL), "call");
        let stop = matches!(call, Call::Stop);
        let (reply, status) = rank.serve(call);
        let reply = reply.delivered();
        send_bytes(0, REPLY, &encode(&(reply, status)));
        if stop {
            return;
        }
    }
}

/// Rank 0's group: itself, and the other processes, which it calls over MPI.
struct Leader<S: Subdomain, T: Transport<S::Halo>> {
    me: Rank<S, T>,
}

impl<S: Subdomain, T: Transport<S::Halo>> Group for Leader<S, T> {
    fn ranks(&self) -> usize {
        world().size() as usize
    }
    /// The others' calls go out first; rank 0 then serves its own (meeting the others in
    /// the transport), and gathers their replies.
    fn call_each(&mut self, calls: Vec<Call>) -> Vec<(Reply, Status)> {
        let mut calls = calls.into_iter();
        let mine = calls.next().expect("rank 0's call");
        for (k, c) in calls.enumerate() {
            send_bytes(k + 1, CALL, &encode(&c));
        }
        let mut out = vec![self.me.serve(mine)];
        for k in 1..self.ranks() {
            out.push(decode(&receive_bytes(k, REPLY), "reply"));
        }
        out
    }
    fn describe(&self, rank0: &BackendInfo) -> BackendInfo {
        BackendInfo {
            backend: rank0.backend.clone(),
            device: format!("{}, {} MPI processes", rank0.device, self.ranks()),
        }
    }
}

/// `Transport` between CPU ranks in separate processes: halos serialised and sent over MPI
/// (all at once, then received), the step size's maxima an MPI all-reduce.
pub struct MpiTransport<M> {
    _m: PhantomData<fn() -> M>,
}

impl<M> Default for MpiTransport<M> {
    fn default() -> Self {
        MpiTransport { _m: PhantomData }
    }
}

impl<M: Serialize + DeserializeOwned + Send> Transport<M> for MpiTransport<M> {
    fn rank(&self) -> usize {
        world().rank() as usize
    }
    fn ranks(&self) -> usize {
        world().size() as usize
    }
    fn max(&mut self, v: &mut [f32]) {
        let mine = v.to_vec();
        world().all_reduce_into(&mine[..], v, SystemOperation::max());
    }
    fn exchange(&mut self, out: Vec<Option<M>>) -> Vec<Option<M>> {
        let (me, n) = (self.rank(), self.ranks());
        let bodies: Vec<Vec<u8>> = (0..n)
            .map(|to| match out.get(to) {
                Some(Some(m)) if to != me => encode(m),
                _ => Vec::new(),
            })
            .collect();
        let heads: Vec<[u8; 8]> = bodies.iter().map(|b| header(b)).collect();
        let w = world();
        mpi::request::scope(|scope| {
            let mut guards = Vec::new();
            for to in (0..n).filter(|&j| j != me) {
                let p = w.process_at_rank(to as i32);
                guards.push(mpi::request::WaitGuard::from(p.immediate_send_with_tag(
                    scope,
                    &heads[to][..],
                    HALO,
                )));
                for chunk in bodies[to].chunks(CHUNK) {
                    guards.push(mpi::request::WaitGuard::from(
                        p.immediate_send_with_tag(scope, chunk, HALO),
                    ));
                }
            }
            (0..n)
                .map(|from| {
                    if from == me {
                        return None;
                    }
                    let bytes = receive_bytes(from, HALO);
                    (!bytes.is_empty()).then(|| decode(&bytes, "halo"))
                })
                .collect()
        })
    }
}
