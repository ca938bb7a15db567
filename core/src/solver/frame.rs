//! Output frames: the particle fields an output carries (`Field`, chosen by the scene's
//! `[output] fields`), copied from a solver in storage order with the ids (`FrameData`).
//!
//! `Readback::capture` starts the copy and returns at once with a `PendingFrame`; whoever
//! writes the frame (the run's writer thread) calls `PendingFrame::wait`, so the solver
//! can step on while the copy finishes. The CPU backend copies at once; the CUDA backend
//! copies on the device into staging buffers and downloads them on a second stream into
//! pinned host memory (`backend/cuda/capture.rs`).

use serde::{Deserialize, Serialize};

use crate::named::Named;
use crate::physics::particle::{Kind, Particle};

/// A particle field of an output frame. Names as in the scene's `[output] fields`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Field {
    Position,
    Velocity,
    Density,
    Pressure,
    Kind,
    Id,
    Group,
    Stress,
}

impl Named for Field {
    const ALL: &'static [(Field, &'static str, &'static str)] = &[
        (
            Field::Position,
            "position",
            "[L] the particle positions (always written)",
        ),
        (Field::Velocity, "velocity", "[L/T] velocity, 3 components"),
        (Field::Density, "density", "[M L^-d] density"),
        (Field::Pressure, "pressure", "[M L^-d L^2 T^-2] pressure"),
        (Field::Kind, "kind", "0 fluid, 1 solid, 2 boundary"),
        (
            Field::Id,
            "id",
            "the particle's stable identity (its index at t = 0)",
        ),
        (
            Field::Group,
            "group",
            "the scene object the particle came from",
        ),
        (
            Field::Stress,
            "stress",
            "[M L^-d L^2 T^-2] a solid's deviatoric stress, eq. (11): xx yy zz xy xz yz",
        ),
    ];
}

/// A set of `Field`s.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Fields(u16);

impl Fields {
    pub const NONE: Fields = Fields(0);

    pub fn of(fields: &[Field]) -> Fields {
        fields.iter().fold(Fields::NONE, |s, &f| s.with(f))
    }

    /// Every field.
    pub fn all() -> Fields {
        Fields::of(&Field::ALL.iter().map(|(f, _, _)| *f).collect::<Vec<_>>())
    }

    pub fn with(self, f: Field) -> Fields {
        Fields(self.0 | 1 << f as u16)
    }

    pub fn without(self, f: Field) -> Fields {
        Fields(self.0 & !(1 << f as u16))
    }

    pub fn union(self, other: Fields) -> Fields {
        Fields(self.0 | other.0)
    }

    pub fn has(self, f: Field) -> bool {
        self.0 & 1 << f as u16 != 0
    }

    /// The fields of the set, in `Field`'s order.
    pub fn list(self) -> Vec<Field> {
        Field::ALL
            .iter()
            .map(|(f, _, _)| *f)
            .filter(|&f| self.has(f))
            .collect()
    }
}

/// One frame's particle fields, in the solver's storage order (`id` says which particle
/// each row is). A field not captured is an empty vector. Vectors carry three components
/// (z = 0 in 2D); stress is (xx, yy, zz, xy, xz, yz).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FrameData {
    pub step: u64,
    /// \[T\]
    pub time: f64,
    /// The number of particles.
    pub len: usize,
    pub position: Vec<[f32; 3]>,
    pub velocity: Vec<[f32; 3]>,
    pub density: Vec<f32>,
    pub pressure: Vec<f32>,
    /// `Kind` codes.
    pub kind: Vec<u8>,
    pub id: Vec<u32>,
    pub group: Vec<u32>,
    pub stress: Vec<[f32; 6]>,
}

impl FrameData {
    /// The chosen fields of `particles` (in their order).
    pub fn from_particles(particles: &[Particle], fields: Fields, step: u64, time: f64) -> Self {
        fn take<T>(on: bool, ps: &[Particle], f: impl Fn(&Particle) -> T) -> Vec<T> {
            if on {
                ps.iter().map(f).collect()
            } else {
                Vec::new()
            }
        }
        let ps = particles;
        FrameData {
            step,
            time,
            len: ps.len(),
            position: take(fields.has(Field::Position), ps, |q| q.position),
            velocity: take(fields.has(Field::Velocity), ps, |q| q.velocity),
            density: take(fields.has(Field::Density), ps, |q| q.density),
            pressure: take(fields.has(Field::Pressure), ps, |q| q.pressure),
            kind: take(fields.has(Field::Kind), ps, |q| q.kind.code()),
            id: take(fields.has(Field::Id), ps, |q| q.id),
            group: take(fields.has(Field::Group), ps, |q| q.group),
            stress: take(fields.has(Field::Stress), ps, |q| q.stress),
        }
    }

    /// Append `other`'s particles (a frame of the same fields: another subdomain's).
    pub fn append(&mut self, other: FrameData) {
        self.len += other.len;
        self.position.extend(other.position);
        self.velocity.extend(other.velocity);
        self.density.extend(other.density);
        self.pressure.extend(other.pressure);
        self.kind.extend(other.kind);
        self.id.extend(other.id);
        self.group.extend(other.group);
        self.stress.extend(other.stress);
    }

    /// The fields this frame carries.
    pub fn fields(&self) -> Fields {
        let mut s = Fields::NONE;
        let n = self.len;
        for (f, len) in [
            (Field::Position, self.position.len()),
            (Field::Velocity, self.velocity.len()),
            (Field::Density, self.density.len()),
            (Field::Pressure, self.pressure.len()),
            (Field::Kind, self.kind.len()),
            (Field::Id, self.id.len()),
            (Field::Group, self.group.len()),
            (Field::Stress, self.stress.len()),
        ] {
            if n > 0 && len == n {
                s = s.with(f);
            }
        }
        s
    }

    /// The particles, ordered by id (fields not captured are zero; without ids, in storage
    /// order). Mass is not part of a frame and is zero.
    pub fn particles(&self) -> Vec<Particle> {
        let mut out: Vec<Particle> = (0..self.len)
            .map(|i| Particle {
                id: self.id.get(i).copied().unwrap_or(i as u32),
                kind: self
                    .kind
                    .get(i)
                    .and_then(|&k| Kind::from_code(k))
                    .unwrap_or_default(),
                group: self.group.get(i).copied().unwrap_or(0),
                position: self.position.get(i).copied().unwrap_or_default(),
                velocity: self.velocity.get(i).copied().unwrap_or_default(),
                density: self.density.get(i).copied().unwrap_or(0.0),
                pressure: self.pressure.get(i).copied().unwrap_or(0.0),
                mass: 0.0,
                stress: self.stress.get(i).copied().unwrap_or_default(),
            })
            .collect();
        out.sort_unstable_by_key(|q| q.id);
        out
    }
}

/// A frame being copied out of a solver.
pub trait PendingFrame: Send {
    /// Blocks until the copy is complete. Err: why the device could not deliver it.
    fn wait(self: Box<Self>) -> Result<FrameData, String>;
}

/// A frame copied already.
pub struct Ready(pub FrameData);

impl PendingFrame for Ready {
    fn wait(self: Box<Self>) -> Result<FrameData, String> {
        Ok(self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn field_sets() {
        let all = Fields::all();
        assert_eq!(all.list().len(), Field::ALL.len());
        let no_stress = all.without(Field::Stress);
        assert!(!no_stress.has(Field::Stress) && no_stress.has(Field::Group));
        assert_eq!(no_stress.with(Field::Stress), all);
    }
}
