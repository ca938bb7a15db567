//! Measurements on particle sets, shared by the run driver, the tests and validation.

pub mod bodies;
pub mod clusters;
