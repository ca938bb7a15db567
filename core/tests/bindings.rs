//! The committed Rust bindings of `cuda/sph_params.h` and `cuda/sph_consts.h` match what
//! bindgen makes of the headers; and every float constant of `sph_consts.h` reaches Rust as
//! the float nvcc makes of it.
//!
//! A build without libclang uses the committed copies and has nothing to compare, so the
//! first test is ignored there, unless the build had `MESHFREE_REQUIRE_LIBCLANG=1` (CI), which
//! makes it run and fail (`build.rs` sets the cfgs).

/// (header, its generated bindings in OUT_DIR, the committed copy: path and text).
const HEADERS: [(&str, &str, &str, &str); 2] = [
    (
        "cuda/sph_params.h",
        include_str!(concat!(env!("OUT_DIR"), "/sph_params.rs")),
        "src/physics/params/bindings.rs",
        include_str!("../src/physics/params/bindings.rs"),
    ),
    (
        "cuda/sph_consts.h",
        include_str!(concat!(env!("OUT_DIR"), "/sph_consts.rs")),
        "src/consts/bindings.rs",
        include_str!("../src/consts/bindings.rs"),
    ),
];

const CONSTS_HEADER: &str = include_str!("../cuda/sph_consts.h");
const CONSTS_BINDINGS: &str = include_str!("../src/consts/bindings.rs");

#[test]
#[cfg_attr(
    not(any(meshfree_bindgen, meshfree_require_libclang)),
    ignore = "libclang was not found at build time: the committed bindings were used \
              (install libclang-dev; MESHFREE_REQUIRE_LIBCLANG=1 makes this a failure)"
)]
fn bindings_match_header() {
    assert_eq!(
        meshfree_core::physics::params::BINDINGS_SOURCE,
        "bindgen",
        "libclang was not found at build time; the committed bindings were used, so there is \
         nothing to compare them with"
    );
    for (header, generated, file, committed) in HEADERS {
        assert!(
            generated == committed,
            "{file} is stale: copy bindgen's output for {header} ($OUT_DIR, named in the \
             build's warning) over it"
        );
    }
}

/// bindgen gives a float macro to Rust as f64; the Rust side takes it `as f32`. That must
/// be the float nvcc makes of the header's `f` literal (the correctly rounded one), or the
/// two backends would compare against different numbers.
#[test]
fn float_constants_reach_rust_as_nvcc_reads_them() {
    let mut checked = 0;
    for line in CONSTS_HEADER.lines() {
        let mut words = line.split_whitespace();
        let (Some("#define"), Some(name), Some(value)) = (words.next(), words.next(), words.next())
        else {
            continue;
        };
        let Some(literal) = value.strip_suffix('f') else {
            continue;
        };
        let Ok(nvcc) = literal.parse::<f32>() else {
            continue;
        };
        let rust = CONSTS_BINDINGS
            .lines()
            .find_map(|l| l.strip_prefix(&format!("pub const {name}: f64 = ")))
            .and_then(|v| v.trim_end_matches(';').parse::<f64>().ok())
            .unwrap_or_else(|| panic!("{name} has no f64 constant in src/consts/bindings.rs"));
        assert_eq!(
            rust as f32, nvcc,
            "{name}: Rust's {rust} as f32 is not the float of the literal {value}"
        );
        checked += 1;
    }
    assert!(
        checked >= 8,
        "only {checked} float constants found in sph_consts.h"
    );
}
