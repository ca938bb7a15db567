//! Time integration: kick and drift, eqs. (18)-(19). Twin: `cuda/integrate.cu`; parity test
//! `tests/cuda_parity/`.

use rayon::prelude::*;

use crate::physics::dim::Dim;
pub use crate::physics::open::smooth_ramp;
use crate::physics::open::{buffer_velocity, open_index};
use crate::physics::params::{
    SphParams, MF_INTEGRATOR_EULER, MF_INTEGRATOR_LEAPFROG, MF_KIND_BOUNDARY, MF_KIND_FLUID,
    MF_KIND_SOLID,
};
use crate::physics::state::State;

/// Wrap a position into the domain on periodic axes.
#[inline]
pub fn wrap<D: Dim>(p: &SphParams, x: &mut D::V) {
    for a in 0..D::D {
        if p.periodic[a] != 0 {
            let (lo, hi) = (p.domain_min[a], p.domain_max[a]);
            let v = D::comp(*x, a);
            if v < lo {
                D::set_comp(x, a, v + (hi - lo));
            } else if v >= hi {
                D::set_comp(x, a, v - (hi - lo));
            }
        }
    }
}

/// The prescribed velocity at time `t` of a particle at `x` of scene group `group` when that
/// group is driven (a piston, a clamp, a flap: `SphParams::driven_motion`), of any kind,
/// its object's pivot where it was at `t0` (`MfMotion::velocity_at`; a steady motion's
/// velocity as it is). [L/T] Twin: `driven_velocity` in cuda/device/motion.cuh.
#[inline]
pub fn driven_velocity<D: Dim>(
    p: &SphParams,
    series: &[f64],
    group: u32,
    x: D::V,
    t0: f64,
    t: f64,
) -> Option<D::V> {
    let m = &p.driven_motion[p.driven_index(group)?];
    // A floating body's particles: its kick sets them (`bodies::kick`).
    if m.floating != 0 {
        return None;
    }
    Some(if m.steady() {
        D::from3(m.velocity)
    } else {
        m.velocity_at::<D>(series, x, t0, t)
    })
}

/// Where a particle at `x` of scene group `group` is after the step [t0, t0 + dt] when
/// that group is driven (`MfMotion::moved`; a steady motion's x + velocity dt in float).
/// [L] Twin: `driven_moved` in cuda/device/motion.cuh.
#[inline]
pub fn driven_moved<D: Dim>(
    p: &SphParams,
    series: &[f64],
    group: u32,
    x: D::V,
    dt: f32,
    t0: f64,
) -> Option<D::V> {
    let m = &p.driven_motion[p.driven_index(group)?];
    // A floating body's particles: its drift moved them (`bodies::drift`).
    if m.floating != 0 {
        return None;
    }
    Some(if m.steady() {
        x + D::from3(m.velocity) * dt
    } else {
        m.moved::<D>(series, x, t0, t0 + dt as f64)
    })
}

/// Whether a particle lies in the scene's inflow band: a fluid particle with
/// `inflow_lo <= x[inflow_axis] < inflow_hi` while `inflow` is on.
#[inline]
pub fn in_inflow_band<D: Dim>(p: &SphParams, kind: u8, x: D::V) -> bool {
    if p.inflow == 0 || kind as u32 != MF_KIND_FLUID {
        return false;
    }
    let c = D::comp(x, p.inflow_axis as usize);
    c >= p.inflow_lo && c < p.inflow_hi
}

/// The continuity density [M L^-d] of a particle of kind `kind` after its update: a dynamic
/// wall particle's held at rho >= rho0 under `wall_density_floor` (the DBC of DualSPHysics,
/// Crespo et al. 2007: "to prevent absorption of fluid particles by boundaries"), so a wall
/// the water has left sits at p = 0 and pushes as soon as water comes back; unchanged
/// otherwise. Twin: `sph_drift` in `cuda/integrate.cu`.
#[inline]
pub fn wall_density_floor(p: &SphParams, kind: u8, rho: f32) -> f32 {
    if p.wall_density_floor != 0 && kind as u32 == MF_KIND_BOUNDARY {
        rho.max(p.rho0)
    } else {
        rho
    }
}

/// The time a kick spans [T]: dt, except under the leapfrog, whose velocities live at half
/// steps: from the middle of the last step to the middle of this one, (dt_prev + dt) / 2
/// (the first step's dt_prev is 0: a half kick from the initial velocities). With the
/// rates at the drift's midpoint (`rates::rates`) this makes the symplectic Euler second
/// order in dt. Twin: `kick_span` in `cuda/integrate.cu`.
#[inline]
pub fn kick_span(p: &SphParams, dt_prev: f32, dt: f32) -> f32 {
    if p.integrator == MF_INTEGRATOR_LEAPFROG as i32 {
        0.5 * (dt_prev + dt)
    } else {
        dt
    }
}

/// The ramp of a ramped start [-] (`inflow_ramp` T_r > 0, `[inflow] ramp`): the share of
/// the inflow velocity reached at time t [T], r = (1 - cos(pi t / T_r)) / 2 for
/// 0 <= t < T_r (smooth: zero slope at both ends), 0 before, 1 after; 1 without a ramp,
/// and under the forward Euler, whose drift comes before its kick (the scene check rejects
/// that pair: the GPU's fused drift-kick advances the clock in the pass that would read
/// it). In double precision, since the kick takes its difference over one step. Twin:
/// `ramp_share` in `cuda/integrate.cu`.
#[inline]
pub fn ramp_share(p: &SphParams, t: f64) -> f64 {
    if p.inflow == 0 || p.integrator == MF_INTEGRATOR_EULER as i32 {
        1.0
    } else {
        smooth_ramp(p.inflow_ramp as f64, t)
    }
}

/// The time a kick taken at time t (the step's start) [T] brings the velocities to: t + dt,
/// under the leapfrog t + dt / 2 (its velocities live at half steps). Twin: `kick_end` in
/// `cuda/integrate.cu`.
#[inline]
pub fn kick_end(p: &SphParams, t: f64, dt: f32) -> f64 {
    if p.integrator == MF_INTEGRATOR_LEAPFROG as i32 {
        t + 0.5 * dt as f64
    } else {
        t + dt as f64
    }
}

/// The damping zone's factor on a fluid particle's velocity over a kick of `dt` at
/// coordinate `c` along `damping_axis`: exp(-damping_rate r^2 dt), r = (c - start) / (end -
/// start) clamped to [0, 1] (a sponge layer, as DualSPHysics' damping zone, Altomare et al.
/// 2017). Twin: `damping_factor` in cuda/integrate.cu.
#[inline]
pub fn damping_factor(p: &SphParams, c: f32, dt: f32) -> f32 {
    let r = ((c - p.damping_start) / (p.damping_end - p.damping_start)).clamp(0.0, 1.0);
    (-p.damping_rate * r * r * dt).exp()
}

/// The kick over `dt` (its span, `kick_span`) of the step that starts at `t0`, ending at
/// time `t_end` (`kick_end`): an open boundary's buffer at its velocity
/// (`open::buffer_velocity`), else v += dt a
/// for fluid and solid particles; v = r(t_end) inflow_velocity for fluid in the inflow band
/// (`in_inflow_band`; r = 1 without a ramp, `ramp_share`), and under a ramped start the
/// mean flow's increase over the span, (r(t_end) - r(t_end - dt)) inflow_velocity, added
/// to every particle the kick integrates outside the band (a uniform body force: the
/// fluid outside the band keeps pace with it without a pressure gradient along the
/// channel); a driven object's velocity is set to its prescribed value at t_end
/// (`driven_velocity`), whatever the forces; a fluid particle in the damping zone is then
/// slowed (`damping_factor`). `series`: the driven objects' knots (`Setup::motion_series`).
/// [L/T]
pub fn kick<D: Dim>(
    p: &SphParams,
    series: &[f64],
    dt: f32,
    (t0, t_end): (f64, f64),
    s: &mut State<D>,
) {
    let (kind, group, acc, pos) = (&s.kind, &s.group, &s.acc, &s.pos);
    let (r1, r0) = (ramp_share(p, t_end), ramp_share(p, t_end - dt as f64));
    let u = D::from3(p.inflow_velocity);
    let band_v = u * r1 as f32;
    let ramp_dv = u * (r1 - r0) as f32;
    s.vel.par_iter_mut().enumerate().for_each(|(i, v)| {
        // An open boundary's buffer: an inlet's prescribed velocity, an outlet's as it is.
        if let Some(u) = buffer_velocity::<D>(p, series, group[i], pos[i], *v, t_end) {
            *v = u;
            return;
        }
        // Inflow band: the velocity is set, not integrated (holds the mean flow of a
        // periodic channel, wiping the wake that comes round).
        if in_inflow_band::<D>(p, kind[i], pos[i]) {
            *v = band_v;
            return;
        }
        if kind[i] as u32 != MF_KIND_BOUNDARY {
            *v += acc[i] * dt;
            *v += ramp_dv;
            if p.damping != 0 && kind[i] as u32 == MF_KIND_FLUID {
                *v = *v * damping_factor(p, D::comp(pos[i], p.damping_axis as usize), dt);
            }
        }
        // Driven object (piston, clamp, flap): prescribed velocity.
        if let Some(u) = driven_velocity::<D>(p, series, group[i], pos[i], t0, t_end) {
            *v = u;
        }
    });
}

/// The drift: x += dt (v + xsph), eq. (18) (an open boundary's buffer x += dt v); rho += dt d rho/dt (for solids, rho_dev += dt
/// d rho/dt and rho = rho0_s + rho_dev); S += dt dS/dt. With the
/// paper's forward Euler, eq. (19), it runs before the kick (x^{n+1} takes v^n); with the
/// symplectic Euler after it (x^{n+1} takes v^{n+1}). Boundary particles stay put (their
/// density changes with dynamic walls), except a driven object, which follows its
/// prescribed motion over the step from `t0` (`driven_moved`; no XSPH), whatever its kind.
pub fn drift<D: Dim>(p: &SphParams, series: &[f64], dt: f32, t0: f64, s: &mut State<D>) {
    let (kind, group, vel, xsph) = (&s.kind, &s.group, &s.vel, &s.xsph);
    s.pos.par_iter_mut().enumerate().for_each(|(i, x)| {
        if let Some(y) = driven_moved::<D>(p, series, group[i], *x, dt, t0) {
            *x = y;
            wrap::<D>(p, x);
        } else if open_index(p, group[i]).is_some() {
            // An open boundary's buffer moves at its velocity: no XSPH, no shifting.
            *x += vel[i] * dt;
            wrap::<D>(p, x);
        } else if kind[i] as u32 != MF_KIND_BOUNDARY {
            *x += (vel[i] + xsph[i]) * dt;
            wrap::<D>(p, x);
        }
    });
    if let Some(drho) = &s.drho {
        // Dynamic wall particles (`wall_coupling`) take part; their d rho/dt is zero otherwise.
        let rho = s.rho.par_iter_mut().zip(drho.par_iter()).enumerate();
        match s.solid.as_mut() {
            // Solids integrate their departure from rest, rho_dev += dt d rho/dt, and take
            // rho = rho0_s + rho_dev [M L^-d] (`SolidState::rho_dev`: in rho itself a stiff
            // solid's change per step rounds away).
            Some(so) => rho
                .zip(so.rho_dev.par_iter_mut())
                .for_each(|((i, (r, d)), dev)| {
                    if kind[i] as u32 == MF_KIND_SOLID {
                        *dev += dt * d;
                        *r = p.solid_rho0 + *dev;
                    } else {
                        *r = wall_density_floor(p, kind[i], *r + dt * d);
                    }
                }),
            None => rho.for_each(|(i, (r, d))| *r = wall_density_floor(p, kind[i], *r + dt * d)),
        }
    }
    if let Some(solid) = s.solid.as_mut() {
        // S += dt dS/dt needs no departure: S starts at zero and is its own departure, and
        // a step's change relative to S is about dt / (the period of the motion), which
        // does not fall with the stiffness (dt and the elastic periods both go as
        // 1/sqrt(E)); the same holds for the Jaumann rate, eqs. (12)-(15), made of velocity
        // differences. rho's step change relative to rho falls as strain x dt / period,
        // i.e. as 1/E: that is what rounded away.
        let rate = &solid.stress_rate;
        solid.stress.par_iter_mut().enumerate().for_each(|(i, st)| {
            if kind[i] as u32 == MF_KIND_SOLID {
                *st += rate[i] * dt;
            }
        });
    }
}
