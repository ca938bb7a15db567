//! `Decomposed`: the ranks of a run as one `Solver`, which the run driver, the stepper and
//! the tests use as they use any solver. It speaks to its ranks through a `Group` (`Call`
//! and `Reply`): threads of this process (`Threads`: `--decompose N`, `--gpus N`) or other
//! processes (`meshfree run --mpi`).

use crate::exchange::call::unexpected;
use crate::exchange::{
    balanced, halo_width, longest_axis, Call, ExchangeStats, Group, InProcess, Rank, Reply, Slab,
    Status, Subdomain, Threads, Transport,
};
use crate::physics::params::SphParams;
use crate::physics::particle::Particle;
use crate::solver::checkpoint::{Piece, SolverCheckpoint};
use crate::solver::frame::{Fields, FrameData, PendingFrame};
use crate::solver::{
    forward_stages, stage_list, BackendInfo, Diagnostics, ExchangeCost, Fault, Persist,
    PointSample, Readback, Setup, Shown, Snapshot, Solver, Stage,
};

/// The subdomains of one scene, one rank each, stepping together (`Group`: threads of this
/// process by default, talking through `InProcess` or NCCL; or processes).
pub struct Decomposed<G: Group> {
    group: G,
    /// The whole domain's parameters (`own_slab` off).
    params: SphParams,
    slabs: Vec<Slab>,
    wall_surface: Vec<[f32; 4]>,
    /// Times the cuts were moved (`rebalance`).
    rebalances: u32,
    /// Each rank's status after the last call.
    status: Vec<Status>,
    info: BackendInfo,
}

/// The load the most loaded rank may carry beyond the mean before `advance` moves the
/// cuts: the step waits for the slowest rank, so 10 % more particles on one rank cost
/// about 10 % of the whole run's speed.
pub const IMBALANCE: f64 = 1.1;

/// Why a scene cannot be decomposed as asked (`refusal`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("cannot decompose this scene: {0}")]
pub struct Refused(pub String);

/// Why a scene cannot be decomposed as asked.
pub fn refusal(setup: &Setup, n: usize) -> Option<String> {
    if n == 0 {
        return Some("--decompose takes 1 or more subdomains".into());
    }
    if crate::physics::tlsph::total_lagrangian(&setup.params) && setup.has_solids() {
        return Some(
            "total-Lagrangian bodies cannot be decomposed yet (their reference neighbour \
             lists span the whole body): run on one domain, or with [solid] formulation = \
             \"jaumann\""
                .into(),
        );
    }
    None
}

/// The `n` slabs of `setup`: equal particle counts along the domain's longest axis. Every
/// process of a run cuts its own copy of the scene alike.
pub fn cut(setup: &Setup, n: usize) -> Result<Vec<Slab>, Refused> {
    if let Some(why) = refusal(setup, n) {
        return Err(Refused(why));
    }
    let axis = longest_axis(&setup.params);
    let coords: Vec<f32> = setup.particles.iter().map(|q| q.position[axis]).collect();
    Ok(balanced(&setup.params, axis, &coords, n))
}

/// The part of `setup` a rank owning `slab` starts with: its particles, the whole domain's
/// parameters and the whole wall surface.
pub fn part(setup: &Setup, slab: &Slab) -> Setup {
    Setup {
        params: setup.params,
        particles: setup
            .particles
            .iter()
            .filter(|q| slab.contains(q.position[slab.axis]))
            .cloned()
            .collect(),
        wall_surface: setup.wall_surface.clone(),
        bodies: setup.bodies.clone(),
        motion_series: setup.motion_series.clone(),
    }
}

impl<S: Subdomain> Decomposed<Threads<S, InProcess<S::Halo>>> {
    /// Split `setup` into `n` slabs (`cut`), and build each subdomain's solver with `make`
    /// (`part`); the ranks are threads of this process and talk in process.
    pub fn new<E: From<Refused>>(
        setup: Setup,
        n: usize,
        make: impl Fn(Setup) -> Result<S, E>,
    ) -> Result<Self, E> {
        Self::build(setup, n, |_, s| make(s), |_| Ok(InProcess::group(n)))
    }
}

impl<S: Subdomain, T: Transport<S::Halo>> Decomposed<Threads<S, T>> {
    /// `new` with the transport's ends made by `connect` from the built solvers (an NCCL
    /// communicator takes their streams), one per rank in rank order; `make` gets the rank
    /// (a GPU's ordinal) with its part of the scene.
    pub fn build<E: From<Refused>>(
        setup: Setup,
        n: usize,
        make: impl Fn(usize, Setup) -> Result<S, E>,
        connect: impl FnOnce(&mut [S]) -> Result<Vec<T>, E>,
    ) -> Result<Self, E> {
        let slabs = cut(&setup, n)?;
        let width = halo_width(&setup.params);
        let mut subs = Vec::with_capacity(n);
        for (k, slab) in slabs.iter().enumerate() {
            subs.push(make(k, part(&setup, slab))?);
        }
        let ends = connect(&mut subs)?;
        assert_eq!(ends.len(), n, "one transport end per rank");
        let ranks = subs
            .into_iter()
            .zip(ends)
            .map(|(sub, end)| Rank::new(sub, end, slabs.clone(), width))
            .collect();
        Ok(Decomposed::with_group(
            setup.params,
            slabs,
            setup.wall_surface,
            Threads { ranks },
        ))
    }
}

impl<G: Group> Decomposed<G> {
    /// The ranks of `group`, which own `slabs` in rank order, as one solver of the scene
    /// with `params` and `wall_surface` (the whole domain's).
    pub fn with_group(
        params: SphParams,
        slabs: Vec<Slab>,
        wall_surface: Vec<[f32; 4]>,
        group: G,
    ) -> Self {
        let n = group.ranks();
        assert_eq!(slabs.len(), n, "one slab per rank");
        let mut d = Decomposed {
            group,
            params,
            slabs,
            wall_surface,
            rebalances: 0,
            status: vec![Status::default(); n],
            info: BackendInfo {
                backend: String::new(),
                device: String::new(),
            },
        };
        d.info = match d.first(Call::Info) {
            Reply::Info(i) => i,
            _ => unexpected("its backend"),
        };
        d
    }

    /// Every rank carries out `call`; the replies in rank order.
    fn call(&mut self, call: Call) -> Vec<Reply> {
        let n = self.group.ranks();
        self.each(vec![call; n])
    }

    /// Rank k carries out `calls[k]`; the replies in rank order.
    fn each(&mut self, calls: Vec<Call>) -> Vec<Reply> {
        let (replies, status): (Vec<Reply>, Vec<Status>) =
            self.group.call_each(calls).into_iter().unzip();
        self.status = status;
        replies
    }

    /// Every rank runs `stage` at once.
    fn run_stage(&mut self, stage: Stage) {
        self.call(Call::Stage(stage));
    }

    /// `call` on every rank; rank 0's reply.
    fn first(&mut self, call: Call) -> Reply {
        self.call(call).into_iter().next().expect("a rank")
    }

    /// The ranks' answers to a call that returns a value of one kind.
    fn gather<R>(&mut self, call: Call, pick: impl Fn(Reply) -> Option<R>, what: &str) -> Vec<R> {
        self.call(call)
            .into_iter()
            .map(|r| pick(r).unwrap_or_else(|| unexpected(what)))
            .collect()
    }

    /// Each rank's `Restored` reply, the first failure if any.
    fn restored(replies: Vec<Reply>) -> Result<(), String> {
        replies.into_iter().try_for_each(|r| match r {
            Reply::Restored(r) => r,
            _ => unexpected("a restore's result"),
        })
    }

    pub fn slabs(&self) -> &[Slab] {
        &self.slabs
    }

    /// Each rank's exchange costs, in rank order.
    pub fn exchange_stats(&self) -> Vec<ExchangeStats> {
        self.status.iter().map(|s| s.stats).collect()
    }

    /// Each rank's particle count, in rank order.
    pub fn counts(&self) -> Vec<usize> {
        self.status.iter().map(|s| s.len).collect()
    }

    /// How often the cuts were moved so far.
    pub fn rebalances(&self) -> u32 {
        self.rebalances
    }

    /// The most loaded rank's particles over the mean (1 when balanced).
    pub fn imbalance(&self) -> f64 {
        let counts = self.counts();
        let total: usize = counts.iter().sum();
        let max = counts.iter().copied().max().unwrap_or(0);
        max as f64 * counts.len() as f64 / total.max(1) as f64
    }

    /// Move the cuts so that every rank holds about as many particles as the others, where
    /// the most loaded holds more than `threshold` x the mean (`imbalance`); true where
    /// they moved. Exact: ownership changes at a step boundary, and every particle steps
    /// alike whoever owns it. The particles pass through the caller (`save`, `Recut`):
    /// occasional, not per step.
    pub fn rebalance(&mut self, threshold: f64) -> Result<bool, String> {
        if self.group.ranks() == 1 || self.imbalance() <= threshold {
            return Ok(false);
        }
        let all = self.save();
        let axis = self.slabs[0].axis;
        let coords: Vec<f32> = all.pos.iter().map(|x| x[axis]).collect();
        let slabs = balanced(&self.params, axis, &coords, self.group.ranks());
        self.recut(&slabs, &all)?;
        self.rebalances += 1;
        Ok(true)
    }

    /// Every rank owns its slab of `slabs` from now on, with the particles of `all` in it.
    fn recut(&mut self, slabs: &[Slab], all: &SolverCheckpoint) -> Result<(), String> {
        let calls = slabs
            .iter()
            .map(|s| Call::Recut {
                slabs: slabs.to_vec(),
                part: all.select(|x| s.contains(x[s.axis])),
            })
            .collect();
        let done = self.each(calls);
        Self::restored(done)?;
        self.slabs = slabs.to_vec();
        Ok(())
    }
}

impl<G: Group> Drop for Decomposed<G> {
    /// Ranks in other processes stop serving.
    fn drop(&mut self) {
        if !std::thread::panicking() {
            self.call(Call::Stop);
        }
    }
}

impl<G: Group> Solver for Decomposed<G> {
    fn info(&self) -> BackendInfo {
        let i = self.group.describe(&self.info);
        BackendInfo {
            backend: i.backend,
            device: format!(
                "{}, {} subdomains along {}",
                i.device,
                self.group.ranks(),
                ["x", "y", "z"][self.slabs[0].axis]
            ),
        }
    }
    fn params(&self) -> &SphParams {
        &self.params
    }
    fn len(&self) -> usize {
        self.status.iter().map(|s| s.len).sum()
    }
    fn has_solids(&self) -> bool {
        self.status.iter().any(|s| s.has_solids)
    }
    stage_list!(forward_stages);
    /// Every rank steps at once in the trait's order.
    fn step(&mut self) {
        self.call(Call::Step);
    }
    /// The cuts moved first where the load drifted past `IMBALANCE` (the water of a dam
    /// break runs from one end of the tank to the other).
    fn advance(&mut self, steps: u64) {
        if let Err(e) = self.rebalance(IMBALANCE) {
            panic!("moving the subdomains' cuts: {e}");
        }
        self.call(Call::Advance(steps));
    }
    /// Every rank's clock is the same: each adds the same agreed steps.
    fn time(&mut self) -> f64 {
        match self.first(Call::Time) {
            Reply::Time(t) => t,
            _ => unexpected("a clock"),
        }
    }
    fn steps(&self) -> u64 {
        self.status[0].steps
    }
    fn check(&mut self) -> Result<(), Fault> {
        self.gather(
            Call::Check,
            |r| match r {
                Reply::Checked(c) => Some(c),
                _ => None,
            },
            "a check",
        )
        .into_iter()
        .collect()
    }
    fn remove_group(&mut self, group: u32) -> usize {
        self.gather(
            Call::RemoveGroup(group),
            |r| match r {
                Reply::Removed(n) => Some(n),
                _ => None,
            },
            "a count",
        )
        .into_iter()
        .sum()
    }
}

impl<G: Group> Readback for Decomposed<G> {
    /// Counts and sums added and maxima taken over the ranks (the sums in another order
    /// than one domain's: equal to round-off).
    fn diagnostics(&mut self) -> Diagnostics {
        let all = self.gather(
            Call::Diagnostics,
            |r| match r {
                Reply::Diagnostics(d) => Some(d),
                _ => None,
            },
            "diagnostics",
        );
        let mut d = all[0].clone();
        for o in &all[1..] {
            d.kinetic_energy += o.kinetic_energy;
            d.max_speed = d.max_speed.max(o.max_speed);
            d.density_error = d.density_error.max(o.density_error);
            for a in 0..3 {
                d.momentum[a] += o.momentum[a];
            }
            d.fluid += o.fluid;
            d.solid += o.solid;
            d.boundary += o.boundary;
        }
        d
    }
    fn particles(&mut self) -> Vec<Particle> {
        let parts = self.gather(
            Call::Particles,
            |r| match r {
                Reply::Particles(p) => Some(p),
                _ => None,
            },
            "particles",
        );
        let mut all: Vec<Particle> = parts.concat();
        all.sort_unstable_by_key(|q| q.id);
        all
    }
    /// The ranks' frames one after the other (each in its storage order, with the ids).
    fn capture(&mut self, fields: Fields) -> Box<dyn PendingFrame> {
        let pending = self
            .call(Call::Capture(fields))
            .into_iter()
            .map(Reply::into_frame)
            .collect();
        Box::new(Joined(pending))
    }
    fn snapshot(&mut self, shown: Shown, out: &mut Snapshot) {
        let parts = self.gather(
            Call::Snapshot(shown),
            |r| match r {
                Reply::Snapshot(s) => Some(s),
                _ => None,
            },
            "a snapshot",
        );
        out.positions.clear();
        out.values.clear();
        out.kinds.clear();
        for s in parts {
            out.positions.extend(s.positions);
            out.values.extend(s.values);
            out.kinds.extend(s.kinds);
        }
    }
    /// Each point's sample from the rank whose slab holds it.
    fn sample_points(
        &mut self,
        points: &[[f32; 3]],
        include_walls: bool,
        out: &mut Vec<PointSample>,
    ) {
        let all = self.gather(
            Call::SamplePoints {
                points: points.to_vec(),
                include_walls,
            },
            |r| match r {
                Reply::Samples(s) => Some(s),
                _ => None,
            },
            "samples",
        );
        out.clear();
        for (i, x) in points.iter().enumerate() {
            let k = self
                .slabs
                .iter()
                .position(|s| s.contains(x[s.axis]))
                .unwrap_or(0);
            out.push(all[k][i]);
        }
    }
    fn wall_surface(&self) -> &[[f32; 4]] {
        &self.wall_surface
    }
    fn exchange_cost(&self) -> Option<ExchangeCost> {
        let stats = self.exchange_stats();
        Some(ExchangeCost {
            ranks: stats.len(),
            fills: stats.iter().map(|s| s.fills).max().unwrap_or(0),
            particles: stats.iter().map(|s| s.received).sum(),
            bytes: stats.iter().map(|s| s.bytes).sum(),
            seconds: stats
                .iter()
                .map(|s| s.time.as_secs_f64())
                .fold(0.0, f64::max),
            transfer_seconds: stats
                .iter()
                .map(|s| s.transfer.as_secs_f64())
                .fold(0.0, f64::max),
            device_bytes: self.status.iter().map(|s| s.device_bytes as u64).sum(),
        })
    }
    fn wall_forces(&mut self, groups: &[u32]) -> Vec<[f64; 3]> {
        let all = self.gather(
            Call::WallForces(groups.to_vec()),
            |r| match r {
                Reply::Forces(f) => Some(f),
                _ => None,
            },
            "forces",
        );
        let mut sum = vec![[0.0f64; 3]; groups.len()];
        for part in all {
            for (s, f) in sum.iter_mut().zip(part) {
                for a in 0..3 {
                    s[a] += f[a];
                }
            }
        }
        sum
    }
}

impl<G: Group> Persist for Decomposed<G> {
    /// The ranks' states one after the other.
    fn save(&mut self) -> SolverCheckpoint {
        let parts = self.gather(
            Call::Save,
            |r| match r {
                Reply::State(s) => Some(s),
                _ => None,
            },
            "a state",
        );
        SolverCheckpoint::concat(&parts)
    }
    /// Checked against the whole scene's particles (`SolverCheckpoint::mismatch_with`), then
    /// each rank takes the saved particles in its slab.
    fn restore(&mut self, saved: &SolverCheckpoint) -> Result<(), String> {
        let now = self.save();
        if let Some(why) = saved.mismatch_with(&now) {
            return Err(why);
        }
        let calls = self
            .slabs
            .iter()
            .map(|s| Call::Restore(saved.select(|x| s.contains(x[s.axis]))))
            .collect();
        let done = self.each(calls);
        Self::restored(done)
    }
    fn save_pieces(&mut self) -> Option<Vec<Piece>> {
        Some(self.gather(
            Call::SavePiece,
            |r| match r {
                Reply::Piece(p) => Some(p),
                _ => None,
            },
            "a piece",
        ))
    }
    /// With as many pieces as ranks (cut along this run's axis), each rank takes its own
    /// piece and slab; otherwise the pieces gathered (`restore`). Checked as `restore`
    /// against the whole scene's particles, and each piece against its slab and the first
    /// piece's clock (`Piece::mismatch`).
    fn restore_pieces(&mut self, pieces: &[Piece]) -> Result<(), String> {
        let axis = self.slabs[0].axis;
        if pieces.len() != self.group.ranks() || pieces.iter().any(|p| p.slab.axis != axis) {
            return self.restore(&Piece::gather(pieces));
        }
        let tiled = pieces[0].slab.lo == f32::NEG_INFINITY
            && pieces[pieces.len() - 1].slab.hi == f32::INFINITY
            && pieces.windows(2).all(|w| w[0].slab.hi == w[1].slab.lo);
        if !tiled {
            return Err(format!(
                "the pieces' slabs do not follow each other along the axis: {:?}",
                pieces
                    .iter()
                    .map(|p| (p.slab.lo, p.slab.hi))
                    .collect::<Vec<_>>()
            ));
        }
        for (k, p) in pieces.iter().enumerate() {
            if let Some(why) = p.mismatch(&pieces[0].state) {
                return Err(format!("rank {k}'s piece: {why}"));
            }
        }
        let now = self.save();
        if let Some(why) = Piece::gather(pieces).mismatch_with(&now) {
            return Err(why);
        }
        let slabs: Vec<Slab> = pieces.iter().map(|p| p.slab).collect();
        let calls = pieces
            .iter()
            .map(|p| Call::Recut {
                slabs: slabs.clone(),
                part: p.state.clone(),
            })
            .collect();
        let done = self.each(calls);
        Self::restored(done)?;
        self.slabs = slabs;
        Ok(())
    }
}

/// The frames of several ranks delivered as one.
struct Joined(Vec<Box<dyn PendingFrame>>);

impl PendingFrame for Joined {
    fn wait(self: Box<Self>) -> Result<FrameData, String> {
        let mut all: Option<FrameData> = None;
        for p in self.0 {
            let f = p.wait()?;
            match all.as_mut() {
                None => all = Some(f),
                Some(a) => a.append(f),
            }
        }
        Ok(all.unwrap_or_default())
    }
}
