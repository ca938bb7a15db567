//! Probes: fields kernel-interpolated at points, for `Readback::sample_points`. Twin:
//! `cuda/probes.cu` (the per-point sum `PointSum` in `cuda/device/probes.cuh`); parity test
//! `tests/cuda_parity/`.
//!
//! Eqs. (1)-(4) with Shepard normalisation: f(x) = sum_j f_j W(x - x_j) V_j / sum_j
//! W(x - x_j) V_j, V_j = m_j / rho_j [L^d], over the particles within the support of x,
//! visited in the grid's order (`Grid::for_each_neighbor`), as the GPU visits them.

use rayon::prelude::*;

use super::density::pressure;
use super::grid::Grid;
use crate::physics::dim::Dim;
use crate::physics::kernel;
use crate::physics::params::{SphParams, MF_KIND_BOUNDARY, MF_KIND_FLUID};
use crate::physics::state::State;
use crate::solver::PointSample;

/// The sums of one point, neighbour by neighbour. Twin: `PointSum` in
/// `cuda/device/probes.cuh`.
#[derive(Clone, Copy, Debug, Default)]
pub struct PointSum {
    /// [-] sum W V over the interpolated particles (Shepard's denominator).
    pub weight: f32,
    /// [-] sum W V over fluid particles: the colour.
    pub colour: f32,
    /// [M L^-d L^2 T^-2] sum P W V.
    pub pressure: f32,
    /// [L/T] sum v W V.
    pub velocity: [f32; 3],
    /// [M L^-d] sum rho W V.
    pub density: f32,
    pub neighbours: u32,
}

impl PointSum {
    /// Add neighbour j of kind `kind` at distance `r` \[L\] with mass `m` \[M\], density `rho`,
    /// velocity `v` (D components used); walls enter only where `walls`.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn add(
        &mut self,
        p: &SphParams,
        walls: bool,
        kind: u8,
        r: f32,
        m: f32,
        rho: f32,
        v: [f32; 3],
        dim: usize,
    ) {
        let fluid = kind as u32 == MF_KIND_FLUID;
        if !(fluid || (walls && kind as u32 == MF_KIND_BOUNDARY)) {
            return;
        }
        let wv = kernel::w(p, r) * (m / rho); // W(x - x_j) m_j / rho_j, eqs. (1)-(4)
        if fluid {
            self.colour += wv;
        }
        self.weight += wv;
        // (Fluid and wall particles only: the solid departure argument is never read.)
        self.pressure += pressure(p, kind, rho, rho - p.solid_rho0) * wv; // eq. (9) at the neighbour's density
        for (a, va) in v.iter().enumerate().take(dim) {
            self.velocity[a] += va * wv;
        }
        self.density += rho * wv;
        self.neighbours += 1;
    }

    /// The Shepard-normalised sample; `PointSample::EMPTY` (with the colour) where no
    /// neighbour entered.
    pub fn finish(&self) -> PointSample {
        if self.neighbours == 0 || self.weight <= 0.0 {
            return PointSample {
                colour: self.colour,
                ..PointSample::EMPTY
            };
        }
        let inv = 1.0 / self.weight;
        PointSample {
            pressure: self.pressure * inv,
            velocity: self.velocity.map(|v| v * inv),
            density: self.density * inv,
            colour: self.colour,
            neighbours: self.neighbours,
        }
    }
}

/// One `PointSample` per point of `points` (z ignored in 2D) into `out`, from the state `s`
/// sorted by `grid` (which must list the particles at their current positions).
pub fn sample<D: Dim>(
    p: &SphParams,
    grid: &Grid,
    s: &State<D>,
    points: &[[f32; 3]],
    walls: bool,
    out: &mut Vec<PointSample>,
) {
    points
        .par_iter()
        .map(|x| {
            let mut sum = PointSum::default();
            grid.for_each_neighbor::<D>(p, &s.pos, D::from3(*x), |j, _r, r2| {
                sum.add(
                    p,
                    walls,
                    s.kind[j],
                    r2.sqrt(),
                    s.mass[j],
                    s.rho[j],
                    D::to3(s.vel[j]),
                    D::D,
                );
            });
            sum.finish()
        })
        .collect_into_vec(out);
}
