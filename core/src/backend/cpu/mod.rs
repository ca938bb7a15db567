//! The CPU backend: the stages of `Solver` on rayon, in 2D and 3D from one source.
//! Twin of `src/backend/cuda/`; each stage module names its CUDA file.

mod bodies;
mod density;
mod forces;
mod grid;
mod integrate;
mod interface;
mod monitor;
mod open;
mod probes;
mod rates;
mod reduce;
mod stress;
mod subdomain;
mod tlsph;

pub use density::pressure;
pub use forces::{cohesion_over_r, ForceSum};
pub use grid::{cell_coords, cell_index, Grid};
pub use integrate::smooth_ramp;
pub use monitor::{refresh_pressure, wall_force, wall_load};
pub use probes::PointSum;
pub use rates::shift_velocity;
pub use reduce::step_size;
pub use stress::{artificial_stress, jacobi_eigen};
pub use tlsph::TlBodies;

use crate::backend::fault;
use crate::physics::dim::Dim;
use crate::physics::open::{OpenState, OpenTally};
use crate::physics::params::{needs_density_gradient, MfBody, SphParams, MF_DENSITY_CONTINUITY};
use crate::physics::particle::Particle;
use crate::physics::state::State;
use crate::solver::checkpoint::{BodyState, SolverCheckpoint};
use crate::solver::frame::{Fields, FrameData, PendingFrame, Ready};
use crate::solver::{
    BackendInfo, Diagnostics, Fault, Persist, PointSample, Readback, Setup, Solver,
};

/// The whole state in host memory, worked on by rayon.
pub struct CpuSolver<D: Dim> {
    params: SphParams,
    state: State<D>,
    grid: Grid,
    /// Whether the particles moved (or were removed) since the last `build_grid`, or none
    /// was built: `sample_points` then builds one.
    grid_stale: bool,
    /// `Setup::wall_surface` (empty unless `params::needs_wall_surface`).
    wall_surface: Vec<[f32; 4]>,
    /// The density gradient stage's output in storage order (`rates::density_gradient`),
    /// which the rates stage reads; None until that stage ran since the last sort, or where
    /// the scheme needs none.
    grad_rho: Option<Vec<D::V>>,
    /// The interface stage's (P', rho') per slot (`interface::solid_interface`), which the
    /// force stage reads; None until that stage ran since the last sort, or where the bodies
    /// meet the fluid at their own pressure.
    iface: Option<Vec<[f32; 2]>>,
    /// The total-Lagrangian bodies (`crate::physics::tlsph`); `None` under the Jaumann rate or
    /// without solids.
    tl: Option<TlBodies<D>>,
    /// The floating rigid bodies (`physics::body`), advanced in the kick and the drift.
    bodies: Vec<MfBody>,
    /// `Setup::motion_series`: the driven objects' time series.
    motion_series: Vec<f64>,
    /// The open boundaries' next id and tally (`open::open_boundaries`).
    open: OpenState,
    time: f64,
    steps: u64,
    dt: f32,
    /// [T] the last completed step's dt (0 before the first): the leapfrog's kick spans
    /// (dt_prev + dt) / 2.
    dt_prev: f32,
}

impl<D: Dim> CpuSolver<D> {
    /// Panics where `no_slip` is on and `setup.wall_surface` misses a boundary particle
    /// (`Setup::wall_surface_error`).
    pub fn new(setup: Setup) -> Self {
        if let Some(e) = setup.wall_surface_error() {
            panic!("{e}");
        }
        let p = setup.params;
        let mut state = State::from_particles(
            &setup.particles,
            p.density_form as u32 == MF_DENSITY_CONTINUITY,
            p.artificial_stress > 0.0,
            p.solid_rho0,
        );
        if p.own_solids != 0 {
            state = state.with_solid_arrays(p.artificial_stress > 0.0);
        }
        let tl = (crate::physics::tlsph::total_lagrangian(&p) && setup.has_solids())
            .then(|| TlBodies::new(&p, &setup.particles));
        CpuSolver {
            params: p,
            tl,
            state,
            grid: Grid::default(),
            grid_stale: true,
            grad_rho: None,
            iface: None,
            wall_surface: setup.wall_surface,
            bodies: setup.bodies,
            motion_series: setup.motion_series,
            open: OpenState::start(&p, &setup.particles),
            time: 0.0,
            steps: 0,
            dt: 0.0,
            dt_prev: 0.0,
        }
    }

    /// The raw arrays, in storage (sorted) order: for tests and parity checks.
    pub fn state(&self) -> &State<D> {
        &self.state
    }

    /// The grid of the last `build_grid`.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// The total-Lagrangian bodies, where the scene has them.
    pub fn tl_bodies(&self) -> Option<&TlBodies<D>> {
        self.tl.as_ref()
    }

    /// Sort the storage by (cell, id), and map the total-Lagrangian solid space onto it.
    fn sort(&mut self) {
        self.grid.build(&self.params, &mut self.state);
        self.grad_rho = None;
        self.iface = None;
        if let Some(tl) = self.tl.as_mut() {
            tl.map_slots(&self.state);
        }
        self.grid_stale = false;
    }

    /// The step size of the last `time_step` \[T\].
    pub fn dt(&self) -> f32 {
        self.dt
    }
}

impl<D: Dim> Solver for CpuSolver<D> {
    fn info(&self) -> BackendInfo {
        BackendInfo {
            backend: "cpu".into(),
            device: format!("rayon, {} threads", rayon::current_num_threads()),
        }
    }
    fn params(&self) -> &SphParams {
        &self.params
    }
    fn len(&self) -> usize {
        self.state.len()
    }
    fn has_solids(&self) -> bool {
        self.state.solid.is_some()
    }
    fn open_boundaries(&mut self) {
        if open::open_boundaries(&self.params, &mut self.state, &mut self.open) {
            self.grid_stale = true;
        }
    }
    fn build_grid(&mut self) {
        self.sort();
    }
    fn density(&mut self) {
        density::wall_density(
            &self.params,
            &self.grid,
            &mut self.state,
            &self.wall_surface,
            &self.bodies,
            &self.motion_series,
            self.time,
        );
        density::density(&self.params, &self.grid, &mut self.state);
        open::buffer_density(&self.params, &self.grid, &mut self.state);
    }
    fn density_gradient(&mut self) {
        self.grad_rho = rates::density_gradient(&self.params, &self.grid, &self.state);
    }
    /// Panics where the scheme needs the density gradient and its stage did not run since
    /// the storage was last sorted (the trait's order runs it first).
    fn rates(&mut self) {
        let grad_rho = needs_density_gradient(&self.params).then(|| {
            self.grad_rho
                .as_deref()
                .filter(|g| g.len() == self.state.len())
                .expect("the density gradient stage runs before the rates (Solver::step)")
        });
        rates::rates(&self.params, self.dt, &self.grid, grad_rho, &mut self.state);
    }
    fn solid_interface(&mut self) {
        if self.has_solids() && crate::physics::pairs::extrapolated(&self.params) {
            self.iface = Some(interface::solid_interface(
                &self.params,
                &self.grid,
                &self.state,
            ));
        }
    }
    fn solid_stress(&mut self) {
        if let Some(tl) = self.tl.as_mut() {
            tl.stress(&self.params, &mut self.state);
        }
    }
    fn forces(&mut self) {
        let iface =
            (self.has_solids() && crate::physics::pairs::extrapolated(&self.params)).then(|| {
                self.iface
                    .as_deref()
                    .filter(|f| f.len() == self.state.len())
                    .expect("the interface stage runs before the forces (Solver::step)")
            });
        forces::forces(
            &self.params,
            &self.grid,
            &self.wall_surface,
            iface,
            &mut self.state,
        );
    }
    fn solid_forces(&mut self) {
        if let Some(tl) = self.tl.as_ref() {
            tl.forces(&self.params, &mut self.state);
        }
    }
    fn time_step(&mut self) {
        let (v, a, c) = reduce::extremes(&self.params, &self.state);
        self.dt = step_size(&self.params, c, v, a);
    }
    fn kick(&mut self) {
        let dt = integrate::kick_span(&self.params, self.dt_prev, self.dt);
        let t_end = integrate::kick_end(&self.params, self.time, self.dt);
        // The bodies' loads from the state the force stage saw, before the kick.
        let loads = bodies::loads(
            &self.params,
            &self.grid,
            &self.wall_surface,
            &self.bodies,
            &self.state,
        );
        integrate::kick(
            &self.params,
            &self.motion_series,
            dt,
            (self.time, t_end),
            &mut self.state,
        );
        bodies::kick(&self.params, dt, &loads, &mut self.bodies, &mut self.state);
    }
    fn drift(&mut self) {
        if let Some(tl) = self.tl.as_mut() {
            tl.drift(
                &self.params,
                &self.motion_series,
                self.dt,
                self.time,
                &self.state,
            );
        }
        bodies::drift(self.dt, &mut self.bodies, &mut self.state);
        integrate::drift(
            &self.params,
            &self.motion_series,
            self.dt,
            self.time,
            &mut self.state,
        );
        self.grid_stale = true;
        self.time += self.dt as f64;
        self.steps += 1;
        self.dt_prev = self.dt;
    }
    fn time(&mut self) -> f64 {
        self.time
    }
    fn steps(&self) -> u64 {
        self.steps
    }
    fn check(&mut self) -> Result<(), Fault> {
        let Some((i, code, value)) = reduce::first_fault(&self.params, &self.state) else {
            return Ok(());
        };
        let (id, kind) = (self.state.id[i], self.state.particle(i).kind);
        Err(fault(self.steps, self.time, id, kind, code, value))
    }
    fn remove_group(&mut self, group: u32) -> usize {
        let before = self.state.len();
        let g = self.state.group.clone();
        self.state.retain(|i| g[i] != group);
        if let Some(tl) = self.tl.as_mut() {
            tl.map_slots(&self.state);
        }
        self.grid_stale = true;
        before - self.state.len()
    }
}

impl<D: Dim> Readback for CpuSolver<D> {
    fn diagnostics(&mut self) -> Diagnostics {
        let mut d = reduce::diagnostics(&self.params, &self.state);
        d.step = self.steps;
        d.time = self.time;
        d.dt = self.dt;
        d
    }
    fn particles(&mut self) -> Vec<Particle> {
        self.state.to_particles()
    }
    /// A copy at once, in storage order (no sort by id).
    fn capture(&mut self, fields: Fields) -> Box<dyn PendingFrame> {
        let st = &self.state;
        let storage: Vec<Particle> = (0..st.len()).map(|i| st.particle(i)).collect();
        let data = FrameData::from_particles(&storage, fields, self.steps, self.time);
        Box::new(Ready(data))
    }
    fn wall_surface(&self) -> &[[f32; 4]] {
        &self.wall_surface
    }
    fn bodies(&mut self) -> Vec<MfBody> {
        self.bodies.clone()
    }
    fn open_tally(&mut self) -> Vec<OpenTally> {
        self.open.tally.clone()
    }
    fn sample_points(
        &mut self,
        points: &[[f32; 3]],
        include_walls: bool,
        out: &mut Vec<PointSample>,
    ) {
        if self.grid_stale {
            self.build_grid();
        }
        probes::sample(
            &self.params,
            &self.grid,
            &self.state,
            points,
            include_walls,
            out,
        );
    }
    /// On the state itself (`monitor.rs`): the grid rebuilt from the current positions (the
    /// drift moved the particles since the last build, and before the first step there is
    /// none) and the pressures of the current densities (`refresh_pressure`), as the next
    /// step's `build_grid` and `density` make them: that step then finds the storage sorted
    /// and runs as it would have without the sample, bit for bit.
    fn wall_forces(&mut self, groups: &[u32]) -> Vec<[f64; 3]> {
        self.sort();
        refresh_pressure(&self.params, &mut self.state);
        groups
            .iter()
            .map(|&g| wall_force(&self.params, &self.state, &self.grid, &self.wall_surface, g))
            .collect()
    }
}

impl<D: Dim> Persist for CpuSolver<D> {
    fn save(&mut self) -> SolverCheckpoint {
        let disp = self.tl.as_ref().map_or(&[][..], |t| &t.disp[..]);
        let mut c = SolverCheckpoint::of_state(&self.state, self.time, self.steps, self.dt, disp);
        c.bodies = self.bodies.iter().map(BodyState::of).collect();
        c.open = (self.params.open_count > 0).then(|| self.open.clone());
        c
    }
    fn restore(&mut self, saved: &SolverCheckpoint) -> Result<(), String> {
        let state = saved.to_state(&self.state)?;
        let n_solid = self.tl.as_ref().map_or(0, |t| t.disp.len());
        let disp = saved.tl_displacements::<D>(n_solid)?;
        BodyState::restore_all(&saved.bodies, &mut self.bodies)?;
        self.open = saved.open_state(&self.params)?;
        self.state = state;
        if let Some(tl) = self.tl.as_mut() {
            tl.disp = disp;
            tl.map_slots(&self.state);
        }
        self.grid_stale = true;
        self.time = saved.time;
        self.steps = saved.steps;
        self.dt = saved.dt;
        self.dt_prev = saved.dt;
        Ok(())
    }
}
