//! The struct-of-arrays particle state the stages work on, and its conversion to and from
//! the composite `Particle` (the paper converts composite C++ structures to raw arrays for
//! its CUDA kernels; here that conversion is this one module). Round trip: `tests/state.rs`.
//!
//! Arrays are allocated only where a scene needs them: `drho` only with the continuity
//! density, the stress arrays only where there are solid particles.

use crate::physics::dim::Dim;
use crate::physics::particle::{Kind, Particle};

use rayon::prelude::*;

/// Struct-of-arrays particle state. Index `i` is a storage slot; `id[i]` is the particle's
/// stable identity. The backends keep the storage sorted by (grid cell, id).
/// Serialised (`serde`) as a halo between processes (`meshfree run --mpi`).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
#[serde(bound = "")]
pub struct State<D: Dim> {
    pub id: Vec<u32>,
    /// `Kind` codes (`MF_KIND_*`).
    pub kind: Vec<u8>,
    pub group: Vec<u32>,
    /// \[M\]
    pub mass: Vec<f32>,
    /// \[L\]
    pub pos: Vec<D::V>,
    /// [L/T]
    pub vel: Vec<D::V>,
    /// [M L^-d]
    pub rho: Vec<f32>,
    /// [M L^-d L^2 T^-2]
    pub p: Vec<f32>,
    /// [L/T^2] dv/dt from the forces stage, eqs. (7), (16), (17).
    pub acc: Vec<D::V>,
    /// [L/T] XSPH velocity correction eps sum_j ..., eq. (18).
    pub xsph: Vec<D::V>,
    /// [M L^-d / T] d rho/dt; only with the continuity density.
    pub drho: Option<Vec<f32>>,
    /// Solid-only arrays; `None` where the scene has no solid particles.
    pub solid: Option<SolidState<D>>,
}

/// Arrays of the elastic-solid model, eqs. (11)-(16) (one entry per particle, zero for
/// non-solid particles so that the storage order stays shared).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
#[serde(bound = "")]
pub struct SolidState<D: Dim> {
    /// Deviatoric stress S^{ab}, eq. (11).
    pub stress: Vec<D::M>,
    /// Jaumann rate dS^{ab}/dt, eq. (12).
    pub stress_rate: Vec<D::M>,
    /// Artificial stress R^{ab} (Gray, Monaghan & Swift 2001); `None` when switched off.
    pub art_stress: Option<Vec<D::M>>,
    /// [M L^-d] rho - rho0_s, the solid particles' density as a departure from rest (zero for
    /// other kinds). The continuity density integrates it, and the solid pressure
    /// P = c_s^2 (rho - rho0_s) is taken from it: for a stiff solid the change per step,
    /// dt d rho/dt, is below f32's resolution of rho itself (the ulp of 2700 is 2.4e-4) and
    /// rounds away in rho += dt d rho/dt, but not in the departure. `rho` stays
    /// rho0_s + rho_dev (what every other stage reads).
    pub rho_dev: Vec<f32>,
}

impl<D: Dim> State<D> {
    /// Composite -> raw arrays, in the given order. `solid_rho0` [M L^-d]: the solids' rest
    /// density (`SphParams::solid_rho0`), from which the solid particles' density departure
    /// `SolidState::rho_dev` is taken (unused without solid particles).
    pub fn from_particles(
        particles: &[Particle],
        continuity: bool,
        art_stress: bool,
        solid_rho0: f32,
    ) -> Self {
        let n = particles.len();
        // Every array filled by all threads: 13 M particles took 3 s on one.
        fn each<T: Send>(ps: &[Particle], f: impl Fn(&Particle) -> T + Sync + Send) -> Vec<T> {
            ps.par_iter().map(f).collect()
        }
        let has_solids = particles.par_iter().any(|p| p.kind == Kind::Solid);
        let solid = has_solids.then(|| SolidState {
            stress: each(particles, |p| D::sym_from6(p.stress)),
            stress_rate: vec![D::zero(); n],
            art_stress: art_stress.then(|| vec![D::zero(); n]),
            // Exact in f32 where density and rho0_s are within a factor 2 (Sterbenz).
            rho_dev: each(particles, |p| {
                if p.kind == Kind::Solid {
                    p.density - solid_rho0
                } else {
                    0.0
                }
            }),
        });
        State {
            id: each(particles, |p| p.id),
            kind: each(particles, |p| p.kind.code()),
            group: each(particles, |p| p.group),
            mass: each(particles, |p| p.mass),
            pos: each(particles, |p| D::from3(p.position)),
            vel: each(particles, |p| D::from3(p.velocity)),
            rho: each(particles, |p| p.density),
            p: each(particles, |p| p.pressure),
            acc: vec![D::V::default(); n],
            xsph: vec![D::V::default(); n],
            drho: continuity.then(|| vec![0.0; n]),
            solid,
        }
    }

    /// Raw arrays -> composite, ordered by id.
    pub fn to_particles(&self) -> Vec<Particle> {
        let mut out: Vec<Particle> = (0..self.len()).map(|i| self.particle(i)).collect();
        out.sort_by_key(|p| p.id);
        out
    }

    /// The composite view of storage slot `i`.
    pub fn particle(&self, i: usize) -> Particle {
        Particle {
            id: self.id[i],
            kind: Kind::from_code(self.kind[i]).expect("valid kind code"),
            group: self.group[i],
            position: D::to3(self.pos[i]),
            velocity: D::to3(self.vel[i]),
            // rho: rho0_s + rho_dev for solids, as the drift and the density pass keep it.
            density: self.rho[i],
            pressure: self.p[i],
            mass: self.mass[i],
            stress: self
                .solid
                .as_ref()
                .map_or([0.0; 6], |s| D::sym_to6(s.stress[i])),
        }
    }

    /// The density departure from rest `SolidState::rho_dev` of slot `i` (0 without
    /// solids). [M L^-d]
    #[inline]
    pub fn rho_dev(&self, i: usize) -> f32 {
        self.solid.as_ref().map_or(0.0, |s| s.rho_dev[i])
    }

    pub fn len(&self) -> usize {
        self.id.len()
    }

    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Keep the slots for which `keep(slot)` holds, in order, in every array.
    pub fn retain(&mut self, keep: impl Fn(usize) -> bool) {
        let slots: Vec<usize> = (0..self.len()).filter(|&i| keep(i)).collect();
        self.gather(&slots);
    }

    /// Reorder every array so that new slot `k` holds old slot `order[k]`.
    pub fn gather(&mut self, order: &[usize]) {
        *self = self.select(order);
    }

    /// A state of the slots `order` (new slot `k` is old slot `order[k]`), every array.
    pub fn select(&self, order: &[usize]) -> Self {
        fn g<T: Copy>(v: &[T], order: &[usize]) -> Vec<T> {
            order.iter().map(|&i| v[i]).collect()
        }
        State {
            id: g(&self.id, order),
            kind: g(&self.kind, order),
            group: g(&self.group, order),
            mass: g(&self.mass, order),
            pos: g(&self.pos, order),
            vel: g(&self.vel, order),
            rho: g(&self.rho, order),
            p: g(&self.p, order),
            acc: g(&self.acc, order),
            xsph: g(&self.xsph, order),
            drho: self.drho.as_ref().map(|d| g(d, order)),
            solid: self.solid.as_ref().map(|s| SolidState {
                stress: g(&s.stress, order),
                stress_rate: g(&s.stress_rate, order),
                art_stress: s.art_stress.as_ref().map(|r| g(r, order)),
                rho_dev: g(&s.rho_dev, order),
            }),
        }
    }

    /// Append `other`'s slots (a state with the same arrays) after this one's.
    pub fn extend(&mut self, other: &State<D>) {
        fn e<T: Copy>(v: &mut Vec<T>, w: &[T]) {
            v.extend_from_slice(w);
        }
        e(&mut self.id, &other.id);
        e(&mut self.kind, &other.kind);
        e(&mut self.group, &other.group);
        e(&mut self.mass, &other.mass);
        e(&mut self.pos, &other.pos);
        e(&mut self.vel, &other.vel);
        e(&mut self.rho, &other.rho);
        e(&mut self.p, &other.p);
        e(&mut self.acc, &other.acc);
        e(&mut self.xsph, &other.xsph);
        if let (Some(d), Some(w)) = (&mut self.drho, &other.drho) {
            e(d, w);
        }
        if let (Some(s), Some(o)) = (&mut self.solid, &other.solid) {
            e(&mut s.stress, &o.stress);
            e(&mut s.stress_rate, &o.stress_rate);
            e(&mut s.rho_dev, &o.rho_dev);
            if let (Some(r), Some(q)) = (&mut s.art_stress, &o.art_stress) {
                e(r, q);
            }
        }
    }

    /// Hold the solid arrays (zero) where there are none: a subdomain of a scene with
    /// solids that starts with none of them (`SphParams::own_solids`).
    pub fn with_solid_arrays(mut self, art_stress: bool) -> Self {
        let n = self.len();
        if self.solid.is_none() {
            self.solid = Some(SolidState {
                stress: vec![D::zero(); n],
                stress_rate: vec![D::zero(); n],
                art_stress: art_stress.then(|| vec![D::zero(); n]),
                rho_dev: vec![0.0; n],
            });
        }
        self
    }
}
