//! The viewer's vertex buffers (`cuda/view.cu`, `view.rs`): CUDA-OpenGL interop (the
//! registration the driver API leaves to us, map and unmap), the fill and the visibility
//! splat.

use std::sync::Arc;

use cudarc::driver::{sys, CudaContext, CudaSlice, CudaStream, DriverError, PushKernelArg};

use super::{cfg, grid::scan, NULL};
use crate::backend::cuda::buffers::Buffers;
use crate::backend::cuda::kernels::{Family, Kernels};
use crate::backend::cuda::view::KindScans;
use crate::interop::GlSplat;
use crate::physics::params::SphParams;

/// `cuGraphicsGLRegisterBuffer` of `cudaGL.h`, which cudarc does not declare:
/// `CUresult cuGraphicsGLRegisterBuffer(CUgraphicsResource* pCudaResource, GLuint buffer,
/// unsigned int Flags)`.
type GlRegisterBuffer =
    unsafe extern "C" fn(*mut sys::CUgraphicsResource, u32, u32) -> sys::CUresult;

/// The driver's `cuGraphicsGLRegisterBuffer`, looked up by `cuGetProcAddress` (the driver is
/// loaded at run time, as cudarc loads it).
fn gl_register_entry() -> Result<GlRegisterBuffer, DriverError> {
    let mut f: *mut std::ffi::c_void = std::ptr::null_mut();
    let mut found = sys::CUdriverProcAddressQueryResult::CU_GET_PROC_ADDRESS_SYMBOL_NOT_FOUND;
    // SAFETY: the symbol is a NUL-terminated string; f and found are written once each.
    // 3000: the API version that introduced the entry (CUDA 3.0), flags 0: the default.
    unsafe {
        sys::cuGetProcAddress_v2(
            c"cuGraphicsGLRegisterBuffer".as_ptr(),
            &mut f,
            3000,
            0,
            &mut found,
        )
    }
    .result()?;
    if f.is_null() || found != sys::CUdriverProcAddressQueryResult::CU_GET_PROC_ADDRESS_SUCCESS {
        return Err(DriverError(sys::CUresult::CUDA_ERROR_NOT_FOUND));
    }
    // SAFETY: the driver's entry of that name at API version 3000 has the signature of
    // cudaGL.h that `GlRegisterBuffer` declares (a pointer to the resource handle, the GL
    // buffer name as GLuint = u32, the flags as unsigned int = u32).
    Ok(unsafe { std::mem::transmute::<*mut std::ffi::c_void, GlRegisterBuffer>(f) })
}

/// Registers the OpenGL buffer named `buffer` (in the context current on this thread, which
/// must run on the device of `ctx`) for CUDA to overwrite whole (write-discard).
pub fn gl_register(ctx: &CudaContext, buffer: u32) -> Result<sys::CUgraphicsResource, DriverError> {
    let register = gl_register_entry()?;
    ctx.bind_to_thread()?;
    let mut r: sys::CUgraphicsResource = std::ptr::null_mut();
    let flags = sys::CUgraphicsRegisterFlags::CU_GRAPHICS_REGISTER_FLAGS_WRITE_DISCARD as u32;
    // SAFETY: `register` is the driver's cuGraphicsGLRegisterBuffer (gl_register_entry); r
    // receives one handle; the caller's GL context is current (the driver checks that the
    // name is a buffer of it and fails otherwise).
    unsafe { register(&mut r, buffer, flags) }.result()?;
    Ok(r)
}

/// Unregisters a resource of `gl_register` (unmapped; the GL context should still exist).
pub fn gl_unregister(ctx: &CudaContext, r: sys::CUgraphicsResource) -> Result<(), DriverError> {
    ctx.bind_to_thread()?;
    // SAFETY: r came from gl_register and is unregistered once (its owner forgets it).
    unsafe { sys::cuGraphicsUnregisterResource(r) }.result()
}

/// Maps `res` for the work queued on `s` after it (the map waits for OpenGL's work on the
/// buffers) and returns each one's device address and size in bytes.
pub fn gl_map(
    s: &CudaStream,
    res: &mut [sys::CUgraphicsResource],
) -> Result<Vec<(sys::CUdeviceptr, usize)>, DriverError> {
    s.context().bind_to_thread()?;
    // SAFETY: res holds registered, unmapped resources of this context; the map is ordered
    // on s.
    unsafe { sys::cuGraphicsMapResources(res.len() as u32, res.as_mut_ptr(), s.cu_stream()) }
        .result()?;
    res.iter()
        .map(|&r| {
            let (mut ptr, mut size) = (0, 0usize);
            // SAFETY: r is mapped (above); ptr and size are written once each.
            unsafe { sys::cuGraphicsResourceGetMappedPointer_v2(&mut ptr, &mut size, r) }
                .result()
                .map(|_| (ptr, size))
        })
        .collect()
}

/// Unmaps `res` after the work queued on `s` (OpenGL's next use of the buffers waits for it).
pub fn gl_unmap(s: &CudaStream, res: &mut [sys::CUgraphicsResource]) -> Result<(), DriverError> {
    s.context().bind_to_thread()?;
    // SAFETY: res holds the resources `gl_map` mapped on s.
    unsafe { sys::cuGraphicsUnmapResources(res.len() as u32, res.as_mut_ptr(), s.cu_stream()) }
        .result()
}

/// The viewer's vertex fill (`cuda/view.cu`): the marks of the fluid and the solids
/// (`Family::ViewMark`), their scans, then `Family::ViewFill`, which writes the `b.n`
/// particles' positions, quantity `shown` (MF_SHOWN_*) and kinds into the mapped buffers
/// `out` (positions, values, kinds: device addresses of at least 12 n, 4 n and n bytes),
/// each at its place in the kind order (`b.kinds` the class counts, equal to the storage's:
/// checked by the caller), and, where `range` is given (two words, zeroed here), the colour
/// range of the particles that set it (`hidden`: bit k hides kind k).
#[allow(clippy::too_many_arguments)]
pub fn view_fill(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &Buffers,
    shown: u32,
    hidden: u32,
    out: [sys::CUdeviceptr; 3],
    range: Option<&mut CudaSlice<u32>>,
    order: &mut KindScans,
) -> Result<(), DriverError> {
    let n = b.n as u32;
    if n == 0 {
        return Ok(());
    }
    let c = &b.cur;
    let solids = b.kinds[1] > 0;
    let km = k.get(Family::ViewMark);
    {
        let [mf, ms] = &mut order.mark;
        let mut l = s.launch_builder(&km.f);
        l.arg(&n).arg(&c.kind).arg(mf);
        if solids {
            l.arg(ms);
        } else {
            l.arg(&NULL);
        }
        // SAFETY: the arguments of `Family::ViewMark`: kind holds n particles, the marks
        // `order.cap` >= n entries (the caller's check), mark_solid null without solids.
        km.check(unsafe { l.launch(cfg(b.n)) }.map(|_| ()));
    }
    // The grid build's scan over the n marks of each (mark and local hold cap >= n entries,
    // 16-byte aligned allocations; bsum ceil(cap / MF_SCAN_CELLS) blocks).
    for q in 0..if solids { 2 } else { 1 } {
        scan(
            k,
            s,
            n,
            &order.mark[q],
            &mut order.local[q].slice_mut(..),
            &mut order.bsum[q],
        );
    }
    let (n_fluid, n_solid) = (b.kinds[0] as u32, b.kinds[1] as u32);
    let kf = k.get(Family::ViewFill);
    let mut l = s.launch_builder(&kf.f);
    l.arg(p)
        .arg(&n)
        .arg(&shown)
        .arg(&hidden)
        .arg(&c.pos)
        .arg(&c.vel)
        .arg(&c.rho)
        .arg(&c.p)
        .arg(&c.kind)
        .arg(&out[0])
        .arg(&out[1])
        .arg(&out[2]);
    match range {
        Some(r) => {
            s.memset_zeros(&mut *r)?;
            l.arg(r);
        }
        None => {
            l.arg(&NULL);
        }
    }
    l.arg(&order.local[0]).arg(&order.bsum[0]);
    if solids {
        l.arg(&order.local[1]).arg(&order.bsum[1]);
    } else {
        l.arg(&NULL).arg(&NULL);
    }
    l.arg(&n_fluid).arg(&n_solid);
    // SAFETY: the arguments of `Family::ViewFill`: pos, vel, rho, p and kind hold the n
    // current particles; out holds device addresses of mapped buffers of at least 12 n, 4 n
    // and n bytes (checked by the caller, view.rs); range holds 2 words or is null; the
    // scans hold n entries (the solids' null without solids), and n_fluid + n_solid <= n
    // counts the kinds of the storage (`b.kinds`, checked by the caller), so every slot
    // written is below n.
    unsafe { l.launch(cfg(b.n)) }.map(|_| ())
}

/// The viewer's visibility splat (`cuda/view.cu`) over the filled buffers `filled`
/// (positions, values, kinds: device addresses of `view_fill`'s output): `key` zeroed,
/// `Family::ViewSplat` over the particles `sp.first .. sp.first + sp.count`, then
/// `Family::ViewPixels` into the mapped buffer `out` (`sp.bytes()` bytes: the pixels'
/// quadruples, then their kinds). `cam` holds 17 floats, `key` at least width x height words.
pub fn view_splat(
    k: &Kernels,
    s: &Arc<CudaStream>,
    sp: &GlSplat,
    filled: [sys::CUdeviceptr; 3],
    out: sys::CUdeviceptr,
    cam: &mut CudaSlice<f32>,
    key: &mut CudaSlice<u64>,
) -> Result<(), DriverError> {
    let pixels = sp.width as usize * sp.height as usize;
    let mut c = [0.0f32; 17];
    c[..12].copy_from_slice(&sp.view);
    c[12..16].copy_from_slice(&sp.ray);
    c[16] = sp.radius;
    s.memcpy_htod(&c, &mut *cam)?;
    s.memset_zeros(&mut key.slice_mut(..pixels))?;
    let (first, count, hidden) = (sp.first as u32, sp.count as u32, u32::from(sp.hidden));
    let (w, h) = (sp.width, sp.height);
    if count > 0 {
        let ks = k.get(Family::ViewSplat);
        let mut l = s.launch_builder(&ks.f);
        l.arg(&first)
            .arg(&count)
            .arg(&filled[0])
            .arg(&filled[2])
            .arg(&hidden)
            .arg(&*cam)
            .arg(&w)
            .arg(&h)
            .arg(&mut *key);
        // SAFETY: the arguments of `Family::ViewSplat`: pos and kind are filled buffers of
        // at least first + count particles (the caller's check), cam 17 floats, key at least
        // width x height words (every pixel written lies in the view).
        ks.check(unsafe { l.launch(cfg(sp.count)) }.map(|_| ()));
    }
    let kp = k.get(Family::ViewPixels);
    let out_kind = out + 16 * pixels as u64;
    let n = pixels as u32;
    let mut l = s.launch_builder(&kp.f);
    l.arg(&n)
        .arg(&*key)
        .arg(&filled[0])
        .arg(&filled[1])
        .arg(&filled[2])
        .arg(&out)
        .arg(&out_kind);
    // SAFETY: the arguments of `Family::ViewPixels`: key holds the pixels' words, whose
    // particles index the filled buffers (the splat's), and out holds 17 bytes a pixel
    // (the caller's check): 16 from its start, then one from out_kind.
    unsafe { l.launch(cfg(pixels)) }.map(|_| ())
}
