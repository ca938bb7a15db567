//! Probe the driver, open a context and load the modules built by `build.rs`: one fatbin
//! per `cuda/*.cu`, with machine code for every architecture the nvcc knows from Turing on
//! and the newest PTX; the driver picks what fits the GPU (`code_for` says what it picked).

use std::collections::HashMap;
use std::sync::Arc;

use cudarc::driver::{sys, CudaContext, CudaFunction, CudaModule, CudaStream};
use cudarc::nvrtc::Ptx;

use crate::backend::error::BackendError;

mod built {
    include!(concat!(env!("OUT_DIR"), "/modules.rs"));
}

/// The nvcc that compiled the embedded modules (recorded by `build.rs`).
pub const NVCC_VERSION: &str = env!("MESHFREE_NVCC_VERSION");

/// A context on device 0, its stream and every loaded module.
pub struct Device {
    #[allow(dead_code)] // the context outlives every module and buffer
    pub ctx: Arc<CudaContext>,
    pub stream: Arc<CudaStream>,
    /// The device's name and the code it runs, e.g. "NVIDIA H100 80GB HBM3, sm_90 machine
    /// code" (`code_for`).
    pub name: String,
    modules: HashMap<&'static str, Arc<CudaModule>>,
}

/// The driver's CUDA version as "major.minor", or "unknown".
pub fn driver_version() -> String {
    let mut v = 0i32;
    // SAFETY: cuDriverGetVersion writes one int; only called after the library was found.
    let r = unsafe { sys::cuDriverGetVersion(&mut v) };
    if r == sys::CUresult::CUDA_SUCCESS {
        format!("{}.{}", v / 1000, (v % 1000) / 10)
    } else {
        "unknown".into()
    }
}

/// How many CUDA devices the driver reports (0 where no driver answers).
pub fn device_count() -> usize {
    // SAFETY: only tries to dlopen libcuda before asking it.
    if !unsafe { sys::is_culib_present() } {
        return 0;
    }
    CudaContext::device_count().map_or(0, |n| n.max(0) as usize)
}

/// What the driver runs of this build's modules on a GPU of compute capability `cc`
/// (10 major + minor), as `cuModuleLoadData` chooses by default (`CU_PREFER_PTX`): the
/// machine code for exactly `cc`; else PTX of an architecture `cc` can run, JIT-compiled
/// (once per driver cache); else machine code of the same major architecture and a lower
/// minor one, which runs unchanged on `cc`; else nothing (the load fails).
fn code_for(cc: u32, sass: &[u32], ptx: &[u32]) -> String {
    if sass.contains(&cc) {
        return format!("sm_{cc} machine code");
    }
    if let Some(p) = ptx.iter().filter(|&&p| p <= cc).max() {
        return format!("sm_{cc}: PTX compute_{p} JIT-compiled by the driver");
    }
    match sass.iter().filter(|&&s| s / 10 == cc / 10 && s < cc).max() {
        Some(s) => format!("sm_{cc}: sm_{s} machine code"),
        None => format!("sm_{cc}: no code in this build"),
    }
}

/// The targets of this build, e.g. "sm_75, sm_80, ..., sm_121, PTX compute_121".
fn targets() -> String {
    let sass = built::SASS.iter().map(|n| format!("sm_{n}"));
    let ptx = built::PTX.iter().map(|n| format!("PTX compute_{n}"));
    sass.chain(ptx).collect::<Vec<_>>().join(", ")
}

impl Device {
    /// Device 0, or why it cannot be used. Never panics where no driver is installed.
    pub fn open() -> Result<Device, BackendError> {
        Device::open_ordinal(0)
    }

    /// Device `ordinal` (as the driver numbers them, 0 first), or why it cannot be used:
    /// a context (the device's primary one, shared by every solver on it), a stream of this
    /// solver's own, and every module loaded. Never panics where no driver is installed.
    pub fn open_ordinal(ordinal: usize) -> Result<Device, BackendError> {
        let unavailable = |s: String| BackendError::CudaUnavailable(s);
        if built::MODULES.is_empty() {
            return Err(unavailable(format!(
                "this build carries no CUDA modules (nvcc at build time: {NVCC_VERSION}); rebuild with nvcc on PATH or NVCC set"
            )));
        }
        // SAFETY: only tries to dlopen libcuda; no CUDA call is made.
        if !unsafe { sys::is_culib_present() } {
            return Err(unavailable(
                "no CUDA driver library (libcuda.so) found".into(),
            ));
        }
        let count = CudaContext::device_count()
            .map_err(|e| unavailable(format!("the CUDA driver does not answer: {e:?}")))?;
        if count < 1 {
            return Err(unavailable("the CUDA driver reports no device".into()));
        }
        if ordinal >= count as usize {
            return Err(unavailable(format!(
                "no device {ordinal}: the CUDA driver reports {count}"
            )));
        }
        let ctx = CudaContext::new(ordinal)
            .map_err(|e| unavailable(format!("cannot open device {ordinal}: {e:?}")))?;
        let gpu = ctx.name().unwrap_or_else(|_| "unknown CUDA device".into());
        let cc = ctx
            .compute_capability()
            .map(|(major, minor)| (major * 10 + minor) as u32)
            .map_err(|e| unavailable(format!("cannot read the compute capability: {e:?}")))?;
        let code = code_for(cc, built::SASS, built::PTX);
        // SAFETY: every allocation, copy and launch of this backend goes to this one stream,
        // in order, so cudarc's cross-stream event tracking has nothing to order; without it
        // a step can be captured into a CUDA graph (no events recorded during capture). The
        // one exception, a subdomain's halo (`subdomain.rs`), which one solver's stream
        // writes and another's reads, is ordered by hand: the sender synchronises its stream
        // before handing it over, the receiver its own before dropping it.
        unsafe { ctx.disable_event_tracking() };
        // A stream of our own: the legacy default stream cannot be captured into a graph.
        let stream = ctx
            .new_stream()
            .map_err(|e| BackendError::Cuda(format!("cannot create a CUDA stream: {e:?}")))?;
        let mut modules = HashMap::new();
        // MESHFREE_PTX_DIR: modules found there as <stem>.ptx (or compiled, <stem>.fatbin or
        // <stem>.cubin) replace the embedded ones, for A/B measurements of compile-time
        // variants of the kernels (same signatures: e.g. `nvcc --ptx -DMF_QUEUE=0 ...`)
        // without rebuilding the binary.
        let ptx_dir = std::env::var_os("MESHFREE_PTX_DIR").map(std::path::PathBuf::from);
        let mut replaced = Vec::new();
        for (stem, fatbin) in built::MODULES {
            let found = ptx_dir.as_ref().and_then(|d| {
                ["ptx", "fatbin", "cubin"]
                    .iter()
                    .map(|ext| d.join(format!("{stem}.{ext}")))
                    .find(|f| f.is_file())
            });
            let (image, origin) = match &found {
                Some(f) => {
                    eprintln!(
                        "meshfree: CUDA module `{stem}` from {} (MESHFREE_PTX_DIR)",
                        f.display()
                    );
                    let read = |e: std::io::Error| {
                        BackendError::Cuda(format!("cannot read {}: {e}", f.display()))
                    };
                    replaced.push(*stem);
                    let image = if f.extension().is_some_and(|e| e == "ptx") {
                        Ptx::from_src(std::fs::read_to_string(f).map_err(read)?)
                    } else {
                        Ptx::from_binary(std::fs::read(f).map_err(read)?)
                    };
                    (image, f.display().to_string())
                }
                // A copy: cudarc takes the image by value (and the heap copy is aligned).
                None => (Ptx::from_binary(fatbin.to_vec()), targets()),
            };
            let m = ctx.load_module(image).map_err(|e| {
                BackendError::Cuda(format!(
                    "loading CUDA module `{stem}` ({stem}.cu: {origin}) on {gpu} ({code}) \
                     failed: {e:?}; built by nvcc {NVCC_VERSION}, driver supports CUDA {} (a \
                     driver older than the nvcc refuses its code; MESHFREE_CUDA_ARCH=sm_{cc} \
                     builds this GPU's machine code)",
                    driver_version()
                ))
            })?;
            modules.insert(*stem, m);
        }
        let name = if replaced.is_empty() {
            format!("{gpu}, {code}")
        } else {
            format!(
                "{gpu}, {code} ({} from MESHFREE_PTX_DIR)",
                replaced.join(", ")
            )
        };
        Ok(Device {
            ctx,
            stream,
            name,
            modules,
        })
    }

    /// Kernel `name` of module `module`.
    pub fn function(&self, module: &str, name: &str) -> Result<CudaFunction, BackendError> {
        let m = self.modules.get(module).ok_or_else(|| {
            BackendError::Cuda(format!("no CUDA module `{module}` in this build"))
        })?;
        m.load_function(name).map_err(|e| {
            BackendError::Cuda(format!(
                "kernel `{name}` not found in module `{module}`: {e:?}"
            ))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::code_for;

    #[test]
    fn the_driver_prefers_exact_machine_code_then_ptx_then_the_same_major() {
        let sass = [75, 80, 86, 90, 100, 120];
        let ptx = [120];
        assert_eq!(code_for(90, &sass, &ptx), "sm_90 machine code");
        // No exact match: PTX the GPU can run comes first (CU_PREFER_PTX) ...
        assert_eq!(
            code_for(121, &sass, &ptx),
            "sm_121: PTX compute_120 JIT-compiled by the driver"
        );
        // ... else the same major architecture's machine code of a lower minor one.
        assert_eq!(code_for(89, &sass, &ptx), "sm_89: sm_86 machine code");
        assert_eq!(code_for(103, &sass, &ptx), "sm_103: sm_100 machine code");
        assert_eq!(code_for(110, &sass, &ptx), "sm_110: no code in this build");
        assert_eq!(
            code_for(90, &[], &[75]),
            "sm_90: PTX compute_75 JIT-compiled by the driver"
        );
    }
}
