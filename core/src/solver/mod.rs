//! The `Solver` trait: the stages of the paper's Fig. 1. The trait's `step` fixes their
//! order; backends implement the stages, never the order.

use serde::{Deserialize, Serialize};

use crate::checkpoint::{Piece, SolverCheckpoint};
use crate::frame::{Fields, FrameData, PendingFrame, Ready};
use crate::params::{SphParams, MF_INTEGRATOR_EULER, MF_NO_SLIP_WALL_VELOCITY};
use crate::particle::{Kind, Particle};

/// Everything a backend needs to start: the derived parameters and the initial particles.
#[derive(Clone, Debug)]
pub struct Setup {
    pub params: SphParams,
    pub particles: Vec<Particle>,
    /// Per boundary particle, at index id - `params.wall_first_id`: the unit normal of the
    /// nearest wall surface, pointing into the fluid (x, y, z; z = 0 in 2D) [-], and the
    /// particle's distance behind that surface d_B [L]. Only for `params.no_slip` (Morris,
    /// Fox & Zhu 1997); empty otherwise. One entry per boundary particle, none per fluid
    /// particle.
    pub wall_surface: Vec<[f32; 4]>,
}

impl Setup {
    pub fn has_solids(&self) -> bool {
        self.particles.iter().any(|p| p.kind == Kind::Solid)
    }

    /// Why `wall_surface` cannot serve `params.no_slip`: a boundary particle whose id falls
    /// outside it. None when it can, or when no_slip is off.
    pub fn wall_surface_error(&self) -> Option<String> {
        if self.params.no_slip as u32 == MF_NO_SLIP_WALL_VELOCITY {
            return None;
        }
        let (first, n) = (self.params.wall_first_id, self.wall_surface.len());
        self.particles
            .iter()
            .find(|q| q.kind == Kind::Boundary && (q.id < first || (q.id - first) as usize >= n))
            .map(|q| {
                format!(
                    "no_slip needs a wall surface entry for every boundary particle: particle {} \
                     is outside ids {first}..{} of Setup::wall_surface",
                    q.id,
                    first as usize + n
                )
            })
    }
}

/// Which backend built a solver, and on what.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, Eq)]
pub struct BackendInfo {
    /// "cpu" or "cuda".
    pub backend: String,
    /// e.g. "rayon, 2 threads" or "NVIDIA H100 80GB HBM3".
    pub device: String,
}

/// Whole-system numbers, cheap enough to take every output interval.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Diagnostics {
    pub step: u64,
    /// [T]
    pub time: f64,
    /// [T] the last step's size.
    pub dt: f32,
    /// [M L^2 T^-2] sum of m v^2 / 2 over fluid and solid particles.
    pub kinetic_energy: f64,
    /// [L/T] over fluid and solid particles.
    pub max_speed: f32,
    /// [-] max |rho / rho0 - 1| over fluid particles.
    pub density_error: f32,
    /// [M L/T] sum of m v over fluid and solid particles.
    pub momentum: [f64; 3],
    pub fluid: usize,
    pub solid: usize,
    pub boundary: usize,
}

/// What a decomposed run's exchange cost so far (`crate::exchange`), over all ranks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ExchangeCost {
    /// Subdomains (ranks).
    pub ranks: usize,
    /// Halo fills of each rank: one per step, and one per wall-force or probe sample.
    pub fills: u64,
    /// Halo particles received, summed over the ranks and fills.
    pub particles: u64,
    /// Halo bytes received (what a transport between GPUs carries), summed likewise.
    pub bytes: u64,
    /// [s] wall time of the slowest rank in halo fills and step-size agreement (waits for
    /// the GPU's queued work and for the other ranks included).
    pub seconds: f64,
    /// Device memory the ranks hold now, spare capacity for halos included (0 on the CPU).
    pub device_bytes: u64,
    /// [s] of `seconds`, the slowest rank's time in the transport's exchange itself.
    pub transfer_seconds: f64,
}

/// A blow-up: the first bad particle found and what was wrong with it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, thiserror::Error)]
#[error("blow-up at step {step}, t = {time:.6}: particle {particle} ({kind}) has {quantity} = {value} ({reason})")]
pub struct Fault {
    pub step: u64,
    pub time: f64,
    /// The particle's id.
    pub particle: u32,
    pub kind: String,
    /// "position", "velocity", "density", ...
    pub quantity: String,
    /// The offending value (the first bad component for vectors).
    pub value: f64,
    pub reason: String,
}

/// The particle quantity a snapshot carries for display.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum Shown {
    #[default]
    Speed,
    Pressure,
    Density,
    Kind,
}

/// What the viewer draws: positions, kinds and one quantity, in storage order, in buffers
/// that are reused from frame to frame.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Snapshot {
    pub positions: Vec<[f32; 3]>,
    pub values: Vec<f32>,
    pub kinds: Vec<u8>,
}

/// The viewer's particle vertex buffers, by their OpenGL names in the context current on the
/// calling thread, which a backend with the particles in device memory fills in place
/// (`Solver::fill_gl`): per particle, the position as three f32 [L] (z = 0 in 2D), the
/// shown quantity as one f32, the kind as one u8; each buffer holds `capacity` particles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GlBuffers {
    pub positions: u32,
    pub values: u32,
    pub kinds: u32,
    pub capacity: usize,
}

/// What `Solver::fill_gl` wrote: `count` particles, `kinds` of them of each kind class in
/// the buffers' order (fluid, solid, every other kind), and the least and greatest shown
/// value of the particles that set the colour range (finite, neither boundary nor hidden),
/// where the range was reduced and any particle set it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GlFill {
    pub count: usize,
    pub kinds: [usize; 3],
    pub range: Option<(f32, f32)>,
    /// Whether the splat asked for was written.
    pub splat: bool,
}

/// A visibility splat asked of `Solver::fill_gl` with the fill (the viewer's `SplatView`):
/// of the particles `first .. first + count` of the filled buffers whose kind is not
/// `hidden` (bit k: kind k), the nearest sphere of `radius` [L] at each pixel of a `width` x
/// `height` perspective view, written to the OpenGL buffer `buffer`: `width * height`
/// quadruples of `f32` (the sphere's world centre and shown value), then as many kind bytes
/// (255 where no sphere is), pixel (X, Y) at Y width + X. `view`: the world-to-view rows
/// (3 x 4); a pixel centre (X + 1/2, Y + 1/2) looks along (X' ray[0] + ray[1], Y' ray[2] +
/// ray[3], -1) in view space (X', Y' the centre's coordinates).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GlSplat {
    pub buffer: u32,
    pub width: u32,
    pub height: u32,
    pub view: [f32; 12],
    pub ray: [f32; 4],
    pub radius: f32,
    pub first: usize,
    pub count: usize,
    pub hidden: u8,
}

impl GlSplat {
    /// Bytes of `buffer`.
    pub fn bytes(&self) -> usize {
        self.width as usize * self.height as usize * 17
    }
}

/// Fields kernel-interpolated at one point (`Solver::sample_points`): eqs. (1)-(4) with
/// Shepard normalisation, f(x) = sum_j f_j W(x - x_j) V_j / sum_j W(x - x_j) V_j with
/// V_j = m_j / rho_j, over the fluid particles within the support of x (and the wall
/// particles too where asked). Elastic solid particles never enter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PointSample {
    /// [M L^-d L^2 T^-2] each neighbour's pressure from its density by its equation of
    /// state (eq. (9), with the background pressure); NaN where no particle is near.
    pub pressure: f32,
    /// [L/T] (z = 0 in 2D); NaN where no particle is near.
    pub velocity: [f32; 3],
    /// [M L^-d] NaN where no particle is near.
    pub density: f32,
    /// [-] the fluid's colour sum_j W(x - x_j) m_j / rho_j over fluid particles only
    /// (whatever the walls): about 1 inside the fluid, 1/2 on its free surface, 0 outside
    /// (the free-surface gauges, `crate::probe`).
    pub colour: f32,
    /// Particles in the interpolation (fluid, and walls where asked).
    pub neighbours: u32,
}

impl PointSample {
    /// The sample of a point with no particle near: NaN fields, zero colour.
    pub const EMPTY: PointSample = PointSample {
        pressure: f32::NAN,
        velocity: [f32::NAN; 3],
        density: f32::NAN,
        colour: 0.0,
        neighbours: 0,
    };
}

/// The solver stages (Fig. 1) and the read-back the driver, output and tests need.
pub trait Solver: Send {
    fn info(&self) -> BackendInfo;
    fn params(&self) -> &SphParams;
    fn len(&self) -> usize;
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    fn has_solids(&self) -> bool;

    /// Neighbour search: cell index, sort by (cell, id), cell ranges, reorder.
    fn build_grid(&mut self);
    /// Density by summation, eq. (8) (nothing for the continuity form); the Tait equation
    /// of state, eq. (9), and the solid pressure law; the artificial stress of solids.
    fn density(&mut self);
    /// The total-Lagrangian bodies' stress (`[solid] formulation = "total-lagrangian"`,
    /// `crate::tlsph`): the deformation gradient from the displacements, the Saint
    /// Venant-Kirchhoff stress, and the deviator of its Cauchy stress written into S, where
    /// the force stage reads it (the particle's density and pressure stay the continuity
    /// density's, the interface's). Nothing under the Jaumann rate (the default does
    /// nothing).
    fn solid_stress(&mut self) {}
    /// Accelerations: eqs. (7), (10), (16), (17), laminar viscosity, artificial stress,
    /// gravity.
    fn forces(&mut self);
    /// The total-Lagrangian bodies' internal force and hourglass control, added to the
    /// force stage's accelerations (which left out the stress term between particles of one
    /// total-Lagrangian body). Nothing under the Jaumann rate (the default does nothing).
    fn solid_forces(&mut self) {}
    /// Rates from the current velocities: d rho/dt (continuity, with the density diffusion
    /// of Molteni & Colagrossi 2009 where `density_diffusion` > 0), the XSPH velocity of
    /// eq. (18), and, with solids, the velocity gradient eq. (15), strain and rotation
    /// rates eqs. (13)-(14) and the Jaumann stress rate eq. (12).
    fn rates(&mut self);
    /// `forces` and `rates` of one state, as the paper's forward Euler takes them (both from
    /// the old velocities; neither reads what the other writes). A backend may compute both
    /// in one neighbour pass (the CUDA backend does); the default runs the two stages.
    fn forces_and_rates(&mut self) {
        self.rates();
        self.forces();
    }
    /// The step size: fixed, or the CFL eq. (19) with the force and viscous limits.
    fn time_step(&mut self);
    /// v += dt a.
    fn kick(&mut self);
    /// x += dt (v + xsph), rho += dt d rho/dt, S += dt dS/dt, and the total-Lagrangian
    /// bodies' displacement u += dt (v + xsph); advances the clock.
    fn drift(&mut self);
    /// The forward Euler's `drift` then `kick` (the positions move with the old velocity).
    /// A backend may do both in one pass over the particles (the CUDA backend does).
    fn drift_kick(&mut self) {
        self.drift();
        self.kick();
    }

    /// One time step, in the order of the paper's Fig. 1. The paper's forward Euler,
    /// eq. (19), takes every rate at the old velocity; the symplectic Euler kicks first and
    /// takes the rates, positions, density and stress from the new velocity.
    fn step(&mut self) {
        self.build_grid();
        self.density();
        self.solid_stress();
        if self.params().integrator as u32 == MF_INTEGRATOR_EULER {
            self.forces_and_rates();
            self.solid_forces();
            self.time_step();
            self.drift_kick();
        } else {
            self.forces();
            self.solid_forces();
            self.time_step();
            self.kick();
            self.rates();
            self.drift();
        }
    }

    /// `steps` steps of `step`, as one batch: a backend may record the trait's `step` once
    /// and replay the recording (the CUDA backend replays a CUDA graph), never reorder it.
    fn advance(&mut self, steps: u64) {
        for _ in 0..steps {
            self.step();
        }
    }

    /// Simulated time [T] (a read-back on the GPU).
    fn time(&mut self) -> f64;
    fn steps(&self) -> u64;
    /// The first particle with non-finite values, a density out of the sane range, or
    /// outside the domain on a non-periodic axis.
    fn check(&mut self) -> Result<(), Fault>;
    /// `check` of the particles as they are now, whose fault may be reported later, by
    /// `queued_fault`, with the step, time and particle of this check: a GPU backend queues
    /// the check and keeps the first fault on the device, so that stepping never waits for
    /// it (`step::Stepper` reads it with the clock at the end of each batch). The default
    /// checks at once.
    fn queue_check(&mut self) -> Result<(), Fault> {
        self.check()
    }
    /// The first fault that the checks queued so far found, if any (the default queues
    /// none).
    fn queued_fault(&mut self) -> Result<(), Fault> {
        Ok(())
    }
    fn diagnostics(&mut self) -> Diagnostics;
    /// All particles, ordered by id (a read-back on the GPU).
    fn particles(&mut self) -> Vec<Particle>;
    /// Start copying `fields` of every particle for an output (`crate::frame`): returns
    /// at once where the backend can copy in the background (CUDA), and the frame's `wait`
    /// delivers it in storage order with the ids. The default reads back whole particles.
    fn capture(&mut self, fields: Fields) -> Box<dyn PendingFrame> {
        let (step, time) = (self.steps(), self.time());
        let data = FrameData::from_particles(&self.particles(), fields, step, time);
        Box::new(Ready(data))
    }
    /// Positions, kinds and one quantity, for display. The default reads back whole
    /// particles; a GPU backend copies only what is shown.
    fn snapshot(&mut self, shown: Shown, out: &mut Snapshot) {
        out.positions.clear();
        out.values.clear();
        out.kinds.clear();
        for q in self.particles() {
            out.positions.push(q.position);
            out.kinds.push(q.kind.code());
            out.values.push(match shown {
                Shown::Speed => q.speed(),
                Shown::Pressure => q.pressure,
                Shown::Density => q.density,
                Shown::Kind => q.kind.code() as f32,
            });
        }
    }
    /// Fills the viewer's vertex buffers `gl` from device memory (CUDA-OpenGL interop:
    /// positions, quantity `shown` and kinds of the fluid, then of the solids, then of the
    /// other kinds, each in storage order, as `snapshot` gives them), and
    /// reduces the colour range on the device unless `fixed_range` (then nothing comes back
    /// to the host); `hidden`'s bit k keeps kind k out of the range; with `splat`, also the
    /// spheres' visibility (`GlSplat`). `None`: this backend has no device memory to fill
    /// from (the viewer uploads a `snapshot`); `Err`: what failed.
    fn fill_gl(
        &mut self,
        _gl: &GlBuffers,
        _shown: Shown,
        _hidden: u8,
        _fixed_range: bool,
        _splat: Option<&GlSplat>,
    ) -> Option<Result<GlFill, String>> {
        None
    }
    /// Bytes copied from the device to the host since the solver was made (the read-backs of
    /// time, health checks, diagnostics, snapshots, probes, monitors, the colour range and
    /// whole states); `None` on a backend without a device.
    fn device_to_host_bytes(&self) -> Option<u64> {
        None
    }
    /// Pressure, velocity, density and the fluid's colour at each of `points` [L] (z
    /// ignored in 2D), kernel-interpolated on the device with Shepard normalisation
    /// (`PointSample`), over fluid particles and, where `include_walls`, the wall
    /// particles too; `out` gets one sample per point, in order. Nothing per particle is
    /// read back. The neighbour grid is rebuilt first where the particles moved since the
    /// last build (a step ends with the drift, so after every step): the sums then see
    /// every particle within the support, and the stepping that follows is unchanged (the
    /// next step's build gives the same order from the same positions).
    fn sample_points(
        &mut self,
        points: &[[f32; 3]],
        include_walls: bool,
        out: &mut Vec<PointSample>,
    );
    /// The state a restart needs (`crate::checkpoint`), at this step boundary (a
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
    /// Remove every particle of a scene group (opening a gate). Returns how many went.
    fn remove_group(&mut self, group: u32) -> usize;
    /// `Setup::wall_surface` as the solver took it (empty unless `no_slip`), for the force
    /// monitors, which take the wall pair terms from the CPU force stage.
    fn wall_surface(&self) -> &[[f32; 4]];
    /// The force [M L T^-2] (z = 0 in 2D; per unit depth in 2D) that the fluid and solid
    /// particles exert on the boundary particles of each scene group of `groups`, in their
    /// order (`[[monitors]]`): the force stage's wall pair terms, F = - sum_i m_i a_i(from
    /// the group's walls), eqs. (7), (9), (10), (16), (17) and the laminar viscosity, at the
    /// current positions and densities (`crate::monitor`, whose `wall_force` on a particle
    /// read-back is the reference: `tests/monitor.rs`, `tests/cuda_parity/`). Each backend
    /// sums on its own state, leaving the run as it would be without the sample.
    fn wall_forces(&mut self, groups: &[u32]) -> Vec<[f64; 3]>;
    /// A decomposed solver's exchange so far (`crate::exchange::Decomposed`); None for one
    /// domain.
    fn exchange_cost(&self) -> Option<ExchangeCost> {
        None
    }
}
