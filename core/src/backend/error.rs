//! Why a solver could not be built, whichever backend was asked, and the `Fault` both
//! backends report for a blow-up.

use crate::consts::{
    MF_DENSITY_SANE_HIGH, MF_DENSITY_SANE_LOW, MF_FAULT_DENSITY_RANGE, MF_FAULT_ESCAPED,
    MF_FAULT_NON_FINITE_DENSITY, MF_FAULT_NON_FINITE_POSITION, MF_FAULT_NON_FINITE_VELOCITY,
};
use crate::physics::particle::Kind;
use crate::solver::Fault;

/// Why a solver could not be built.
#[derive(Debug, thiserror::Error)]
pub enum BackendError {
    #[error("the CUDA backend is unavailable: {0}")]
    CudaUnavailable(String),
    #[error("CUDA error: {0}")]
    Cuda(String),
    #[error("cannot decompose this scene: {0}")]
    Decomposition(String),
    /// The ranks of a run in several processes could not start together (`run --mpi`).
    #[error("starting the ranks: {0}")]
    Launch(String),
}

impl From<crate::exchange::Refused> for BackendError {
    fn from(r: crate::exchange::Refused) -> Self {
        BackendError::Decomposition(r.0)
    }
}

/// The `Fault` for the particle `id` of kind `kind` with fault class `code` (`MF_FAULT_*`
/// in `cuda/sph_consts.h`); shared by both backends so that they report blow-ups alike.
pub fn fault(step: u64, time: f64, id: u32, kind: Kind, code: u32, value: f32) -> Fault {
    let (quantity, reason) = match code {
        MF_FAULT_NON_FINITE_POSITION => ("position", "not finite".to_string()),
        MF_FAULT_NON_FINITE_VELOCITY => ("velocity", "not finite".to_string()),
        MF_FAULT_NON_FINITE_DENSITY => ("density", "not finite".to_string()),
        MF_FAULT_DENSITY_RANGE => (
            "density",
            format!(
                "outside [{}, {}] x the reference density",
                MF_DENSITY_SANE_LOW as f32, MF_DENSITY_SANE_HIGH as f32
            ),
        ),
        MF_FAULT_ESCAPED => ("position", "outside the domain".to_string()),
        _ => ("unknown", format!("fault code {code}")),
    };
    Fault {
        step,
        time,
        particle: id,
        kind: kind.name().into(),
        quantity: quantity.into(),
        value: value as f64,
        reason,
    }
}
