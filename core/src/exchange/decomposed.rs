//! `Decomposed`: the ranks of one process (one thread each, `InProcess` transport) as one
//! `Solver`, which the run driver, the stepper and the tests use as they use any solver.

use crate::checkpoint::{Piece, SolverCheckpoint};
use crate::exchange::{
    balanced, halo_width, longest_axis, ExchangeStats, InProcess, Rank, Slab, Subdomain, Transport,
};
use crate::frame::{Fields, FrameData, PendingFrame};
use crate::params::SphParams;
use crate::particle::Particle;
use crate::solver::{
    BackendInfo, Diagnostics, ExchangeCost, Fault, PointSample, Setup, Shown, Snapshot, Solver,
};

/// `n` subdomains of one scene, each a rank on its own thread, stepping together and
/// talking through `T` (`InProcess` by default; NCCL between GPUs).
pub struct Decomposed<S: Subdomain, T: Transport<S::Halo> = InProcess<<S as Subdomain>::Halo>> {
    ranks: Vec<Rank<S, T>>,
    /// The whole domain's parameters (`own_slab` off).
    params: SphParams,
    slabs: Vec<Slab>,
    wall_surface: Vec<[f32; 4]>,
    /// Times the cuts were moved (`rebalance`).
    rebalances: u32,
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
    if crate::tlsph::total_lagrangian(&setup.params) && setup.has_solids() {
        return Some(
            "total-Lagrangian bodies cannot be decomposed yet (their reference neighbour \
             lists span the whole body): run on one domain, or with [solid] formulation = \
             \"jaumann\""
                .into(),
        );
    }
    None
}

impl<S: Subdomain> Decomposed<S> {
    /// Split `setup` into `n` slabs of equal particle counts along the domain's longest
    /// axis, and build each subdomain's solver with `make` (its particles, the whole
    /// domain's parameters, the whole wall surface); the ranks talk in process.
    pub fn new<E: From<Refused>>(
        setup: Setup,
        n: usize,
        make: impl Fn(Setup) -> Result<S, E>,
    ) -> Result<Self, E> {
        Self::build(setup, n, |_, s| make(s), |_| Ok(InProcess::group(n)))
    }
}

impl<S: Subdomain, T: Transport<S::Halo>> Decomposed<S, T> {
    /// `new` with the transport's ends made by `connect` from the built solvers (an NCCL
    /// communicator takes their streams), one per rank in rank order; `make` gets the rank
    /// (a GPU's ordinal) with its part of the scene.
    pub fn build<E: From<Refused>>(
        setup: Setup,
        n: usize,
        make: impl Fn(usize, Setup) -> Result<S, E>,
        connect: impl FnOnce(&mut [S]) -> Result<Vec<T>, E>,
    ) -> Result<Self, E> {
        if let Some(why) = refusal(&setup, n) {
            return Err(Refused(why).into());
        }
        let p = setup.params;
        let axis = longest_axis(&p);
        let coords: Vec<f32> = setup.particles.iter().map(|q| q.position[axis]).collect();
        let width = halo_width(&p);
        let slabs = balanced(&p, axis, &coords, n);
        let mut subs = Vec::with_capacity(n);
        for (k, slab) in slabs.iter().enumerate() {
            let part = Setup {
                params: p,
                particles: setup
                    .particles
                    .iter()
                    .filter(|q| slab.contains(q.position[axis]))
                    .cloned()
                    .collect(),
                wall_surface: setup.wall_surface.clone(),
            };
            subs.push(make(k, part)?);
        }
        let ends = connect(&mut subs)?;
        assert_eq!(ends.len(), n, "one transport end per rank");
        let ranks = subs
            .into_iter()
            .zip(ends)
            .map(|(sub, end)| Rank::new(sub, end, slabs.clone(), width))
            .collect();
        Ok(Decomposed {
            ranks,
            params: p,
            slabs,
            wall_surface: setup.wall_surface,
            rebalances: 0,
        })
    }

    pub fn slabs(&self) -> &[Slab] {
        &self.slabs
    }

    /// Each rank's exchange costs, in rank order.
    pub fn exchange_stats(&self) -> Vec<ExchangeStats> {
        self.ranks.iter().map(|r| r.stats).collect()
    }

    /// Each rank's particle count, in rank order.
    pub fn counts(&self) -> Vec<usize> {
        self.ranks.iter().map(|r| r.len()).collect()
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
    /// alike whoever owns it. The particles pass through the host (`save`, `replace`):
    /// occasional, not per step.
    pub fn rebalance(&mut self, threshold: f64) -> Result<bool, String> {
        if self.ranks.len() == 1 || self.imbalance() <= threshold {
            return Ok(false);
        }
        let all = self.save();
        let axis = self.slabs[0].axis;
        let coords: Vec<f32> = all.pos.iter().map(|x| x[axis]).collect();
        let slabs = balanced(&self.params, axis, &coords, self.ranks.len());
        let parts: Vec<SolverCheckpoint> = slabs
            .iter()
            .map(|s| all.select(|x| s.contains(x[axis])))
            .collect();
        let (slabs_ref, parts) = (&slabs, &parts);
        let done: Result<(), String> = self
            .on_all(|r| {
                r.set_slabs(slabs_ref.clone());
                let k = r.index();
                r.sub().replace(&parts[k])
            })
            .into_iter()
            .collect();
        done?;
        self.slabs = slabs;
        self.rebalances += 1;
        Ok(true)
    }

    /// `f` on every rank at once, each on its own thread (the ranks meet in the transport's
    /// collective calls); the results in rank order.
    fn on_all<R: Send>(&mut self, f: impl Fn(&mut Rank<S, T>) -> R + Sync) -> Vec<R> {
        if self.ranks.len() == 1 {
            return vec![f(&mut self.ranks[0])];
        }
        let f = &f;
        std::thread::scope(|s| {
            let handles: Vec<_> = self
                .ranks
                .iter_mut()
                .map(|r| s.spawn(move || f(r)))
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                .collect()
        })
    }
}

impl<S: Subdomain, T: Transport<S::Halo>> Solver for Decomposed<S, T> {
    fn info(&self) -> BackendInfo {
        let i = self.ranks[0].info();
        BackendInfo {
            backend: i.backend,
            device: format!(
                "{}, {} subdomains along {}",
                i.device,
                self.ranks.len(),
                ["x", "y", "z"][self.slabs[0].axis]
            ),
        }
    }
    fn params(&self) -> &SphParams {
        &self.params
    }
    fn len(&self) -> usize {
        self.ranks.iter().map(|r| r.len()).sum()
    }
    fn has_solids(&self) -> bool {
        self.ranks.iter().any(|r| r.has_solids())
    }
    fn build_grid(&mut self) {
        self.on_all(|r| r.build_grid());
    }
    fn density(&mut self) {
        self.on_all(|r| r.density());
    }
    fn solid_stress(&mut self) {
        self.on_all(|r| r.solid_stress());
    }
    fn forces(&mut self) {
        self.on_all(|r| r.forces());
    }
    fn solid_forces(&mut self) {
        self.on_all(|r| r.solid_forces());
    }
    fn rates(&mut self) {
        self.on_all(|r| r.rates());
    }
    fn forces_and_rates(&mut self) {
        self.on_all(|r| r.forces_and_rates());
    }
    fn time_step(&mut self) {
        self.on_all(|r| r.time_step());
    }
    fn kick(&mut self) {
        self.on_all(|r| r.kick());
    }
    fn drift(&mut self) {
        self.on_all(|r| r.drift());
    }
    fn drift_kick(&mut self) {
        self.on_all(|r| r.drift_kick());
    }
    /// Every rank steps on its own thread in the trait's order.
    fn step(&mut self) {
        self.on_all(|r| r.step());
    }
    /// The cuts moved first where the load drifted past `IMBALANCE` (the water of a dam
    /// break runs from one end of the tank to the other).
    fn advance(&mut self, steps: u64) {
        if let Err(e) = self.rebalance(IMBALANCE) {
            panic!("moving the subdomains' cuts: {e}");
        }
        self.on_all(|r| r.advance(steps));
    }
    /// Every rank's clock is the same: each adds the same agreed steps.
    fn time(&mut self) -> f64 {
        self.ranks[0].time()
    }
    fn steps(&self) -> u64 {
        self.ranks[0].steps()
    }
    fn check(&mut self) -> Result<(), Fault> {
        self.on_all(|r| r.check()).into_iter().collect()
    }
    /// Counts and sums added and maxima taken over the ranks (the sums in another order
    /// than one domain's: equal to round-off).
    fn diagnostics(&mut self) -> Diagnostics {
        let all = self.on_all(|r| r.diagnostics());
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
        let mut all: Vec<Particle> = self.on_all(|r| r.particles()).concat();
        all.sort_unstable_by_key(|q| q.id);
        all
    }
    /// The ranks' frames one after the other (each in its storage order, with the ids).
    fn capture(&mut self, fields: Fields) -> Box<dyn PendingFrame> {
        let pending: Vec<Box<dyn PendingFrame>> = self.on_all(|r| r.capture(fields));
        Box::new(Joined(pending))
    }
    fn snapshot(&mut self, shown: Shown, out: &mut Snapshot) {
        let parts = self.on_all(|r| {
            let mut s = Snapshot::default();
            r.snapshot(shown, &mut s);
            s
        });
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
        let all = self.on_all(|r| {
            let mut o = Vec::new();
            r.sample_points(points, include_walls, &mut o);
            o
        });
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
    /// The ranks' states one after the other.
    fn save(&mut self) -> SolverCheckpoint {
        let parts = self.on_all(|r| r.save());
        SolverCheckpoint::concat(&parts)
    }
    /// Checked against the whole scene's particles (`SolverCheckpoint::mismatch_with`), then
    /// each rank takes the saved particles in its slab.
    fn restore(&mut self, saved: &SolverCheckpoint) -> Result<(), String> {
        let now = self.save();
        if let Some(why) = saved.mismatch_with(&now) {
            return Err(why);
        }
        let slabs = self.slabs.clone();
        let parts: Vec<SolverCheckpoint> = slabs
            .iter()
            .map(|s| saved.select(|x| s.contains(x[s.axis])))
            .collect();
        let parts = &parts;
        let done = self.on_all(|r| {
            let k = r.index();
            r.restore(&parts[k])
        });
        done.into_iter().collect()
    }
    fn save_pieces(&mut self) -> Option<Vec<Piece>> {
        Some(self.on_all(|r| Piece {
            slab: r.slab(),
            state: r.save(),
        }))
    }
    /// With as many pieces as ranks (cut along this run's axis), each rank takes its own
    /// piece and slab; otherwise the pieces gathered (`restore`). Checked as `restore`
    /// against the whole scene's particles, and each piece against its slab and the first
    /// piece's clock (`Piece::mismatch`).
    fn restore_pieces(&mut self, pieces: &[Piece]) -> Result<(), String> {
        let axis = self.slabs[0].axis;
        if pieces.len() != self.ranks.len() || pieces.iter().any(|p| p.slab.axis != axis) {
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
        let slabs_ref = &slabs;
        let done: Result<(), String> = self
            .on_all(|r| {
                r.set_slabs(slabs_ref.clone());
                let k = r.index();
                r.restore(&pieces[k].state)
            })
            .into_iter()
            .collect();
        done?;
        self.slabs = slabs;
        Ok(())
    }
    fn remove_group(&mut self, group: u32) -> usize {
        self.on_all(|r| r.remove_group(group)).into_iter().sum()
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
            device_bytes: self.ranks.iter().map(|r| r.device_bytes() as u64).sum(),
        })
    }
    fn wall_forces(&mut self, groups: &[u32]) -> Vec<[f64; 3]> {
        let all = self.on_all(|r| r.wall_forces(groups));
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
