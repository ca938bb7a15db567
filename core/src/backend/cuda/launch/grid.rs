//! The neighbour grid's build (`cuda/grid.cu`): the cell counts' scan, the scatter and the
//! reorder, with the stamps of the cells near moving particles.

use std::sync::Arc;

use cudarc::driver::{CudaSlice, CudaStream, CudaViewMut, LaunchConfig, PushKernelArg};

use super::{cfg, NULL};
use crate::backend::cuda::buffers::{self, Buffers};
use crate::backend::cuda::handover::{By, Mark};
use crate::backend::cuda::kernels::{Family, Kernels};
use crate::consts::{MF_SCAN_BLOCK, MF_SCAN_CELLS};
use crate::physics::params::{SphParams, MF_DENSITY_CONTINUITY};

/// The two-pass exclusive scan of `n_scan` words of `input` into `local` (per block) and
/// `bsum` (the blocks' totals, then their offsets): `Family::ScanLocal` over
/// ceil(n_scan / MF_SCAN_CELLS) blocks, then `Family::ScanTop` in one; where that is one
/// or two blocks, `Family::ScanLocal` or `Family::ScanOne` alone, in one block, writes the
/// offsets (0): a small grid's build is a kernel shorter. The caller's buffers hold n_scan
/// entries (`local`, 16-byte aligned as `input`) and that many blocks (`bsum`).
pub(super) fn scan(
    k: &Kernels,
    s: &Arc<CudaStream>,
    n_scan: u32,
    input: &CudaSlice<u32>,
    local: &mut CudaViewMut<u32>,
    bsum: &mut CudaSlice<u32>,
) {
    let nb = n_scan.div_ceil(MF_SCAN_CELLS);
    let (ks, blocks) = match nb {
        2 => (k.get(Family::ScanOne), 1),
        _ => (k.get(Family::ScanLocal), nb),
    };
    // SAFETY: the arguments of `Family::ScanLocal` (or `ScanOne`, the same), over n_scan
    // entries; grid of nb blocks (ScanOne: one, for nb = 2) of MF_SCAN_BLOCK; input and
    // local hold n_scan entries, bsum nb (the caller's word).
    ks.check(unsafe {
        s.launch_builder(&ks.f)
            .arg(&n_scan)
            .arg(input)
            .arg(local)
            .arg(&mut *bsum)
            .launch(LaunchConfig {
                grid_dim: (blocks, 1, 1),
                block_dim: (MF_SCAN_BLOCK, 1, 1),
                shared_mem_bytes: 0,
            })
            .map(|_| ())
    });
    if nb <= 2 {
        return;
    }
    let kt = k.get(Family::ScanTop);
    // SAFETY: the arguments of `Family::ScanTop` over nb block totals; one block of
    // MF_SCAN_BLOCK.
    kt.check(unsafe {
        s.launch_builder(&kt.f)
            .arg(&nb)
            .arg(bsum)
            .launch(LaunchConfig {
                grid_dim: (1, 1, 1),
                block_dim: (MF_SCAN_BLOCK, 1, 1),
                shared_mem_bytes: 0,
            })
            .map(|_| ())
    });
}

/// The last grid build's stamps of the cells near moving particles, where it wrote them
/// (`Mark::Stamped`), for the neighbour passes' skip of a wall's rows of walls at rest.
pub(super) fn stamps(stamp: &Option<CudaSlice<u8>>, stamped: bool) -> Option<&CudaSlice<u8>> {
    stamp.as_ref().filter(|_| stamped)
}

/// Neighbour grid: hist (unless the last drift did it), scan (1 or 2 kernels), scatter, then the
/// sort by id within cells fused with the reorder (gather), which also writes the cell
/// ranges; then the two persistent buffer sets are swapped.
pub fn build_grid(k: &Kernels, s: &Arc<CudaStream>, p: &SphParams, b: &mut Buffers) {
    // The reorder writes alt and the cells change: the forces pass's record goes.
    b.handover.moved();
    let n = b.n as u32;
    let nc = b.n_cells as u32;
    // The scan runs over n_cells + 1 counts (the last, 0, closes the last cell's range).
    let n_scan = nc + 1;
    if n == 0 {
        return;
    }
    // Cells and counts: already filed by the last drift from the positions it wrote, else
    // here.
    if !b.handover.take(Mark::CellsFiled, By::GridBuild) {
        let kh = k.get(Family::GridHist);
        // SAFETY: the arguments of `Family::GridHist` (kernels.rs); pos holds n vectors,
        // cell n, count n_cells + 1 (zero: counted down by the last scatter, cleared by
        // write_state or at allocation).
        kh.check(unsafe {
            s.launch_builder(&kh.f)
                .arg(p)
                .arg(&n)
                .arg(&b.cur.pos)
                .arg(&mut b.cell)
                .arg(&mut b.count)
                .launch(cfg(b.n))
                .map(|_| ())
        });
    }
    // order and local live in the spare acc and xsph (`buffers::grid_scratch`).
    let (mut order, mut local) =
        buffers::grid_scratch(&mut b.acc, &mut b.xsph, &mut b.local, b.cap, b.n_cells);
    // count holds n_cells + 1 entries, local n_cells + 1 and bsum n_blocks >= nb (16-byte
    // aligned allocations).
    scan(k, s, n_scan, &b.count, &mut local, &mut b.bsum);
    // The cells near moving particles are stamped (and a wall's rows of walls at rest
    // skipped) in 3D at one lane (`Mark::Stamped`).
    let stamped = b.stamp.is_some() && k.lanes == 1;
    b.handover.leave(Mark::Stamped, stamped, By::GridBuild);
    let mut stamp = b.stamp.as_mut().filter(|_| stamped);
    let mut epoch = stamp.as_mut().map(|st| st.slice_mut(b.n_cells..));
    let kc = k.get(Family::GridScatter);
    // SAFETY: the arguments of `Family::GridScatter`; cell and order hold n entries, red 3
    // (zeroed: the step size's maxima, which no pass holds during a grid build); epoch null
    // or the last byte of `stamp` (advanced).
    kc.check(unsafe {
        let mut l = s.launch_builder(&kc.f);
        l.arg(&n)
            .arg(&b.cell)
            .arg(&mut local)
            .arg(&b.bsum)
            .arg(&mut b.count)
            .arg(&mut order)
            .arg(&mut b.red);
        opt!(l, epoch.as_mut());
        l.launch(cfg(b.n)).map(|_| ())
    });
    b.handover.take(Mark::RedStale, By::GridBuild);
    // Continuity density without artificial stress: the reorder applies the equation of
    // state and the density pass has nothing left to do (`density` skips it).
    let eos = p.density_form as u32 == MF_DENSITY_CONTINUITY && b.art.is_none();
    let eos_arg = eos as u32;
    {
        let (c, a) = (&b.cur, &mut b.alt);
        let kg = k.get(Family::GridGather);
        let mut l = s.launch_builder(&kg.f);
        l.arg(p)
            .arg(&n)
            .arg(&nc)
            .arg(&eos_arg)
            .arg(&mut order)
            .arg(&mut local)
            .arg(&b.bsum)
            .arg(&mut b.cell_start);
        opt!(l, stamp);
        l.arg(&c.id)
            .arg(&c.kind)
            .arg(&c.group)
            .arg(&c.pos)
            .arg(&c.vel);
        l.arg(&c.rho).arg(&c.p);
        opt!(l, &c.stress);
        opt!(l, &c.rho_dev);
        l.arg(&mut a.id)
            .arg(&mut a.kind)
            .arg(&mut a.group)
            .arg(&mut a.pos)
            .arg(&mut a.vel);
        l.arg(&mut a.rho).arg(&mut a.p);
        opt!(l, &mut a.stress);
        opt!(l, &mut a.rho_dev);
        let threads = b.n.max(b.n_cells + 1);
        // SAFETY: the arguments of `Family::GridGather` (the nine persistent arrays of
        // `cur`, then the same nine of `alt`); cell_start has n_cells + 1 entries, stamp
        // null or n_cells + 1 (its last: the epoch the scatter advanced); stress
        // and rho_dev null in both sets or in neither (both with solids); grid of
        // max(n, n_cells + 1) threads.
        kg.check(unsafe { l.launch(cfg(threads)).map(|_| ()) });
    }
    b.handover.leave(Mark::EosApplied, eos, By::GridBuild);
    std::mem::swap(&mut b.cur, &mut b.alt);
    b.swapped = !b.swapped;
}
