//! The open-boundary stage and the buffers' densities on the device (`cuda/open.cu`), with
//! the exchange's moves (`launch/exchange.rs`: packing the particles an inlet copies,
//! compacting the storage, unpacking the copies at its end). Twin:
//! `src/backend/cpu/open.rs`.

use std::sync::Arc;

use cudarc::driver::{CudaSlice, CudaStream, DriverError, PushKernelArg};

use super::cfg;
use super::exchange::{compact, counted, pack, unpack};
use crate::backend::cuda::buffers::Buffers;
use crate::backend::cuda::kernels::{Family, Kernels};
use crate::physics::dim::Dim;
use crate::physics::params::SphParams;

/// What one open-boundary stage did: copies made, particles removed.
pub struct Opened {
    pub born: usize,
    pub removed: usize,
}

/// The open-boundary stage (`sph_open_mark`, `sph_open_apply`, `sph_open_born`): the inlet
/// particles that join the fluid are copied (`pack`) while they still hold the inlet's group,
/// every fate is applied in place and the tally (`tally`: 4 doubles per boundary) added
/// to, the removed particles dropped (`compact`), and the copies appended (`unpack`) with ids
/// from `next_id` and moved `depth` behind. `words`: the exchange record's length
/// (`halo_words`), `planes` the stress's components. Three words come back.
#[allow(clippy::too_many_arguments)]
pub fn open_boundaries<D: Dim>(
    k: &Kernels,
    s: &Arc<CudaStream>,
    p: &SphParams,
    b: &mut Buffers,
    tally: &mut CudaSlice<f64>,
    next_id: u32,
    (words, planes): (usize, usize),
) -> Result<Opened, DriverError> {
    let n = b.n;
    if n == 0 {
        return Ok(Opened {
            born: 0,
            removed: 0,
        });
    }
    let n32 = n as u32;
    b.scratch(s)?;
    {
        let x = b.scratch.as_mut().expect("allocated above");
        let c = &b.cur;
        let km = k.get(Family::OpenMark);
        // SAFETY: the arguments of `Family::OpenMark`; kind, group and pos hold n particles,
        // mark n + 1 words (cap + 1); grid of n + 1 threads.
        km.check(unsafe {
            s.launch_builder(&km.f)
                .arg(p)
                .arg(&n32)
                .arg(&c.kind)
                .arg(&c.group)
                .arg(&c.pos)
                .arg(&mut x.mark)
                .launch(cfg(n + 1))
                .map(|_| ())
        });
    }
    let born = counted(k, s, b)?;
    let mut copies = s.alloc_zeros::<u32>((born * words).max(1))?;
    if born > 0 {
        pack(k, s, b, words, &mut copies);
    }
    {
        let x = b.scratch.as_mut().expect("allocated above");
        let c = &mut b.cur;
        let ka = k.get(Family::OpenApply);
        // SAFETY: the arguments of `Family::OpenApply`; kind, group, pos and vel hold n
        // particles, mark n + 1 words, tally 4 x open_count doubles; grid of n + 1 threads.
        ka.check(unsafe {
            s.launch_builder(&ka.f)
                .arg(p)
                .arg(&n32)
                .arg(&c.kind)
                .arg(&mut c.group)
                .arg(&c.pos)
                .arg(&c.vel)
                .arg(&mut x.mark)
                .arg(tally)
                .launch(cfg(n + 1))
                .map(|_| ())
        });
    }
    let kept = counted(k, s, b)?;
    if kept < n {
        compact(k, s, b, kept);
    }
    if born > 0 {
        b.reserve::<D>(s, kept + born)?;
        unpack(k, s, b, (words, planes), &[(born, &copies)]);
        let (base, m) = (kept as u32, born as u32);
        let c = &mut b.cur;
        let kb = k.get(Family::OpenBorn);
        // SAFETY: the arguments of `Family::OpenBorn`; slots base .. base + m < b.n hold the
        // copies just unpacked; grid of m threads.
        kb.check(unsafe {
            s.launch_builder(&kb.f)
                .arg(p)
                .arg(&base)
                .arg(&m)
                .arg(&next_id)
                .arg(&mut c.id)
                .arg(&c.group)
                .arg(&mut c.pos)
                .launch(cfg(born))
                .map(|_| ())
        });
    }
    // The copies are read on this stream before they are freed.
    s.synchronize()?;
    Ok(Opened {
        born,
        removed: n - kept,
    })
}

/// The buffers' densities, pressures and w slots (`sph_buffer_density`), after the density
/// pass. Nothing without open boundaries.
pub fn buffer_density(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    if p.open_count == 0 || b.n == 0 {
        return;
    }
    let n = b.n as u32;
    let c = &mut b.cur;
    let kb = k.get(Family::BufferDensity);
    // SAFETY: the arguments of `Family::BufferDensity`; the grid of the last build over these
    // n particles (cell_start), every array n particles; grid of n threads.
    kb.check(unsafe {
        s.launch_builder(&kb.f)
            .arg(p)
            .arg(&n)
            .arg(&b.cell_start)
            .arg(&c.pos)
            .arg(&mut c.vel)
            .arg(&c.kind)
            .arg(&c.group)
            .arg(&mut c.rho)
            .arg(&mut c.p)
            .launch(cfg(b.n))
            .map(|_| ())
    });
}
