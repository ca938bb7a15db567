//! The CPU solver as one subdomain of a decomposed run (`crate::exchange`): halos are host
//! arrays (`State`), cut from and appended to the storage. Tests: `tests/exchange.rs`.

use crate::exchange::{Slab, Subdomain};
use crate::physics::dim::Dim;
use crate::physics::state::State;
use crate::solver::checkpoint::SolverCheckpoint;

use super::{reduce, step_size, CpuSolver};

impl<D: Dim> Subdomain for CpuSolver<D> {
    type Halo = State<D>;

    fn set_owned(&mut self, slab: Slab) {
        slab.own(&mut self.params);
    }
    fn halo(
        &mut self,
        target: &Slab,
        width: f32,
        periodic: Option<(f32, f32)>,
    ) -> Option<State<D>> {
        let a = target.axis;
        let slots: Vec<usize> = (0..self.state.len())
            .filter(|&i| target.gap(D::comp(self.state.pos[i], a), periodic) < width)
            .collect();
        (!slots.is_empty()).then(|| self.state.select(&slots))
    }
    fn halo_len(halo: &State<D>) -> usize {
        halo.len()
    }
    /// The arrays a step reads that an earlier one wrote, as a device halo packs them.
    fn halo_bytes(halo: &State<D>) -> usize {
        let v = std::mem::size_of::<D::V>();
        let per = 4 * 5 // id, kind (as a word), group, mass, rho
            + 4 // p
            + 2 * v // pos, vel
            + halo.drho.as_ref().map_or(0, |_| 4)
            + halo
                .solid
                .as_ref()
                .map_or(0, |_| std::mem::size_of::<D::M>() + 4);
        per * halo.len()
    }
    fn append(&mut self, halos: Vec<State<D>>) {
        for h in &halos {
            self.state.extend(h);
        }
        self.grid_stale = true;
    }
    fn retain_owned(&mut self) {
        let (p, pos) = (&self.params, &self.state.pos);
        let keep: Vec<bool> = pos
            .iter()
            .map(|&x| p.owns(D::comp(x, p.own_axis as usize)))
            .collect();
        self.state.retain(|i| keep[i]);
        self.grid_stale = true;
    }
    fn extremes(&mut self) -> [f32; 3] {
        let (v, a, c) = reduce::extremes(&self.params, &self.state);
        [v, a, c]
    }
    fn set_step(&mut self, e: [f32; 3]) {
        self.dt = step_size(&self.params, e[2], e[0], e[1]);
    }
    fn replace(&mut self, part: &SolverCheckpoint) -> Result<(), String> {
        if part.dim != D::D as u32 {
            return Err(format!(
                "it holds a {}D state and the scene is {}D",
                part.dim,
                D::D
            ));
        }
        self.state = part.to_state_unchecked(&self.state);
        self.grid_stale = true;
        self.time = part.time;
        self.steps = part.steps;
        self.dt = part.dt;
        self.dt_prev = part.dt;
        Ok(())
    }
}
