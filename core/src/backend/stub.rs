//! `backend::cuda` in a build with the `cuda` feature off: the entry points `backend::create`
//! calls, each answering that this build has no CUDA backend.

use crate::backend::error::BackendError;
use crate::solver::{Setup, Solver};

fn off() -> BackendError {
    BackendError::CudaUnavailable("this build has the `cuda` feature off".into())
}

/// Never: this build has no CUDA backend.
pub fn available() -> Result<String, BackendError> {
    Err(off())
}

/// Never: this build has no CUDA backend.
pub fn create(_: Setup) -> Result<Box<dyn Solver>, BackendError> {
    Err(off())
}

/// Never: this build has no CUDA backend.
pub fn decomposed(_: Setup, _: usize) -> Result<Box<dyn Solver>, BackendError> {
    Err(off())
}

/// Never: this build has no CUDA backend.
pub fn multi_gpu(_: Setup, _: usize) -> Result<Box<dyn Solver>, BackendError> {
    Err(off())
}
