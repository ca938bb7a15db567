//! Probe the driver, open a context and load the PTX modules built by `build.rs`.

use std::collections::HashMap;
use std::sync::Arc;

use cudarc::driver::{sys, CudaContext, CudaFunction, CudaModule, CudaStream};
use cudarc::nvrtc::Ptx;

use crate::backend::BackendError;

mod ptx {
    include!(concat!(env!("OUT_DIR"), "/ptx.rs"));
}

/// The nvcc that compiled the embedded PTX (recorded by `build.rs`).
pub const NVCC_VERSION: &str = env!("MESHFREE_NVCC_VERSION");

/// A context on device 0, its stream and every loaded module.
pub struct Device {
    #[allow(dead_code)] // the context outlives every module and buffer
    pub ctx: Arc<CudaContext>,
    pub stream: Arc<CudaStream>,
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

impl Device {
    /// Device 0, or why it cannot be used. Never panics where no driver is installed.
    pub fn open() -> Result<Device, BackendError> {
        let unavailable = |s: String| BackendError::CudaUnavailable(s);
        if ptx::MODULES.is_empty() {
            return Err(unavailable(format!(
                "this build carries no PTX (nvcc at build time: {NVCC_VERSION}); rebuild with nvcc on PATH or NVCC set"
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
        let ctx =
            CudaContext::new(0).map_err(|e| unavailable(format!("cannot open device 0: {e:?}")))?;
        let name = ctx.name().unwrap_or_else(|_| "unknown CUDA device".into());
        // SAFETY: every allocation, copy and launch of this backend goes to this one stream,
        // in order, so cudarc's cross-stream event tracking has nothing to order; without it
        // a step can be captured into a CUDA graph (no events recorded during capture).
        unsafe { ctx.disable_event_tracking() };
        // A stream of our own: the legacy default stream cannot be captured into a graph.
        let stream = ctx
            .new_stream()
            .map_err(|e| BackendError::Cuda(format!("cannot create a CUDA stream: {e:?}")))?;
        let mut modules = HashMap::new();
        // MESHFREE_PTX_DIR: modules found there as <stem>.ptx replace the embedded ones, for
        // A/B measurements of compile-time variants of the kernels (same signatures: e.g.
        // `nvcc --ptx -DMF_QUEUE=0 ...`) without rebuilding the binary.
        let ptx_dir = std::env::var_os("MESHFREE_PTX_DIR").map(std::path::PathBuf::from);
        for (stem, src) in ptx::MODULES {
            let replaced = ptx_dir
                .as_ref()
                .map(|d| d.join(format!("{stem}.ptx")))
                .filter(|f| f.is_file());
            let src = match &replaced {
                Some(f) => {
                    eprintln!(
                        "meshfree: PTX module `{stem}` from {} (MESHFREE_PTX_DIR)",
                        f.display()
                    );
                    std::fs::read_to_string(f).map_err(|e| {
                        BackendError::Cuda(format!("cannot read {}: {e}", f.display()))
                    })?
                }
                None => src.to_string(),
            };
            let m = ctx.load_module(Ptx::from_src(src)).map_err(|e| {
                BackendError::Cuda(format!(
                    "loading PTX module `{stem}` ({stem}.cu) failed: {e:?}; built by nvcc {NVCC_VERSION}, driver \
                     supports CUDA {} (a driver older than the nvcc refuses its PTX)",
                    driver_version()
                ))
            })?;
            modules.insert(*stem, m);
        }
        Ok(Device {
            ctx,
            stream,
            name,
            modules,
        })
    }

    /// Kernel `name` of module `module`.
    pub fn function(&self, module: &str, name: &str) -> Result<CudaFunction, BackendError> {
        let m = self
            .modules
            .get(module)
            .ok_or_else(|| BackendError::Cuda(format!("no PTX module `{module}` in this build")))?;
        m.load_function(name).map_err(|e| {
            BackendError::Cuda(format!(
                "kernel `{name}` not found in module `{module}`: {e:?}"
            ))
        })
    }
}
