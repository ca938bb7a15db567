//! What the viewer asks of every solver (`Readback::snapshot`): the shown quantity and a host
//! snapshot. The OpenGL buffers a GPU backend fills in place are the interop wing's
//! (`crate::interop`, the `interop` feature).

use serde::{Deserialize, Serialize};

use crate::consts::{MF_SHOWN_DENSITY, MF_SHOWN_KIND, MF_SHOWN_PRESSURE, MF_SHOWN_SPEED};
use crate::named::Named;
use crate::physics::particle::Particle;
use crate::solver::frame::Field;

/// The particle quantity the viewer colours by: the one registry of them. The command
/// line's `--field` values and their help (`Named`), the device's codes (`MF_SHOWN_*` in
/// `cuda/sph_consts.h`, the discriminants), the output field each is computed from
/// (`source`) and its value on the host (`of`) all come from here; the viewer's own `Field`
/// (which knows nothing of the solver) is mapped to it in the binary's glue.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum Shown {
    #[default]
    Speed = MF_SHOWN_SPEED,
    Pressure = MF_SHOWN_PRESSURE,
    Density = MF_SHOWN_DENSITY,
    Kind = MF_SHOWN_KIND,
}

impl Named for Shown {
    const ALL: &'static [(Shown, &'static str, &'static str)] = &[
        (Shown::Speed, "speed", "[L/T] the velocity's magnitude"),
        (Shown::Pressure, "pressure", "[M L^-d L^2 T^-2] pressure"),
        (Shown::Density, "density", "[M L^-d] density"),
        (Shown::Kind, "kind", "0 fluid, 1 solid, 2 boundary"),
    ];
}

impl Shown {
    /// The device's code of this quantity (`MF_SHOWN_*`, `cuda/view.cu`).
    pub const fn code(self) -> u32 {
        self as u32
    }

    /// The output frame's field this quantity is computed from.
    pub fn source(self) -> Field {
        match self {
            Shown::Speed => Field::Velocity,
            Shown::Pressure => Field::Pressure,
            Shown::Density => Field::Density,
            Shown::Kind => Field::Kind,
        }
    }

    /// This quantity of one particle (the host path; `cuda/view.cu` computes it alike).
    pub fn of(self, q: &Particle) -> f32 {
        match self {
            Shown::Speed => q.speed(),
            Shown::Pressure => q.pressure,
            Shown::Density => q.density,
            Shown::Kind => q.kind.code() as f32,
        }
    }
}

/// What the viewer draws: positions, kinds and one quantity, in storage order, in buffers
/// that are reused from frame to frame.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Snapshot {
    pub positions: Vec<[f32; 3]>,
    pub values: Vec<f32>,
    pub kinds: Vec<u8>,
}
