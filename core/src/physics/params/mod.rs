//! The one parameter struct, `cuda/sph_params.h`, as Rust (bindgen, see `build.rs`), and
//! `derive`, the one function that fills its derived fields.
pub mod sph_params;
pub use sph_params::*;

use crate::physics::kernel;

/// Where the Rust bindings came from in this build: "bindgen" or "committed".
pub const BINDINGS_SOURCE: &str = env!("MESHFREE_BINDINGS_SOURCE");

/// Whether the scheme has none of the terms beyond the paper's fluid scheme: no laminar
/// viscosity, cohesion, Morris's no-slip walls, density diffusion or shifting. Fluid-only
/// scenes where this holds run the lean CUDA kernels (`EXTRAS = false` in cuda/forces.cuh
/// and cuda/rates.cuh), which compile those terms out instead of testing them per pair: the
/// same results with fewer registers and branches (docs/reference/performance.md, "lean fluid kernels").
pub fn lean_scheme(p: &SphParams) -> bool {
    p.viscosity <= 0.0
        && p.cohesion == 0.0
        && p.no_slip != MF_NO_SLIP_MORRIS as i32
        && p.density_diffusion <= 0.0
        && p.shifting <= 0.0
}

/// Whether a rates pass needs renormalised density gradients first (`grad_rho`: the density
/// diffusion in Antuono et al. 2010's form, inside bodies or in the fluid): the CPU's
/// `density_gradient` and the CUDA pass `sph_grad_rho` run, and the CUDA buffer is held, only
/// where this holds.
pub fn needs_density_gradient(p: &SphParams) -> bool {
    p.solid_density_diffusion > 0.0 || p.fluid_density_gradient != 0
}

/// Whether the solver needs each wall particle's surface (`Setup::wall_surface`: its normal
/// into the fluid and its distance behind the surface): Morris's no-slip walls and mDBC's
/// ghost nodes read it.
pub fn needs_wall_surface(p: &SphParams) -> bool {
    p.no_slip == MF_NO_SLIP_MORRIS as i32 || p.wall_coupling == MF_WALL_COUPLING_MDBC as i32
}

/// Fill the derived fields (marked "derived" in the header) from the primary ones.
/// Needs `dim`, `kernel`, `h`, `dx`, `rho0`, `c0`, `tait_gamma`, the domain and `periodic`,
/// `attractive` and `lj_r0`, `density_diffusion` and `density_diffusion_form`.
pub fn derive(p: &mut SphParams) {
    let d = p.dim as usize;
    p.support = 2.0 * p.h;
    p.support2 = p.support * p.support;
    p.kernel_norm = kernel::sigma(p.kernel, p.dim) / p.h.powi(p.dim);
    p.tait_b = p.rho0 * p.c0 * p.c0 / p.tait_gamma; // eq. (9)
    p.av_eta2 = 0.001 * p.h * p.h; // eq. (10)
    p.visc_eta2 = 0.01 * p.h * p.h; // Morris, Fox & Zhu 1997
    p.inv_w_dx = 1.0 / kernel::w(p, p.dx);
    p.lj_range = if p.attractive != 0 {
        p.support
    } else {
        p.lj_r0
    }; // eq. (17)
       // The fluid's density diffusion in Antuono et al. 2010's form takes the gradients.
    p.fluid_density_gradient = (p.density_diffusion > 0.0
        && p.density_diffusion_form == MF_DIFFUSION_ANTUONO as i32)
        as i32;
    p.n_cells = 1;
    for a in 0..3 {
        if a < d {
            let len = p.domain_max[a] - p.domain_min[a];
            let n = ((len * MF_CELL_REACH as f32 / p.support).floor() as i32).max(1);
            p.grid_dims[a] = n;
            p.cell_size[a] = len / n as f32;
        } else {
            p.grid_dims[a] = 1;
            p.cell_size[a] = 1.0;
            p.periodic[a] = 0;
        }
        p.n_cells *= p.grid_dims[a];
    }
}

impl SphParams {
    /// The speed of sound of particles of `kind` (fluid c0; solid: bulk plus shear waves).
    pub fn sound_speed(&self, kind: u8) -> f32 {
        if kind as u32 == MF_KIND_SOLID {
            (self.solid_c0 * self.solid_c0
                + 4.0 / 3.0 * self.shear_modulus / self.solid_rho0.max(f32::MIN_POSITIVE))
            .sqrt()
        } else {
            self.c0
        }
    }

    /// Whether this solver owns a particle whose coordinate on the `own_axis` is `c` \[L\]:
    /// always in one domain; in a subdomain of a decomposed run (`own_slab`,
    /// `crate::exchange`) where own_lo <= c < own_hi, so that the reductions that must count
    /// each particle once (the step size's extremes, the wall forces) skip the halo.
    #[inline]
    pub fn owns(&self, c: f32) -> bool {
        self.own_slab == 0 || (c >= self.own_lo && c < self.own_hi)
    }

    /// Which driven object scene group `group` is (a piston, a clamp, a flap; any kind): k
    /// where `driven_motion[k].group == group`, following `driven_motion[k]` whatever the
    /// forces. Twin: `driven_index` in cuda/device/particle.cuh.
    #[inline]
    pub fn driven_index(&self, group: u32) -> Option<usize> {
        let n = (self.driven.max(0) as usize).min(self.driven_motion.len());
        self.driven_motion[..n]
            .iter()
            .position(|m| m.group as u32 == group)
    }

    /// Whether scene group `group` is driven (`driven_index`).
    #[inline]
    pub fn is_driven(&self, group: u32) -> bool {
        self.driven_index(group).is_some()
    }

    /// Reference density of particles of `kind`.
    pub fn rest_density(&self, kind: u8) -> f32 {
        if kind as u32 == MF_KIND_SOLID {
            self.solid_rho0
        } else {
            self.rho0
        }
    }
}
