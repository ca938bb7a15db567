//! Build script: Rust bindings of `cuda/sph_params.h` and `cuda/sph_consts.h` (bindgen) and
//! PTX of every `cuda/*.cu` (nvcc). It never probes a GPU.
//!
//! * Bindings: generated with bindgen where libclang loads; elsewhere the committed copies
//!   (`src/params/bindings.rs`, `src/consts/bindings.rs`) are used (`tests/bindings.rs` checks
//!   that they agree with bindgen's where libclang exists).
//! * PTX: nvcc is looked up in `NVCC`, `CUDA_HOME`/`CUDA_PATH` (`bin/nvcc`), then `PATH`.
//!   Without nvcc the crate builds the CPU backend only and says so once;
//!   `MESHFREE_REQUIRE_NVCC=1` turns that into an error (CI sets it).
//!   `MESHFREE_CUDA_ARCH` overrides the virtual architecture (default `compute_75`, Turing:
//!   the driver JIT-compiles it for any newer GPU).
//!   Modules are the `cuda/*.cu` files only; the headers they include (`cuda/*.h`,
//!   `cuda/device/*.cuh`) are not compiled on their own, but a change to any file under
//!   `cuda/` (nested folders included) reruns the build.
//! * Test cfgs: `MESHFREE_REQUIRE_CUDA=1` sets `meshfree_require_cuda`, under which the GPU
//!   tests (`tests/cuda_parity.rs`) are not `#[ignore]`d and fail without a usable GPU;
//!   `MESHFREE_REQUIRE_LIBCLANG=1` sets `meshfree_require_libclang`, and bindings made by
//!   bindgen set `meshfree_bindgen`: `tests/bindings.rs` is ignored under neither.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A header that bindgen turns into Rust.
struct Header {
    /// The C header, relative to the crate.
    path: &'static str,
    /// The bindings' file name in OUT_DIR (the crate includes it from there).
    out: &'static str,
    /// The committed copy, used where libclang cannot be loaded.
    committed: &'static str,
    /// A C type to bind besides the `MF_*` constants.
    ty: Option<&'static str>,
}

const HEADERS: [Header; 2] = [
    Header {
        path: "cuda/sph_params.h",
        out: "sph_params.rs",
        committed: "src/params/bindings.rs",
        ty: Some("SphParams"),
    },
    Header {
        path: "cuda/sph_consts.h",
        out: "sph_consts.rs",
        committed: "src/consts/bindings.rs",
        ty: None,
    },
];

fn main() {
    let out = PathBuf::from(env::var("OUT_DIR").expect("OUT_DIR"));
    for h in &HEADERS {
        println!("cargo:rerun-if-changed={}", h.path);
        println!("cargo:rerun-if-changed={}", h.committed);
    }
    // A directory: cargo reruns the script when any file under it changes, in nested
    // folders too (cuda/device/*.cuh).
    println!("cargo:rerun-if-changed=cuda");
    for var in [
        "NVCC",
        "CUDA_HOME",
        "CUDA_PATH",
        "PATH",
        "MESHFREE_REQUIRE_NVCC",
        "MESHFREE_CUDA_ARCH",
        "MESHFREE_NVCC_FLAGS",
        "MESHFREE_REQUIRE_CUDA",
        "MESHFREE_REQUIRE_LIBCLANG",
    ] {
        println!("cargo:rerun-if-env-changed={var}");
    }
    println!("cargo::rustc-check-cfg=cfg(meshfree_ptx)");
    for (var, cfg) in [
        ("MESHFREE_REQUIRE_CUDA", "meshfree_require_cuda"),
        ("MESHFREE_REQUIRE_LIBCLANG", "meshfree_require_libclang"),
    ] {
        println!("cargo::rustc-check-cfg=cfg({cfg})");
        if env::var(var).is_ok_and(|v| v == "1") {
            println!("cargo:rustc-cfg={cfg}");
        }
    }
    println!("cargo::rustc-check-cfg=cfg(meshfree_bindgen)");
    // Every header's bindings are written (no short cut): either all from bindgen or, where
    // libclang does not load, all committed.
    let generated: Vec<bool> = HEADERS.iter().map(|h| bindings(&out, h)).collect();
    let source = if generated.iter().all(|&g| g) {
        "bindgen"
    } else {
        "committed"
    };
    println!("cargo:rustc-env=MESHFREE_BINDINGS_SOURCE={source}");
    if source == "bindgen" {
        println!("cargo:rustc-cfg=meshfree_bindgen");
    }
    ptx(&out);
    commit();
}

/// `MESHFREE_COMMIT`: the checkout's commit (`build_info::COMMIT`), rebuilt when HEAD moves.
fn commit() {
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    if let Some(dir) = git(&["rev-parse", "--git-dir"]) {
        println!("cargo:rerun-if-changed={dir}/HEAD");
    }
    if let (Some(common), Some(head)) = (
        git(&["rev-parse", "--git-common-dir"]),
        git(&["symbolic-ref", "-q", "HEAD"]),
    ) {
        println!("cargo:rerun-if-changed={common}/{head}");
    }
    let hash = git(&["rev-parse", "--short=7", "HEAD"]).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=MESHFREE_COMMIT={hash}");
}

/// bindgen's output for header `h`, or `None` where libclang cannot be loaded.
fn generate_bindings(h: &Header) -> Option<String> {
    let generate = || {
        let mut b = bindgen::Builder::default().header(h.path);
        if let Some(ty) = h.ty {
            b = b.allowlist_type(ty);
        }
        b.allowlist_var("MF_.*")
            .derive_default(true)
            .derive_debug(true)
            .derive_copy(true)
            .derive_partialeq(true)
            .layout_tests(false)
            .generate_comments(true)
            .clang_arg("-fparse-all-comments")
            .generate()
    };
    // bindgen panics where libclang cannot be loaded: that is the "no libclang" answer.
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(generate)) {
        Ok(Ok(b)) => Some(b.to_string()),
        _ => None,
    }
}

/// Writes the bindings of `h` to OUT_DIR: bindgen's (true) or, where libclang cannot be
/// loaded, the committed copy (false).
fn bindings(out: &Path, h: &Header) -> bool {
    let committed = fs::read_to_string(h.committed).unwrap_or_default();
    let fresh = generate_bindings(h);
    let dst = out.join(h.out);
    if fresh.as_ref().is_some_and(|f| *f != committed) {
        println!(
            "cargo:warning=the committed {} differs from bindgen's output for {}: copy {} over \
             it (tests/bindings.rs fails until then)",
            h.committed,
            h.path,
            dst.display()
        );
    }
    let generated = fresh.is_some();
    fs::write(&dst, fresh.unwrap_or(committed)).expect("write bindings");
    generated
}

fn find_nvcc() -> Option<PathBuf> {
    if let Ok(p) = env::var("NVCC") {
        // The build script runs in core/: a relative NVCC is taken from the workspace root,
        // where `cargo` is usually started, unless it names a file from core/.
        let p = PathBuf::from(p);
        if p.is_relative() && !p.exists() {
            return Some(Path::new("..").join(p));
        }
        return Some(p);
    }
    for var in ["CUDA_HOME", "CUDA_PATH"] {
        if let Ok(root) = env::var(var) {
            let p = Path::new(&root).join("bin").join("nvcc");
            if p.exists() {
                return Some(p);
            }
        }
    }
    env::var_os("PATH").and_then(|paths| {
        env::split_paths(&paths)
            .map(|d| d.join("nvcc"))
            .find(|p| p.is_file())
    })
}

fn ptx(out: &Path) {
    let require = env::var("MESHFREE_REQUIRE_NVCC").is_ok_and(|v| v == "1");
    let mut sources: Vec<PathBuf> = fs::read_dir("cuda")
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    sources.retain(|p| p.extension().is_some_and(|e| e == "cu"));
    sources.sort();

    let registry = out.join("ptx.rs");
    let Some(nvcc) = find_nvcc() else {
        if require {
            panic!(
                "MESHFREE_REQUIRE_NVCC=1 but no nvcc was found (looked in NVCC, CUDA_HOME/bin, \
                 CUDA_PATH/bin and PATH)"
            );
        }
        println!(
            "cargo:warning=nvcc not found (NVCC, CUDA_HOME, CUDA_PATH, PATH): building the CPU \
             backend only"
        );
        fs::write(&registry, "pub const MODULES: &[(&str, &str)] = &[];\n").unwrap();
        println!("cargo:rustc-env=MESHFREE_NVCC_VERSION=none (no nvcc at build time)");
        return;
    };
    // The nvcc release, for the error a PTX load failure reports.
    let version = Command::new(&nvcc)
        .arg("--version")
        .output()
        .ok()
        .and_then(|o| {
            String::from_utf8_lossy(&o.stdout)
                .lines()
                .find(|l| l.contains("release"))
                .map(|l| l.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into());
    println!(
        "cargo:rustc-env=MESHFREE_NVCC_VERSION={} ({})",
        version,
        nvcc.display()
    );
    let arch = env::var("MESHFREE_CUDA_ARCH").unwrap_or_else(|_| "compute_75".into());
    // Extra nvcc flags for experiments (e.g. `-DMF_NO_QUEUE` for an A/B measurement).
    let extra = env::var("MESHFREE_NVCC_FLAGS").unwrap_or_default();
    let mut entries = String::from("pub const MODULES: &[(&str, &str)] = &[\n");
    for src in &sources {
        let stem = src.file_stem().unwrap().to_string_lossy().into_owned();
        let dst = out.join(format!("{stem}.ptx"));
        let mut cmd = Command::new(&nvcc);
        // -ftz=true: denormal floats flush to zero, so that a reciprocal, reciprocal root or
        // division in the pair sums is one instruction, not a range test and rescale around it
        // (3D step 8 % shorter on the H100, docs/reference/performance.md, "-ftz=true"). No SPH quantity
        // of a scene comes near 1e-38 in SI units; the parity tests hold unchanged.
        cmd.args([
            "--ptx",
            "-std=c++17",
            "-O3",
            "-ftz=true",
            "-lineinfo",
            "-Icuda",
        ])
        .arg(format!("-arch={arch}"))
        .args(extra.split_whitespace())
        .arg(src)
        .arg("-o")
        .arg(&dst);
        let shown = format!("{cmd:?}");
        let result = cmd
            .output()
            .unwrap_or_else(|e| panic!("could not start nvcc: {shown}: {e}"));
        if !result.status.success() {
            panic!(
                "nvcc failed on {}:\n  command: {shown}\n  stderr:\n{}",
                src.display(),
                String::from_utf8_lossy(&result.stderr)
            );
        }
        entries += &format!(
            "    ({stem:?}, include_str!({:?})),\n",
            dst.display().to_string()
        );
    }
    entries += "];\n";
    fs::write(&registry, entries).unwrap();
    if !sources.is_empty() {
        println!("cargo:rustc-cfg=meshfree_ptx");
    }
    println!(
        "cargo:warning=nvcc {} compiled {} CUDA modules for {arch}",
        nvcc.display(),
        sources.len()
    );
}
