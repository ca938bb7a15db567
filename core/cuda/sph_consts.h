/*
 * meshfree: the numbers both languages use, one home each. The CUDA side includes this
 * header; bindgen turns its MF_* macros into Rust constants (`crate::consts`, see build.rs).
 * Integers reach Rust as u32, floats as f64: the Rust side takes a float `as f32`, which is
 * the float nvcc makes of the `f` literal (tests/bindings.rs checks every one).
 *
 * C99, macros only. The enumerations of SphParams fields (MF_KERNEL_*, MF_KIND_*, ...) live
 * with the struct in sph_params.h.
 */
#ifndef MESHFREE_SPH_CONSTS_H
#define MESHFREE_SPH_CONSTS_H

/* ---- launch geometry ---- */

/* Threads per block of the per-particle kernels (the scans take MF_SCAN_BLOCK). */
#define MF_BLOCK 256

/* The grid build's scan of the cell counts: blocks of MF_SCAN_BLOCK threads, each thread
 * taking MF_SCAN_ITEMS consecutive cells (one 16-byte load and store), so MF_SCAN_CELLS cells
 * per block. */
#define MF_SCAN_BLOCK 1024
#define MF_SCAN_ITEMS 4
#define MF_SCAN_CELLS (MF_SCAN_BLOCK * MF_SCAN_ITEMS)

/* Lanes per particle in the neighbour kernels (density, forces, rates): each particle's
 * candidate ranges are split over L consecutive threads (lane l takes every L-th candidate,
 * so a warp's loads are contiguous), then the partial sums are combined by shuffles in a
 * fixed order. Deterministic; the summation order differs from the CPU's only in this
 * split. Every power of two L from 1 to MF_LANES_MAX has its own kernel entries
 * (`name_L_2d`, `name_L_3d`), which MF_LANES_EACH lists for the CUDA entry macros; the
 * solver picks L by system size (`lanes_for` in src/backend/cuda/mod.rs). */
#define MF_LANES_MAX 8
#define MF_LANES_EACH(X) X(1) X(2) X(4) X(8)

/* ---- neighbour grid ---- */

/* Relative slack of the cell pruning in `rows`: a cell is skipped only when it is farther
 * than (1 + slack) x the support, so rounding never drops a neighbour. [-] */
#define MF_PRUNE_SLACK 1e-4f

/* ---- the health check (Solver::check) ---- */

/* Fault classes, in the order the check tests them. */
#define MF_FAULT_NON_FINITE_POSITION 1
#define MF_FAULT_NON_FINITE_VELOCITY 2
#define MF_FAULT_NON_FINITE_DENSITY 3
#define MF_FAULT_DENSITY_RANGE 4 /* outside [LOW, HIGH] x the reference density */
#define MF_FAULT_ESCAPED 5       /* outside the domain on a closed axis */

/* The device's first fault: the lowest (slot << MF_FAULT_SLOT_SHIFT) | fault class (kept
 * as its complement by atomicMax, so that 0 means none). */
#define MF_FAULT_SLOT_SHIFT 8
/* Words of a queued check's fault record (sph_check_record: id, kind, position, velocity,
 * density, step, time). */
#define MF_FAULT_RECORD_WORDS 13

/* Density outside [LOW, HIGH] x the reference density counts as a blow-up. LOW is loose
 * because summation density, eq. (8), gives an isolated splash particle about 0.27 rho0. [-] */
#define MF_DENSITY_SANE_LOW 0.1f
#define MF_DENSITY_SANE_HIGH 2.0f

/* ---- particle shifting (Lind et al. 2012, Sun et al. 2017) ---- */

/* R of the anti-clumping factor 1 + R (W_ij / W(dx))^4 in the shifting sum (Sun et al.
 * 2017). [-] */
#define MF_SHIFT_ANTI_CLUMP 0.2f
/* The free-surface test of the shifting: a fluid particle whose position divergence
 * -sum_j V_j r_ij . grad_i W_ij (d inside the fluid, about half of it at a free surface) is
 * below d - MF_SHIFT_SURFACE_MARGIN is not shifted (Lind, Xu, Stansby & Rogers 2012 take 1.5
 * in 2D). [-] */
#define MF_SHIFT_SURFACE_MARGIN 0.5f

/* ---- small matrices ---- */

/* A moment matrix sum_j V_j (x_j - x_i) (x) grad_i W_ij (the kernel-gradient correction of
 * eq. (15), the renormalised density gradients) with |det| at or below this counts as
 * singular, and the correction is skipped. [-] */
#define MF_MOMENT_DET_MIN 1e-3f

/* The cyclic Jacobi eigen-decomposition of the artificial stress: at most MF_JACOBI_SWEEPS
 * sweeps, ending when the off-diagonal sum is at most MF_JACOBI_OFF_MIN; an off-diagonal
 * entry at most MF_JACOBI_PIVOT_MIN is not rotated. */
#define MF_JACOBI_SWEEPS 8
#define MF_JACOBI_OFF_MIN 1e-20f
#define MF_JACOBI_PIVOT_MIN 1e-30f

/* mDBC (English et al. 2022; device/mdbc.cuh, src/physics/mdbc.rs): the smallest |det A| of
 * a ghost node's corrected system (dimensionless) solved at first order; below it (too few
 * fluid neighbours, on too few sides) the Shepard sum. The reference code's `determlimit`. */
#define MF_MDBC_DET_MIN 1e-3
/* ... and the smallest kernel sum sum V W [-] at the ghost node solved at first order: a ghost
 * node barely in the fluid (by a free surface) takes the Shepard sum (DualSPHysics 5.2's 0.1). */
#define MF_MDBC_SUM_MIN 0.1
/* ... and the largest scaled condition number dx^2 |A| |A^-1| (infinity norms) solved at first
 * order: an ill-conditioned ghost node (between a wall and a free surface) takes the Shepard
 * sum (DualSPHysics 5.2's 50). */
#define MF_MDBC_COND_MAX 50.0

/* ---- probes (Solver::sample_points) ---- */

/* Floats per point that the probes kernel writes (sph_sample_points, device/probes.cuh):
 * pressure, velocity x, y, z, density, colour, the neighbour count (an unsigned's bits), 0. */
#define MF_SAMPLE_FLOATS 8

/* ---- time step ---- */

/* The viscous limit of the step, dt <= MF_VISCOUS_DT h^2 / nu (with laminar viscosity). [-] */
#define MF_VISCOUS_DT 0.125f

/* ---- the viewer's vertex fill (cuda/view.cu) ---- */

/* The quantity that colours the particles (`solver::Shown`): speed |v| [L/T], pressure
 * [M L^-1 T^-2], density [M L^-3], the particle's kind (0 fluid, 1 solid, 2 boundary). */
#define MF_SHOWN_SPEED 0
#define MF_SHOWN_PRESSURE 1
#define MF_SHOWN_DENSITY 2
#define MF_SHOWN_KIND 3

#endif /* MESHFREE_SPH_CONSTS_H */
