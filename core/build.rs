//! Build script: Rust bindings of `cuda/sph_params.h` and `cuda/sph_consts.h` (bindgen) and
//! a fatbin of every `cuda/*.cu` (nvcc). It never probes a GPU.
//!
//! * Bindings: generated with bindgen where libclang loads; elsewhere the committed copies
//!   (`src/physics/params/bindings.rs`, `src/consts/bindings.rs`) are used (`tests/bindings.rs` checks
//!   that they agree with bindgen's where libclang exists).
//! * CUDA modules: nvcc is looked up in `NVCC`, `CUDA_HOME`/`CUDA_PATH` (`bin/nvcc`), then
//!   `PATH`. Without nvcc the crate builds the CPU backend only and says so once;
//!   `MESHFREE_REQUIRE_NVCC=1` turns that into an error (CI sets it).
//!   Each module becomes one fatbin (`src/backend/cuda/device.rs` loads it; the driver picks
//!   the code for the GPU at hand): by default machine code (SASS) for every real
//!   architecture that the nvcc lists (`nvcc --list-gpu-code`) from Turing on (sm_75 ...
//!   sm_121 for nvcc 13.0; not the family-specific `a`/`f` variants), all compiled from one
//!   `compute_75` PTX, plus the PTX of the newest virtual architecture, which the driver
//!   JIT-compiles only for a GPU newer than the nvcc. So no GPU waits for the driver's JIT
//!   at its first run (33 s on an H100 with the PTX-only builds before), at the price of a
//!   longer build: `ptxas` runs once per architecture, on every core (`--threads 0`), and
//!   the modules compile `NUM_JOBS` at a time.
//!   `MESHFREE_CUDA_ARCH` overrides the targets with a comma-separated list of `sm_XY`
//!   (machine code) and `compute_XY` (PTX): `MESHFREE_CUDA_ARCH=sm_90` builds the H100's
//!   machine code alone (a fast developer build, the same code as the default build's
//!   sm_90), `compute_75` the PTX alone (what the driver JIT-compiles for any GPU).
//!   Modules are the `cuda/*.cu` files only; the headers they include (`cuda/*.h`,
//!   `cuda/device/*.cuh`) are not compiled on their own, but a change to any file under
//!   `cuda/` (nested folders included) reruns the build. The PTX text of each module is
//!   kept beside its fatbin for the kernel table's test (`src/backend/cuda/kernels.rs`).
//!   A module compiled before in the same target profile, from the same sources, nvcc and
//!   flags, is copied from `<target>/<profile>/build/meshfree-core-nvcc/` instead of being
//!   compiled again, whichever OUT_DIR a feature set gives the crate.
//! * Test cfgs: `MESHFREE_REQUIRE_CUDA=1` sets `meshfree_require_cuda`, under which the GPU
//!   tests (`tests/cuda_parity/`) are not `#[ignore]`d and fail without a usable GPU;
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
    /// The C types to bind besides the `MF_*` constants (a regular expression).
    ty: Option<&'static str>,
}

const HEADERS: [Header; 2] = [
    Header {
        path: "cuda/sph_params.h",
        out: "sph_params.rs",
        committed: "src/physics/params/bindings.rs",
        ty: Some("SphParams|MfBody"),
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
    cuda_modules(&out);
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

/// What nvcc builds into every module: machine code (SASS, `sm_XY`) and PTX (`compute_XY`).
struct Targets {
    /// Compute capabilities (10 major + minor) with machine code, ascending.
    sass: Vec<u32>,
    /// Virtual architectures whose PTX is embedded, ascending.
    ptx: Vec<u32>,
}

/// The oldest architecture the kernels are written for (Turing). The machine code of every
/// target is compiled from this one PTX (one front-end pass for all of them): for the H100 the
/// same code that the driver's JIT made from the `compute_75` PTX of earlier builds.
const BASE_ARCH: u32 = 75;

/// The `XY` of `sm_XY` / `compute_XY` in nvcc's `--list-gpu-code` / `--list-gpu-arch` output
/// from `BASE_ARCH` on, without the family-specific `a`/`f` variants.
fn listed(nvcc: &Path, flag: &str, prefix: &str) -> Vec<u32> {
    let out = Command::new(nvcc).arg(flag).output().ok();
    let text = out
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    let mut v: Vec<u32> = text
        .split_whitespace()
        .filter_map(|w| w.strip_prefix(prefix)?.parse().ok())
        .filter(|&n| n >= BASE_ARCH)
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

impl Targets {
    /// `MESHFREE_CUDA_ARCH` (a comma- or space-separated list of `sm_XY` and `compute_XY`),
    /// or by default machine code for every real architecture nvcc lists from Turing on
    /// and PTX for the newest virtual one (what the driver JIT-compiles for a GPU newer than
    /// this nvcc).
    fn choose(nvcc: &Path) -> Targets {
        if let Ok(v) = env::var("MESHFREE_CUDA_ARCH") {
            let mut t = Targets {
                sass: Vec::new(),
                ptx: Vec::new(),
            };
            for w in v.split([',', ' ']).filter(|w| !w.is_empty()) {
                let parsed = |p: &str| w.strip_prefix(p).and_then(|n| n.parse::<u32>().ok());
                match (parsed("sm_"), parsed("compute_")) {
                    (Some(n), _) => t.sass.push(n),
                    (_, Some(n)) => t.ptx.push(n),
                    _ => panic!(
                        "MESHFREE_CUDA_ARCH={v:?}: `{w}` is neither sm_XY (machine code) nor \
                         compute_XY (PTX)"
                    ),
                }
            }
            assert!(
                !t.sass.is_empty() || !t.ptx.is_empty(),
                "MESHFREE_CUDA_ARCH={v:?} names no architecture"
            );
            t.sass.sort_unstable();
            t.sass.dedup();
            t.ptx.sort_unstable();
            t.ptx.dedup();
            return t;
        }
        let mut sass = listed(nvcc, "--list-gpu-code", "sm_");
        if sass.is_empty() {
            // An nvcc that cannot list them: the architectures of CUDA 12.
            sass = vec![75, 80, 86, 89, 90];
        }
        let newest = listed(nvcc, "--list-gpu-arch", "compute_")
            .last()
            .copied()
            .unwrap_or(*sass.last().expect("one architecture"));
        Targets {
            sass,
            ptx: vec![newest],
        }
    }

    /// nvcc's `-gencode` arguments.
    fn gencode(&self) -> Vec<String> {
        let mut g = Vec::new();
        if let Some(&lowest) = self.sass.first() {
            let codes: Vec<String> = self.sass.iter().map(|n| format!("sm_{n}")).collect();
            g.push(format!(
                "arch=compute_{},code=[{}]",
                lowest.min(BASE_ARCH),
                codes.join(",")
            ));
        }
        for n in &self.ptx {
            g.push(format!("arch=compute_{n},code=compute_{n}"));
        }
        g.into_iter().flat_map(|g| ["-gencode".into(), g]).collect()
    }

    fn describe(&self) -> String {
        let sass = self.sass.iter().map(|n| format!("sm_{n}"));
        let ptx = self.ptx.iter().map(|n| format!("compute_{n}"));
        sass.chain(ptx).collect::<Vec<_>>().join(",")
    }
}

/// The PTX that nvcc kept (`--keep`) for module `stem` in `dir`: `<stem>.ptx` where one
/// virtual architecture was compiled, else the first `<stem>.compute_XY.ptx`.
fn kept_ptx(dir: &Path, stem: &str) -> Option<PathBuf> {
    let single = dir.join(format!("{stem}.ptx"));
    if single.is_file() {
        return Some(single);
    }
    let mut found: Vec<PathBuf> = fs::read_dir(dir)
        .ok()?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name().is_some_and(|n| {
                let n = n.to_string_lossy();
                n.starts_with(&format!("{stem}.compute_")) && n.ends_with(".ptx")
            })
        })
        .collect();
    found.sort();
    found.into_iter().next()
}

fn cuda_modules(out: &Path) {
    let require = env::var("MESHFREE_REQUIRE_NVCC").is_ok_and(|v| v == "1");
    let mut sources: Vec<PathBuf> = fs::read_dir("cuda")
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    sources.retain(|p| p.extension().is_some_and(|e| e == "cu"));
    sources.sort();

    let registry = out.join("modules.rs");
    let texts = out.join("ptx_text.rs");
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
        fs::write(
            &registry,
            "pub const MODULES: &[(&str, &[u8])] = &[];\npub const SASS: &[u32] = &[];\n\
             pub const PTX: &[u32] = &[];\n",
        )
        .unwrap();
        fs::write(&texts, "pub const PTX_TEXT: &[(&str, &str)] = &[];\n").unwrap();
        println!("cargo:rustc-env=MESHFREE_NVCC_VERSION=none (no nvcc at build time)");
        return;
    };
    // The nvcc release, for the error a module load failure reports.
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
    let targets = Targets::choose(&nvcc);
    // Extra nvcc flags for experiments (e.g. `-DMF_NO_QUEUE` for an A/B measurement).
    let extra = env::var("MESHFREE_NVCC_FLAGS").unwrap_or_default();
    // Every file under cuda/ (a module includes the shared headers), for the reuse test below.
    let tree = cuda_tree_digest();
    let reused = std::sync::atomic::AtomicUsize::new(0);
    // OUT_DIR is `<target>/<profile>/build/meshfree-core-<hash>/out`.
    let cache = out
        .ancestors()
        .nth(2)
        .unwrap_or(out)
        .join("meshfree-core-nvcc");
    let compile = |src: &PathBuf| -> (String, PathBuf, PathBuf) {
        let stem = src.file_stem().unwrap().to_string_lossy().into_owned();
        let dst = out.join(format!("{stem}.fatbin"));
        let text = out.join(format!("{stem}.ptx"));
        // nvcc's intermediate files, of which the PTX is kept (the kernel table's test reads
        // it: the fatbin's copy is compressed).
        let keep = out.join("nvcc").join(&stem);
        let mut cmd = Command::new(&nvcc);
        // -ftz=true: denormal floats flush to zero, so that a reciprocal, reciprocal root or
        // division in the pair sums is one instruction, not a range test and rescale around it
        // (3D step 8 % shorter on the H100, docs/reference/performance.md, "-ftz=true"). No SPH quantity
        // of a scene comes near 1e-38 in SI units; the parity tests hold unchanged.
        // --threads 0: the targets' ptxas runs on every core; -compress-all: the machine code
        // is compressed too (the driver unpacks it at load), 7x smaller.
        cmd.args([
            "-fatbin",
            "-std=c++17",
            "-O3",
            "-ftz=true",
            "-lineinfo",
            "-Icuda",
            "--threads",
            "0",
            "-Xfatbin=-compress-all",
            "--keep",
        ])
        .arg("--keep-dir")
        .arg(&keep)
        .args(targets.gencode())
        .args(extra.split_whitespace())
        .arg(src)
        .arg("-o")
        .arg(&dst);
        let shown = format!("{cmd:?}");
        // The build script reruns whenever HEAD moves (`commit`) and in every OUT_DIR that a
        // change of features or build dependencies opens (CI's `--features mpi` test build
        // is one: a second 1000 s nvcc pass once pushed CI past its limit). A module whose
        // sources under cuda/, nvcc release and flags are those of an earlier compile in this
        // target profile keeps that fatbin and PTX, from the profile's shared cache
        // (`<target>/<profile>/build/meshfree-core-nvcc/`), instead of minutes of nvcc.
        let flags: Vec<String> = cmd
            .get_args()
            .map(|a| a.to_string_lossy().into_owned())
            .filter(|a| !a.starts_with(&*out.to_string_lossy()))
            .collect();
        let key = format!("{tree:016x} {version} {} {flags:?}", nvcc.display());
        let cached = |ext: &str| cache.join(format!("{stem}.{:016x}.{ext}", fnv(key.as_bytes())));
        let stamp = out.join(format!("{stem}.key"));
        if dst.exists() && text.exists() && fs::read_to_string(&stamp).is_ok_and(|k| k == key) {
            reused.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            return (stem, dst, text);
        }
        if fs::copy(cached("fatbin"), &dst).is_ok() && fs::copy(cached("ptx"), &text).is_ok() {
            fs::write(&stamp, &key).expect("write the module's compile key");
            reused.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            return (stem, dst, text);
        }
        let _ = fs::remove_file(&stamp);
        let _ = fs::remove_dir_all(&keep);
        fs::create_dir_all(&keep).expect("create nvcc's keep folder");
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
        let ptx = kept_ptx(&keep, &stem).unwrap_or_else(|| {
            panic!(
                "nvcc kept no PTX of {} in {}",
                src.display(),
                keep.display()
            )
        });
        fs::rename(&ptx, &text).expect("move the kept PTX");
        // The rest (preprocessed sources, one cubin per target) is large and unused.
        let _ = fs::remove_dir_all(&keep);
        fs::write(&stamp, &key).expect("write the module's compile key");
        // Into the shared cache through a temporary name, so that a concurrent build never
        // reads half a file (the PTX last: its presence marks the pair complete).
        let _ = fs::create_dir_all(&cache);
        for (from, ext) in [(&dst, "fatbin"), (&text, "ptx")] {
            let tmp = cached(&format!("{ext}.{}", std::process::id()));
            if fs::copy(from, &tmp).is_ok() {
                let _ = fs::rename(&tmp, cached(ext));
            }
        }
        (stem, dst, text)
    };
    // The modules on `NUM_JOBS` threads (cargo's -j), each nvcc on every core: the machine
    // code of one large module for all targets takes minutes on one.
    let started = std::time::Instant::now();
    let jobs = env::var("NUM_JOBS")
        .ok()
        .and_then(|n| n.parse::<usize>().ok())
        .unwrap_or(1)
        .clamp(1, sources.len().max(1));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut built: Vec<(usize, (String, PathBuf, PathBuf))> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..jobs)
            .map(|_| {
                s.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        let Some(src) = sources.get(i) else {
                            return mine;
                        };
                        mine.push((i, compile(src)));
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    built.sort_by_key(|(i, _)| *i);
    let list = |v: &[u32]| {
        v.iter()
            .map(|n| n.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut entries = String::from(
        "/// Per module (`cuda/<stem>.cu`): its fatbin.\n\
         pub const MODULES: &[(&str, &[u8])] = &[\n",
    );
    let mut text_entries = String::from("pub const PTX_TEXT: &[(&str, &str)] = &[\n");
    for (_, (stem, fatbin, text)) in &built {
        entries += &format!(
            "    ({stem:?}, include_bytes!({:?})),\n",
            fatbin.display().to_string()
        );
        text_entries += &format!(
            "    ({stem:?}, include_str!({:?})),\n",
            text.display().to_string()
        );
    }
    entries += &format!(
        "];\n/// Compute capabilities (10 major + minor) with machine code in every module.\n\
         pub const SASS: &[u32] = &[{}];\n\
         /// Virtual architectures (10 major + minor) whose PTX every module carries.\n\
         pub const PTX: &[u32] = &[{}];\n",
        list(&targets.sass),
        list(&targets.ptx)
    );
    text_entries += "];\n";
    fs::write(&registry, entries).unwrap();
    fs::write(&texts, text_entries).unwrap();
    if !sources.is_empty() {
        println!("cargo:rustc-cfg=meshfree_ptx");
    }
    let reused = reused.into_inner();
    if reused < sources.len() {
        println!(
            "cargo:warning=nvcc {} compiled {} CUDA modules for {} in {:.0} s ({reused} unchanged)",
            nvcc.display(),
            sources.len() - reused,
            targets.describe(),
            started.elapsed().as_secs_f64()
        );
    }
}

/// FNV-1a over the paths and bytes of every file under cuda/, in path order.
fn cuda_tree_digest() -> u64 {
    fn walk(dir: &Path, files: &mut Vec<PathBuf>) {
        for e in fs::read_dir(dir).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, files);
            } else {
                files.push(p);
            }
        }
    }
    let mut files = Vec::new();
    walk(Path::new("cuda"), &mut files);
    files.sort();
    let mut bytes = Vec::new();
    for p in files {
        bytes.extend(p.to_string_lossy().as_bytes());
        bytes.push(0);
        bytes.extend(fs::read(&p).unwrap_or_default());
    }
    fnv(&bytes)
}

/// FNV-1a, 64 bits.
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ *b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}
