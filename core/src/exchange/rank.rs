//! One rank of a decomposed run: a subdomain solver and its end of the transport. As a
//! `Solver` it steps in the trait's one order; three of its stages talk to the other ranks:
//! the grid build first fills the halo, the step size is the maximum of every rank's
//! extremes, and the drift ends by dropping what the subdomain no longer owns.

use std::time::{Duration, Instant};

use crate::exchange::{Slab, Subdomain, Transport};
use crate::physics::params::SphParams;
use crate::physics::particle::Particle;
use crate::solver::checkpoint::SolverCheckpoint;
use crate::solver::frame::{Fields, PendingFrame};
use crate::solver::{
    forward_stages, stage_list, BackendInfo, Diagnostics, Fault, Persist, PointSample, Readback,
    Shown, Snapshot, Solver, Stage,
};

/// What the exchange cost one rank so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ExchangeStats {
    /// Halo fills (one per step, and one per wall-force or probe sample).
    pub fills: u64,
    /// Halo particles received, over all fills.
    pub received: u64,
    /// Their bytes (`Subdomain::halo_bytes`).
    pub bytes: u64,
    /// Wall time in the halo fills and the step-size maxima.
    pub time: Duration,
    /// Of which in the transport's exchange itself (sizes and halos sent and received,
    /// the wait for the slower rank included).
    pub transfer: Duration,
}

/// A subdomain solver `S` talking to the other ranks through `T`.
pub struct Rank<S: Subdomain, T: Transport<S::Halo>> {
    sub: S,
    transport: T,
    /// Every rank's slab, in rank order.
    slabs: Vec<Slab>,
    /// The halo's width [L] (`halo_width`).
    width: f32,
    /// The slabs' axis's (min, max) where it is periodic.
    periodic: Option<(f32, f32)>,
    pub stats: ExchangeStats,
}

impl<S: Subdomain, T: Transport<S::Halo>> Rank<S, T> {
    /// `sub` holds the particles of `slabs[transport.rank()]`, which it owns from now on.
    pub fn new(mut sub: S, transport: T, slabs: Vec<Slab>, width: f32) -> Self {
        let me = slabs[transport.rank()];
        sub.set_owned(me);
        let p = sub.params();
        let a = me.axis;
        let periodic = (p.periodic[a] != 0).then(|| (p.domain_min[a], p.domain_max[a]));
        Rank {
            sub,
            transport,
            slabs,
            width,
            periodic,
            stats: ExchangeStats::default(),
        }
    }

    /// Take new slabs (every rank's, in rank order; `Decomposed::rebalance`): this rank
    /// owns its own of them from now on.
    pub fn set_slabs(&mut self, slabs: Vec<Slab>) {
        self.sub.set_owned(slabs[self.transport.rank()]);
        self.slabs = slabs;
    }

    /// Device memory its subdomain holds (`Subdomain::device_bytes`).
    pub fn device_bytes(&self) -> usize {
        self.sub.device_bytes()
    }

    /// This rank's index, as its transport numbers it.
    pub fn index(&self) -> usize {
        self.transport.rank()
    }

    pub fn slab(&self) -> Slab {
        self.slabs[self.transport.rank()]
    }

    pub fn sub(&mut self) -> &mut S {
        &mut self.sub
    }

    /// Run `stage` on the subdomain. Three stages talk to the other ranks: the grid build
    /// first fills the halo (the particles within reach of this slab, as they start the
    /// step); the step size is eq. (19) from the largest speed, acceleration and sound
    /// speed of all ranks' owned particles (the one-domain step, bit for bit: a maximum
    /// does not depend on the order); a drift ends by dropping what this slab no longer
    /// owns. Every other stage is the subdomain's own.
    fn run_stage(&mut self, stage: Stage) {
        match stage {
            Stage::BuildGrid => {
                self.fill_halo();
                self.sub.build_grid();
            }
            Stage::TimeStep => {
                let t0 = Instant::now();
                let mut e = self.sub.extremes();
                self.transport.max(&mut e);
                self.sub.set_step(e);
                self.stats.time += t0.elapsed();
            }
            Stage::Drift | Stage::DriftKick => {
                stage.run(&mut self.sub);
                self.sub.retain_owned();
            }
            _ => stage.run(&mut self.sub),
        }
    }

    /// Send each rank copies of the particles within the halo width of its slab, and add
    /// what the others sent. Collective: every rank calls it at the same point.
    fn fill_halo(&mut self) {
        let t0 = Instant::now();
        let me = self.transport.rank();
        let out = (0..self.slabs.len())
            .map(|j| {
                (j != me)
                    .then(|| self.sub.halo(&self.slabs[j], self.width, self.periodic))
                    .flatten()
            })
            .collect();
        let t1 = Instant::now();
        let got: Vec<S::Halo> = self.transport.exchange(out).into_iter().flatten().collect();
        self.stats.transfer += t1.elapsed();
        self.stats.received += got.iter().map(|h| S::halo_len(h) as u64).sum::<u64>();
        self.stats.bytes += got.iter().map(|h| S::halo_bytes(h) as u64).sum::<u64>();
        self.sub.append(got);
        self.stats.fills += 1;
        self.stats.time += t0.elapsed();
    }
}

impl<S: Subdomain, T: Transport<S::Halo>> Solver for Rank<S, T> {
    fn info(&self) -> BackendInfo {
        self.sub.info()
    }
    fn params(&self) -> &SphParams {
        self.sub.params()
    }
    fn len(&self) -> usize {
        self.sub.len()
    }
    fn has_solids(&self) -> bool {
        self.sub.has_solids()
    }
    stage_list!(forward_stages);
    fn time(&mut self) -> f64 {
        self.sub.time()
    }
    fn steps(&self) -> u64 {
        self.sub.steps()
    }
    fn check(&mut self) -> Result<(), Fault> {
        self.sub.check()
    }
    fn remove_group(&mut self, group: u32) -> usize {
        self.sub.remove_group(group)
    }
}

impl<S: Subdomain, T: Transport<S::Halo>> Readback for Rank<S, T> {
    fn diagnostics(&mut self) -> Diagnostics {
        self.sub.diagnostics()
    }
    fn particles(&mut self) -> Vec<Particle> {
        self.sub.particles()
    }
    fn capture(&mut self, fields: Fields) -> Box<dyn PendingFrame> {
        self.sub.capture(fields)
    }
    fn snapshot(&mut self, shown: Shown, out: &mut Snapshot) {
        self.sub.snapshot(shown, out)
    }
    /// With the halo filled (collective), so that points near the slab's ends see every
    /// particle within reach; only the samples of points in this slab are this rank's to
    /// report (`Decomposed::sample_points` picks them).
    fn sample_points(
        &mut self,
        points: &[[f32; 3]],
        include_walls: bool,
        out: &mut Vec<PointSample>,
    ) {
        self.fill_halo();
        self.sub.sample_points(points, include_walls, out);
        self.sub.retain_owned();
    }
    fn wall_surface(&self) -> &[[f32; 4]] {
        self.sub.wall_surface()
    }
    /// With the halo filled (collective); the sums count the owned wall particles alone
    /// (`SphParams::owns`), so the ranks' sums add up to the one-domain force.
    fn wall_forces(&mut self, groups: &[u32]) -> Vec<[f64; 3]> {
        self.fill_halo();
        let f = self.sub.wall_forces(groups);
        self.sub.retain_owned();
        f
    }
}

impl<S: Subdomain, T: Transport<S::Halo>> Persist for Rank<S, T> {
    fn save(&mut self) -> SolverCheckpoint {
        self.sub.save()
    }
    fn restore(&mut self, saved: &SolverCheckpoint) -> Result<(), String> {
        self.sub.replace(saved)
    }
}
