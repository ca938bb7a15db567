/*
 * meshfree: the one parameter struct, shared by every CUDA kernel (passed by value) and the
 * Rust side (bindgen turns it into `crate::physics::params::SphParams`; the CPU backend reads it too).
 *
 * C99, fixed-width scalars and fixed arrays only: no pointers, no float3, no bool.
 * Units: the scenes are dimensionless like the paper's; [L] length, [T] time, [M] mass,
 * d = `dim`. Derived fields (marked "derived") are filled by `params::derive` on the host,
 * never by hand.
 * A field that a scene key sets is named by that key (`core/src/scene/scheme.rs` declares each):
 * `density_diffusion` is [fluid] density_diffusion; a [solid] key the [fluid] table also has
 * takes `solid_` (`solid_density_diffusion`).
 */
#ifndef MESHFREE_SPH_PARAMS_H
#define MESHFREE_SPH_PARAMS_H

#include <stdint.h>

/* Smoothing kernels (`kernel`). Both have support radius 2h. */
#define MF_KERNEL_CUBIC_SPLINE 0 /* Monaghan 1992 cubic B-spline */
#define MF_KERNEL_WENDLAND_C2 1  /* Wendland 1995 C2 */

/* Density forms (`density_form`). */
#define MF_DENSITY_SUMMATION 0  /* eq. (8), as the paper */
#define MF_DENSITY_CONTINUITY 1 /* d rho/dt = sum_j m_j v_ij . grad_i W_ij */

/* Time integrators (`integrator`). */
#define MF_INTEGRATOR_EULER 0            /* eq. (19) forward Euler: x += dt (v^n + xsph) */
#define MF_INTEGRATOR_SYMPLECTIC_EULER 1 /* semi-implicit: x += dt (v^{n+1} + xsph) */
#define MF_INTEGRATOR_LEAPFROG 2         /* the same with v at half steps, v += (dt_prev + dt) / 2 a, and the rates at the drift's midpoint */

/* Neighbour grid: cells of at least support / MF_CELL_REACH per axis, so the support of a
 * particle spans at most MF_CELL_REACH cells on each side of its own (finer cells: fewer
 * candidates outside the support). */
#define MF_CELL_REACH 2

/* The most driven groups (objects with a `motion`) a scene may have. */
#define MF_MAX_DRIVEN 8

/* The most open boundaries (`[[open_boundaries]]`: inlets and outlets) a scene may have. */
#define MF_MAX_OPEN 4

/* What an open boundary is (`MfOpen::kind`). */
#define MF_OPEN_INLET 0  /* particles made in its buffer at a prescribed velocity enter the fluid */
#define MF_OPEN_OUTLET 1 /* the fluid that enters its buffer coasts out and is removed */

/* Particle kinds (the `kind` array). */
#define MF_KIND_FLUID 0
#define MF_KIND_SOLID 1
#define MF_KIND_BOUNDARY 2

/* How dynamic walls enter the laminar viscosity (`no_slip`). */
#define MF_NO_SLIP_WALL_VELOCITY 0 /* with the wall particles' own velocity (the default) */
#define MF_NO_SLIP_MORRIS 1        /* Morris, Fox & Zhu 1997 (J. Comput. Phys. 136, 214),
                                      boundary conditions: the wall particle's velocity
                                      extrapolated across the wall surface */

/* What the fluid's density diffusion acts on (`density_diffusion_form`). */
#define MF_DIFFUSION_MOLTENI 0   /* rho_i - rho_j (Molteni & Colagrossi 2009) */
#define MF_DIFFUSION_FOURTAKAS 1 /* its departure from hydrostatics (Fourtakas et al. 2019) */
#define MF_DIFFUSION_ANTUONO 2   /* less the renormalised gradients' part (Antuono et al. 2010) */

/* What a pair across two objects exchanges in eq. (16) (`interface`). */
#define MF_INTERFACE_PRESSURE 0 /* the pressure part -P I (Antoci, Gallati & Sibilla 2007) */
#define MF_INTERFACE_STRESS 1   /* the whole stress -P I + S: the paper's eq. (16) */

/* What pressure an elastic body's particles present to the fluid (`solid_fluid_pressure`). */
#define MF_SOLID_FLUID_PRESSURE_EXTRAPOLATED 1 /* the fluid's, extrapolated to them (Adami, Hu &
                                                  Adams 2012), as to walls' */
#define MF_SOLID_FLUID_PRESSURE_OWN 0          /* the body's own P = c_s^2 (rho - rho0_s) of its
                                                  continuity density: the paper's, the default */

/* The stress the artificial stress is taken from (`artificial_stress_from`). */
#define MF_ART_STRESS_FROM_STRESS 0     /* sigma = -P I + S (Gray, Monaghan & Swift 2001) */
#define MF_ART_STRESS_FROM_DEVIATORIC 1 /* S alone */

/* The elastic solid's formulation (`solid_formulation`). */
#define MF_SOLID_JAUMANN 0           /* updated Lagrangian, the Jaumann stress rate: the paper's
                                        eqs. (11)-(16) */
#define MF_SOLID_TOTAL_LAGRANGIAN 1  /* total Lagrangian (O'Connor & Rogers 2021): the stress
                                        from the deformation gradient on the reference
                                        configuration, Saint Venant-Kirchhoff */

/* How wall particles act (`wall_coupling`). */
#define MF_WALL_COUPLING_LENNARD_JONES_ONLY 0 /* eq. (17) alone: the paper's walls */
#define MF_WALL_COUPLING_DYNAMIC 1            /* dynamic walls (Crespo et al. 2007), with eq. (17) */
#define MF_WALL_COUPLING_MDBC 2               /* modified dynamic walls (English et al. 2022): each
                                                 wall particle's density from its ghost node in
                                                 the fluid (density.cu), no continuity of its
                                                 own; the rest as dynamic walls */

/* A driven object's prescribed rigid motion (`motion` of a wall or a solid; evaluated by
 * `motion_*` in device/motion.cuh, twin src/physics/motion.rs). Its particles move with a pivot
 * c(t) = pivot + s(t) and turn about it by theta(t) about `axis`:
 *   x(t) = c(t) + R(axis, theta(t)) (x(0) - pivot),
 *   s(t)     = velocity I(t) + r(t) amplitude (sin(2 pi t / period + phase) - sin phase)  [L],
 *   theta(t) = rate I(t) + r(t) angle (sin(2 pi t / angle_period + angle_phase)
 *              - sin angle_phase)                                                       [rad],
 * r(t) the smooth start over `ramp`, (1 - cos(pi t / ramp)) / 2 up to `ramp`, then 1 (1 without
 * a ramp), and I(t) its integral over [0, t] (t without). A time series from a file adds its
 * displacement and turn to s(t) and theta(t) (`series_*`: knots interpolated linearly or by cubic
 * Hermite, Catmull-Rom tangents). A motion with only `velocity`, no ramp and no series is
 * steady: x += velocity dt, as before time-dependent motion existed. */
#define MF_SERIES_STRIDE 5 /* doubles a knot of a motion's series: t, s_x, s_y, s_z, theta */

typedef struct MfMotion {
    int32_t group;        /* the scene group it moves */
    float velocity[3];    /* [L/T] */
    float amplitude[3];   /* [L] of the translation's oscillation */
    float period;         /* [T] of the translation's oscillation (> 0 where amplitude != 0) */
    float phase;          /* [rad] */
    float pivot[3];       /* [L] the centre of rotation at t = 0 */
    float axis[3];        /* unit axis of rotation; (0, 0, 1) in 2D */
    float rate;           /* [rad/T] steady angular velocity */
    float angle;          /* [rad] amplitude of the angle's oscillation */
    float angle_period;   /* [T] (> 0 where angle != 0) */
    float angle_phase;    /* [rad] */
    float ramp;           /* [T] smooth start; 0: none (a series is not ramped) */
    int32_t series_first; /* the first knot of its series in the knots' table (Setup::motion_series:
                             MF_SERIES_STRIDE doubles a knot: t [T], s_x, s_y, s_z [L], theta [rad],
                             each 0 at t = 0) */
    int32_t series_count; /* its knots; 0: no series */
    int32_t series_cubic; /* 1: cubic Hermite between knots (a continuous velocity); 0: linear */
    int32_t floating;     /* 1: a floating body's group (`MfBody`): the other fields are unused,
                             the kick and the drift leave its particles to the bodies' stages
                             (cuda/bodies.cu), which move them with the body */
} MfMotion;

/* A floating rigid body (`floating` of a wall): the wall's particles, moved rigidly by the
 * force and torque the fluid exerts on them (device/body.cuh, twin src/physics/body.rs). One
 * per floating wall, in an array beside the particles (`Setup::bodies`). Its group is also a
 * driven group (`MfMotion::floating`), so that the walls' shortcuts treat its particles as
 * moving. The first fields come from the scene (the mass properties of the wall's shape);
 * the rest is its state, advanced by the scheme's integrator: the momenta by the kick (at
 * the kick's time: half steps under the leapfrog), the pose by the drift. Double precision
 * throughout: a body's pose is the sum of many small moves. 2D: rotation about z only, the
 * mass and inertia per unit depth. */
typedef struct MfBody {
    int32_t group;          /* the wall's scene group */
    int32_t free;           /* bits 0-2: free to move along x, y, z; bits 3-5: free to turn
                               about x, y, z (a fixed one is held: its force or torque is
                               taken up by the constraint) */
    double mass;            /* [M] */
    double inertia[9];      /* [M L^2] about the centre of mass, in the body's frame (its axes
                               at t = 0: the scene's), row-major */
    double centre[3];       /* [L] the centre of mass */
    double orientation[4];  /* the unit quaternion (w, x, y, z) from the body's frame to the
                               scene's */
    double velocity[3];     /* [L/T] the centre's */
    double momentum[3];     /* [M L^2/T] the angular momentum about the centre, scene frame */
    double omega[3];        /* [rad/T] the angular velocity, scene frame (from momentum) */
    double force[3];        /* [M L T^-2] the fluid's on the particles, of the last kick
                               (gravity's, mass x g, comes on top) */
    double torque[3];       /* [M L^2 T^-2] the fluid's about the centre, of the last kick */
    double contact[3];      /* [M L T^-2] the walls' and other bodies' on the particles, of the
                               last kick: the Lennard-Jones repulsion of eq. (17) between its
                               particles and theirs */
    double contact_torque[3]; /* [M L^2 T^-2] its torque about the centre */
    double shift[3];        /* [L] the last drift's move of the centre */
    double turn[9];         /* the last drift's rotation (scene frame, row-major): a particle
                               at x goes to centre + turn (x - centre + shift) */
} MfBody;

/* An open boundary (`[[open_boundaries]]`; device/open.cuh, twin src/physics/open.rs): a buffer
 * box behind a plane normal to one axis, of `depth` along it. s = sign (x[axis] - plane) [L] is
 * a point's distance on the fluid's side of the plane (negative in the buffer). The buffer's
 * particles are fluid of scene group `group`; the open-boundary stage, first in each step:
 *  - inlet: a buffer particle at s >= 0 joins the fluid (group `through`) and a copy of it
 *    takes its place depth behind (new id); a fluid particle in the box (s < 0) is removed;
 *    the kick sets the buffer's velocity to r(t) f(x) velocity (r the smooth start over
 *    `ramp`, f the profile across the inlet: 1, or parabolic across `profile_axes`);
 *  - outlet: a fluid particle in the box joins the buffer; a buffer particle beyond the box
 *    (s < -depth, or outside it sideways) is removed, and one back at s >= 0 rejoins the
 *    fluid (group `through`); the kick leaves the buffer's velocity as it entered.
 * The drift moves buffer particles at their velocity, without XSPH or shifting; their
 * density follows the continuity equation (or the summation) as the fluid's. */
typedef struct MfOpen {
    int32_t kind;       /* MF_OPEN_INLET or MF_OPEN_OUTLET */
    int32_t group;      /* the buffer's scene group */
    int32_t through;    /* the scene group of the particles that left the buffer for the fluid */
    int32_t axis;       /* 0, 1 or 2: the plane's normal */
    float sign;         /* +1 or -1: the inward normal (into the fluid) is sign e_axis */
    float plane;        /* [L] the plane's coordinate on `axis` */
    float depth;        /* [L] the buffer's depth behind the plane */
    float lo[3];        /* [L] the buffer box's lower corner (sideways extent) */
    float hi[3];        /* [L] its upper corner */
    float velocity[3];  /* [L/T] inlet: the prescribed velocity (pointing into the fluid) */
    float ramp;         /* [T] inlet: the smooth start of the velocity; 0: none */
    int32_t profile_axes; /* inlet: bit a set: the velocity is parabolic across axis a,
                             6 eta (1 - eta) with eta = (x_a - lo_a) / (hi_a - lo_a) (mean 1:
                             `velocity` is the mean); 0: uniform */
    int32_t series_first; /* inlet: the first knot of its scale's time series in the knots' table
                             (Setup::motion_series; the scale in a knot's s_x slot): the velocity
                             is `velocity` times the scale at the time */
    int32_t series_count; /* its knots; 0: no series (scale 1) */
    int32_t series_cubic; /* 1: cubic Hermite between knots; 0: linear */
} MfOpen;

typedef struct SphParams {
    /* ---- geometry and neighbour grid ---- */
    int32_t dim;           /* 2 or 3 */
    int32_t periodic[3];   /* 1 where the axis wraps around the domain, else 0 */
    int32_t grid_dims[3];  /* derived: cells per axis (1 on axes beyond dim) */
    int32_t n_cells;       /* derived: product of grid_dims */
    float domain_min[3];   /* [L] lower corner of the domain */
    float domain_max[3];   /* [L] upper corner of the domain */
    float cell_size[3];    /* derived: [L] cell edge per axis, >= support / MF_CELL_REACH */

    /* ---- kernel, eqs. (1)-(4) ---- */
    int32_t kernel;        /* MF_KERNEL_* */
    float dx;              /* [L] initial particle spacing */
    float h;               /* [L] smoothing length */
    float support;         /* derived: [L] support radius, 2h */
    float support2;        /* derived: [L^2] support^2 */
    float kernel_norm;     /* derived: [L^-d] sigma_d / h^d */

    /* ---- fluid: eqs. (7)-(10) ---- */
    int32_t density_form;  /* MF_DENSITY_* */
    float rho0;            /* [M L^-d] fluid reference density */
    float c0;              /* [L/T] fluid speed of sound */
    float tait_gamma;      /* [-] Tait exponent, 7, eq. (9) */
    float tait_b;          /* derived: [M L^-d L^2/T^2] rho0 c0^2 / gamma, eq. (9) */
    float background_pressure;    /* [M L^-d L^2/T^2] background pressure added to eq. (9) for fluid and
                              dynamic wall particles: keeps a confined flow's pressure positive
                              where it dips (a wake, a vortex core), so the fluid does not tear
                              there (tensile instability); 0 = off (the paper); not for a free
                              surface, where the pressure must fall to zero */
    int32_t gradient_correction; /* 1: the fluid-fluid pressure term of eq. (7) takes the kernel
                              gradient renormalised by the mean of the pair's matrices
                              L = (sum_j V_j (x_j - x_i) (x) grad W_ij)^-T (Bonet & Lok 1999),
                              blended to the plain gradient where the kernel sum falls below
                              0.95 (none below 0.7: the free surface's top row, spray);
                              CPU backend only; 0 = off (the paper) */
    float alpha;           /* [-] artificial viscosity, linear term, eq. (10) */
    float beta;            /* [-] artificial viscosity, quadratic term, eq. (10) */
    float av_eta2;         /* derived: [L^2] 0.001 h^2, singularity guard in mu_ij, eq. (10) */
    float viscosity;              /* [L^2/T] laminar kinematic viscosity (Morris 1997); 0 = off */
    float visc_eta2;       /* derived: [L^2] 0.01 h^2, singularity guard of the laminar term */
    float xsph;        /* [-] XSPH factor epsilon, eq. (18) */

    /* ---- elastic solid: eqs. (11)-(16) ---- */
    float solid_rho0;      /* [M L^-d] solid reference density */
    float solid_c0;        /* [L/T] solid sound speed: P = c^2 (rho - rho0) */
    float shear_modulus;   /* [M L^-d L^2/T^2] mu_s in eq. (12) */
    float artificial_stress;  /* [-] Gray-Monaghan-Swift 2001 artificial stress factor; 0 = off */
    float solid_density_diffusion; /* [-] delta of the density diffusion within one body (solid-solid
                              pairs of `same_body`), with the solid's h c and the correction of
                              Antuono et al. 2010 (renormalised density gradients), which
                              leaves a linear density alone, even where the support is cut:
                              damps the particle-scale (odd-even) pressure mode of a finely
                              resolved bending plate, not its bending; 0 = off (the paper) */
    float artificial_stress_exponent;    /* [-] exponent n of f_ij^n, usually 4 */
    float inv_w_dx;        /* derived: [L^d] 1 / W(dx), normalises f_ij = W_ij / W(dx) */
    int32_t interface; /* 1: a pair across two objects (fluid-solid, two bodies, a body
                                 and a wall) exchanges the whole stress -P I + S, the paper's
                                 eq. (16); 0: its pressure part only (Antoci, Gallati &
                                 Sibilla 2007), the default */
    int32_t wall_contact;  /* 1: solid and wall particles meet (the Lennard-Jones force,
                              eq. (17), the wall pressure, each in the other's density sum),
                              the default; 0: they skip each other, both ways: a body that
                              meets only the fluid and other bodies (e.g. the free end of a
                              gate on the tank floor). A zeroed struct must set it to 1 */
    int32_t artificial_stress_from; /* 1: the artificial stress is taken from the deviatoric
                                      stress S alone, without the pressure of the continuity
                                      density, whose part drove a particle-scale density mode
                                      in a fine plate (docs/reference/accuracy.md); 0: from the whole
                                      sigma = -P I + S (Gray et al. 2001), the default */
    int32_t solid_formulation; /* MF_SOLID_*: JAUMANN, the paper's rate form (the default), or
                                  TOTAL_LAGRANGIAN (O'Connor & Rogers 2021, J. Fluids Struct.
                                  104, 103312): per body the deformation gradient
                                  F = I + sum_j V0_j (u_j - u_i) (x) L_i grad W0_ij on the
                                  reference configuration, the Saint Venant-Kirchhoff stress,
                                  and the internal force sum_j V0_i V0_j (P_i L_i + P_j L_j)
                                  grad W0_ij; the pairs of one body skip eq. (16)'s stress
                                  term; no Jaumann rate, no artificial stress */
    int32_t solid_fluid_pressure; /* MF_SOLID_FLUID_PRESSURE_*: in a pair of a fluid particle
                              and a body's particle b. EXTRAPOLATED: b meets
                              the fluid as fluid of its volume V_b = m_b / rho_b at the
                              fluid's pressure extrapolated to it, P'_b = (sum_f P_f W_bf +
                              rho_f g . (x_b - x_f) W_bf) / sum_f W_bf (Adami, Hu & Adams
                              2012, J. Comput. Phys. 231, 7057, eq. (27) without the body's
                              acceleration), and its Tait density rho'_b, eq. (9) inverted;
                              the pair's force on b is the reaction of the fluid's (momentum
                              conserved), and b's continuity density sums no fluid. OWN (the
                              default): b's own P and rho, its continuity summing the fluid
                              too (the paper) */
    float hourglass;       /* [-] alpha of the hourglass control of Ganzenmueller 2015 (total
                              Lagrangian only): a pair force against the part of the pair's
                              separation that F does not predict; 0 = off */

    /* ---- boundary particles: eq. (17) ---- */
    float lj_c0;           /* [L/T^2] C0, strength of the Lennard-Jones force */
    float lj_r0;           /* [L] r0, the initial particle spacing */
    int32_t lj_p1;         /* 12 */
    int32_t lj_p2;         /* 6 */
    int32_t attractive; /* 1: the force acts for r < support (cohesive beyond r0); 0: r < r0 */
    float lj_range;        /* derived: [L] the force acts for r < lj_range: support where
                              attractive, else lj_r0 */
    int32_t wall_coupling; /* MF_WALL_COUPLING_*: DYNAMIC (Crespo 2007): boundary particles
                              carry density and Tait pressure, enter the pressure and viscosity
                              sums (no leaks, no-slip); MDBC: as DYNAMIC, their density from
                              the ghost node (needs Setup::wall_surface); LENNARD_JONES_ONLY (0):
                              the paper's form. Nonzero: the walls carry density */
    int32_t no_slip;       /* MF_NO_SLIP_*: the laminar term between a fluid particle A and a
                              dynamic wall particle B. MORRIS (Morris, Fox & Zhu 1997): B
                              takes the velocity v_w - (d_B / d_A) (v_A - v_w), with d_A, d_B
                              the distances of A and B from the wall surface and v_w the
                              wall's velocity, so v_AB = beta (v_A - v_w),
                              beta = min(no_slip_beta_max, 1 + d_B / d_A); needs
                              Setup::wall_surface. The laminar term only: pressure, density
                              and artificial viscosity see v_w */
    float no_slip_beta_max; /* [-] cap of beta (Morris et al. 1997: 1.5), against the
                               singular d_B / d_A of fluid next to the surface */
    uint32_t wall_first_id; /* the smallest id of a boundary particle: Setup::wall_surface is
                               indexed by id - wall_first_id (set with it by Scene::setup) */
    int32_t wall_density_floor; /* 1: a dynamic wall particle's continuity density is held at
                               rho >= rho0 after each update (DualSPHysics' DBC, "to prevent
                               absorption of fluid particles by boundaries"): a wall the water
                               leaves returns to p = 0 instead of keeping a tension, and
                               pushes again as soon as water comes back; 0: unclamped */

    /* ---- prescribed motion: pistons, clamps, inflow bands ---- */
    int32_t driven;             /* how many driven objects (0 .. MF_MAX_DRIVEN): the particles of
                                   scene group driven_motion[k].group (any kind) follow
                                   driven_motion[k], whatever the forces (pistons, clamps,
                                   flaps, a rotating tank) */
    MfMotion driven_motion[MF_MAX_DRIVEN];
    int32_t inflow;             /* 1: fluid particles with inflow_lo <= x[inflow_axis] < inflow_hi
                                   have their velocity set to `inflow_velocity` every step (holds
                                   the mean flow of a periodic channel) */
    int32_t inflow_axis;        /* 0, 1 or 2 */
    float inflow_lo;            /* [L] */
    float inflow_hi;            /* [L] */
    float inflow_velocity[3];   /* [L/T] */
    float inflow_ramp;          /* [T] T_r: 0 = the mean flow from the start; > 0: a start from rest,
                                   the band at r(t) inflow_velocity and every particle the kick
                                   integrates outside it accelerated by d(r inflow_velocity)/dt,
                                   r = (1 - cos(pi t / T_r)) / 2 up to T_r, then 1 */
    int32_t open_count;         /* how many open boundaries (0 .. MF_MAX_OPEN) */
    MfOpen open[MF_MAX_OPEN];
    int32_t damping;            /* 1: a damping zone (a sponge layer at a flume's far end, as
                                   DualSPHysics' damping zone, Altomare et al. 2017, Coastal Eng.
                                   127): the kick relaxes a fluid particle's velocity,
                                   v *= exp(-damping_rate r^2 dt), r = (x[damping_axis] -
                                   damping_start) / (damping_end - damping_start) clamped to
                                   [0, 1]: nothing at the start, full strength from the end on */
    int32_t damping_axis;       /* 0, 1 or 2 */
    float damping_start;        /* [L] where the damping begins (either side of the end) */
    float damping_end;          /* [L] where it reaches damping_rate */
    float damping_rate;         /* [1/T] the relaxation rate at full strength */

    /* ---- beyond the paper: cohesion and density diffusion ---- */
    float cohesion;        /* [L^(d+1) M^-1 T^-2] gamma of the fluid-fluid cohesion force of
                              Akinci, Akinci & Teschner 2013 (droplets); 0 = off */
    float density_diffusion;       /* [-] delta of the density-diffusion term of Molteni & Colagrossi
                              2009 in the continuity equation; 0 = off (the paper) */
    int32_t density_diffusion_form;    /* MF_DIFFUSION_*: what the fluid's term diffuses.
                              FOURTAKAS (Fourtakas, Dominguez, Vacondio & Rogers 2019, Comput.
                              Fluids 190, 346): rho_i - rho_j becomes rho_i - rho_j + rho^H_ji,
                              rho^H_ji = rho0 ((1 + rho0 g . (r_j - r_i) / B)^(1 / gamma) - 1),
                              so water at rest under `gravity` diffuses nothing, next to a free
                              surface or a wall too. ANTUONO (Antuono, Colagrossi, Marrone &
                              Molteni 2010, Comput. Phys. Commun. 181, 532): the pair term less
                              (grad rho_i + grad rho_j) . grad W with renormalised gradients
                              (`grad_rho`), zero for any linear density, whatever the
                              direction of gravity. MOLTENI: the plain difference */
    int32_t fluid_density_gradient; /* derived: 1 where the fluid's particles take renormalised
                                       density gradients (`grad_rho`) for their diffusion:
                                       density_diffusion > 0 and density_diffusion_form == MF_DIFFUSION_ANTUONO;
                                       else 0 (solids take them wherever solid_density_diffusion > 0) */
    float shifting;        /* [-] C of the particle shifting velocity
                              dv_i = -C h c0 sum_j V_j (1 + 0.2 (W_ij / W(dx))^4) grad_i W_ij
                              of fluid particles (Lind et al. 2012, with the anti-clumping term of
                              Sun et al. 2017), added to the XSPH velocity of the drift; none at a
                              free surface; 0 = off (the paper) */

    /* ---- body force and time step ---- */
    float gravity[3];      /* [L/T^2] */
    int32_t integrator;    /* MF_INTEGRATOR_* */
    float courant;         /* [-] Courant number for dt, eq. (19) */
    float dt;        /* [T] fixed time step; 0 = adaptive (CFL, force, viscous limits) */

    /* ---- domain decomposition (crate::exchange): set by the run, not by a scene key ---- */
    int32_t own_slab;      /* 1: this solver is one subdomain of a decomposed run and owns the
                              particles with own_lo <= x[own_axis] < own_hi; the others it holds
                              are its halo, copies of particles its neighbours own, and the step
                              size's extremes and the wall forces count only the owned ones
                              (each particle once over the subdomains); 0: one domain, every
                              particle owned */
    int32_t own_axis;      /* 0, 1 or 2: the slab's axis */
    float own_lo;          /* [L] the slab's lower bound (-inf at the domain's low end) */
    float own_hi;          /* [L] its upper bound, excluded (+inf at the high end) */
    int32_t own_solids;    /* 1: hold the solids' arrays (stress, rates, density departure)
                              even where none of the particles this subdomain starts with is
                              solid: the scene has solids, and its halo may bring some */
} SphParams;

#endif /* MESHFREE_SPH_PARAMS_H */
