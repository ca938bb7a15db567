//! What comes back from a solver: whole-system diagnostics, particles, frames for output,
//! fields interpolated at points, the force on walls, the viewer's snapshot (and its buffers, `crate::interop`),
//! and the decomposition's cost. Nothing here changes the stepping.

use serde::{Deserialize, Serialize};

use crate::physics::particle::Particle;
use crate::solver::frame::{Fields, PendingFrame};
use crate::solver::{Shown, Snapshot};

/// Whole-system numbers, cheap enough to take every output interval.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Diagnostics {
    pub step: u64,
    /// \[T\]
    pub time: f64,
    /// \[T\] the last step's size.
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
    /// \[s\] wall time of the slowest rank in halo fills and step-size agreement (waits for
    /// the GPU's queued work and for the other ranks included).
    pub seconds: f64,
    /// Device memory the ranks hold now, spare capacity for halos included (0 on the CPU).
    pub device_bytes: u64,
    /// \[s\] of `seconds`, the slowest rank's time in the transport's exchange itself.
    pub transfer_seconds: f64,
}

/// Fields kernel-interpolated at one point (`Readback::sample_points`): eqs. (1)-(4) with
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
    /// (the free-surface gauges, `crate::measure::probe`).
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

/// Read-back and measurement (`Solver`'s supertrait): what the run driver, the output, the
/// viewer and the tests take from a solver.
pub trait Readback {
    fn diagnostics(&mut self) -> Diagnostics;
    /// All particles, ordered by id (a read-back on the GPU).
    fn particles(&mut self) -> Vec<Particle>;
    /// Start copying `fields` of every particle for an output (`crate::solver::frame`): returns
    /// at once where the backend can copy in the background (CUDA), and the frame's `wait`
    /// delivers it in storage order with the ids.
    fn capture(&mut self, fields: Fields) -> Box<dyn PendingFrame>;
    /// Pressure, velocity, density and the fluid's colour at each of `points` \[L\] (z
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
    /// The floating rigid bodies as they are now (`Setup::bodies`' order: pose, momenta,
    /// last load); none by default (a solver without bodies, or a decomposed one, which
    /// refuses them).
    fn bodies(&mut self) -> Vec<crate::physics::params::MfBody> {
        Vec::new()
    }
    /// Each open boundary's tally of the particles and mass in and out since the run began
    /// (`[[open_boundaries]]`' order); none by default (a solver without open boundaries,
    /// or a decomposed one, which refuses them).
    fn open_tally(&mut self) -> Vec<crate::physics::open::OpenTally> {
        Vec::new()
    }
    /// `Setup::wall_surface` as the solver took it (empty unless `no_slip`), for the force
    /// monitors, which take the wall pair terms from the CPU force stage.
    fn wall_surface(&self) -> &[[f32; 4]];
    /// The force [M L T^-2] (z = 0 in 2D; per unit depth in 2D) that the fluid and solid
    /// particles exert on the boundary particles of each scene group of `groups`, in their
    /// order (`[[monitors]]`): the force stage's wall pair terms, F = - sum_i m_i a_i(from
    /// the group's walls), eqs. (7), (9), (10), (16), (17) and the laminar viscosity, at the
    /// current positions and densities (`crate::measure::monitor`, whose `wall_force` on a particle
    /// read-back is the reference: `tests/monitor.rs`, `tests/cuda_parity/`). Each backend
    /// sums on its own state, leaving the run as it would be without the sample.
    fn wall_forces(&mut self, groups: &[u32]) -> Vec<[f64; 3]>;
    /// Positions, kinds and one quantity, for display. The default reads back whole
    /// particles; a GPU backend copies only what is shown.
    fn snapshot(&mut self, shown: Shown, out: &mut Snapshot) {
        out.positions.clear();
        out.values.clear();
        out.kinds.clear();
        for q in self.particles() {
            out.positions.push(q.position);
            out.kinds.push(q.kind.code());
            out.values.push(shown.of(&q));
        }
    }
    /// The backend's CUDA-OpenGL interop (`crate::interop`), where it fills the viewer's
    /// buffers from device memory; `None`: the viewer uploads a `snapshot`.
    #[cfg(feature = "interop")]
    fn gl_interop(&mut self) -> Option<&mut dyn crate::interop::GlInterop> {
        None
    }
    /// Bytes copied from the device to the host since the solver was made (the read-backs of
    /// time, health checks, diagnostics, snapshots, probes, monitors, the colour range and
    /// whole states); `None` on a backend without a device.
    fn device_to_host_bytes(&self) -> Option<u64> {
        None
    }
    /// A decomposed solver's exchange so far (`crate::exchange::Decomposed`); None for one
    /// domain.
    fn exchange_cost(&self) -> Option<ExchangeCost> {
        None
    }
}
