//! The void metric of a confined flow (issue #23): how evenly the particles fill the fluid
//! region, measured on a particle set on the host (the run's writer thread takes it from
//! the frame it already has; `meshfree validate` from a read-back).
//!
//! * The **fluid region** is the cells (squares or cubes of side dx on the lattice of the
//!   domain's lower corner) that hold a fluid particle at the start. It is meant for flows
//!   that fill their domain (the vortex streets, the validation cylinder): where the fluid
//!   leaves a region on purpose (a free surface), cells it leaves count as empty.
//! * The **empty fraction**: the share of the region's cells that hold no particle (of any
//!   kind). A lattice holds one particle per cell; a disordered but even distribution
//!   leaves some cells empty and doubles up others, so this is a measure of disorder as
//!   well as of voids.
//! * The **largest void** \[dx\]: the diameter of the largest circle (sphere) with its centre
//!   in the region and no particle inside, i.e. twice the largest distance from a point of
//!   the region to its nearest particle, over dx. Measured at the points of a sub-lattice
//!   of spacing dx / `SUBDIVISION` (cell corners and centres among them), so it reads low by
//!   at most sqrt(dim) dx / SUBDIVISION. A square lattice gives sqrt 2 = 1.41, one missing
//!   particle 2.0, a hole of radius R (every particle closer than R to a point removed)
//!   about 2 R / dx. Searched up to `MAX_RADIUS_DX`: larger voids read as 2 MAX_RADIUS_DX.
//!
//! Periodic axes wrap (nearest image). Cost per frame: one counting sort of the particles
//! into the cells, then a search of the nearest cells for each sample point, O(N).

use serde::{Deserialize, Serialize};

use crate::physics::particle::{Kind, Particle};
use crate::scene::scheme::SceneFile;

/// Sample points per dx along each axis: 4 in 2D (16 per cell), 2 in 3D (8 per cell).
pub fn subdivision(dim: u32) -> usize {
    if dim == 2 {
        4
    } else {
        2
    }
}

/// \[dx\] the search radius for the nearest particle: a void wider than 2 x this reads as
/// 2 x this.
pub const MAX_RADIUS_DX: usize = 16;

/// One measurement.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct VoidSample {
    /// \[T\]
    pub time: f64,
    /// [-] share of the fluid region's cells with no particle.
    pub empty_fraction: f64,
    /// \[dx\] diameter of the largest empty circle (sphere) centred in the fluid region.
    pub largest_void_dx: f64,
}

/// The void metric over a run's outputs (`summary.json`'s `voids`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct VoidSummary {
    /// Outputs measured.
    pub outputs: usize,
    /// Cells of side dx in the fluid region.
    pub region_cells: usize,
    /// \[dx\] the largest void over every output, and the time \[T\] of that output.
    pub largest_void_dx: f64,
    pub largest_void_time: f64,
    /// [-] the largest and the mean empty fraction over the outputs.
    pub max_empty_fraction: f64,
    pub mean_empty_fraction: f64,
    /// The last output's measurement.
    pub last: Option<VoidSample>,
}

impl VoidSummary {
    /// Take one more output's measurement.
    pub fn add(&mut self, s: VoidSample) {
        if self.outputs == 0 || s.largest_void_dx > self.largest_void_dx {
            self.largest_void_dx = s.largest_void_dx;
            self.largest_void_time = s.time;
        }
        self.max_empty_fraction = self.max_empty_fraction.max(s.empty_fraction);
        let n = self.outputs as f64;
        self.mean_empty_fraction = (self.mean_empty_fraction * n + s.empty_fraction) / (n + 1.0);
        self.outputs += 1;
        self.last = Some(s);
    }
}

/// The cells of a scene's domain and its fluid region.
#[derive(Clone, Debug)]
pub struct VoidMeter {
    dim: usize,
    /// [L]
    dx: f32,
    origin: [f32; 3],
    /// [L] the domain's extent along each axis (the period of a periodic one).
    extent: [f32; 3],
    cells: [usize; 3],
    periodic: [bool; 3],
    /// Per cell: in the fluid region.
    region: Vec<bool>,
    region_cells: usize,
}

impl VoidMeter {
    /// The scene's cells and the fluid region of its initial particles `initial`.
    pub fn new(file: &SceneFile, initial: &[Particle]) -> VoidMeter {
        let dim = file.dimension as usize;
        let dx = file.discretisation.spacing as f32;
        let mut origin = [0.0f32; 3];
        let mut extent = [dx; 3];
        let mut cells = [1usize; 3];
        let mut periodic = [false; 3];
        let p = file.domain.periodic.clone().unwrap_or_default();
        for a in 0..dim {
            origin[a] = file.domain.min[a] as f32;
            let len = (file.domain.max[a] - file.domain.min[a]) as f32;
            cells[a] = ((len / dx).ceil() as usize).max(1);
            extent[a] = len;
            periodic[a] = p.get(a).copied().unwrap_or(false);
        }
        let mut meter = VoidMeter {
            dim,
            dx,
            origin,
            extent,
            cells,
            periodic,
            region: vec![false; cells.iter().product()],
            region_cells: 0,
        };
        for q in initial.iter().filter(|q| q.kind == Kind::Fluid) {
            if let Some(c) = meter.cell_of(&q.position) {
                meter.region[c] = true;
            }
        }
        meter.region_cells = meter.region.iter().filter(|&&r| r).count();
        meter
    }

    /// Cells of side dx in the fluid region.
    pub fn region_cells(&self) -> usize {
        self.region_cells
    }

    /// The cell index of a position (wrapped on periodic axes); none outside the domain.
    fn cell_of(&self, x: &[f32; 3]) -> Option<usize> {
        let mut c = [0usize; 3];
        for a in 0..self.dim {
            let mut k = ((x[a] - self.origin[a]) / self.dx).floor() as i64;
            if self.periodic[a] {
                k = k.rem_euclid(self.cells[a] as i64);
            }
            if k < 0 || k >= self.cells[a] as i64 {
                return None;
            }
            c[a] = k as usize;
        }
        Some(self.flat(c))
    }

    fn flat(&self, c: [usize; 3]) -> usize {
        (c[2] * self.cells[1] + c[1]) * self.cells[0] + c[0]
    }

    /// Measure `particles` (every kind occupies its cell) at time `time`.
    pub fn measure(&self, particles: &[Particle], time: f64) -> VoidSample {
        // Counting sort of the particles into the cells (CSR: start, then the positions).
        let n = self.region.len();
        let mut start = vec![0u32; n + 1];
        let slots: Vec<Option<usize>> = particles
            .iter()
            .map(|q| self.cell_of(&q.position))
            .collect();
        for c in slots.iter().flatten() {
            start[c + 1] += 1;
        }
        for c in 0..n {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut pos = vec![[0.0f32; 3]; start[n] as usize];
        for (q, c) in particles.iter().zip(&slots) {
            if let Some(c) = *c {
                pos[fill[c] as usize] = q.position;
                fill[c] += 1;
            }
        }
        let empty = (0..n)
            .filter(|&c| self.region[c] && start[c] == start[c + 1])
            .count();
        let empty_fraction = if self.region_cells > 0 {
            empty as f64 / self.region_cells as f64
        } else {
            0.0
        };

        // The largest distance from a sample point of the region to its nearest particle.
        let sub = subdivision(self.dim as u32);
        let step = self.dx / sub as f32;
        let subs = [
            sub,
            if self.dim >= 2 { sub } else { 1 },
            if self.dim >= 3 { sub } else { 1 },
        ];
        let mut worst = 0.0f32;
        for cz in 0..self.cells[2] {
            for cy in 0..self.cells[1] {
                for cx in 0..self.cells[0] {
                    let cell = [cx, cy, cz];
                    if !self.region[self.flat(cell)] {
                        continue;
                    }
                    for sz in 0..subs[2] {
                        for sy in 0..subs[1] {
                            for sx in 0..subs[0] {
                                let s = [sx, sy, sz];
                                let mut x = [0.0f32; 3];
                                for a in 0..self.dim {
                                    x[a] = self.origin[a]
                                        + cell[a] as f32 * self.dx
                                        + s[a] as f32 * step;
                                }
                                let d = self.nearest(&x, cell, &start, &pos, worst);
                                worst = worst.max(d);
                            }
                        }
                    }
                }
            }
        }
        VoidSample {
            time,
            empty_fraction,
            largest_void_dx: (2.0 * worst / self.dx) as f64,
        }
    }

    /// [L] the distance from `x` (in `cell`) to its nearest particle, searched ring by ring
    /// of cells up to `MAX_RADIUS_DX`; stops early once it is known to be at most `floor`
    /// (the largest so far, which this sample then cannot raise).
    fn nearest(
        &self,
        x: &[f32; 3],
        cell: [usize; 3],
        start: &[u32],
        pos: &[[f32; 3]],
        floor: f32,
    ) -> f32 {
        let mut best2 = f32::INFINITY;
        for ring in 0..=MAX_RADIUS_DX as i64 {
            self.for_ring(cell, ring, &mut |c| {
                for y in &pos[start[c] as usize..start[c + 1] as usize] {
                    let mut d2 = 0.0f32;
                    for a in 0..self.dim {
                        let mut d = y[a] - x[a];
                        if self.periodic[a] {
                            let l = self.extent[a];
                            d -= l * (d / l).round();
                        }
                        d2 += d * d;
                    }
                    best2 = best2.min(d2);
                }
            });
            // Every particle beyond ring `ring` lies at least ring dx away.
            let reach = ring as f32 * self.dx;
            let best = best2.sqrt();
            if best <= reach || best <= floor {
                return best;
            }
        }
        best2.sqrt().min(MAX_RADIUS_DX as f32 * self.dx)
    }

    /// Call `f` with each cell on the surface of the cube of cells at Chebyshev distance
    /// `ring` from `cell` (wrapped on periodic axes, clipped elsewhere; a ring wider than a
    /// periodic axis meets some cells twice, which leaves the minimum alone).
    fn for_ring(&self, cell: [usize; 3], ring: i64, f: &mut dyn FnMut(usize)) {
        let span = |a: usize| -> i64 {
            if a < self.dim {
                ring
            } else {
                0
            }
        };
        let (rx, ry, rz) = (span(0), span(1), span(2));
        for dz in -rz..=rz {
            for dy in -ry..=ry {
                for dx in -rx..=rx {
                    if dx.abs().max(dy.abs()).max(dz.abs()) != ring {
                        continue;
                    }
                    let mut c = [0usize; 3];
                    let mut inside = true;
                    for (a, d) in [dx, dy, dz].into_iter().enumerate() {
                        let mut k = cell[a] as i64 + d;
                        if self.periodic[a] {
                            k = k.rem_euclid(self.cells[a] as i64);
                        } else if k < 0 || k >= self.cells[a] as i64 {
                            inside = false;
                        }
                        c[a] = k as usize;
                    }
                    if !inside {
                        continue;
                    }
                    f(self.flat(c));
                }
            }
        }
    }
}
