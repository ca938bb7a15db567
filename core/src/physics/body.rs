//! Floating rigid bodies (`MfBody` of `sph_params.h`, `floating` of a wall): Newton-Euler
//! equations of a rigid body moved by the force and torque the fluid exerts on its
//! particles, and gravity:
//!
//! M dV/dt = F + M g,   dc/dt = V \[L/T^2\], \[L/T\]
//! dL/dt = T,           omega = I_w^-1 L,   I_w = R I R^T,   dq/dt = (0, omega) q / 2,
//!
//! with L the angular momentum about the centre of mass in the scene's frame, I the inertia
//! tensor in the body's frame and R the rotation of the unit quaternion q. Integrated by the
//! scheme's own integrator: the kick advances V and L over the kick's span (the leapfrog's
//! half steps), the drift moves c by dt V and turns q by the rotation vector dt omega, omega
//! from L at the orientation the step starts from (exact for a spin about a principal axis;
//! L itself changes only by the torque, so a free body keeps it to round-off). A fixed
//! axis holds: its force or torque is taken up, its velocity stays zero. In 2D the body
//! turns about z only. Double precision: a pose is the sum of many small moves. Twin:
//! `cuda/device/body.cuh`; parity test `tests/cuda_parity/`.

use super::dim::Dim;
use super::params::MfBody;

/// Bit `a` of `MfBody::free`: free to move along axis a; bit 3 + a: free to turn about it.
pub fn free_bits(dim: usize, moves: [bool; 3], turns: [bool; 3]) -> i32 {
    let mut f = 0;
    for a in 0..3 {
        if moves[a] && a < dim {
            f |= 1 << a;
        }
        // 2D: about z only.
        if turns[a] && (dim == 3 || a == 2) {
            f |= 1 << (3 + a);
        }
    }
    f
}

/// The rotation matrix (row-major) of the unit quaternion q = (w, x, y, z).
pub fn matrix(q: &[f64; 4]) -> [f64; 9] {
    let [w, x, y, z] = *q;
    [
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    ]
}

fn mat_vec(m: &[f64; 9], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|r| m[3 * r] * v[0] + m[3 * r + 1] * v[1] + m[3 * r + 2] * v[2])
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The inverse of a symmetric 3 x 3 matrix by its cofactors (zero where singular).
fn inverse(m: &[f64; 9]) -> [f64; 9] {
    let c = [
        m[4] * m[8] - m[5] * m[7],
        m[2] * m[7] - m[1] * m[8],
        m[1] * m[5] - m[2] * m[4],
        m[5] * m[6] - m[3] * m[8],
        m[0] * m[8] - m[2] * m[6],
        m[2] * m[3] - m[0] * m[5],
        m[3] * m[7] - m[4] * m[6],
        m[1] * m[6] - m[0] * m[7],
        m[0] * m[4] - m[1] * m[3],
    ];
    let det = m[0] * c[0] + m[1] * c[3] + m[2] * c[6];
    if det == 0.0 {
        return [0.0; 9];
    }
    c.map(|x| x / det)
}

/// What acts on a body's particles besides gravity, summed over them (`backend::cpu::
/// wall_load`, `sph_body_load_*`): the fluid's force \[M L T^-2\] and torque about the centre
/// \[M L^2 T^-2\], and the contacts' (the Lennard-Jones repulsion of eq. (17) from the
/// particles of walls and other bodies).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Load {
    pub force: [f64; 3],
    pub torque: [f64; 3],
    pub contact: [f64; 3],
    pub contact_torque: [f64; 3],
}

impl Load {
    /// The fluid's force and torque alone.
    pub fn fluid(force: [f64; 3], torque: [f64; 3]) -> Load {
        Load {
            force,
            torque,
            ..Default::default()
        }
    }
}

impl MfBody {
    fn moves(&self, a: usize) -> bool {
        self.free & (1 << a) != 0
    }
    fn turns(&self, a: usize) -> bool {
        self.free & (1 << (3 + a)) != 0
    }

    /// The angular velocity \[rad/T\] of angular momentum `l` at the body's orientation:
    /// I_w^-1 L over the free axes (the rows and columns of the held ones replaced by the
    /// identity, their components zero). Twin: `body_omega`.
    pub fn omega_of(&self, l: [f64; 3]) -> [f64; 3] {
        let r = matrix(&self.orientation);
        // I_w = R I R^T
        let mut iw = [0.0; 9];
        for i in 0..3 {
            for j in 0..3 {
                let mut s = 0.0;
                for k in 0..3 {
                    for m in 0..3 {
                        s += r[3 * i + k] * self.inertia[3 * k + m] * r[3 * j + m];
                    }
                }
                iw[3 * i + j] = s;
            }
        }
        for a in 0..3 {
            if !self.turns(a) {
                for b in 0..3 {
                    iw[3 * a + b] = if a == b { 1.0 } else { 0.0 };
                    iw[3 * b + a] = if a == b { 1.0 } else { 0.0 };
                }
            }
        }
        let mut w = mat_vec(&inverse(&iw), l);
        for (a, w) in w.iter_mut().enumerate() {
            if !self.turns(a) {
                *w = 0.0;
            }
        }
        w
    }

    /// The kick over `span` \[T\] under `load`: V += span (F + C + M g) / M and L += span (T +
    /// T_C) along the free axes, omega from L; F, T the fluid's force and torque on the
    /// particles \[M L T^-2\], \[M L^2 T^-2\], C, T_C the contacts' (`Load`), `gravity`
    /// \[L/T^2\]. Keeps the load. Twin: `body_kick`.
    pub fn kick(&mut self, load: &Load, gravity: [f32; 3], span: f32) {
        let s = span as f64;
        self.force = load.force;
        self.torque = load.torque;
        self.contact = load.contact;
        self.contact_torque = load.contact_torque;
        for (a, g) in gravity.iter().enumerate() {
            if self.moves(a) {
                let f = load.force[a] + load.contact[a] + self.mass * *g as f64;
                self.velocity[a] += s * f / self.mass;
            }
            if self.turns(a) {
                self.momentum[a] += s * (load.torque[a] + load.contact_torque[a]);
            }
        }
        self.omega = self.omega_of(self.momentum);
    }

    /// The drift over `dt` \[T\]: c += dt V; q turned by the rotation vector dt omega
    /// (`turn`, kept with `shift` for the particles, `moved`) and renormalised. Twin:
    /// `body_drift`.
    pub fn drift(&mut self, dt: f32) {
        let dt = dt as f64;
        for a in 0..3 {
            self.shift[a] = dt * self.velocity[a];
            self.centre[a] += self.shift[a];
        }
        let phi = self.omega.map(|w| w * dt);
        let angle = (phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]).sqrt();
        let dq = if angle > 0.0 {
            let (s, c) = (0.5 * angle).sin_cos();
            [
                c,
                s * phi[0] / angle,
                s * phi[1] / angle,
                s * phi[2] / angle,
            ]
        } else {
            [1.0, 0.0, 0.0, 0.0]
        };
        self.turn = matrix(&dq);
        let [a0, a1, a2, a3] = dq;
        let [b0, b1, b2, b3] = self.orientation;
        let q = [
            a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
            a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
            a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
        ];
        let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
        self.orientation = q.map(|c| c / n);
        // The momentum is the scene frame's: omega follows the new orientation.
        self.omega = self.omega_of(self.momentum);
    }

    /// Where the last drift took a particle that was at `x` \[L\]: centre + turn (x - centre
    /// + shift), rounded to float once. Twin: `body_moved`.
    pub fn moved<D: Dim>(&self, x: D::V) -> D::V {
        let x = D::to3(x);
        let u = [0, 1, 2].map(|a| x[a] as f64 - self.centre[a] + self.shift[a]);
        let r = mat_vec(&self.turn, u);
        let mut y = [0.0f32; 3];
        for (a, y) in y.iter_mut().enumerate().take(D::D) {
            *y = (self.centre[a] + r[a]) as f32;
        }
        D::from3(y)
    }

    /// The velocity of the body's point at `x` \[L/T\]: V + omega x (x - c). Twin:
    /// `body_point_velocity`.
    pub fn velocity_at<D: Dim>(&self, x: D::V) -> D::V {
        let x = D::to3(x);
        let u = [0, 1, 2].map(|a| x[a] as f64 - self.centre[a]);
        let w = cross(self.omega, u);
        let mut v = [0.0f32; 3];
        for (a, v) in v.iter_mut().enumerate().take(D::D) {
            *v = (self.velocity[a] + w[a]) as f32;
        }
        D::from3(v)
    }

    /// The kinetic energy \[M L^2 T^-2\]: M V^2 / 2 + omega . L / 2.
    pub fn kinetic_energy(&self) -> f64 {
        let v2: f64 = self.velocity.iter().map(|v| v * v).sum();
        let wl: f64 = (0..3).map(|a| self.omega[a] * self.momentum[a]).sum();
        0.5 * self.mass * v2 + 0.5 * wl
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::dim::{D2, D3};
    use glam::{Vec2, Vec3A};

    fn body(inertia: [f64; 3], free: i32) -> MfBody {
        let mut i = [0.0; 9];
        i[0] = inertia[0];
        i[4] = inertia[1];
        i[8] = inertia[2];
        MfBody {
            group: 1,
            free,
            mass: 2.0,
            inertia: i,
            orientation: [1.0, 0.0, 0.0, 0.0],
            turn: matrix(&[1.0, 0.0, 0.0, 0.0]),
            ..Default::default()
        }
    }

    #[test]
    fn a_falling_body_gains_g_t_and_a_held_axis_does_not_move() {
        let mut b = body([1.0; 3], free_bits(3, [true, false, true], [true; 3]));
        let g = [0.0, -9.81, 0.0];
        let dt = 1.0e-3;
        for _ in 0..1000 {
            b.kick(&Load::fluid([0.5, 0.0, 0.0], [0.0; 3]), g, dt);
            b.drift(dt);
        }
        // Along x the fluid's 0.5 on a mass of 2: a = 0.25; y held; z free of force.
        assert!((b.velocity[0] - 0.25).abs() < 1e-6, "{:?}", b.velocity);
        assert_eq!(b.velocity[1], 0.0);
        assert_eq!(b.centre[1], 0.0);
        assert_eq!(b.force, [0.5, 0.0, 0.0]);
    }

    #[test]
    fn a_free_rotor_keeps_its_momentum_and_energy_and_spins_about_its_stable_axis() {
        // A body spun mostly about its axis of largest inertia, nudged about the others:
        // L in the scene's frame is constant (no torque), the energy stays to 1e-6 over
        // 20,000 steps, and the spin axis stays near the axis of largest inertia.
        let mut b = body([1.0, 2.0, 3.0], free_bits(3, [true; 3], [true; 3]));
        b.momentum = [0.03, 0.02, 3.0];
        b.omega = b.omega_of(b.momentum);
        let e0 = b.kinetic_energy();
        for _ in 0..20_000 {
            b.kick(&Load::default(), [0.0; 3], 1.0e-3);
            b.drift(1.0e-3);
        }
        let e1 = b.kinetic_energy();
        assert!(((e1 - e0) / e0).abs() < 1e-4, "energy {e0} -> {e1}");
        assert_eq!(b.momentum, [0.03, 0.02, 3.0]);
        let r = matrix(&b.orientation);
        let body_z = [r[2], r[5], r[8]];
        assert!(body_z[2] > 0.99, "the body's z axis drifted to {body_z:?}");
    }

    #[test]
    fn particles_follow_the_pose_and_move_with_the_velocity_of_their_point() {
        // 2D: a body turning at 1 rad/s about its centre (1, 0.5) while moving at (0.2, 0):
        // after 1000 steps of 1e-3 a particle one unit right of the centre sits at angle 1
        // about the moved centre (1.2, 0.5), and its velocity is V + omega x r.
        let mut b = body([1.0, 1.0, 0.5], free_bits(2, [true; 3], [true; 3]));
        b.centre = [1.0, 0.5, 0.0];
        b.velocity = [0.2, 0.0, 0.0];
        b.momentum = [0.0, 0.0, 0.5];
        b.omega = b.omega_of(b.momentum);
        assert!((b.omega[2] - 1.0).abs() < 1e-12);
        let mut x = Vec2::new(2.0, 0.5);
        for _ in 0..1000 {
            b.kick(&Load::default(), [0.0; 3], 1.0e-3);
            b.drift(1.0e-3);
            x = b.moved::<D2>(x);
        }
        let u = x - Vec2::new(1.2, 0.5);
        assert!((u.length() - 1.0).abs() < 1e-5, "{u:?}");
        assert!((u.y.atan2(u.x) - 1.0).abs() < 1e-5, "{u:?}");
        let v = b.velocity_at::<D2>(x);
        assert!((v - Vec2::new(0.2 - u.y, u.x)).length() < 1e-5, "{v:?}");
        // A held turn: no rotation whatever the torque.
        let mut h = body([1.0; 3], free_bits(3, [true; 3], [false; 3]));
        h.kick(&Load::fluid([0.0; 3], [1.0, 2.0, 3.0]), [0.0; 3], 0.1);
        h.drift(0.1);
        let y = h.moved::<D3>(Vec3A::new(1.0, 0.0, 0.0));
        assert_eq!(y, Vec3A::new(1.0, 0.0, 0.0));
    }
}
