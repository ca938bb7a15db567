//! The committed Rust bindings of `cuda/sph_params.h` match what bindgen makes of the header.
//!
//! A build without libclang uses the committed copy and has nothing to compare, so the test
//! is ignored there, unless the build had `MESHFREE_REQUIRE_LIBCLANG=1` (CI), which makes it
//! run and fail (`build.rs` sets the cfgs).

const GENERATED: &str = include_str!(concat!(env!("OUT_DIR"), "/sph_params.rs"));
const COMMITTED: &str = include_str!("../src/params/bindings.rs");

#[test]
#[cfg_attr(
    not(any(meshfree_bindgen, meshfree_require_libclang)),
    ignore = "libclang was not found at build time: the committed bindings were used \
              (install libclang-dev; MESHFREE_REQUIRE_LIBCLANG=1 makes this a failure)"
)]
fn bindings_match_header() {
    assert_eq!(
        meshfree_core::params::BINDINGS_SOURCE,
        "bindgen",
        "libclang was not found at build time; the committed bindings were used, so there is \
         nothing to compare them with"
    );
    assert!(
        GENERATED == COMMITTED,
        "src/params/bindings.rs is stale: copy $OUT_DIR/sph_params.rs (bindgen's output for cuda/sph_params.h) over it"
    );
}
