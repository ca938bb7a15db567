//! The viewer's vertex buffers filled from device memory (CUDA-OpenGL interop): the
//! renderer's three particle buffers registered with CUDA once, then per drawn frame mapped,
//! filled by `cuda/view.cu` straight from the solver's arrays in the viewer's kind order
//! (fluid, solids, the rest; scans of the kinds' marks rank each particle), and unmapped;
//! no particle crosses PCIe. The colour range is reduced on the device and comes back as 8
//! bytes, or not at all where the range is fixed. Where the viewer asks (`GlSplat`), the
//! same mapping also takes its splat buffer, and after the fill the visibility splat writes
//! each pixel's nearest sphere into it. Twin: the host-copy path, `Readback::snapshot` and the
//! viewer's upload (and its sprites' pass for the splat); test: `app/tests/render_interop.rs`.

use cudarc::driver::{sys, CudaContext, CudaSlice, CudaStream, DriverError};

use super::buffers::Buffers;
use super::kernels::Kernels;
use super::launch;
use super::CudaSolver;
use crate::consts::MF_SCAN_CELLS;
use crate::interop::{GlBuffers, GlFill, GlInterop, GlSplat};
use crate::physics::dim::Dim;
use crate::physics::params::SphParams;
use crate::solver::Shown;
use std::sync::Arc;

/// The scans that rank each particle among its kind (`cuda/view.cu`'s kind order): marks,
/// per-block sums and block offsets, [0] of the fluid and [1] of the solids, for up to `cap`
/// particles (the registered buffers' capacity).
pub struct KindScans {
    pub cap: usize,
    pub mark: [CudaSlice<u32>; 2],
    pub local: [CudaSlice<u32>; 2],
    pub bsum: [CudaSlice<u32>; 2],
}

impl KindScans {
    pub fn new(s: &Arc<CudaStream>, cap: usize) -> Result<KindScans, DriverError> {
        let blocks = cap.div_ceil(MF_SCAN_CELLS as usize).max(1);
        let z = |n: usize| s.alloc_zeros::<u32>(n.max(1));
        Ok(KindScans {
            cap,
            mark: [z(cap)?, z(cap)?],
            local: [z(cap)?, z(cap)?],
            bsum: [z(blocks)?, z(blocks)?],
        })
    }
}

/// Bytes per particle of the position, value and kind buffers (`GlBuffers`).
const BYTES: [usize; 3] = [12, 4, 1];

/// The registered buffers of one renderer.
pub struct GlView {
    ctx: Arc<CudaContext>,
    /// What was registered; a change of names or capacity registers anew.
    target: GlBuffers,
    res: [sys::CUgraphicsResource; 3],
    /// The range's two words (`cuda/view.cu`).
    range: CudaSlice<u32>,
    order: KindScans,
    /// The splat's buffer as registered (name, view size, resource), its camera (17 floats) and
    /// its per-pixel keys (grown to the largest view).
    splat: Option<(u32, (u32, u32), sys::CUgraphicsResource)>,
    cam: CudaSlice<f32>,
    key: Option<CudaSlice<u64>>,
}

// SAFETY: the resource handles are plain driver handles, used only through `&mut self` (so
// never from two threads at once), as cudarc's own handles are.
unsafe impl Send for GlView {}

/// The float whose bits `ordered_bits` (`cuda/view.cu`) mapped to `u`.
fn from_ordered(u: u32) -> f32 {
    f32::from_bits(if u >> 31 == 1 { u & 0x7fff_ffff } else { !u })
}

impl GlView {
    /// Registers the three buffers of `target` (its GL context current on this thread).
    pub fn register(s: &Arc<CudaStream>, target: GlBuffers) -> Result<GlView, DriverError> {
        let ctx = s.context().clone();
        let mut res = [std::ptr::null_mut(); 3];
        let names = [target.positions, target.values, target.kinds];
        for (i, &name) in names.iter().enumerate() {
            match launch::gl_register(&ctx, name) {
                Ok(r) => res[i] = r,
                Err(e) => {
                    for &r in &res[..i] {
                        let _ = launch::gl_unregister(&ctx, r);
                    }
                    return Err(e);
                }
            }
        }
        let range = s.alloc_zeros::<u32>(2)?;
        let order = KindScans::new(s, target.capacity)?;
        let cam = s.alloc_zeros::<f32>(17)?;
        Ok(GlView {
            ctx,
            target,
            res,
            range,
            order,
            splat: None,
            cam,
            key: None,
        })
    }

    /// Whether this view registered `target`'s buffers.
    pub fn serves(&self, target: &GlBuffers) -> bool {
        self.target == *target
    }

    /// Registers the splat's buffer (again where its name or view size changed: the
    /// renderer gives it new storage for each size) and makes room for its keys.
    fn prepare_splat(&mut self, s: &Arc<CudaStream>, sp: &GlSplat) -> Result<(), String> {
        let size = (sp.width, sp.height);
        if self
            .splat
            .is_none_or(|(name, had, _)| name != sp.buffer || had != size)
        {
            if let Some((_, _, r)) = self.splat.take() {
                let _ = launch::gl_unregister(&self.ctx, r);
            }
            let r = launch::gl_register(&self.ctx, sp.buffer)
                .map_err(|e| format!("registering the splat buffer: {e:?}"))?;
            self.splat = Some((sp.buffer, size, r));
        }
        let pixels = sp.width as usize * sp.height as usize;
        if self.key.as_ref().is_none_or(|k| k.len() < pixels) {
            self.key = None;
            self.key = Some(
                s.alloc_zeros::<u64>(pixels)
                    .map_err(|e| format!("allocating the splat's keys: {e:?}"))?,
            );
        }
        Ok(())
    }

    /// Map, fill and unmap: the particles of `b` into the buffers (and, with `splat`, their
    /// visibility into its buffer); returns what was written and the bytes read back (8
    /// with the range, else 0).
    #[allow(clippy::too_many_arguments)]
    pub fn fill(
        &mut self,
        k: &Kernels,
        s: &Arc<CudaStream>,
        p: &SphParams,
        b: &Buffers,
        shown: Shown,
        hidden: u8,
        fixed_range: bool,
        splat: Option<&GlSplat>,
    ) -> Result<(GlFill, u64), String> {
        let n = b.n;
        if n > self.target.capacity || n > self.order.cap {
            return Err(format!(
                "the vertex buffers hold {} particles, the solver has {n}",
                self.target.capacity
            ));
        }
        if b.kinds.iter().sum::<usize>() != n {
            return Err(format!(
                "the particles' kinds are not counted for the {n} held (a subdomain's exchange)"
            ));
        }
        let splat = match splat {
            Some(sp) if sp.first + sp.count <= n && sp.width > 0 && sp.height > 0 => {
                self.prepare_splat(s, sp)?;
                Some(sp)
            }
            _ => None,
        };
        let mut res = self.res.to_vec();
        if let (Some(_), Some((_, _, r))) = (splat, self.splat) {
            res.push(r);
        }
        let mapped = launch::gl_map(s, &mut res).map_err(|e| format!("mapping: {e:?}"))?;
        let mut out = [0; 3];
        let mut short = None;
        for (i, &(ptr, size)) in mapped.iter().take(3).enumerate() {
            out[i] = ptr;
            if size < n * BYTES[i] {
                short = Some(format!(
                    "vertex buffer {i} has {size} bytes, {} needed",
                    n * BYTES[i]
                ));
            }
        }
        if let (Some(sp), Some(&(_, size))) = (splat, mapped.get(3)) {
            if size < sp.bytes() {
                short = Some(format!(
                    "the splat buffer has {size} bytes, {} needed",
                    sp.bytes()
                ));
            }
        }
        let reduce = !fixed_range && shown != Shown::Kind;
        let r = match short {
            Some(m) => Err(m),
            None => launch::view_fill(
                k,
                s,
                p,
                b,
                shown.code(),
                u32::from(hidden),
                out,
                reduce.then_some(&mut self.range),
                &mut self.order,
            )
            .map_err(|e| format!("the fill kernel: {e:?}")),
        };
        let r = match (r, splat, mapped.get(3), self.key.as_mut()) {
            (Ok(()), Some(sp), Some(&(ptr, _)), Some(key)) => {
                launch::view_splat(k, s, sp, out, ptr, &mut self.cam, key)
                    .map_err(|e| format!("the splat kernels: {e:?}"))
            }
            (r, ..) => r,
        };
        let unmapped = launch::gl_unmap(s, &mut res).map_err(|e| format!("unmapping: {e:?}"));
        r?;
        unmapped?;
        let splat = splat.is_some();
        if !reduce {
            return Ok((
                GlFill {
                    count: n,
                    kinds: b.kinds,
                    range: None,
                    splat,
                },
                0,
            ));
        }
        let w = s
            .clone_dtoh(&self.range)
            .map_err(|e| format!("reading the colour range: {e:?}"))?;
        let range = (w[1] != 0).then(|| (from_ordered(!w[0]), from_ordered(w[1])));
        Ok((
            GlFill {
                count: n,
                kinds: b.kinds,
                range,
                splat,
            },
            8,
        ))
    }
}

impl Drop for GlView {
    fn drop(&mut self) {
        let splat = self.splat.map(|(_, _, r)| r);
        for &r in self.res.iter().chain(splat.iter()) {
            // Nothing to do about a failure here (e.g. the GL context went first).
            let _ = launch::gl_unregister(&self.ctx, r);
        }
    }
}

impl<D: Dim> GlInterop for CudaSolver<D> {
    /// Registers `gl`'s buffers with CUDA at the first call (and again where they change),
    /// then maps, fills and unmaps them (`view.rs`, `cuda/view.cu`); 8 bytes come back for
    /// the colour range, none with `fixed_range`.
    fn fill_gl(
        &mut self,
        gl: &GlBuffers,
        shown: Shown,
        hidden: u8,
        fixed_range: bool,
        splat: Option<&GlSplat>,
    ) -> Result<GlFill, String> {
        if !self.gl_view.as_ref().is_some_and(|v| v.serves(gl)) {
            self.gl_view = None;
            match GlView::register(&self.dev.stream, *gl) {
                Ok(v) => self.gl_view = Some(v),
                Err(e) => {
                    return Err(format!(
                        "registering the viewer's OpenGL buffers with CUDA: {e:?}"
                    ))
                }
            }
        }
        let v = self.gl_view.as_mut().expect("registered above");
        let s = &self.dev.stream;
        match v.fill(
            &self.k,
            s,
            &self.params,
            &self.buf,
            shown,
            hidden,
            fixed_range,
            splat,
        ) {
            Ok((fill, read)) => {
                self.d2h += read;
                Ok(fill)
            }
            Err(e) => Err(format!("filling the vertex buffers: {e}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `cuda/view.cu`'s ordered_bits, on the host.
    fn ordered(v: f32) -> u32 {
        let b = v.to_bits();
        if b >> 31 == 1 {
            !b
        } else {
            b | 0x8000_0000
        }
    }

    #[test]
    fn ordered_bits_keep_the_order_and_come_back() {
        let vs = [
            f32::NEG_INFINITY,
            -3.5e30,
            -1.0,
            -1e-40,
            -0.0,
            0.0,
            1e-40,
            2.0,
            7.25e20,
            f32::INFINITY,
        ];
        for w in vs.windows(2) {
            assert!(ordered(w[0]) <= ordered(w[1]), "{} {}", w[0], w[1]);
        }
        for v in vs {
            assert!(ordered(v) > 0);
            assert_eq!(from_ordered(ordered(v)).to_bits(), v.to_bits());
        }
    }
}
