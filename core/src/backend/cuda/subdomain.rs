//! The CUDA solver as one subdomain of a decomposed run (`crate::exchange`), its halos kept
//! on the device: twin of `backend/cpu/subdomain.rs`, kernels in `cuda/exchange.cu`. Tests:
//! `tests/cuda_exchange.rs`.
//!
//! - A halo is one flat device buffer of 32-bit words (`CudaHalo`), a record per particle
//!   of every persistent array (`buffers::Persistent`: all that a step reads which an
//!   earlier step wrote), so that a transport between processes can send it as bytes.
//! - `halo` marks the particles within the width of the target slab (`sph_exchange_mark`,
//!   the twin of `Slab::gap`), scans the marks with the grid build's scan kernels, reads
//!   back their count (one word) and packs them; `append` unpacks the received records
//!   after the particles held, growing the arrays' room (`Buffers::reserve`) where needed;
//!   `retain_owned` marks the owned particles and compacts them into the other persistent
//!   set. Nothing per particle passes through the host.
//! - The step size: `extremes` reads back the three maxima the forces pass reduced over
//!   the owned particles (`owns_slot` in `cuda/device/particle.cuh`), `set_step` writes the
//!   agreed maxima back and runs the one-domain step-size kernel on them, so that dt is
//!   the one domain's, bit for bit.
//! - The lanes of the neighbour kernels are the whole scene's (`CudaSolver::new_subdomain`).
//! - Each rank runs on a thread of its own (`Threads::call_each`); cudarc binds the
//!   context to the calling thread in every call it makes (allocation, copy, launch, drop),
//!   so nothing more is needed here.
//! - CUDA graphs are not used by a rank (`Rank` steps stage by stage); every operation here
//!   drops a captured graph of this solver (its buffers moved).

use cudarc::driver::CudaSlice;

use super::buffers::{nsym, vstride, Buffers};
use super::handover::{By, Mark};
use super::launch::{self, Select};
use super::{oom, CudaSolver};
use crate::exchange::{Slab, Subdomain};
use crate::physics::dim::Dim;
use crate::physics::params::{needs_density_gradient, MF_DENSITY_CONTINUITY};
use crate::physics::state::State;
use crate::solver::checkpoint::SolverCheckpoint;

/// Copies of particles on their way to another subdomain, on the device: `n` records of
/// `words.len() / n` 32-bit words each (`halo_words`), back to back in the sender's
/// storage order. A record holds, by word: 0 id, 1 kind (widened), 2 group, then the
/// position (2D: x, y; 3D: x, y, z, mass), the velocity as stored (float4: 2D vx, vy, mass,
/// w; 3D vx, vy, vz, w; w the density, negated on walls), rho and p; with solids also the
/// stress's symmetric components (2D xx, yy, xy; 3D xx, yy, zz, xy, xz, yz) and rho_dev.
/// Floats as their bits. The layout is fixed for a run (its dimension and whether it holds
/// solids): 11 / 15 words in 2D without / with solids, 13 / 20 in 3D
/// (`cuda/exchange.cu`, `load_record`).
pub struct CudaHalo {
    pub n: usize,
    pub words: CudaSlice<u32>,
}

impl CudaHalo {
    /// Words per particle.
    pub fn record_words(&self) -> usize {
        self.words.len().checked_div(self.n).unwrap_or(0)
    }
}

/// Words per particle of a halo in `D` dimensions, with or without the solids' arrays
/// (the layout of `CudaHalo`).
pub fn halo_words<D: Dim>(solids: bool) -> usize {
    9 + vstride::<D>() + if solids { nsym::<D>() + 1 } else { 0 }
}

impl<D: Dim> CudaSolver<D> {
    /// The stream this solver's work is queued on (an NCCL communicator queues on it too,
    /// `nccl.rs`, so that a halo's send follows its packing).
    pub fn stream(&self) -> std::sync::Arc<cudarc::driver::CudaStream> {
        self.dev.stream.clone()
    }

    /// Words per particle of this solver's halos.
    fn record_words(&self) -> usize {
        halo_words::<D>(self.buf.cur.stress.is_some())
    }

    /// After the particles were added, dropped or replaced: the grid lists other slots, and
    /// a captured graph other buffers.
    fn moved(&mut self) {
        self.grid_current = false;
        self.graph = None;
    }
}

impl<D: Dim> Subdomain for CudaSolver<D> {
    type Halo = CudaHalo;

    fn set_owned(&mut self, slab: Slab) {
        slab.own(&mut self.params);
    }

    fn halo(
        &mut self,
        target: &Slab,
        width: f32,
        periodic: Option<(f32, f32)>,
    ) -> Option<CudaHalo> {
        let s = self.dev.stream.clone();
        let words = self.record_words();
        let sel = Select::Near {
            axis: target.axis,
            lo: target.lo,
            hi: target.hi,
            width,
            periodic,
        };
        let r = (|| {
            let m = launch::select(&self.k, &s, &self.params, &mut self.buf, sel)?;
            if m == 0 {
                return Ok(None);
            }
            let mut out = s.alloc_zeros::<u32>(m * words)?;
            launch::pack(&self.k, &s, &self.buf, words, &mut out);
            // Another solver's stream reads it (no events between streams: device.rs).
            s.synchronize()?;
            Ok(Some(CudaHalo { n: m, words: out }))
        })();
        r.unwrap_or_else(|e| self.sync_err("packing a halo", e))
    }

    fn halo_len(halo: &CudaHalo) -> usize {
        halo.n
    }

    fn halo_bytes(halo: &CudaHalo) -> usize {
        4 * halo.words.len()
    }

    fn device_bytes(&self) -> usize {
        self.buf.bytes
    }

    fn append(&mut self, halos: Vec<CudaHalo>) {
        let m: usize = halos.iter().map(|h| h.n).sum();
        if m == 0 {
            return;
        }
        let words = self.record_words();
        for h in &halos {
            assert_eq!(
                h.record_words(),
                words,
                "append: a halo of {} words per particle into a solver of {words}",
                h.record_words()
            );
        }
        let s = self.dev.stream.clone();
        let need = self.buf.n + m;
        let r = (|| {
            // The cells the last drift filed do not count the new particles: the grid
            // build files them all again.
            if self.buf.handover.take(Mark::CellsFiled, By::Storage) {
                s.memset_zeros(&mut self.buf.count)?;
            }
            self.buf.reserve::<D>(&s, need)?;
            let list: Vec<(usize, &CudaSlice<u32>)> =
                halos.iter().map(|h| (h.n, &h.words)).collect();
            launch::unpack(&self.k, &s, &mut self.buf, (words, nsym::<D>()), &list);
            // The halos were written on their senders' streams (synchronised before they
            // were handed over) and are freed on them when dropped: this stream's reads
            // finish first.
            s.synchronize()
        })();
        if let Err(e) = r {
            self.sync_err("appending halos", e)
        }
        drop(halos);
        self.moved();
    }

    fn retain_owned(&mut self) {
        let s = self.dev.stream.clone();
        let r = (|| {
            let n = self.buf.n;
            let kept = launch::select(&self.k, &s, &self.params, &mut self.buf, Select::Owned)?;
            if kept < n {
                launch::compact(&self.k, &s, &mut self.buf, kept);
                // The cells the drift filed are those of the old slots.
                if self.buf.handover.take(Mark::CellsFiled, By::Storage) {
                    s.memset_zeros(&mut self.buf.count)?;
                }
            }
            Ok(kept < n)
        })();
        match r {
            Ok(true) => self.moved(),
            Ok(false) => {}
            Err(e) => self.sync_err("dropping the particles of other subdomains", e),
        }
    }

    /// The three maxima the forces pass left in `red` (owned particles only), read back.
    fn extremes(&mut self) -> [f32; 3] {
        let red = self
            .dev
            .stream
            .clone_dtoh(&self.buf.red)
            .unwrap_or_else(|e| self.sync_err("reading the step size's extremes", e));
        [
            f32::from_bits(red[0]),
            f32::from_bits(red[1]),
            f32::from_bits(red[2]),
        ]
    }

    /// The agreed maxima written back into `red` and the one-domain step-size kernel run on
    /// them (which clears `red` for the next forces pass): the one domain's dt, bit for bit.
    fn set_step(&mut self, e: [f32; 3]) {
        let bits = e.map(f32::to_bits);
        if let Err(err) = self.dev.stream.memcpy_htod(&bits[..], &mut self.buf.red) {
            self.sync_err("writing the agreed extremes", err)
        }
        self.buf.handover.take(Mark::StepSizeDue, By::StepSize);
        launch::step_size(&self.k, &self.dev.stream, &self.params, &mut self.buf);
    }

    /// On the host (used only at a restore): the buffers rebuilt from `part`.
    fn replace(&mut self, part: &SolverCheckpoint) -> Result<(), String> {
        if part.dim != D::D as u32 {
            return Err(format!(
                "it holds a {}D state and the scene is {}D",
                part.dim,
                D::D
            ));
        }
        let p = &self.params;
        let art = p.artificial_stress > 0.0;
        let mut like = State::<D>::from_particles(
            &[],
            p.density_form as u32 == MF_DENSITY_CONTINUITY,
            art,
            p.solid_rho0,
        );
        if self.buf.cur.stress.is_some() {
            like = like.with_solid_arrays(art);
        }
        let state = part.to_state_unchecked(&like);
        let n = state.len();
        let buf = Buffers::new(
            &self.dev.stream,
            &state,
            self.buf.n_cells,
            &self.wall_surface,
            &self.motion_series,
            needs_density_gradient(&self.params),
        )
        .map_err(|e| oom(n, e).to_string())?;
        self.buf = buf;
        self.set_clock(part.time, part.dt);
        self.steps = part.steps;
        self.moved();
        Ok(())
    }
}
