//! A subdomain's particle exchange (`cuda/exchange.cu`): selection, packing, unpacking and
//! compaction.

use std::sync::Arc;

use cudarc::driver::{CudaSlice, CudaStream, DriverError, PushKernelArg};

use super::{cfg, grid::scan, NULL};
use crate::backend::cuda::buffers::Buffers;
use crate::backend::cuda::kernels::{Family, Kernels};
use crate::physics::params::SphParams;

/// Which particles a subdomain's selection marks (`sph_exchange_mark`).
#[derive(Clone, Copy, Debug)]
pub enum Select {
    /// Those the solver owns (`SphParams::owns`): what `retain_owned` keeps.
    Owned,
    /// Those within `width` [L] of the slab [lo, hi) of `axis` (`Slab::gap`; round
    /// `periodic` = (min, max) where the axis is periodic): a halo.
    Near {
        axis: usize,
        lo: f32,
        hi: f32,
        width: f32,
        periodic: Option<(f32, f32)>,
    },
}

/// Mark the particles `sel` picks, scan the marks (their compacted slots: `Scratch::local`
/// and `bsum`) and read back their count (one word).
pub fn select(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    sel: Select,
) -> Result<usize, DriverError> {
    let n = b.n;
    if n == 0 {
        return Ok(0);
    }
    let (halo, axis, lo, hi, width, (periodic, pmin, pmax)) = match sel {
        Select::Owned => (
            0u32,
            p.own_axis as u32,
            0.0f32,
            0.0f32,
            0.0f32,
            (0u32, 0.0, 0.0),
        ),
        Select::Near {
            axis,
            lo,
            hi,
            width,
            periodic,
        } => (
            1,
            axis as u32,
            lo,
            hi,
            width,
            periodic.map_or((0, 0.0, 0.0), |(a, b)| (1, a, b)),
        ),
    };
    b.scratch(s)?;
    let (pos, x) = (&b.cur.pos, b.scratch.as_mut().expect("allocated above"));
    let n32 = n as u32;
    let km = k.get(Family::ExchangeMark);
    // SAFETY: the arguments of `Family::ExchangeMark` (kernels.rs); pos holds n vectors,
    // mark n + 1 words (`Scratch` has cap + 1 >= n + 1); grid of n + 1 threads.
    km.check(unsafe {
        s.launch_builder(&km.f)
            .arg(p)
            .arg(&n32)
            .arg(&halo)
            .arg(&axis)
            .arg(&lo)
            .arg(&hi)
            .arg(&width)
            .arg(&periodic)
            .arg(&pmin)
            .arg(&pmax)
            .arg(pos)
            .arg(&mut x.mark)
            .launch(cfg(n + 1))
            .map(|_| ())
    });
    counted(k, s, b)
}

/// The count of the n + 1 marks in `b`'s scratch that a mark kernel just wrote (the last,
/// 0, the sentinel): the grid build's scan over them (their compacted slots in
/// `Scratch::local` and `bsum`, which `pack` and `compact` read) and their total, read back
/// (one word). `select`'s, and the open boundaries' (`launch/open.rs`).
pub fn counted(k: &Kernels, s: &Arc<CudaStream>, b: &mut Buffers) -> Result<usize, DriverError> {
    let n32 = b.n as u32;
    let x = b.scratch.as_mut().expect("marked first");
    // mark and local hold cap + 1 >= n + 1 (16-byte aligned allocations), bsum
    // ceil((cap + 1) / MF_SCAN_CELLS) >= its blocks.
    scan(
        k,
        s,
        n32 + 1,
        &x.mark,
        &mut x.local.slice_mut(..),
        &mut x.bsum,
    );
    let kc = k.get(Family::ExchangeTotal);
    // SAFETY: the arguments of `Family::ExchangeTotal`; local holds n + 1 entries, bsum
    // n / MF_SCAN_CELLS + 1, total 1; one thread.
    kc.check(unsafe {
        s.launch_builder(&kc.f)
            .arg(&n32)
            .arg(&x.local)
            .arg(&x.bsum)
            .arg(&mut x.total)
            .launch(cfg(1))
            .map(|_| ())
    });
    Ok(s.clone_dtoh(&x.total)?[0] as usize)
}

/// The particles the last `select` marked, packed as records of `words` words
/// (`cuda/exchange.cu`) into `out` (count x words).
pub fn pack(k: &Kernels, s: &Arc<CudaStream>, b: &Buffers, words: usize, out: &mut CudaSlice<u32>) {
    let x = b.scratch.as_ref().expect("pack follows a select");
    let (n, w) = (b.n as u32, words as u32);
    let c = &b.cur;
    let kp = k.get(Family::ExchangePack);
    let mut l = s.launch_builder(&kp.f);
    l.arg(&n)
        .arg(&w)
        .arg(&x.mark)
        .arg(&x.local)
        .arg(&x.bsum)
        .arg(&c.id)
        .arg(&c.kind)
        .arg(&c.group)
        .arg(&c.pos)
        .arg(&c.vel)
        .arg(&c.rho)
        .arg(&c.p);
    opt!(l, &c.stress);
    opt!(l, &c.rho_dev);
    l.arg(out);
    // SAFETY: the arguments of `Family::ExchangePack`; mark, local and bsum of the `select`
    // of these n particles (nothing moved them since); the persistent arrays hold n
    // particles (stress planes n apart; stress and rho_dev null without solids, and then
    // `words` leaves their words out); out holds (marked count) x words.
    kp.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
}

/// Append the records of `halos` ((count, words) each, `words` words per record) after the
/// `b.n` particles held, which `b.cap` must have room for with them; the stress (`planes`
/// symmetric components) re-laid for the new count. Sets `b.n`.
pub fn unpack(
    k: &Kernels,
    s: &Arc<CudaStream>,
    b: &mut Buffers,
    (words, planes): (usize, usize),
    halos: &[(usize, &CudaSlice<u32>)],
) {
    b.handover.moved();
    let n0 = b.n;
    let n1 = n0 + halos.iter().map(|h| h.0).sum::<usize>();
    assert!(n1 <= b.cap, "unpack: {n1} particles, room for {}", b.cap);
    if n1 == n0 {
        return;
    }
    let planes = planes as u32;
    if let (Some(src), Some(dst)) = (&b.cur.stress, &mut b.alt.stress) {
        let (a, z) = (n0 as u32, n1 as u32);
        let kr = k.get(Family::ExchangeRestride);
        // SAFETY: the arguments of `Family::ExchangeRestride`; src holds planes x n0 floats
        // and dst planes x n1 (both planes x cap); grid of n0 threads.
        kr.check(unsafe {
            s.launch_builder(&kr.f)
                .arg(&a)
                .arg(&z)
                .arg(&planes)
                .arg(src)
                .arg(dst)
                .launch(cfg(n0))
                .map(|_| ())
        });
    }
    let (ku, w, stride) = (k.get(Family::ExchangeUnpack), words as u32, n1 as u32);
    let mut base = n0 as u32;
    for &(m, words_in) in halos {
        if m == 0 {
            continue;
        }
        let m32 = m as u32;
        let c = &mut b.cur;
        let mut l = s.launch_builder(&ku.f);
        l.arg(&m32)
            .arg(&base)
            .arg(&stride)
            .arg(&w)
            .arg(words_in)
            .arg(&mut c.id)
            .arg(&mut c.kind)
            .arg(&mut c.group)
            .arg(&mut c.pos)
            .arg(&mut c.vel)
            .arg(&mut c.rho)
            .arg(&mut c.p);
        opt!(l, &mut b.alt.stress);
        opt!(l, &mut c.rho_dev);
        // SAFETY: the arguments of `Family::ExchangeUnpack`; `in` holds m records of
        // `words` words; slots base .. base + m <= n1 <= cap of every persistent array;
        // the stress (when held) is the other set's, re-laid above with planes n1 apart,
        // and rho_dev null exactly where stress is.
        ku.check(unsafe { l.launch(cfg(m)).map(|_| ()) });
        base += m32;
    }
    std::mem::swap(&mut b.cur.stress, &mut b.alt.stress);
    b.n = n1;
}

/// Keep the `kept` particles the last `select` marked, in storage order: moved into the
/// other persistent set, which becomes the current one. Sets `b.n`.
pub fn compact(k: &Kernels, s: &Arc<CudaStream>, b: &mut Buffers, kept: usize) {
    b.handover.moved();
    let x = b.scratch.as_ref().expect("compact follows a select");
    let (n, kept32) = (b.n as u32, kept as u32);
    let (c, a) = (&b.cur, &mut b.alt);
    let kc = k.get(Family::ExchangeCompact);
    let mut l = s.launch_builder(&kc.f);
    l.arg(&n)
        .arg(&kept32)
        .arg(&x.mark)
        .arg(&x.local)
        .arg(&x.bsum)
        .arg(&c.id)
        .arg(&c.kind)
        .arg(&c.group)
        .arg(&c.pos)
        .arg(&c.vel)
        .arg(&c.rho)
        .arg(&c.p);
    opt!(l, &c.stress);
    opt!(l, &c.rho_dev);
    l.arg(&mut a.id)
        .arg(&mut a.kind)
        .arg(&mut a.group)
        .arg(&mut a.pos)
        .arg(&mut a.vel)
        .arg(&mut a.rho)
        .arg(&mut a.p);
    opt!(l, &mut a.stress);
    opt!(l, &mut a.rho_dev);
    // SAFETY: the arguments of `Family::ExchangeCompact` (the nine persistent arrays of
    // `cur`, n particles with stress planes n apart, then the same nine of `alt`, which
    // receives `kept` <= n with planes kept apart); mark, local and bsum of the `select` of
    // these n particles; stress and rho_dev null in both sets or in neither.
    kc.check(unsafe { l.launch(cfg(b.n)).map(|_| ()) });
    std::mem::swap(&mut b.cur, &mut b.alt);
    b.swapped = !b.swapped;
    b.n = kept;
}
