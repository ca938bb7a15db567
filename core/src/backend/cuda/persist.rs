//! The CUDA solver's checkpoints (`Persist`): the state and the total-Lagrangian
//! displacements read back, and written again with the clock on restore.

use crate::physics::dim::Dim;
use crate::physics::open::OpenState;
use crate::physics::params::needs_density_gradient;
use crate::solver::checkpoint::{BodyState, SolverCheckpoint};
use crate::solver::{Persist, Readback, Solver};

use super::buffers::Buffers;
use super::CudaSolver;

impl<D: Dim> Persist for CudaSolver<D> {
    fn save(&mut self) -> SolverCheckpoint {
        let state = self.download_state();
        let disp = self.tl_displacement().unwrap_or_default();
        let (time, dt) = (self.time(), self.dt());
        let mut c = SolverCheckpoint::of_state(&state, time, self.steps, dt, &disp);
        c.bodies = self.bodies().iter().map(BodyState::of).collect();
        if let Some((next_id, _)) = self.open {
            c.open = Some(OpenState {
                next_id,
                tally: self.open_tally(),
            });
        }
        c
    }
    fn restore(&mut self, saved: &SolverCheckpoint) -> Result<(), String> {
        let state = saved.to_state(&self.download_state())?;
        let n_solid = self.tl.as_ref().map_or(0, |t| t.n_solid);
        let disp = saved.tl_displacements::<D>(n_solid)?;
        let mut bodies = self.bodies();
        BodyState::restore_all(&saved.bodies, &mut bodies)?;
        let open = saved.open_state(&self.params)?;
        if state.len() == self.buf.n {
            self.upload_state(&state);
        } else {
            // Open boundaries: another particle count than the solver holds.
            self.buf = Buffers::new(
                &self.dev.stream,
                &state,
                self.buf.n_cells,
                &self.wall_surface,
                &self.motion_series,
                needs_density_gradient(&self.params),
            )
            .map_err(|e| super::oom(state.len(), e).to_string())?;
            self.grid_current = false;
        }
        if let Some((next_id, tally)) = self.open.as_mut() {
            *next_id = open.next_id;
            let t: Vec<f64> = open
                .tally
                .iter()
                .flat_map(|t| [t.count_in as f64, t.mass_in, t.count_out as f64, t.mass_out])
                .collect();
            if let Err(e) = self.dev.stream.memcpy_htod(&t[..], tally) {
                self.sync_err("restoring the open boundaries' tally", e)
            }
        }
        if let Some(bb) = self.bodies.as_mut() {
            if let Err(e) = bb.write(&self.dev.stream, &bodies) {
                self.sync_err("restoring the floating bodies", e)
            }
        }
        let s = &self.dev.stream;
        let written = self.tl.as_mut().map_or(Ok(()), |t| {
            t.write_disp::<D>(s, &disp).and_then(|_| t.clear_slots(s))
        });
        if let Err(e) = written {
            self.sync_err("restoring the total-Lagrangian displacements", e)
        }
        self.tl_map_slots();
        self.set_clock(saved.time, saved.dt);
        // A queued check's fault belongs to the run before the restore.
        if let Err(e) = self
            .dev
            .stream
            .memcpy_htod(&[saved.time, 0.0][..], &mut self.buf.time.slice_mut(..2))
        {
            self.sync_err("restoring the clock", e)
        }
        self.steps = saved.steps;
        self.graph = None;
        Ok(())
    }
}
