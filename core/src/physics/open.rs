//! Open boundaries (`[[open_boundaries]]`, `MfOpen` in cuda/sph_params.h): inlets and outlets
//! whose buffers make and remove particles, so that a flow enters and leaves a domain that
//! is not periodic. Buffer zones after Tafuni, Dominguez, Vacondio & Crespo 2018 (Comput.
//! Methods Appl. Mech. Eng. 342, 604), in their simplest form: an inlet's buffer moves at the
//! prescribed velocity, an outlet's coasts at the velocity its particles entered with (zero
//! gradient along the stream), and both take their density from the continuity equation as
//! the fluid does. What one particle becomes at a step is `fate`; the stage that applies
//! it is `backend/cpu/open.rs` (twin `cuda/open.cu`, `device/open.cuh`).

use crate::physics::dim::Dim;
use crate::physics::params::{MfOpen, SphParams, MF_KIND_FLUID, MF_OPEN_INLET};

impl MfOpen {
    /// An inlet's scale a(t) of its velocity at time `t` \[T\]: its series' (`knots_at`,
    /// the knots' s_x slot) from the table `series`, 1 without one. Twin: the inlet's branch
    /// of `kick_one` in cuda/integrate.cu.
    #[inline]
    pub fn scale(&self, series: &[f64], t: f64) -> f64 {
        if self.series_count <= 0 {
            return 1.0;
        }
        let at = super::motion::knots_at(
            series,
            self.series_first,
            self.series_count,
            self.series_cubic != 0,
            t,
        );
        at.s[0]
    }

    /// s = sign (x\[axis\] - plane) \[L\]: the distance of `x` on the fluid's side of the
    /// plane (negative in the buffer).
    #[inline]
    pub fn side(&self, x: [f32; 3]) -> f32 {
        self.sign * (x[self.axis as usize] - self.plane)
    }

    /// Whether `x` lies within the buffer box's extent across the normal (every axis of a
    /// `dim`-dimensional scene but the normal's).
    #[inline]
    pub fn beside(&self, x: [f32; 3], dim: usize) -> bool {
        (0..dim).all(|a| a == self.axis as usize || (x[a] >= self.lo[a] && x[a] <= self.hi[a]))
    }

    /// Whether `x` lies in the buffer box: behind the plane by at most `depth`, and beside.
    #[inline]
    pub fn holds(&self, x: [f32; 3], dim: usize) -> bool {
        let s = self.side(x);
        s < 0.0 && s >= -self.depth && self.beside(x, dim)
    }

    /// An inlet's velocity profile at `x` \[-\]: the product over the axes of
    /// `profile_axes` of 6 eta (1 - eta), eta = (x\[a\] - lo\[a\]) / (hi\[a\] - lo\[a\])
    /// clamped to \[0, 1\] (plane Poiseuille flow's parabola, mean 1 over the box's face, so
    /// that `velocity` is the mean and the flux `velocity` times the face's area); 1 where
    /// no axis is set (uniform). Twin: `open_profile` in cuda/device/open.cuh.
    #[inline]
    pub fn profile(&self, x: [f32; 3]) -> f32 {
        (0..3)
            .filter(|&a| self.profile_axes & (1 << a) != 0)
            .map(|a| {
                let eta = ((x[a] - self.lo[a]) / (self.hi[a] - self.lo[a])).clamp(0.0, 1.0);
                6.0 * eta * (1.0 - eta)
            })
            .product()
    }

    /// Where an inlet's new buffer particle goes when one at `x` joins the fluid: `depth`
    /// behind it \[L\].
    #[inline]
    pub fn behind(&self, mut x: [f32; 3]) -> [f32; 3] {
        x[self.axis as usize] -= self.sign * self.depth;
        x
    }

    pub fn is_inlet(&self) -> bool {
        self.kind as u32 == MF_OPEN_INLET
    }
}

/// The ramp's shape alone [-]: (1 - cos(pi t / T_r)) / 2 for 0 <= t < T_r, 0 before, 1 after,
/// and 1 for T_r <= 0 (no ramp), at time t \[T\] of a ramp T_r \[T\] (the inflow band's `ramp_share`, an
/// inlet's `buffer_velocity`, the lattice Boltzmann reference's band, `lab/src/lbm/street.rs`).
/// Twin: `smooth_ramp` in cuda/device/open.cuh.
#[inline]
pub fn smooth_ramp(tr: f64, t: f64) -> f64 {
    if tr <= 0.0 || t >= tr {
        1.0
    } else if t <= 0.0 {
        0.0
    } else {
        0.5 * (1.0 - (std::f64::consts::PI * t / tr).cos())
    }
}

/// The open boundary whose buffer scene group `group` is, if any. Twin: `open_index` in
/// cuda/device/open.cuh.
#[inline]
pub fn open_index(p: &SphParams, group: u32) -> Option<usize> {
    let n = (p.open_count.max(0) as usize).min(p.open.len());
    p.open[..n].iter().position(|o| o.group as u32 == group)
}

/// The velocity the kick gives a buffer particle of group `group` at `x` whose velocity is
/// `v`, at the kick's end time `t` \[T\]: an inlet's r(t) a(t) f(x) velocity (r the smooth
/// start over its `ramp`, `smooth_ramp`; a its series' scale, `MfOpen::scale`; f its
/// profile, `MfOpen::profile`), an outlet's `v` as it is; None outside a buffer. `series`:
/// `Setup::motion_series`. [L/T] Twin: `kick_one` in cuda/integrate.cu.
#[inline]
pub fn buffer_velocity<D: Dim>(
    p: &SphParams,
    series: &[f64],
    group: u32,
    x: D::V,
    v: D::V,
    t: f64,
) -> Option<D::V> {
    let o = &p.open[open_index(p, group)?];
    Some(if o.is_inlet() {
        let r = (smooth_ramp(o.ramp as f64, t) * o.scale(series, t)) as f32;
        D::from3(o.velocity) * (r * o.profile(D::to3(x)))
    } else {
        v
    })
}

/// What the open-boundary stage does with one particle (`fate`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fate {
    /// Nothing.
    Keep,
    /// An inlet's buffer particle that reached the fluid's side (boundary `b`): it joins the
    /// fluid (group `through`), and a copy of it takes its place `depth` behind.
    Spawn(usize),
    /// It joins boundary `b`'s buffer (group `group`): fluid that entered an outlet.
    Enter(usize),
    /// An outlet's buffer particle back on the fluid's side: it rejoins the fluid (group
    /// `through` of boundary `b`).
    Leave(usize),
    /// Removed, through boundary `b`: an outlet's buffer particle past the box, or fluid
    /// that flowed back into an inlet's box.
    Remove(usize),
}

/// What the open-boundary stage does with a particle of kind `kind` and group `group` at
/// `x` (`Fate`); only fluid particles have a fate other than `Keep`. Twin: `open_fate` in
/// cuda/device/open.cuh.
pub fn fate(p: &SphParams, kind: u8, group: u32, x: [f32; 3]) -> Fate {
    if p.open_count == 0 || kind as u32 != MF_KIND_FLUID {
        return Fate::Keep;
    }
    let dim = p.dim as usize;
    if let Some(b) = open_index(p, group) {
        let o = &p.open[b];
        let s = o.side(x);
        return if o.is_inlet() {
            if s >= 0.0 {
                Fate::Spawn(b)
            } else {
                Fate::Keep
            }
        } else if s >= 0.0 {
            Fate::Leave(b)
        } else if s < -o.depth || !o.beside(x, dim) {
            Fate::Remove(b)
        } else {
            Fate::Keep
        };
    }
    for (b, o) in p.open[..p.open_count as usize].iter().enumerate() {
        if o.side(x) < 0.0 && o.beside(x, dim) {
            if o.is_inlet() {
                if o.holds(x, dim) {
                    return Fate::Remove(b);
                }
            } else if o.side(x) < -o.depth {
                return Fate::Remove(b);
            } else {
                return Fate::Enter(b);
            }
        }
    }
    Fate::Keep
}

/// The mass that crossed one open boundary since the run began: in through an inlet (its
/// buffer particles that joined the fluid), out through an outlet (its buffer particles
/// removed) or back through an inlet (fluid removed from its box).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OpenTally {
    /// Particles in.
    pub count_in: u64,
    /// \[M\] their mass.
    pub mass_in: f64,
    /// Particles out.
    pub count_out: u64,
    /// \[M\] their mass.
    pub mass_out: f64,
}

/// What a restart needs of the open boundaries: the next new particle's id and each
/// boundary's tally.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OpenState {
    /// The id the next particle an inlet makes takes (ids are never reused).
    pub next_id: u32,
    /// Per boundary, the scene's order.
    pub tally: Vec<OpenTally>,
}

impl OpenState {
    /// At t = 0: ids after the scene's particles', every tally zero.
    pub fn start(p: &SphParams, particles: &[crate::physics::particle::Particle]) -> OpenState {
        OpenState {
            next_id: particles.iter().map(|q| q.id + 1).max().unwrap_or(0),
            tally: vec![OpenTally::default(); p.open_count.max(0) as usize],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::params::{MF_KIND_BOUNDARY, MF_OPEN_OUTLET};

    /// A 2D scene with an inlet at x = 0 (buffer x in [-0.1, 0), normal +x) and an outlet
    /// at x = 1 (buffer x in [1, 1.1), normal -x), both for y in [0, 0.5].
    fn params() -> SphParams {
        let mut p = SphParams {
            dim: 2,
            open_count: 2,
            ..SphParams::default()
        };
        p.open[0] = MfOpen {
            kind: MF_OPEN_INLET as i32,
            group: 5,
            through: 6,
            axis: 0,
            sign: 1.0,
            plane: 0.0,
            depth: 0.1,
            lo: [-0.1, 0.0, 0.0],
            hi: [0.0, 0.5, 0.0],
            velocity: [2.0, 0.0, 0.0],
            ramp: 0.0,
            profile_axes: 0,
            ..Default::default()
        };
        p.open[1] = MfOpen {
            kind: MF_OPEN_OUTLET as i32,
            group: 7,
            through: 8,
            axis: 0,
            sign: -1.0,
            plane: 1.0,
            depth: 0.1,
            lo: [1.0, 0.0, 0.0],
            hi: [1.1, 0.5, 0.0],
            ..p.open[0]
        };
        p
    }

    #[test]
    fn fates() {
        let p = params();
        let f = MF_KIND_FLUID as u8;
        // An inlet's buffer particle joins the fluid at the plane, not before.
        assert_eq!(fate(&p, f, 5, [-0.01, 0.2, 0.0]), Fate::Keep);
        assert_eq!(fate(&p, f, 5, [0.0, 0.2, 0.0]), Fate::Spawn(0));
        // Fluid in the channel stays; in the inlet's box it goes; in the outlet's it enters.
        assert_eq!(fate(&p, f, 0, [0.5, 0.2, 0.0]), Fate::Keep);
        assert_eq!(fate(&p, f, 0, [-0.05, 0.2, 0.0]), Fate::Remove(0));
        assert_eq!(fate(&p, f, 0, [1.05, 0.2, 0.0]), Fate::Enter(1));
        // Beyond the outlet's box in one step: removed at once.
        assert_eq!(fate(&p, f, 0, [1.2, 0.2, 0.0]), Fate::Remove(1));
        // Beside the boxes (y > 0.5): no boundary's business.
        assert_eq!(fate(&p, f, 0, [1.05, 0.7, 0.0]), Fate::Keep);
        // The outlet's buffer: coasts, leaves past the box or sideways, rejoins the fluid.
        assert_eq!(fate(&p, f, 7, [1.05, 0.2, 0.0]), Fate::Keep);
        assert_eq!(fate(&p, f, 7, [1.11, 0.2, 0.0]), Fate::Remove(1));
        assert_eq!(fate(&p, f, 7, [1.05, 0.6, 0.0]), Fate::Remove(1));
        assert_eq!(fate(&p, f, 7, [0.99, 0.2, 0.0]), Fate::Leave(1));
        // Walls are nobody's.
        assert_eq!(
            fate(&p, MF_KIND_BOUNDARY as u8, 0, [-0.05, 0.2, 0.0]),
            Fate::Keep
        );
    }

    #[test]
    fn buffer_velocities() {
        use crate::physics::dim::D2;
        let mut p = params();
        let v = glam::Vec2::new(0.3, -0.1);
        let x = glam::Vec2::new(-0.05, 0.1);
        assert_eq!(
            buffer_velocity::<D2>(&p, &[], 5, x, v, 1.0),
            Some(glam::Vec2::new(2.0, 0.0))
        );
        assert_eq!(buffer_velocity::<D2>(&p, &[], 7, x, v, 1.0), Some(v));
        assert_eq!(buffer_velocity::<D2>(&p, &[], 0, x, v, 1.0), None);
        // Half way through the ramp: half the velocity.
        p.open[0].ramp = 0.2;
        let u = buffer_velocity::<D2>(&p, &[], 5, x, v, 0.1).unwrap();
        assert!((u.x - 1.0).abs() < 1e-6, "{u}");
        // And a parabolic profile across y: 1.5 times that at the face's middle.
        p.open[0].profile_axes = 1 << 1;
        let mid = glam::Vec2::new(-0.05, 0.25);
        let u = buffer_velocity::<D2>(&p, &[], 5, mid, v, 0.1).unwrap();
        assert!((u.x - 1.5).abs() < 1e-6 && u.y == 0.0, "{u}");
        assert_eq!(p.open[0].behind([0.01, 0.2, 0.0]), [0.01 - 0.1, 0.2, 0.0]);
    }

    #[test]
    fn a_parabolic_profile_is_zero_at_the_sides_and_its_mean_is_one() {
        let mut o = params().open[0];
        // Uniform: 1 everywhere.
        assert_eq!(o.profile([-0.05, 0.01, 0.0]), 1.0);
        // Across y (the box spans 0..0.5): 1.5 at the middle, 0 at and beyond the sides.
        o.profile_axes = 1 << 1;
        assert!((o.profile([-0.05, 0.25, 0.0]) - 1.5).abs() < 1e-6);
        for y in [0.0, 0.5, -0.1, 0.7] {
            assert_eq!(o.profile([-0.05, y, 0.0]), 0.0, "y = {y}");
        }
        // Its mean over the face (the midpoint rule on 1000 points): 1, so that the
        // flux is the velocity times the area.
        let mean = |o: &MfOpen| {
            (0..1000)
                .map(|i| o.profile([-0.05, 0.5 * (i as f32 + 0.5) / 1000.0, 0.3]) as f64)
                .sum::<f64>()
                / 1000.0
        };
        assert!((mean(&o) - 1.0).abs() < 1e-5, "{}", mean(&o));
        // Across y and z: the product (1.5^2 at the middle of the face).
        o.profile_axes = (1 << 1) | (1 << 2);
        o.lo[2] = 0.0;
        o.hi[2] = 1.0;
        assert!((o.profile([-0.05, 0.25, 0.5]) - 2.25).abs() < 1e-6);
        assert!((o.profile([-0.05, 0.25, 0.3]) - 1.5 * 6.0 * 0.3 * 0.7).abs() < 1e-5);
    }

    #[test]
    fn an_inlets_series_scales_its_velocity_over_time() {
        // scale 0.5 at t = 0 rising linearly to 1 at t = 1, after a motion's two knots.
        use crate::physics::dim::D2;
        let mut p = params();
        (p.open[0].series_first, p.open[0].series_count) = (2, 2);
        let series = [
            0.0, 9.0, 9.0, 9.0, 9.0, 1.0, 9.0, 9.0, 9.0, 9.0, // another object's
            0.0, 0.5, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0,
        ];
        let (x, v) = (glam::Vec2::new(-0.05, 0.25), glam::Vec2::ZERO);
        let u = |t| buffer_velocity::<D2>(&p, &series, 5, x, v, t).unwrap();
        assert_eq!(u(0.0), glam::Vec2::new(1.0, 0.0));
        assert!((u(0.5).x - 1.5).abs() < 1e-6, "{}", u(0.5));
        assert_eq!(u(3.0), glam::Vec2::new(2.0, 0.0));
        // An outlet's buffer ignores it.
        assert_eq!(buffer_velocity::<D2>(&p, &series, 7, x, v, 0.5), Some(v));
    }
}
