//! Slabs: the subdomains of a decomposed run, intervals of one axis, and how wide a halo
//! must be for a subdomain's owned particles to step exactly as in one domain.

use crate::physics::params::{SphParams, MF_DENSITY_SUMMATION, MF_INTEGRATOR_EULER};

/// The particles with `lo <= x[axis] < hi` \[L\]. The first slab of a non-periodic axis starts
/// at -inf and the last ends at +inf, so that every particle, one that left the domain too,
/// has one owner.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Slab {
    pub axis: usize,
    pub lo: f32,
    pub hi: f32,
}

impl Slab {
    pub fn contains(&self, c: f32) -> bool {
        c >= self.lo && c < self.hi
    }

    /// The distance \[L\] along the axis from coordinate `c` to the slab: 0 inside; on a
    /// periodic axis spanning `periodic` = (min, max) the shorter way round (the outer
    /// slabs' infinite bounds taken as the domain's).
    pub fn gap(&self, c: f32, periodic: Option<(f32, f32)>) -> f32 {
        if self.contains(c) {
            return 0.0;
        }
        match periodic {
            Some((min, max)) => {
                let len = max - min;
                let (lo, hi) = (self.lo.max(min), self.hi.min(max));
                (lo - c).rem_euclid(len).min((c - hi).rem_euclid(len))
            }
            None if c < self.lo => self.lo - c,
            None => c - self.hi,
        }
    }

    /// Write this slab into `p` as the one its solver owns (`SphParams::owns`).
    pub fn own(&self, p: &mut SphParams) {
        p.own_slab = 1;
        p.own_axis = self.axis as i32;
        p.own_lo = self.lo;
        p.own_hi = self.hi;
    }
}

/// The axis to cut: the domain's longest (GPUSPH's default split), the first of equals.
pub fn longest_axis(p: &SphParams) -> usize {
    let len = |a: usize| p.domain_max[a] - p.domain_min[a];
    (0..p.dim as usize).fold(0, |best, a| if len(a) > len(best) { a } else { best })
}

/// `n` slabs of `axis` holding about equal numbers of the coordinates `coords` \[L\]. The
/// outer bounds are -inf and +inf (on a periodic axis too, where positions stay inside the
/// domain, so that rounding at its ends loses no particle). A slab may be narrower than the
/// halo: its neighbours' halos then reach past it, to the ranks beyond, which the exchange
/// serves as it serves the adjacent ones.
pub fn balanced(p: &SphParams, axis: usize, coords: &[f32], n: usize) -> Vec<Slab> {
    assert!(n >= 1);
    let (dmin, dmax) = (p.domain_min[axis], p.domain_max[axis]);
    let mut sorted: Vec<f32> = coords.to_vec();
    sorted.sort_unstable_by(f32::total_cmp);
    let mut cuts = vec![f32::NEG_INFINITY];
    for k in 1..n {
        let c = if sorted.is_empty() {
            dmin + (dmax - dmin) * k as f32 / n as f32
        } else {
            sorted[sorted.len() * k / n]
        };
        cuts.push(c);
    }
    cuts.push(f32::INFINITY);
    cuts.windows(2)
        .map(|w| Slab {
            axis,
            lo: w[0],
            hi: w[1],
        })
        .collect()
}

/// How many neighbour passes of one step a particle's update depends on, each a support
/// radius further out: the force pass and the rates pass (which reads the neighbours'
/// kicked velocities) under the symplectic Euler, one fused pass under the forward Euler;
/// one more where the density is summed (eq. (8): the force pass reads the neighbours'
/// summed densities), one more where the rates read renormalised density gradients, and one
/// more where bodies meet the fluid at its extrapolated pressure.
pub fn passes(p: &SphParams) -> u32 {
    let mut n = if p.integrator as u32 == MF_INTEGRATOR_EULER {
        1
    } else {
        2
    };
    if p.density_form as u32 == MF_DENSITY_SUMMATION {
        n += 1;
    }
    if crate::physics::params::needs_density_gradient(p) {
        n += 1;
    }
    // The bodies' particles read the fluid's pressures of the density pass
    // (`Solver::solid_interface`) before the force pass reads theirs.
    if p.own_solids != 0 && crate::physics::pairs::extrapolated(p) {
        n += 1;
    }
    n
}

/// The halo's width \[L\]: a particle owned at the end of a step moved there from at most a
/// support radius away (one step moves a particle by a small fraction of h), and its update
/// read particles up to `passes` supports further out.
pub fn halo_width(p: &SphParams) -> f32 {
    (passes(p) + 1) as f32 * p.support
}
