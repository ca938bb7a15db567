//! Device arrays and the conversion between `State<D>` (host, glam vectors, full tensors)

//! and the kernels' layout: vectors as float2 (2D) / float4 (3D; position w = mass, others
//! w = 0), except velocities, float4 in both (w = density negated on walls; 2D z = mass;
//! `vel_load` in `cuda/device/packing.cuh`; the mass has no array of its own), symmetric tensors as
//! 3 (2D: xx, yy, xy) or 6 (3D: xx, yy, zz, xy, xz, yz) planes.

use std::sync::Arc;

use cudarc::driver::{
    CudaSlice, CudaStream, CudaViewMut, DeviceRepr, DriverError, ValidAsZeroBits,
};
use rayon::prelude::*;

use super::handover::{By, Handover, Mark};
use crate::consts::{MF_BLOCK, MF_FAULT_RECORD_WORDS, MF_SCAN_CELLS};
use crate::physics::dim::Dim;
use crate::physics::params::MF_KIND_BOUNDARY;
use crate::physics::state::{SolidState, State};

/// Floats per stored vector.
pub fn vstride<D: Dim>() -> usize {
    if D::D == 2 {
        2
    } else {
        4
    }
}
/// Floats per stored velocity (float4 in both dimensions: `vel_load` in `cuda/device/packing.cuh`).
pub const VEL_STRIDE: usize = 4;
/// Stored components of a symmetric tensor.
pub fn nsym<D: Dim>() -> usize {
    if D::D == 2 {
        3
    } else {
        6
    }
}
/// Which of the six (xx, yy, zz, xy, xz, yz) components are stored, in order.
pub(super) fn sym_slots<D: Dim>() -> &'static [usize] {
    if D::D == 2 {
        &[0, 1, 3]
    } else {
        &[0, 1, 2, 3, 4, 5]
    }
}

/// The per-particle arrays that the grid reorders (two sets, swapped every sort).
pub struct Persistent {
    pub id: CudaSlice<u32>,
    pub kind: CudaSlice<u8>,
    pub group: CudaSlice<u32>,
    pub pos: CudaSlice<f32>,
    pub vel: CudaSlice<f32>,
    pub rho: CudaSlice<f32>,
    pub p: CudaSlice<f32>,
    pub stress: Option<CudaSlice<f32>>,
    /// The solids' density departure rho - rho0_s (`SolidState::rho_dev`); only with solids.
    pub rho_dev: Option<CudaSlice<f32>>,
}

/// Every device array of one solver.
pub struct Buffers {
    /// Particles held now (slots 0 .. n of every per-particle array).
    pub n: usize,
    /// Particles the per-particle arrays have room for (>= n). A one-domain solver holds
    /// n = cap from its upload on; a subdomain's count changes every step (`append`,
    /// `compact` in `subdomain.rs`) and `reserve` grows the room geometrically, never below
    /// the need, and never shrinks it. Tensor planes (stress, stress_rate, art) lie `n`
    /// floats apart (the kernels' stride is the count they are launched with), within
    /// `nsym * cap` floats.
    pub cap: usize,
    pub n_cells: usize,
    pub cur: Persistent,
    pub alt: Persistent,
    pub acc: CudaSlice<f32>,
    pub xsph: CudaSlice<f32>,
    pub drho: Option<CudaSlice<f32>>,
    pub stress_rate: Option<CudaSlice<f32>>,
    pub art: Option<CudaSlice<f32>>,
    /// Renormalised density gradients (`sph_grad_rho`), D floats per particle; only with the
    /// density diffusion in Antuono et al.'s form (`needs_density_gradient`).
    pub grad_rho: Option<CudaSlice<f32>>,
    /// The interface stage's (P', rho') per particle (`sph_solid_interface`), 2 floats
    /// each; with solids (read only where `pairs::extrapolated`).
    pub iface: Option<CudaSlice<f32>>,
    /// `Setup::wall_surface` as float4 per boundary particle (by id - wall_first_id; not
    /// reordered by the grid); only where `params::needs_wall_surface` (Morris's no-slip
    /// walls, mDBC).
    pub wall_surface: Option<CudaSlice<f32>>,
    /// `Setup::motion_series`: the driven objects' knots (one unused double where none),
    /// which the kick, the drifts and the mDBC walls read.
    pub motion_series: CudaSlice<f64>,
    // grid
    pub cell: CudaSlice<u32>,
    /// Per cell, n_cells + 1 (the last stays 0: the scan's sentinel).
    pub count: CudaSlice<u32>,
    /// The scan's block-relative cell starts (n_cells + 1 words), where they do not fit in
    /// the spare `xsph` (`grid_scratch`); `None` where they do.
    pub local: Option<CudaSlice<u32>>,
    /// The scan's block offsets.
    pub bsum: CudaSlice<u32>,
    pub cell_start: CudaSlice<u32>,
    /// Per cell, the epoch of the last grid build that found a moving particle within reach
    /// along x (not a wall at rest, or driven; a moving wall within reach on every axis),
    /// then that epoch (n_cells + 1 bytes, `stamp_moving` in `cuda/device/grid.cuh`): the
    /// neighbour passes skip a wall's candidate rows of walls at rest. Only in 3D
    /// (`Buffers::new`).
    pub stamp: Option<CudaSlice<u8>>,
    // scalars
    /// The forces pass's maxima (max |v|, max |a|, max c as float bits), zero before the
    /// pass: cleared by `sph_step_size`, or, after a kick or drift-kick that took the step
    /// size from them (`Mark::StepSizeDue`), by the next grid build's scatter (`Mark::RedStale`
    /// until).
    pub red: CudaSlice<u32>,
    /// [T] this step's dt, and the last completed step's (written by the drift; 0 before the
    /// first step): the leapfrog's kick spans their mean (`kick_span` in cuda/integrate.cu).
    pub dt: CudaSlice<f32>,
    /// The clock [T] and, as the bits of the second double, the key of the first fault that
    /// a queued health check found (0: none; `sph_check_record`): read back together; the
    /// third, the step's start [T], copied there by the kick for the drifts after it (a
    /// driven object's motion over the step) while sph_drift advances the first.
    pub time: CudaSlice<f64>,
    /// That fault's particle record (`MF_FAULT_RECORD_WORDS` words, `sph_check_record`).
    pub fault_rec: CudaSlice<u32>,
    /// The diagnostics' totals: (kinetic energy, momentum x, y), (momentum z, 0, 0).
    pub diag_sums: CudaSlice<f64>,
    /// Their per-block partial sums (`sph_diagnostics`, summed by `sph_sum_partials`): two
    /// slots of 3 doubles per block of MF_BLOCK particles.
    pub diag_partial: CudaSlice<f64>,
    pub diag_max: CudaSlice<u32>,
    pub diag_counts: CudaSlice<u32>,
    /// The health check's first fault (`sph_check`; 0 between checks).
    pub first: CudaSlice<u64>,
    pub layout: CudaSlice<u32>,
    /// The force monitors' block partial sums (3 doubles per block and wall group) and
    /// totals (3 per group), `cuda/monitor.cu`: allocated by the first sample
    /// (`launch::wall_forces`).
    pub wall_partial: Option<CudaSlice<f64>>,
    pub wall_force: Option<CudaSlice<f64>>,
    /// The marks and their scan of a subdomain's halo selection and compaction
    /// (`cuda/exchange.cu`); allocated by the first (`scratch`).
    pub scratch: Option<Scratch>,
    /// The particles of each kind class as last written from the host (`write_state`): fluid,
    /// solid, every other kind (the viewer's kind order, `cuda/view.cu`). Kinds never change
    /// in a step; a subdomain's exchange changes `n` without it (then the sum differs from n).
    pub kinds: [usize; 3],
    /// Bytes allocated on the device for all of the above.
    pub bytes: usize,
    /// Of which the per-particle arrays (sized by `cap`).
    particle_bytes: usize,
    /// Flips at each swap of `cur` and `alt` (a captured graph is bound to one assignment).
    pub swapped: bool,
    /// What one launch left for a later one of the step (`handover.rs`).
    pub handover: Handover,
}

/// A subdomain's selection of particles (`cuda/exchange.cu`): a mark per slot and the
/// scan of the marks (the grid build's scan kernels over cap + 1 entries), and the count
/// of marked slots.
pub struct Scratch {
    pub mark: CudaSlice<u32>,
    pub local: CudaSlice<u32>,
    pub bsum: CudaSlice<u32>,
    pub total: CudaSlice<u32>,
    /// Slots it has room for.
    pub cap: usize,
}

/// The per-particle arrays other than the persistent sets, for `cap` particles.
struct Working {
    acc: CudaSlice<f32>,
    xsph: CudaSlice<f32>,
    drho: Option<CudaSlice<f32>>,
    stress_rate: Option<CudaSlice<f32>>,
    art: Option<CudaSlice<f32>>,
    grad_rho: Option<CudaSlice<f32>>,
    iface: Option<CudaSlice<f32>>,
    cell: CudaSlice<u32>,
    diag_partial: CudaSlice<f64>,
}

/// Which optional per-particle arrays a solver holds.
#[derive(Clone, Copy)]
struct Held {
    solids: bool,
    drho: bool,
    art: bool,
    grad_rho: bool,
}

impl Persistent {
    fn alloc<D: Dim>(a: &mut Alloc, cap: usize, solids: bool) -> Result<Persistent, DriverError> {
        Ok(Persistent {
            id: a.z(cap)?,
            kind: a.z(cap)?,
            group: a.z(cap)?,
            pos: a.z(cap * vstride::<D>())?,
            vel: a.z(cap * VEL_STRIDE)?,
            rho: a.z(cap)?,
            p: a.z(cap)?,
            stress: if solids {
                Some(a.z(cap * nsym::<D>())?)
            } else {
                None
            },
            rho_dev: if solids { Some(a.z(cap)?) } else { None },
        })
    }

    /// The first `n` particles of `src` (stress planes `n` apart) into these arrays.
    fn copy_from<D: Dim>(
        &mut self,
        s: &Arc<CudaStream>,
        src: &Persistent,
        n: usize,
    ) -> Result<(), DriverError> {
        if n == 0 {
            return Ok(());
        }
        let (vs, ns) = (vstride::<D>(), nsym::<D>());
        s.memcpy_dtod(&src.id.slice(..n), &mut self.id)?;
        s.memcpy_dtod(&src.kind.slice(..n), &mut self.kind)?;
        s.memcpy_dtod(&src.group.slice(..n), &mut self.group)?;
        s.memcpy_dtod(&src.pos.slice(..n * vs), &mut self.pos)?;
        s.memcpy_dtod(&src.vel.slice(..n * VEL_STRIDE), &mut self.vel)?;
        s.memcpy_dtod(&src.rho.slice(..n), &mut self.rho)?;
        s.memcpy_dtod(&src.p.slice(..n), &mut self.p)?;
        if let (Some(a), Some(b)) = (&src.stress, &mut self.stress) {
            s.memcpy_dtod(&a.slice(..n * ns), b)?;
        }
        if let (Some(a), Some(b)) = (&src.rho_dev, &mut self.rho_dev) {
            s.memcpy_dtod(&a.slice(..n), b)?;
        }
        Ok(())
    }
}

impl Working {
    fn alloc<D: Dim>(a: &mut Alloc, cap: usize, h: Held) -> Result<Working, DriverError> {
        let (vs, ns) = (vstride::<D>(), nsym::<D>());
        let opt = |a: &mut Alloc, on: bool, len: usize| -> Result<_, DriverError> {
            if on {
                Ok(Some(a.z(len)?))
            } else {
                Ok(None)
            }
        };
        Ok(Working {
            acc: a.z(cap * vs)?,
            xsph: a.z(cap * vs)?,
            drho: opt(a, h.drho, cap)?,
            stress_rate: opt(a, h.solids, cap * ns)?,
            art: opt(a, h.art, cap * ns)?,
            grad_rho: opt(a, h.grad_rho, cap * D::D)?,
            iface: opt(a, h.solids, cap * 2)?,
            cell: a.z(cap)?,
            diag_partial: a.z(2 * 3 * (cap.max(1) as u32).div_ceil(MF_BLOCK) as usize)?,
        })
    }
}

/// Zeroed device arrays, counting their bytes.
pub(super) struct Alloc<'a> {
    pub(super) s: &'a Arc<CudaStream>,
    pub(super) bytes: usize,
}
impl Alloc<'_> {
    pub(super) fn z<T: DeviceRepr + ValidAsZeroBits>(
        &mut self,
        n: usize,
    ) -> Result<CudaSlice<T>, DriverError> {
        self.bytes += n.max(1) * std::mem::size_of::<T>();
        self.s.alloc_zeros::<T>(n.max(1))
    }
}

impl Buffers {
    /// Allocate for `state`, a grid of `n_cells`, the wall surface `surface`
    /// (`Setup::wall_surface`; none where empty) and the motions' knots `series`
    /// (`Setup::motion_series`), and the density gradients where `density_gradient`, then
    /// upload `state`, `surface` and `series`.
    pub fn new<D: Dim>(
        s: &Arc<CudaStream>,
        state: &State<D>,
        n_cells: usize,
        surface: &[[f32; 4]],
        series: &[f64],
        density_gradient: bool,
    ) -> Result<Buffers, DriverError> {
        let n = state.len();
        let held = Held {
            solids: state.solid.is_some(),
            drho: state.drho.is_some(),
            art: state
                .solid
                .as_ref()
                .is_some_and(|so| so.art_stress.is_some()),
            grad_rho: density_gradient,
        };
        let mut a = Alloc { s, bytes: 0 };
        let cur = Persistent::alloc::<D>(&mut a, n, held.solids)?;
        let alt = Persistent::alloc::<D>(&mut a, n, held.solids)?;
        let w = Working::alloc::<D>(&mut a, n, held)?;
        let particle_bytes = a.bytes;
        let n_blocks = (n_cells + 1).div_ceil(MF_SCAN_CELLS as usize);
        let mut b = Buffers {
            n,
            cap: n,
            n_cells,
            cur,
            alt,
            acc: w.acc,
            xsph: w.xsph,
            drho: w.drho,
            stress_rate: w.stress_rate,
            art: w.art,
            grad_rho: w.grad_rho,
            iface: w.iface,
            wall_surface: if surface.is_empty() {
                None
            } else {
                Some(a.z(surface.len() * 4)?)
            },
            motion_series: a.z(series.len())?,
            cell: w.cell,
            count: a.z(n_cells + 1)?,
            local: if local_fits::<D>(n, n_cells) {
                None
            } else {
                Some(a.z(n_cells + 1)?)
            },
            bsum: a.z(n_blocks)?,
            cell_start: a.z(n_cells + 1)?,
            stamp: if D::D == 3 {
                Some(a.z(n_cells + 1)?)
            } else {
                None
            },
            red: a.z(3)?,
            dt: a.z(2)?,
            time: a.z(3)?,
            fault_rec: a.z(MF_FAULT_RECORD_WORDS as usize)?,
            diag_sums: a.z(6)?,
            diag_partial: w.diag_partial,
            diag_max: a.z(2)?,
            diag_counts: a.z(3)?,
            first: a.z(1)?,
            layout: a.z(4)?,
            wall_partial: None,
            wall_force: None,
            scratch: None,
            kinds: [0; 3],
            bytes: 0,
            particle_bytes,
            swapped: false,
            handover: Handover::default(),
        };
        b.bytes = a.bytes;
        b.write_state(s, state)?;
        if let Some(d) = &mut b.wall_surface {
            s.memcpy_htod(surface.as_flattened(), d)?;
        }
        if !series.is_empty() {
            s.memcpy_htod(series, &mut b.motion_series)?;
        }
        Ok(b)
    }

    /// Room for `need` particles: where `cap` is short, every per-particle array
    /// reallocated for 9/8 of the larger of `need` and `cap` (geometric growth: a
    /// subdomain's count changes every step, by its halo and the particles crossing its
    /// ends, a few per cent of it; 3/2 took 255 B per particle in 3D where one domain takes
    /// 153, 9/8 leaves room for the halo's swings) and the `n` particles held copied over (the persistent arrays of `cur`;
    /// the others are rewritten before they are read each step). Whether it reallocated
    /// (a captured graph of the old arrays is then stale).
    pub fn reserve<D: Dim>(
        &mut self,
        s: &Arc<CudaStream>,
        need: usize,
    ) -> Result<bool, DriverError> {
        if need <= self.cap {
            return Ok(false);
        }
        let cap = need.max(self.cap) + need.max(self.cap) / 8;
        self.handover.moved();
        let held = Held {
            solids: self.cur.stress.is_some(),
            drho: self.drho.is_some(),
            art: self.art.is_some(),
            grad_rho: self.grad_rho.is_some(),
        };
        let mut a = Alloc { s, bytes: 0 };
        let mut cur = Persistent::alloc::<D>(&mut a, cap, held.solids)?;
        cur.copy_from::<D>(s, &self.cur, self.n)?;
        self.alt = Persistent::alloc::<D>(&mut a, cap, held.solids)?;
        self.cur = cur;
        let w = Working::alloc::<D>(&mut a, cap, held)?;
        self.acc = w.acc;
        self.xsph = w.xsph;
        self.drho = w.drho;
        self.stress_rate = w.stress_rate;
        self.art = w.art;
        self.grad_rho = w.grad_rho;
        self.iface = w.iface;
        self.cell = w.cell;
        self.diag_partial = w.diag_partial;
        // The scan's cell starts move into the new `xsph` where they fit now (they never
        // stop fitting: cap only grows).
        if self.local.is_some() && local_fits::<D>(cap, self.n_cells) {
            self.local = None;
            self.bytes -= 4 * (self.n_cells + 1);
        }
        self.bytes = self.bytes - self.particle_bytes + a.bytes;
        self.particle_bytes = a.bytes;
        self.cap = cap;
        // The cells the last drift filed went with the old `cell` array.
        if self.handover.take(Mark::CellsFiled, By::Storage) {
            s.memset_zeros(&mut self.count)?;
        }
        Ok(true)
    }

    /// The selection scratch (`Scratch`) with room for the `cap` slots.
    pub fn scratch(&mut self, s: &Arc<CudaStream>) -> Result<&mut Scratch, DriverError> {
        let cap = self.cap;
        if self.scratch.as_ref().is_none_or(|x| x.cap < cap) {
            let mut a = Alloc { s, bytes: 0 };
            let entries = cap + 1;
            self.scratch = Some(Scratch {
                mark: a.z(entries)?,
                local: a.z(entries)?,
                bsum: a.z(entries.div_ceil(MF_SCAN_CELLS as usize))?,
                total: a.z(1)?,
                cap,
            });
            self.bytes += a.bytes;
        }
        Ok(self.scratch.as_mut().expect("allocated above"))
    }

    /// Copy `state` (same length) into the current arrays; the grid is left as it is.
    pub fn write_state<D: Dim>(
        &mut self,
        s: &Arc<CudaStream>,
        st: &State<D>,
    ) -> Result<(), DriverError> {
        assert_eq!(
            st.len(),
            self.n,
            "write_state: length differs from the allocation"
        );
        self.kinds = [0; 3];
        for &k in &st.kind {
            self.kinds[usize::from(k.min(MF_KIND_BOUNDARY as u8))] += 1;
        }
        // What a drift, a grid build or a forces pass derived from the old state goes with it.
        self.handover.take(Mark::EosApplied, By::Storage);
        self.handover.moved();
        if self.handover.take(Mark::CellsFiled, By::Storage) {
            s.memset_zeros(&mut self.count)?;
        }
        let c = &mut self.cur;
        s.memcpy_htod(&st.id, &mut c.id)?;
        s.memcpy_htod(&st.kind, &mut c.kind)?;
        s.memcpy_htod(&st.group, &mut c.group)?;
        // Mass and density (negated on walls) in the spare slots (`vel_load` in
        // cuda/device/packing.cuh).
        let wall = |i: usize| st.kind[i] as u32 == MF_KIND_BOUNDARY;
        let pos = flat_v::<D>(&st.pos, |i| st.mass[i]);
        let vel = flat_vel::<D>(&st.vel, &st.mass, |i| {
            if wall(i) {
                -st.rho[i]
            } else {
                st.rho[i]
            }
        });
        s.memcpy_htod(&pos, &mut c.pos)?;
        s.memcpy_htod(&vel, &mut c.vel)?;
        s.memcpy_htod(&st.rho, &mut c.rho)?;
        s.memcpy_htod(&st.p, &mut c.p)?;
        s.memcpy_htod(&flat_v::<D>(&st.acc, |_| 0.0), &mut self.acc)?;
        s.memcpy_htod(&flat_v::<D>(&st.xsph, |_| 0.0), &mut self.xsph)?;
        if let (Some(h), Some(d)) = (&st.drho, &mut self.drho) {
            s.memcpy_htod(h, d)?;
        }
        if let Some(so) = &st.solid {
            if let Some(d) = &mut c.stress {
                s.memcpy_htod(&flat_s::<D>(&so.stress), d)?;
            }
            if let Some(d) = &mut c.rho_dev {
                s.memcpy_htod(&so.rho_dev, d)?;
            }
            if let Some(d) = &mut self.stress_rate {
                s.memcpy_htod(&flat_s::<D>(&so.stress_rate), d)?;
            }
            if let (Some(h), Some(d)) = (&so.art_stress, &mut self.art) {
                s.memcpy_htod(&flat_s::<D>(h), d)?;
            }
        }
        Ok(())
    }

    /// The whole state, in storage order; adds the bytes read back to `read`.
    pub fn read_state<D: Dim>(
        &self,
        s: &Arc<CudaStream>,
        read: &mut u64,
    ) -> Result<State<D>, DriverError> {
        let c = &self.cur;
        let n = self.n;
        let (vs, ns) = (vstride::<D>(), nsym::<D>());
        let solid = match &c.stress {
            Some(st) => Some(SolidState {
                stress: unflat_s::<D>(&counted(s, &st.slice(..n * ns), read)?, n),
                stress_rate: match &self.stress_rate {
                    Some(r) => unflat_s::<D>(&counted(s, &r.slice(..n * ns), read)?, n),
                    None => vec![D::zero(); n],
                },
                art_stress: match &self.art {
                    Some(r) => Some(unflat_s::<D>(&counted(s, &r.slice(..n * ns), read)?, n)),
                    None => None,
                },
                rho_dev: match &c.rho_dev {
                    Some(r) => counted(s, &r.slice(..n), read)?,
                    None => vec![0.0; n],
                },
            }),
            None => None,
        };
        let (pos, vel) = (
            counted(s, &c.pos.slice(..n * vs), read)?,
            counted(s, &c.vel.slice(..n * VEL_STRIDE), read)?,
        );
        let kind = counted(s, &c.kind.slice(..n), read)?;
        Ok(State {
            id: counted(s, &c.id.slice(..n), read)?,
            kind,
            group: counted(s, &c.group.slice(..n), read)?,
            mass: mass_of::<D>(&pos, &vel, n),
            pos: unflat_v::<D>(&pos, n),
            vel: unflat::<D>(&vel, n, VEL_STRIDE),
            rho: counted(s, &c.rho.slice(..n), read)?,
            p: counted(s, &c.p.slice(..n), read)?,
            acc: unflat_v::<D>(&counted(s, &self.acc.slice(..n * vs), read)?, n),
            xsph: unflat_v::<D>(&counted(s, &self.xsph.slice(..n * vs), read)?, n),
            drho: match &self.drho {
                Some(d) => Some(counted(s, &d.slice(..n), read)?),
                None => None,
            },
            solid,
        })
    }
}

/// The grid build's two scratch arrays of `b`'s `acc`, `xsph` and `local`, in memory no
/// stage needs during the build: the scatter's order (`cap` words) in `acc` (written by the
/// forces pass, last read by the kick or the drift-kick) and the scan's block-relative cell
/// starts (n_cells + 1 words, 16-byte aligned) in `xsph` (written by the rates pass, last
/// read by the drift), or in `local` where they do not fit there (`local_fits`): 4 + 4
/// n_cells / n B per particle fewer than arrays of their own. Takes the fields, so that
/// the caller keeps the others.
pub fn grid_scratch<'a>(
    acc: &'a mut CudaSlice<f32>,
    xsph: &'a mut CudaSlice<f32>,
    local: &'a mut Option<CudaSlice<u32>>,
    cap: usize,
    n_cells: usize,
) -> (CudaViewMut<'a, u32>, CudaViewMut<'a, u32>) {
    // SAFETY: `transmute_mut` asks only that the memory be valid as the new type (it checks
    // the length: None past the buffer): u32 and f32 have one size and alignment, and every
    // bit pattern is a valid u32; the grid kernels write these words before they read them
    // (the scatter: order), and the stages that own acc write it whole before reading it.
    let order =
        unsafe { acc.transmute_mut::<u32>(cap.max(1)) }.expect("acc holds 2 or 4 words a particle");
    let local = match local {
        Some(l) => l.slice_mut(..),
        // SAFETY: as for `order`: the scan writes its cell starts before reading them, and
        // the rates pass writes xsph whole before the drift reads it.
        None => unsafe { xsph.transmute_mut::<u32>(n_cells + 1) }
            .expect("local_fits: xsph holds the cell starts"),
    };
    (order, local)
}

/// Whether the scan's n_cells + 1 cell starts fit in the `xsph` of `cap` particles
/// (`Buffers::grid_scratch`).
fn local_fits<D: Dim>(cap: usize, n_cells: usize) -> bool {
    n_cells < cap * vstride::<D>()
}

/// `clone_dtoh` of `src`, adding its bytes to `read`.
fn counted<T: DeviceRepr, S: cudarc::driver::DevicePtr<T>>(
    s: &Arc<CudaStream>,
    src: &S,
    read: &mut u64,
) -> Result<Vec<T>, DriverError> {
    let v = s.clone_dtoh(src)?;
    *read += std::mem::size_of_val(v.as_slice()) as u64;
    Ok(v)
}

/// The masses from the flat positions and velocities: pos.w in 3D, vel.z in 2D (no array of
/// their own on the device; `mass_of` in cuda/device/packing.cuh).
fn mass_of<D: Dim>(pos: &[f32], vel: &[f32], n: usize) -> Vec<f32> {
    if D::D == 3 {
        (0..n).map(|i| pos[i * vstride::<D>() + 3]).collect()
    } else {
        (0..n).map(|i| vel[i * VEL_STRIDE + 2]).collect()
    }
}

/// Vectors -> float2 (2D) or float4 (3D) with `w(i)` in the w slot.
pub(super) fn flat_v<D: Dim>(v: &[D::V], w: impl Fn(usize) -> f32 + Sync) -> Vec<f32> {
    let vs = vstride::<D>();
    let mut out = vec![0.0f32; v.len() * vs];
    out.par_chunks_mut(vs)
        .zip(v.par_iter())
        .enumerate()
        .for_each(|(i, (o, x))| {
            o[..D::D].copy_from_slice(&D::to3(*x)[..D::D]);
            if vs == 4 {
                o[3] = w(i);
            }
        });
    out
}
/// Velocities -> float4 (`vel_load` in cuda/device/packing.cuh): w = `w(i)`, and in 2D z =
/// the mass.
fn flat_vel<D: Dim>(v: &[D::V], mass: &[f32], w: impl Fn(usize) -> f32 + Sync) -> Vec<f32> {
    let mut out = vec![0.0f32; v.len() * VEL_STRIDE];
    out.par_chunks_mut(VEL_STRIDE)
        .zip(v.par_iter())
        .enumerate()
        .for_each(|(i, (o, x))| {
            o[..D::D].copy_from_slice(&D::to3(*x)[..D::D]);
            if D::D == 2 {
                o[2] = mass[i];
            }
            o[3] = w(i);
        });
    out
}
pub(super) fn unflat_v<D: Dim>(f: &[f32], n: usize) -> Vec<D::V> {
    unflat::<D>(f, n, vstride::<D>())
}
/// The first D components of each of n vectors stored `vs` floats apart.
fn unflat<D: Dim>(f: &[f32], n: usize, vs: usize) -> Vec<D::V> {
    (0..n)
        .map(|i| {
            let mut a = [0.0f32; 3];
            a[..D::D].copy_from_slice(&f[i * vs..i * vs + D::D]);
            D::from3(a)
        })
        .collect()
}
/// Full tensors -> planes of symmetric components.
fn flat_s<D: Dim>(m: &[D::M]) -> Vec<f32> {
    let n = m.len();
    let slots = sym_slots::<D>();
    let mut out = vec![0.0f32; n * slots.len()];
    for (i, x) in m.iter().enumerate() {
        let s6 = D::sym_to6(*x);
        for (k, &c) in slots.iter().enumerate() {
            out[k * n + i] = s6[c];
        }
    }
    out
}
fn unflat_s<D: Dim>(f: &[f32], n: usize) -> Vec<D::M> {
    let slots = sym_slots::<D>();
    (0..n)
        .map(|i| {
            let mut s6 = [0.0f32; 6];
            for (k, &c) in slots.iter().enumerate() {
                s6[c] = f[k * n + i];
            }
            D::sym_from6(s6)
        })
        .collect()
}
