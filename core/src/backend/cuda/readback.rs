//! What comes back from the CUDA solver (`Readback`): diagnostics reduced on the device,
//! particles, output frames copied on a second stream (`capture.rs`), the viewer's host
//! snapshot, probes and wall forces summed on the device. Twin: `Readback`'s CPU
//! implementation in `backend/cpu/mod.rs`; parity test `tests/cuda_parity/`.

use crate::consts::MF_SAMPLE_FLOATS;
use crate::physics::dim::Dim;
use crate::physics::particle::Particle;
use crate::solver::frame::{Fields, FrameData, PendingFrame, Ready};
use crate::solver::{Diagnostics, PointSample, Readback, Shown, Snapshot, Solver};

use super::buffers;
use super::capture::Capturer;
use super::launch;
use super::CudaSolver;

impl<D: Dim> Readback for CudaSolver<D> {
    fn diagnostics(&mut self) -> Diagnostics {
        let s = &self.dev.stream;
        let r = launch::diagnostics(&self.k, s, &self.params, &mut self.buf).and_then(|_| {
            Ok((
                s.clone_dtoh(&self.buf.diag_sums)?,
                s.clone_dtoh(&self.buf.diag_max)?,
                s.clone_dtoh(&self.buf.diag_counts)?,
                s.clone_dtoh(&self.buf.dt.slice(..1))?,
                s.clone_dtoh(&self.buf.time.slice(..1))?,
            ))
        });
        let (sums, maxes, counts, dt, time) =
            r.unwrap_or_else(|e| self.sync_err("reducing diagnostics", e));
        self.d2h += (8 * sums.len() + 4 * maxes.len() + 4 * counts.len() + 4 + 8) as u64;
        Diagnostics {
            step: self.steps,
            time: time[0],
            dt: if self.steps == 0 { 0.0 } else { dt[0] },
            kinetic_energy: sums[0],
            max_speed: f32::from_bits(maxes[0]),
            density_error: f32::from_bits(maxes[1]),
            momentum: [sums[1], sums[2], sums[3]],
            fluid: counts[0] as usize,
            solid: counts[1] as usize,
            boundary: counts[2] as usize,
        }
    }
    fn particles(&mut self) -> Vec<Particle> {
        self.download_state().to_particles()
    }
    /// A device-side copy into a staging set, downloaded by the frame's `wait` on a second
    /// stream (`capture.rs`); a synchronous read-back where no staging set fits in memory.
    fn capture(&mut self, fields: Fields) -> Box<dyn PendingFrame> {
        let (step, time) = (self.steps, self.time());
        if self.capturer.is_none() {
            match Capturer::new(&self.dev.ctx) {
                Ok(c) => self.capturer = Some(c),
                Err(e) => self.sync_err("creating the download stream", e),
            }
        }
        let c = self.capturer.as_ref().expect("created above");
        match c.start::<D>(&self.dev.stream, &self.buf, fields, step, time) {
            Ok(pending) => pending,
            Err(_) => {
                let ps = self.download_state().to_particles();
                Box::new(Ready(FrameData::from_particles(&ps, fields, step, time)))
            }
        }
    }
    /// Copies only positions, kinds and the shown quantity (one read-back per drawn frame,
    /// into buffers that keep their size from frame to frame).
    fn snapshot(&mut self, shown: Shown, out: &mut Snapshot) {
        let n = self.buf.n;
        let vs = buffers::vstride::<D>();
        let s = self.dev.stream.clone();
        let c = &self.buf.cur;
        self.host_pos.resize(n * vs, 0.0);
        out.kinds.resize(n, 0);
        out.values.resize(n, 0.0);
        let r = (|| {
            s.memcpy_dtoh(&c.pos, &mut self.host_pos)?;
            s.memcpy_dtoh(&c.kind, &mut out.kinds)?;
            match shown {
                Shown::Speed => {
                    self.host_vel.resize(n * buffers::VEL_STRIDE, 0.0);
                    s.memcpy_dtoh(&c.vel, &mut self.host_vel)?;
                }
                Shown::Pressure => s.memcpy_dtoh(&c.p, &mut out.values)?,
                Shown::Density => s.memcpy_dtoh(&c.rho, &mut out.values)?,
                Shown::Kind => {}
            }
            s.synchronize()
        })();
        if let Err(e) = r {
            self.sync_err("reading a snapshot back", e)
        }
        self.d2h += (n * (4 * vs + 1)) as u64
            + match shown {
                Shown::Speed => 4 * (n * buffers::VEL_STRIDE) as u64,
                Shown::Pressure | Shown::Density => 4 * n as u64,
                Shown::Kind => 0,
            };
        out.positions.clear();
        out.positions.extend(
            self.host_pos
                .chunks_exact(vs)
                .map(|x| [x[0], x[1], if vs == 4 { x[2] } else { 0.0 }]),
        );
        match shown {
            Shown::Speed => {
                for (v, x) in out
                    .values
                    .iter_mut()
                    .zip(self.host_vel.chunks_exact(buffers::VEL_STRIDE))
                {
                    *v = x.iter().take(D::D).map(|c| c * c).sum::<f32>().sqrt();
                }
            }
            Shown::Kind => {
                for (v, k) in out.values.iter_mut().zip(&out.kinds) {
                    *v = *k as f32;
                }
            }
            Shown::Pressure | Shown::Density => {}
        }
    }
    #[cfg(feature = "interop")]
    fn gl_interop(&mut self) -> Option<&mut dyn crate::interop::GlInterop> {
        Some(self)
    }
    /// The read-backs of time, dt, health checks, diagnostics, snapshots, probes, monitors,
    /// the colour range and whole-state reads; not counted: the output frames (`capture`'s
    /// second stream), a checkpoint's solid displacements and a subdomain's exchange sizes.
    fn device_to_host_bytes(&self) -> Option<u64> {
        Some(self.d2h)
    }
    fn wall_surface(&self) -> &[[f32; 4]] {
        &self.wall_surface
    }
    /// Read back (`BodyBuffers::read`): a few hundred bytes per body.
    fn bodies(&mut self) -> Vec<crate::physics::params::MfBody> {
        let Some(bb) = self.bodies.as_ref() else {
            return Vec::new();
        };
        match bb.read(&self.dev.stream) {
            Ok(v) => {
                self.d2h += std::mem::size_of_val(&v[..]) as u64;
                v
            }
            Err(e) => self.sync_err("reading the floating bodies back", e),
        }
    }
    fn open_tally(&mut self) -> Vec<crate::physics::open::OpenTally> {
        let Some((_, tally)) = self.open.as_ref() else {
            return Vec::new();
        };
        let t = match self.dev.stream.clone_dtoh(tally) {
            Ok(t) => t,
            Err(e) => self.sync_err("reading the open boundaries' tally back", e),
        };
        self.d2h += 8 * t.len() as u64;
        t.chunks(4)
            .map(|c| crate::physics::open::OpenTally {
                count_in: c[0] as u64,
                mass_in: c[1],
                count_out: c[2] as u64,
                mass_out: c[3],
            })
            .collect()
    }
    /// One kernel over the points (`cuda/probes.cu`) after a grid build where the particles
    /// moved since the last (which leaves the stepping as it was: the next step's build finds
    /// the same order; a replayed graph first takes one single step, `advance`). Uploads the
    /// points and reads back `MF_SAMPLE_FLOATS` floats per point, nothing per particle.
    fn sample_points(
        &mut self,
        points: &[[f32; 3]],
        include_walls: bool,
        out: &mut Vec<PointSample>,
    ) {
        out.clear();
        if points.is_empty() {
            return;
        }
        if self.buf.n == 0 {
            out.resize(points.len(), PointSample::EMPTY);
            return;
        }
        if !self.grid_current {
            self.build_grid();
        }
        let n = points.len();
        let per = MF_SAMPLE_FLOATS as usize;
        let s = self.dev.stream.clone();
        let flat: Vec<f32> = points
            .iter()
            .flat_map(|x| [x[0], x[1], x[2], 0.0])
            .collect();
        let r = (|| {
            if self.probe_points.as_ref().is_none_or(|b| b.len() < 4 * n) {
                self.probe_points = Some(s.alloc_zeros::<f32>(4 * n)?);
                self.probe_out = Some(s.alloc_zeros::<f32>(per * n)?);
            }
            let (pts, sums) = (
                self.probe_points.as_mut().expect("allocated above"),
                self.probe_out.as_mut().expect("allocated above"),
            );
            s.memcpy_htod(&flat, &mut *pts)?;
            launch::sample_points(
                &self.k,
                &s,
                &self.params,
                &self.buf,
                (&pts.slice(..4 * n), include_walls),
                sums,
            )?;
            let mut host = vec![0.0f32; per * n];
            s.memcpy_dtoh(&sums.slice(..per * n), &mut host)?;
            s.synchronize()?;
            Ok(host)
        })();
        let host = r.unwrap_or_else(|e| self.sync_err("sampling the probes", e));
        self.d2h += 4 * host.len() as u64;
        out.extend(host.chunks_exact(per).map(|c| PointSample {
            pressure: c[0],
            velocity: [c[1], c[2], c[3]],
            density: c[4],
            colour: c[5],
            neighbours: c[6].to_bits(),
        }));
    }
    /// Summed on the device (`cuda/monitor.cu`, `launch::wall_forces`): 3 doubles per group
    /// come back. The grid is rebuilt and the pressures refreshed as the next step will, so
    /// the run goes on as without the sample (its next `advance` starts with one single step:
    /// the rebuild swapped the buffer sets its graph was captured with).
    fn wall_forces(&mut self, groups: &[u32]) -> Vec<[f64; 3]> {
        let f = launch::wall_forces(
            &self.k,
            &self.dev.stream,
            &self.params,
            &mut self.buf,
            groups,
        )
        .unwrap_or_else(|e| self.sync_err("summing the wall forces", e));
        self.d2h += 24 * f.len() as u64;
        // Its grid build reordered the storage.
        self.tl_map_slots();
        f
    }
}
