//! `Particle`: one particle with all its fields, the composite structure used for scene
//! set-up, I/O and tests. The solver stages work on the struct-of-arrays `State`; the
//! conversion between the two is in `state.rs` (the paper's composite <-> raw-array step).

use serde::{Deserialize, Serialize};

/// What a particle is. The numeric codes are the `MF_KIND_*` of `cuda/sph_params.h`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u8)]
pub enum Kind {
    #[default]
    Fluid = 0,
    /// Elastic solid, eqs. (11)-(16).
    Solid = 1,
    /// Fixed wall particle acting through the Lennard-Jones force, eq. (17).
    Boundary = 2,
}

impl Kind {
    pub const ALL: [Kind; 3] = [Kind::Fluid, Kind::Solid, Kind::Boundary];

    pub fn code(self) -> u8 {
        self as u8
    }

    pub fn from_code(code: u8) -> Option<Kind> {
        Kind::ALL.into_iter().find(|k| k.code() == code)
    }

    pub fn name(self) -> &'static str {
        match self {
            Kind::Fluid => "fluid",
            Kind::Solid => "solid",
            Kind::Boundary => "boundary",
        }
    }
}

/// One particle. Vectors carry three components; a 2D scene leaves z at zero.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Particle {
    /// Stable identity: the index in the scene's initial particle list.
    pub id: u32,
    pub kind: Kind,
    /// The scene object (fluid block, solid body, wall, gate) the particle came from.
    pub group: u32,
    /// \[L\]
    pub position: [f32; 3],
    /// [L/T]
    pub velocity: [f32; 3],
    /// [M L^-d]
    pub density: f32,
    /// [M L^-d L^2 T^-2]
    pub pressure: f32,
    /// \[M\]
    pub mass: f32,
    /// Deviatoric stress S^{ab} of a solid particle, eq. (11): (xx, yy, zz, xy, xz, yz).
    /// Zero for fluid and boundary particles.
    pub stress: [f32; 6],
}

impl Particle {
    pub fn speed(&self) -> f32 {
        self.velocity.iter().map(|v| v * v).sum::<f32>().sqrt()
    }
}
