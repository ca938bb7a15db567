//! The CUDA solver's checkpoints (`Persist`): the state and the total-Lagrangian
//! displacements read back, and written again with the clock on restore.

use crate::physics::dim::Dim;
use crate::solver::checkpoint::{BodyState, SolverCheckpoint};
use crate::solver::{Persist, Readback, Solver};

use super::CudaSolver;

impl<D: Dim> Persist for CudaSolver<D> {
    fn save(&mut self) -> SolverCheckpoint {
        let state = self.download_state();
        let disp = self.tl_displacement().unwrap_or_default();
        let (time, dt) = (self.time(), self.dt());
        let mut c = SolverCheckpoint::of_state(&state, time, self.steps, dt, &disp);
        c.bodies = self.bodies().iter().map(BodyState::of).collect();
        c
    }
    fn restore(&mut self, saved: &SolverCheckpoint) -> Result<(), String> {
        let state = saved.to_state(&self.download_state())?;
        let n_solid = self.tl.as_ref().map_or(0, |t| t.n_solid);
        let disp = saved.tl_displacements::<D>(n_solid)?;
        let mut bodies = self.bodies();
        BodyState::restore_all(&saved.bodies, &mut bodies)?;
        self.upload_state(&state);
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
