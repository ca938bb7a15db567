//! The numbers both languages use, `cuda/sph_consts.h`, as Rust (bindgen, see `build.rs`):
//! launch geometry, the health check's fault classes and density bounds, the grid's pruning
//! slack, the shifting's constants, the singular-moment and Jacobi thresholds, the viscous
//! step limit. Integers are `u32`; floats are `f64` and are taken `as f32` where used (the
//! float nvcc makes of the header's `f` literal: `tests/bindings.rs`).
#[allow(
    non_upper_case_globals,
    non_camel_case_types,
    non_snake_case,
    dead_code,
    clippy::all
)]
mod bindings {
    include!(concat!(env!("OUT_DIR"), "/sph_consts.rs"));
}
pub use bindings::*;
