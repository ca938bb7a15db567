//! `SphParams` and the `MF_*` constants of `cuda/sph_params.h`, as bindgen makes them (the
//! committed copy `bindings.rs` where libclang is missing; `core/build.rs`). Its own file, so
//! that the kernel (`crate::physics::kernel`) can read the struct without depending on `derive`.
#![allow(
    non_upper_case_globals,
    non_camel_case_types,
    non_snake_case,
    dead_code,
    clippy::all,
    // The header's comments are C's: its units ([L]) and subscripts (x[own_axis]) are no
    // links.
    rustdoc::broken_intra_doc_links
)]
include!(concat!(env!("OUT_DIR"), "/sph_params.rs"));
