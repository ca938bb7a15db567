//! The one table of the CUDA backend's kernels (`Family::spec`): for every family, the
//! module that holds it, how its entries are named (per dimension, per lane count and, for
//! forces and rates, per scheme: the entry macros of `cuda/device/entries.cuh`), and the C
//! parameter list every entry of the family shares. Loading (`Kernels::load`), selection
//! (`Kernels::neighbour`) and the SAFETY comments of `launch/` all go by it; a test checks
//! it against the PTX (every entry present, nothing more, each parameter of the right kind).

use cudarc::driver::{CudaFunction, DriverError};

use super::device::Device;
use crate::backend::error::BackendError;
use crate::consts::MF_LANES_MAX;
use crate::physics::params::{lean_scheme, SphParams};

/// Lane counts with kernel entries, in index order: the powers of two from 1 to
/// `MF_LANES_MAX` (`MF_LANES_EACH` in `cuda/sph_consts.h`).
pub const LANE_COUNTS: [usize; MF_LANES_MAX.trailing_zeros() as usize + 1] = {
    let mut l = [1; MF_LANES_MAX.trailing_zeros() as usize + 1];
    let mut k = 1;
    while k < l.len() {
        l[k] = 2 * l[k - 1];
        k += 1;
    }
    l
};

/// The schemes of the forces and rates kernels (`MF_SCHEMES` in `cuda/device/entries.cuh`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// With solids: the stress and artificial stress terms.
    Solids,
    /// Fluid-only: no tensor registers; a neighbour's kind from the sign of its vel.w.
    Fluid,
    /// Fluid-only with the terms beyond the paper's fluid scheme compiled out
    /// (`params::lean_scheme`).
    Lean,
}

impl Scheme {
    pub const ALL: [Scheme; 3] = [Scheme::Solids, Scheme::Fluid, Scheme::Lean];

    /// The scheme a scene runs: with solids where it has any (`solids`), else lean where
    /// `lean_scheme` holds, else fluid-only.
    pub fn of(solids: bool, p: &SphParams) -> Scheme {
        match (solids, lean_scheme(p)) {
            (true, _) => Scheme::Solids,
            (false, false) => Scheme::Fluid,
            (false, true) => Scheme::Lean,
        }
    }

    /// What the scheme adds to an entry's stem: `sph_rates_4_2d`, `sph_rates_fluid_4_2d`,
    /// `sph_rates_lean_4_2d`.
    fn infix(self) -> &'static str {
        match self {
            Scheme::Solids => "",
            Scheme::Fluid => "_fluid",
            Scheme::Lean => "_lean",
        }
    }
}

/// How a family's entries are named.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// One entry, `stem` (`extern "C"` in the `.cu`).
    One,
    /// One per dimension, `stem_2d` and `stem_3d` (`MF_ENTRY2`).
    Dims,
    /// One per lane count and dimension, `stem_L_2d` (`MF_LANES_EACH`).
    Lanes,
    /// One per scheme, lane count and dimension, `stem{,_fluid,_lean}_L_2d` (`MF_SCHEMES`).
    Schemes,
}

/// A family of kernels: the entries of one `.cu` function, all with one signature.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    GridHist,
    ScanLocal,
    ScanOne,
    ScanTop,
    GridScatter,
    GridGather,
    Density,
    WallDensity,
    SolidInterface,
    GradRho,
    Forces,
    Rates,
    ForcesRates,
    StepSize,
    Kick,
    Drift,
    DriftKick,
    Diagnostics,
    Check,
    CheckRecord,
    ParamsLayout,
    SamplePoints,
    MonitorEos,
    WallForce,
    WallForceFluid,
    SumPartials,
    BodyLoad,
    BodyLoadFluid,
    BodyKick,
    BodyVelocity,
    BodyDrift,
    BodyMove,
    TlSlots,
    TlStress,
    TlForces,
    TlDrift,
    ExchangeMark,
    ExchangeTotal,
    ExchangePack,
    ExchangeUnpack,
    ExchangeCompact,
    ExchangeRestride,
    OpenMark,
    OpenApply,
    OpenBorn,
    BufferDensity,
    ViewMark,
    ViewFill,
    ViewSplat,
    ViewPixels,
}

/// What the table says of a family.
pub struct Spec {
    /// The CUDA module, `cuda/<module>.cu`.
    pub module: &'static str,
    /// The entry names' stem.
    pub stem: &'static str,
    pub shape: Shape,
    /// The C parameter list of every entry; `launch/` pushes the arguments in this order.
    pub signature: &'static str,
}

/// The parameters of the forces kernels, which the forces kernels follow with the record of
/// accepted candidates and the fused forces-and-rates kernels with theirs (`more`).
macro_rules! forces_params {
    ($($more:literal)?) => {
        concat!(
            "const SphParams p, unsigned n, const unsigned* cell_start, \
             const unsigned char* stamp, const float* pos, \
             const float* vel, const float* rho, const float* pr, const unsigned char* kind, \
             const unsigned* group, const float* stress, const float* art, const float* iface, \
             const unsigned* id, \
             const float* surf, float* acc, unsigned* red"
            $(, ", ", $more)?
        )
    };
}

/// The parameters of a floating body's load (`cuda/monitor.cu`'s `sph_body_load*`), with and
/// without solids.
const BODY_LOAD_PARAMS: &str =
    "const SphParams p, unsigned n, const MfBody* bodies, unsigned body, \
     const unsigned* cell_start, const float* pos, const float* vel, const float* rho, \
     const float* pr, const unsigned char* kind, const unsigned* group, const float* stress, \
     const unsigned* id, const float* surf, double* partial";

/// The parameters of the force monitors' pair sums (`cuda/monitor.cu`), with and without
/// solids.
const WALL_FORCE_PARAMS: &str =
    "const SphParams p, unsigned n, unsigned wall_group, unsigned slot, \
     const unsigned* cell_start, const float* pos, const float* vel, const float* rho, \
     const float* pr, const unsigned char* kind, const unsigned* group, const float* stress, \
     const unsigned* id, const float* surf, double* partial";

impl Family {
    /// Every family, in the order of the discriminants.
    pub const ALL: [Family; 50] = [
        Family::GridHist,
        Family::ScanLocal,
        Family::ScanOne,
        Family::ScanTop,
        Family::GridScatter,
        Family::GridGather,
        Family::Density,
        Family::WallDensity,
        Family::SolidInterface,
        Family::GradRho,
        Family::Forces,
        Family::Rates,
        Family::ForcesRates,
        Family::StepSize,
        Family::Kick,
        Family::Drift,
        Family::DriftKick,
        Family::Diagnostics,
        Family::Check,
        Family::CheckRecord,
        Family::ParamsLayout,
        Family::SamplePoints,
        Family::MonitorEos,
        Family::WallForce,
        Family::WallForceFluid,
        Family::SumPartials,
        Family::BodyLoad,
        Family::BodyLoadFluid,
        Family::BodyKick,
        Family::BodyVelocity,
        Family::BodyDrift,
        Family::BodyMove,
        Family::TlSlots,
        Family::TlStress,
        Family::TlForces,
        Family::TlDrift,
        Family::ExchangeMark,
        Family::ExchangeTotal,
        Family::ExchangePack,
        Family::ExchangeUnpack,
        Family::ExchangeCompact,
        Family::ExchangeRestride,
        Family::OpenMark,
        Family::OpenApply,
        Family::OpenBorn,
        Family::BufferDensity,
        Family::ViewMark,
        Family::ViewFill,
        Family::ViewSplat,
        Family::ViewPixels,
    ];

    /// The table.
    pub const fn spec(self) -> Spec {
        use Shape::*;
        let (module, stem, shape, signature) = match self {
            Family::GridHist => (
                "grid",
                "sph_grid_hist",
                Dims,
                "const SphParams p, unsigned n, const float* pos, unsigned* cell, unsigned* count",
            ),
            Family::ScanLocal => (
                "grid",
                "sph_scan_local",
                One,
                "unsigned n_cells, const unsigned* count, unsigned* local, unsigned* bsum",
            ),
            Family::ScanOne => (
                "grid",
                "sph_scan_one",
                One,
                "unsigned n_cells, const unsigned* count, unsigned* local, unsigned* bsum",
            ),
            Family::ScanTop => (
                "grid",
                "sph_scan_top",
                One,
                "unsigned n_blocks, unsigned* bsum",
            ),
            Family::GridScatter => (
                "grid",
                "sph_grid_scatter",
                One,
                "unsigned n, const unsigned* cell, const unsigned* local, const unsigned* bsum, \
                 unsigned* count, unsigned* order, unsigned* red, unsigned char* epoch",
            ),
            Family::GridGather => (
                "grid",
                "sph_grid_gather",
                Dims,
                "const SphParams p, unsigned n, unsigned n_cells, unsigned eos, \
                 const unsigned* order, const unsigned* local, const unsigned* bsum, \
                 unsigned* cell_start, unsigned char* stamp, const unsigned* id, \
                 const unsigned char* kind, \
                 const unsigned* group, const float* pos, const float* vel, const float* rho, \
                 const float* pr, const float* stress, const float* rho_dev, unsigned* id2, \
                 unsigned char* kind2, unsigned* group2, float* pos2, float* vel2, float* rho2, \
                 float* pr2, float* stress2, float* rho_dev2",
            ),
            Family::Density => (
                "density",
                "sph_density",
                Lanes,
                "const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, \
                 float* vel, const unsigned char* kind, float* rho, float* pr, float* rho_dev, \
                 const float* stress, float* art",
            ),
            Family::WallDensity => (
                "density",
                "sph_wall_density",
                Dims,
                "const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, \
                 float* vel, const unsigned char* kind, const unsigned* id, const unsigned* group, \
                 const float* surface, const double* clock, const MfBody* bodies, \
                 unsigned n_bodies, const double* series, float* rho, float* pr",
            ),
            Family::SolidInterface => (
                "density",
                "sph_solid_interface",
                Dims,
                "const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, \
                 const float* rho, const float* pr, const unsigned char* kind, float* iface",
            ),
            Family::GradRho => (
                "rates",
                "sph_grad_rho",
                Dims,
                "const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, \
                 const float* vel, const float* rho, const unsigned char* kind, \
                 const unsigned* group, float* grad",
            ),
            Family::Forces => (
                "forces",
                "sph_forces",
                Schemes,
                forces_params!("unsigned* pair_a, unsigned* pair_b"),
            ),
            Family::Rates => (
                "rates",
                "sph_rates",
                Schemes,
                "const SphParams p, unsigned n, const float* dt_dev, const unsigned* cell_start, \
                 const unsigned char* stamp, const float* pos, \
                 const float* vel, const float* rho, const unsigned char* kind, \
                 const unsigned* group, const float* stress, const float* grad_rho, \
                 float* drho, float* xsph, float* rate, const unsigned* pair_a, \
                 const unsigned* pair_b",
            ),
            Family::ForcesRates => (
                "forces_rates",
                "sph_forces_rates",
                Schemes,
                forces_params!("const float* grad_rho, float* drho, float* xsph, float* rate"),
            ),
            Family::StepSize => (
                "reduce",
                "sph_step_size",
                One,
                "const SphParams p, unsigned* red, float* dt_out",
            ),
            Family::Kick => (
                "integrate",
                "sph_kick",
                Dims,
                "const SphParams p, unsigned n, float* dt_dev, const unsigned* red, \
                 double* time, const unsigned char* kind, const unsigned* group, \
                 const float* pos, float* vel, const float* acc, const double* series",
            ),
            Family::Drift => (
                "integrate",
                "sph_drift",
                Dims,
                "const SphParams p, unsigned n, float* dt_dev, double* time, \
                 const unsigned char* kind, const unsigned* group, float* pos, \
                 const float* vel, const float* xsph, float* rho, const float* drho, \
                 float* rho_dev, float* stress, const float* rate, unsigned* cell, \
                 unsigned* count, const double* series",
            ),
            Family::DriftKick => (
                "integrate",
                "sph_drift_kick",
                Dims,
                "const SphParams p, unsigned n, float* dt_dev, const unsigned* red, double* time, \
                 const unsigned char* kind, const unsigned* group, float* pos, float* vel, \
                 const float* xsph, float* rho, const float* drho, float* rho_dev, \
                 float* stress, const float* rate, const float* acc, unsigned* cell, \
                 unsigned* count",
            ),
            Family::Diagnostics => (
                "reduce",
                "sph_diagnostics",
                Dims,
                "const SphParams p, unsigned n, const unsigned char* kind, const float* pos, \
                 const float* vel, const float* rho, double* partial, unsigned* maxes, \
                 unsigned* counts",
            ),
            Family::Check => (
                "reduce",
                "sph_check",
                Dims,
                "const SphParams p, unsigned n, const unsigned char* kind, const float* pos, \
                 const float* vel, const float* rho, unsigned long long* first",
            ),
            Family::CheckRecord => (
                "reduce",
                "sph_check_record",
                Dims,
                "unsigned long long step, unsigned long long* first, double* clock, \
                 unsigned* rec, const unsigned* id, const unsigned char* kind, \
                 const float* pos, const float* vel, const float* rho",
            ),
            Family::ParamsLayout => (
                "reduce",
                "sph_params_layout",
                One,
                "const SphParams p, unsigned* out",
            ),
            Family::SamplePoints => (
                "probes",
                "sph_sample_points",
                Dims,
                "const SphParams p, unsigned n_points, const float* points, unsigned walls, \
                 const unsigned* cell_start, const float* pos, const float* vel, \
                 const float* rho, const unsigned char* kind, float* out",
            ),
            Family::MonitorEos => (
                "monitor",
                "sph_monitor_eos",
                One,
                "const SphParams p, unsigned n, const unsigned char* kind, const float* rho, \
                 const float* rho_dev, float* pr, float* vel",
            ),
            Family::WallForce => ("monitor", "sph_wall_force", Dims, WALL_FORCE_PARAMS),
            Family::WallForceFluid => ("monitor", "sph_wall_force_fluid", Dims, WALL_FORCE_PARAMS),
            Family::BodyLoad => ("monitor", "sph_body_load", Dims, BODY_LOAD_PARAMS),
            Family::BodyLoadFluid => ("monitor", "sph_body_load_fluid", Dims, BODY_LOAD_PARAMS),
            Family::BodyKick => (
                "bodies",
                "sph_body_kick",
                One,
                "const SphParams p, unsigned n_bodies, const float* dt_dev, const double* load, \
                 MfBody* bodies",
            ),
            Family::BodyVelocity => (
                "bodies",
                "sph_body_velocity",
                Dims,
                "unsigned n, unsigned n_bodies, const MfBody* bodies, const unsigned char* kind, \
                 const unsigned* group, const float* pos, float* vel",
            ),
            Family::BodyDrift => (
                "bodies",
                "sph_body_drift",
                One,
                "unsigned n_bodies, const float* dt_dev, MfBody* bodies",
            ),
            Family::BodyMove => (
                "bodies",
                "sph_body_move",
                Dims,
                "unsigned n, unsigned n_bodies, const MfBody* bodies, const unsigned char* kind, \
                 const unsigned* group, float* pos",
            ),
            Family::SumPartials => (
                "reduce",
                "sph_sum_partials",
                One,
                "unsigned n_blocks, const double* partial, double* out",
            ),
            Family::TlSlots => (
                "tlsph",
                "sph_tl_slots",
                One,
                "unsigned n, unsigned n_index, const unsigned* id, const unsigned char* kind, \
                 const unsigned* index, unsigned* slot",
            ),
            Family::TlStress => (
                "tlsph",
                "sph_tl_stress",
                Dims,
                "const SphParams p, unsigned n, unsigned n_solid, const unsigned* slot, \
                 const unsigned* start, const unsigned* nbr, const float* x0, const float* vol, \
                 const float* corr, const float* quad, const float* face, \
                 const unsigned* face_clamp, const float* disp, float* grad, float* pk1_corr, \
                 float* stress",
            ),
            Family::TlForces => (
                "tlsph",
                "sph_tl_forces",
                Dims,
                "const SphParams p, unsigned n_solid, const unsigned* slot, const unsigned* start, \
                 const unsigned* nbr, const float* x0, const float* vol, const float* face, \
                 const unsigned* face_clamp, const unsigned* face_start, const float* face_pts, \
                 const float* disp, const float* grad, const float* pk1_corr, const float* pos, \
                 float* acc, unsigned* red",
            ),
            Family::TlDrift => (
                "tlsph",
                "sph_tl_drift",
                Dims,
                "const SphParams p, unsigned n_solid, const float* dt_dev, const double* time, \
                 const unsigned* slot, const unsigned* group, const float* pos, \
                 const float* vel, const float* xsph, float* disp, const double* series",
            ),
            Family::OpenMark => (
                "open",
                "sph_open_mark",
                Dims,
                "const SphParams p, unsigned n, const unsigned char* kind, const unsigned* group, \
                 const float* pos, unsigned* mark",
            ),
            Family::OpenApply => (
                "open",
                "sph_open_apply",
                Dims,
                "const SphParams p, unsigned n, const unsigned char* kind, unsigned* group, \
                 const float* pos, const float* vel, unsigned* mark, double* tally",
            ),
            Family::OpenBorn => (
                "open",
                "sph_open_born",
                Dims,
                "const SphParams p, unsigned base, unsigned m, unsigned next_id, unsigned* id, \
                 const unsigned* group, float* pos",
            ),
            Family::BufferDensity => (
                "open",
                "sph_buffer_density",
                Dims,
                "const SphParams p, unsigned n, const unsigned* cell_start, const float* pos, \
                 float* vel, const unsigned char* kind, const unsigned* group, float* rho, \
                 float* pr",
            ),
            Family::ExchangeMark => (
                "exchange",
                "sph_exchange_mark",
                Dims,
                "const SphParams p, unsigned n, unsigned halo, unsigned axis, float lo, float hi, \
                 float width, unsigned periodic, float pmin, float pmax, const float* pos, \
                 unsigned* mark",
            ),
            Family::ExchangeTotal => (
                "exchange",
                "sph_exchange_total",
                One,
                "unsigned n, const unsigned* local, const unsigned* bsum, unsigned* total",
            ),
            Family::ExchangePack => (
                "exchange",
                "sph_exchange_pack",
                Dims,
                "unsigned n, unsigned words, const unsigned* mark, const unsigned* local, \
                 const unsigned* bsum, const unsigned* id, const unsigned char* kind, \
                 const unsigned* group, const float* pos, const float* vel, const float* rho, \
                 const float* pr, const float* stress, const float* rho_dev, unsigned* out",
            ),
            Family::ExchangeUnpack => (
                "exchange",
                "sph_exchange_unpack",
                Dims,
                "unsigned m, unsigned base, unsigned stride, unsigned words, const unsigned* in, \
                 unsigned* id, unsigned char* kind, unsigned* group, float* pos, float* vel, \
                 float* rho, float* pr, float* stress, float* rho_dev",
            ),
            Family::ExchangeCompact => (
                "exchange",
                "sph_exchange_compact",
                Dims,
                "unsigned n, unsigned kept, const unsigned* mark, const unsigned* local, \
                 const unsigned* bsum, const unsigned* id, const unsigned char* kind, \
                 const unsigned* group, const float* pos, const float* vel, const float* rho, \
                 const float* pr, const float* stress, const float* rho_dev, unsigned* id2, \
                 unsigned char* kind2, unsigned* group2, float* pos2, float* vel2, float* rho2, \
                 float* pr2, float* stress2, float* rho_dev2",
            ),
            Family::ExchangeRestride => (
                "exchange",
                "sph_exchange_restride",
                One,
                "unsigned n_old, unsigned n_new, unsigned planes, const float* src, float* dst",
            ),
            Family::ViewMark => (
                "view",
                "sph_view_mark",
                One,
                "unsigned n, const unsigned char* kind, unsigned* mark_fluid, unsigned* mark_solid",
            ),
            Family::ViewFill => (
                "view",
                "sph_view_fill",
                Dims,
                "const SphParams p, unsigned n, unsigned shown, unsigned hidden, const float* pos, \
                 const float* vel, const float* rho, const float* pr, const unsigned char* kind, \
                 float* out_pos, float* out_val, unsigned char* out_kind, unsigned* range, \
                 const unsigned* f_local, const unsigned* f_bsum, const unsigned* s_local, \
                 const unsigned* s_bsum, unsigned n_fluid, unsigned n_solid",
            ),
            Family::ViewSplat => (
                "view",
                "sph_view_splat",
                One,
                "unsigned first, unsigned n, const float* pos, const unsigned char* kind, \
                 unsigned hidden, const float* cam, unsigned width, unsigned height, unsigned long long* key",
            ),
            Family::ViewPixels => (
                "view",
                "sph_view_pixels",
                One,
                "unsigned pixels, const unsigned long long* key, const float* pos, \
                 const float* val, const unsigned char* kind, float* out4, unsigned char* out_kind",
            ),
        };
        Spec {
            module,
            stem,
            shape,
            signature,
        }
    }

    /// The family's entries in dimension `dim`, in storage order (scheme, then lane count).
    pub fn entries(self, dim: usize) -> Vec<String> {
        let Spec { stem, shape, .. } = self.spec();
        let lanes = |infix: &str| -> Vec<String> {
            LANE_COUNTS
                .iter()
                .map(|l| format!("{stem}{infix}_{l}_{dim}d"))
                .collect()
        };
        match shape {
            Shape::One => vec![stem.to_string()],
            Shape::Dims => vec![format!("{stem}_{dim}d")],
            Shape::Lanes => lanes(""),
            Shape::Schemes => Scheme::ALL.iter().flat_map(|s| lanes(s.infix())).collect(),
        }
    }
}

/// One loaded kernel, where it came from and its signature (for error messages).
pub struct Kernel {
    pub(super) f: CudaFunction,
    module: &'static str,
    name: String,
    signature: &'static str,
}

impl Kernel {
    /// Panics with the kernel's name and module where a launch failed.
    pub(super) fn check(&self, r: Result<(), DriverError>) {
        if let Err(e) = r {
            panic!(
                "CUDA launch of kernel `{}({})` (module `{}`) failed: {e:?}",
                self.name, self.signature, self.module
            );
        }
    }
}

/// Every kernel of one dimension, loaded by the table.
pub struct Kernels {
    /// Per family (`Family as usize`), its entries in `Family::entries` order.
    entries: Vec<Vec<Kernel>>,
    /// Threads per particle in the neighbour kernels (density, forces, rates), one of
    /// `LANE_COUNTS`; set by the solver from the system size.
    pub lanes: usize,
}

impl Kernels {
    pub fn load(dev: &Device, dim: usize) -> Result<Kernels, BackendError> {
        let mut entries = Vec::with_capacity(Family::ALL.len());
        for (i, f) in Family::ALL.into_iter().enumerate() {
            debug_assert_eq!(f as usize, i, "Family::ALL is out of order");
            let Spec {
                module, signature, ..
            } = f.spec();
            let loaded = f
                .entries(dim)
                .into_iter()
                .map(|name| {
                    Ok(Kernel {
                        f: dev.function(module, &name)?,
                        module,
                        name,
                        signature,
                    })
                })
                .collect::<Result<Vec<_>, BackendError>>()?;
            entries.push(loaded);
        }
        Ok(Kernels { entries, lanes: 1 })
    }

    /// The one entry of a family without lane counts (`Shape::One` or `Shape::Dims`).
    pub fn get(&self, f: Family) -> &Kernel {
        debug_assert!(matches!(f.spec().shape, Shape::One | Shape::Dims));
        &self.entries[f as usize][0]
    }

    /// The entry of neighbour family `f` at the current lane count, for a scene of scheme
    /// `s` (a family without schemes has one entry for all of them).
    pub fn neighbour(&self, f: Family, s: Scheme) -> &Kernel {
        let l = LANE_COUNTS
            .iter()
            .position(|&l| l == self.lanes)
            .unwrap_or_else(|| {
                panic!(
                    "no kernel entry for {} lanes (have {LANE_COUNTS:?})",
                    self.lanes
                )
            });
        let i = match f.spec().shape {
            Shape::Lanes => l,
            Shape::Schemes => s as usize * LANE_COUNTS.len() + l,
            shape => panic!("{f:?} has no lane counts ({shape:?})"),
        };
        &self.entries[f as usize][i]
    }
}

#[cfg(test)]
#[path = "kernels_tests.rs"]
mod tests;
