//! The solver state a restart needs (`Persist::save`, `Persist::restore`), in storage order
//! and in a form that neither the backend nor the dimension's vector types shape: vectors
//! as three components (z = 0 in 2D), symmetric tensors as six. The file around it (its
//! version, checksum and the run's own state) is the app's (`meshfree run --resume`).
//!
//! Kept: everything a step reads that an earlier step wrote. Positions, velocities and
//! density, the deviatoric stress and the solids' density departure from rest, the
//! total-Lagrangian displacements, the floating bodies' states (`BodyState`), the clock, the
//! step count and the last step size; the
//! ids, kinds, groups and masses with them, to check that the restored scene is the saved
//! one. The pressure rides along (a restored solver reads back as the saved one did).
//! Left out: what a step writes before it reads it (accelerations, XSPH velocities,
//! d rho/dt, the stress rate, the artificial stress, the total-Lagrangian deformation
//! gradients and first Piola-Kirchhoff stresses) and what the scene gives again (the
//! total-Lagrangian reference configuration, the walls' surface normals).
//!
//! Restored in the saved storage order, a run steps on exactly as it would have: every
//! stage's sums visit the neighbours in the (cell, id) order of the next grid build, which
//! the positions alone fix.

use crate::exchange::Slab;
use crate::physics::dim::Dim;
use crate::physics::params::MfBody;
use crate::physics::state::{SolidState, State};

/// One rank's share of a decomposed solver's state (`Persist::save_pieces`): the slab it
/// owns and its particles (all of them in that slab: between steps a rank holds its owned
/// particles alone), with the clock, step count and step size, which every rank shares.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Piece {
    pub slab: Slab,
    pub state: SolverCheckpoint,
}

impl Piece {
    /// The pieces of every rank, in rank order, as one checkpoint (`SolverCheckpoint::concat`).
    pub fn gather(pieces: &[Piece]) -> SolverCheckpoint {
        let states: Vec<SolverCheckpoint> = pieces.iter().map(|p| p.state.clone()).collect();
        SolverCheckpoint::concat(&states)
    }

    /// Why this piece is not what rank `rank` of `ranks` saved: a particle outside its
    /// slab, or a clock other than `like`'s (the pieces of two checkpoints mixed). None
    /// where it fits.
    pub fn mismatch(&self, like: &SolverCheckpoint) -> Option<String> {
        let s = &self.state;
        if (s.time.to_bits(), s.steps, s.dt.to_bits())
            != (like.time.to_bits(), like.steps, like.dt.to_bits())
        {
            return Some(format!(
                "it was saved at t = {} (step {}), the other pieces at t = {} (step {})",
                s.time, s.steps, like.time, like.steps
            ));
        }
        let a = self.slab.axis;
        if let Some(i) = (0..s.len()).find(|&i| !self.slab.contains(s.pos[i][a])) {
            return Some(format!(
                "particle {} lies outside its slab ({} <= x[{a}] < {})",
                s.id[i], self.slab.lo, self.slab.hi
            ));
        }
        None
    }
}

/// The particle arrays `SolverCheckpoint::mismatch` compares against.
struct Layout<'a> {
    dim: u32,
    id: &'a [u32],
    kind: &'a [u8],
    group: &'a [u32],
    mass: &'a [f32],
    solids: bool,
}

/// The solver state of one step boundary (`Persist::save`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SolverCheckpoint {
    /// 2 or 3.
    pub dim: u32,
    /// \[T\] the simulated time.
    pub time: f64,
    /// Steps taken.
    pub steps: u64,
    /// \[T\] the last step's size (0 before the first).
    pub dt: f32,
    pub id: Vec<u32>,
    /// `Kind` codes.
    pub kind: Vec<u8>,
    pub group: Vec<u32>,
    /// \[M\]
    pub mass: Vec<f32>,
    /// \[L\]
    pub pos: Vec<[f32; 3]>,
    /// [L/T]
    pub vel: Vec<[f32; 3]>,
    /// [M L^-d]
    pub rho: Vec<f32>,
    /// [M L^-d L^2 T^-2]
    pub p: Vec<f32>,
    /// The deviatoric stress S (xx, yy, zz, xy, xz, yz) [M L^-d L^2 T^-2]; empty without
    /// solid particles.
    pub stress: Vec<[f32; 6]>,
    /// [M L^-d] the solids' rho - rho0_s (`SolidState::rho_dev`); empty without solids.
    pub rho_dev: Vec<f32>,
    /// \[L\] the total-Lagrangian displacements u = x - X0, in solid space (the reference's
    /// order, not the storage's); empty under the Jaumann rate.
    pub tl_disp: Vec<[f32; 3]>,
    /// The floating rigid bodies' states (`Setup::bodies`' order); empty without.
    #[serde(default)]
    pub bodies: Vec<BodyState>,
    /// The open boundaries' next id and tallies; None without open boundaries. Under open
    /// boundaries the fluid's particles are not the scene's (`mismatch` compares the
    /// others).
    #[serde(default)]
    pub open: Option<crate::physics::open::OpenState>,
}

/// A floating body's state for a restart: the fields of `MfBody` that its steps change
/// (its constants, mass, inertia and free axes, the scene gives again).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BodyState {
    pub group: i32,
    pub centre: [f64; 3],
    pub orientation: [f64; 4],
    pub velocity: [f64; 3],
    pub momentum: [f64; 3],
    pub omega: [f64; 3],
    pub force: [f64; 3],
    pub torque: [f64; 3],
    pub contact: [f64; 3],
    pub contact_torque: [f64; 3],
    pub shift: [f64; 3],
    pub turn: [f64; 9],
}

impl BodyState {
    pub fn of(b: &MfBody) -> BodyState {
        BodyState {
            group: b.group,
            centre: b.centre,
            orientation: b.orientation,
            velocity: b.velocity,
            momentum: b.momentum,
            omega: b.omega,
            force: b.force,
            torque: b.torque,
            contact: b.contact,
            contact_torque: b.contact_torque,
            shift: b.shift,
            turn: b.turn,
        }
    }

    /// The states `saved` put back into the scene's `bodies`; an error where they are not
    /// the scene's (another count, or another group).
    pub fn restore_all(saved: &[BodyState], bodies: &mut [MfBody]) -> Result<(), String> {
        if saved.len() != bodies.len() {
            return Err(format!(
                "it holds {} floating bodies and the scene has {}",
                saved.len(),
                bodies.len()
            ));
        }
        for (s, b) in saved.iter().zip(bodies.iter_mut()) {
            if s.group != b.group {
                return Err(format!(
                    "its floating body of group {} is the scene's of group {}",
                    s.group, b.group
                ));
            }
            b.centre = s.centre;
            b.orientation = s.orientation;
            b.velocity = s.velocity;
            b.momentum = s.momentum;
            b.omega = s.omega;
            b.force = s.force;
            b.torque = s.torque;
            b.contact = s.contact;
            b.contact_torque = s.contact_torque;
            b.shift = s.shift;
            b.turn = s.turn;
        }
        Ok(())
    }
}

impl SolverCheckpoint {
    /// The checkpoint of `state` (storage order) at the clock `time` \[T\] after `steps`
    /// steps, the last of size `dt` \[T\], with the total-Lagrangian displacements `tl_disp`
    /// (empty where there are none).
    pub fn of_state<D: Dim>(
        state: &State<D>,
        time: f64,
        steps: u64,
        dt: f32,
        tl_disp: &[D::V],
    ) -> SolverCheckpoint {
        let solid = state.solid.as_ref();
        SolverCheckpoint {
            dim: D::D as u32,
            time,
            steps,
            dt,
            id: state.id.clone(),
            kind: state.kind.clone(),
            group: state.group.clone(),
            mass: state.mass.clone(),
            pos: state.pos.iter().map(|&v| D::to3(v)).collect(),
            vel: state.vel.iter().map(|&v| D::to3(v)).collect(),
            rho: state.rho.clone(),
            p: state.p.clone(),
            stress: solid.map_or_else(Vec::new, |s| {
                s.stress.iter().map(|&m| D::sym_to6(m)).collect()
            }),
            rho_dev: solid.map_or_else(Vec::new, |s| s.rho_dev.clone()),
            tl_disp: tl_disp.iter().map(|&v| D::to3(v)).collect(),
            bodies: Vec::new(),
            open: None,
        }
    }

    /// The open boundaries' state of this checkpoint, for a scene with the parameters `p`:
    /// one with open boundaries must have it, one without must not.
    pub fn open_state(
        &self,
        p: &crate::physics::params::SphParams,
    ) -> Result<crate::physics::open::OpenState, String> {
        use crate::physics::open::OpenState;
        let saved = self;
        let n = p.open_count.max(0) as usize;
        match &saved.open {
            None if n == 0 => Ok(OpenState::default()),
            Some(o) if o.tally.len() == n && saved.id.iter().all(|&i| i < o.next_id) => {
                Ok(o.clone())
            }
            Some(o) if o.tally.len() == n => Err(format!(
                "it holds a particle id at or past its next new id {}",
                o.next_id
            )),
            Some(o) => Err(format!(
                "it holds {} open boundaries and the scene {n}",
                o.tally.len()
            )),
            None => Err(format!("it holds no open boundaries and the scene {n}")),
        }
    }

    pub fn len(&self) -> usize {
        self.id.len()
    }

    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Why this checkpoint cannot have been taken from a solver whose state is laid out as
    /// `like` (a solver of the same scene, started afresh, its gates opened alike): another
    /// dimension, particle set, kind, group or mass (compared by id, bit for bit), array
    /// lengths that disagree, or solids on one side only. None where it fits.
    pub fn mismatch<D: Dim>(&self, like: &State<D>) -> Option<String> {
        let like = Layout {
            dim: D::D as u32,
            id: &like.id,
            kind: &like.kind,
            group: &like.group,
            mass: &like.mass,
            solids: like.solid.is_some(),
        };
        self.mismatch_layout(&like)
    }

    /// `mismatch` against another checkpoint's particles (a decomposed solver's, gathered
    /// from its subdomains), which has solids where it carries stress.
    pub fn mismatch_with(&self, like: &SolverCheckpoint) -> Option<String> {
        self.mismatch_layout(&Layout {
            dim: like.dim,
            id: &like.id,
            kind: &like.kind,
            group: &like.group,
            mass: &like.mass,
            solids: !like.stress.is_empty(),
        })
    }

    fn mismatch_layout(&self, like: &Layout) -> Option<String> {
        let n = self.len();
        if self.dim != like.dim {
            return Some(format!(
                "it holds a {}D state and the scene is {}D",
                self.dim, like.dim
            ));
        }
        let lengths = [
            self.kind.len(),
            self.group.len(),
            self.mass.len(),
            self.pos.len(),
            self.vel.len(),
            self.rho.len(),
            self.p.len(),
        ];
        if lengths.iter().any(|&l| l != n) {
            return Some(format!(
                "its arrays disagree in length ({n} ids; {lengths:?})"
            ));
        }
        // Under open boundaries the fluid's particles come and go: the others are compared.
        let fluid = crate::physics::params::MF_KIND_FLUID as u8;
        let open = self.open.is_some();
        let compared = |kind: &[u8]| -> Vec<usize> {
            (0..kind.len())
                .filter(|&i| !(open && kind[i] == fluid))
                .collect()
        };
        let (mine, theirs) = (compared(&self.kind), compared(like.kind));
        if mine.len() != theirs.len() {
            return Some(format!(
                "it holds {} {}particles and the scene has {}",
                mine.len(),
                if open { "wall and solid " } else { "" },
                theirs.len()
            ));
        }
        let solids = like.solids;
        let (stress, rho_dev) = (self.stress.len(), self.rho_dev.len());
        if (stress, rho_dev) != if solids { (n, n) } else { (0, 0) } {
            return Some(format!(
                "it holds stress for {stress} and density departures for {rho_dev} of {n} \
                 particles, and the scene has {} solid particles",
                if solids { "some" } else { "no" }
            ));
        }
        // Compare by id: the two storages are ordered differently.
        let by_id = |ids: &[u32], mut order: Vec<usize>| {
            order.sort_unstable_by_key(|&i| ids[i]);
            order
        };
        let (mine, theirs) = (by_id(&self.id, mine), by_id(like.id, theirs));
        for (&a, &b) in mine.iter().zip(&theirs) {
            let (id, other) = (self.id[a], like.id[b]);
            if id != other {
                return Some(format!(
                    "particle {} is in {} only",
                    id.min(other),
                    if id < other { "it" } else { "the scene" }
                ));
            }
            let what = if self.kind[a] != like.kind[b] {
                Some("kind")
            } else if self.group[a] != like.group[b] {
                Some("group")
            } else if self.mass[a].to_bits() != like.mass[b].to_bits() {
                Some("mass")
            } else {
                None
            };
            if let Some(what) = what {
                return Some(format!(
                    "particle {id} has another {what} in it than in the scene"
                ));
            }
        }
        None
    }

    /// The checkpoints of a decomposed solver's subdomains as one: their particles one
    /// after the other, the clock, step count and step size of the first (the same in all).
    pub fn concat(parts: &[SolverCheckpoint]) -> SolverCheckpoint {
        let mut all = parts.first().cloned().unwrap_or_default();
        for q in &parts[1.min(parts.len())..] {
            all.id.extend_from_slice(&q.id);
            all.kind.extend_from_slice(&q.kind);
            all.group.extend_from_slice(&q.group);
            all.mass.extend_from_slice(&q.mass);
            all.pos.extend_from_slice(&q.pos);
            all.vel.extend_from_slice(&q.vel);
            all.rho.extend_from_slice(&q.rho);
            all.p.extend_from_slice(&q.p);
            all.stress.extend_from_slice(&q.stress);
            all.rho_dev.extend_from_slice(&q.rho_dev);
            all.tl_disp.extend_from_slice(&q.tl_disp);
        }
        all
    }

    /// The particles whose position `at(x)` takes, in order (one subdomain's share), with
    /// the clock, step count and step size. Total-Lagrangian displacements are not split
    /// (a decomposed run has none).
    pub fn select(&self, at: impl Fn([f32; 3]) -> bool) -> SolverCheckpoint {
        let keep: Vec<usize> = (0..self.len()).filter(|&i| at(self.pos[i])).collect();
        fn pick<T: Copy>(v: &[T], keep: &[usize]) -> Vec<T> {
            if v.is_empty() {
                return Vec::new();
            }
            keep.iter().map(|&i| v[i]).collect()
        }
        SolverCheckpoint {
            dim: self.dim,
            time: self.time,
            steps: self.steps,
            dt: self.dt,
            id: pick(&self.id, &keep),
            kind: pick(&self.kind, &keep),
            group: pick(&self.group, &keep),
            mass: pick(&self.mass, &keep),
            pos: pick(&self.pos, &keep),
            vel: pick(&self.vel, &keep),
            rho: pick(&self.rho, &keep),
            p: pick(&self.p, &keep),
            stress: pick(&self.stress, &keep),
            rho_dev: pick(&self.rho_dev, &keep),
            tl_disp: Vec::new(),
            bodies: self.bodies.clone(),
            open: self.open.clone(),
        }
    }

    /// The state in the saved storage order, with the arrays `like` has (the continuity
    /// density's d rho/dt, the solids' stress rate and artificial stress: zero, as a step
    /// writes them before it reads them). Err: `mismatch`.
    pub fn to_state<D: Dim>(&self, like: &State<D>) -> Result<State<D>, String> {
        if let Some(why) = self.mismatch(like) {
            return Err(why);
        }
        Ok(self.to_state_unchecked(like))
    }

    /// `to_state` without the check that the particles are `like`'s (a subdomain's share
    /// of a decomposed checkpoint, `crate::exchange`): the arrays `like` holds. A checkpoint
    /// without stress gives a state with zero stress where `like` holds solid arrays.
    pub fn to_state_unchecked<D: Dim>(&self, like: &State<D>) -> State<D> {
        let n = self.len();
        let vectors = |v: &[[f32; 3]]| v.iter().map(|&a| D::from3(a)).collect::<Vec<_>>();
        let solid = like.solid.as_ref().map(|s| SolidState {
            stress: if self.stress.len() == n {
                self.stress.iter().map(|&m| D::sym_from6(m)).collect()
            } else {
                vec![D::zero(); n]
            },
            stress_rate: vec![D::zero(); n],
            art_stress: s.art_stress.as_ref().map(|_| vec![D::zero(); n]),
            rho_dev: if self.rho_dev.len() == n {
                self.rho_dev.clone()
            } else {
                vec![0.0; n]
            },
        });
        State {
            id: self.id.clone(),
            kind: self.kind.clone(),
            group: self.group.clone(),
            mass: self.mass.clone(),
            pos: vectors(&self.pos),
            vel: vectors(&self.vel),
            rho: self.rho.clone(),
            p: self.p.clone(),
            acc: vec![D::V::default(); n],
            xsph: vec![D::V::default(); n],
            drho: like.drho.as_ref().map(|_| vec![0.0; n]),
            solid,
        }
    }

    /// The total-Lagrangian displacements for a solver whose solid space holds `n_solid`
    /// particles. Err: another count.
    pub fn tl_displacements<D: Dim>(&self, n_solid: usize) -> Result<Vec<D::V>, String> {
        if self.tl_disp.len() != n_solid {
            return Err(format!(
                "it holds {} total-Lagrangian displacements and the scene has {n_solid} \
                 total-Lagrangian solid particles",
                self.tl_disp.len()
            ));
        }
        Ok(self.tl_disp.iter().map(|&a| D::from3(a)).collect())
    }
}
