//! `floating.csv`: one row per floating rigid body (`floating` walls, `physics::body`) every
//! output interval, flushed as written: its centre of mass, its orientation as a quaternion
//! and as angles, its velocities, and its load by source (the fluid's force on its
//! particles, gravity's, the fluid's torque about its centre, and the contacts' force and
//! torque from walls and other bodies). Vectors have three
//! components (z = 0 in 2D; a 2D body turns about z only).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use meshfree_core::physics::params::MfBody;

/// The header line (without the newline).
pub const FLOATING_HEADER: &str = "time,group,cx,cy,cz,qw,qx,qy,qz,roll_deg,pitch_deg,yaw_deg,\
vx,vy,vz,omega_x,omega_y,omega_z,fluid_fx,fluid_fy,fluid_fz,gravity_fx,gravity_fy,gravity_fz,\
fluid_tx,fluid_ty,fluid_tz,contact_fx,contact_fy,contact_fz,contact_tx,contact_ty,contact_tz";

/// The open CSV file.
pub struct FloatingCsv {
    w: BufWriter<File>,
}

/// Roll, pitch and yaw \[deg\] of a unit quaternion (w, x, y, z): turns about x, then y, then
/// z (z-y'-x'' Tait-Bryan angles, as ship motions are given); in 2D the yaw is the body's
/// turn about z.
pub fn angles(q: &[f64; 4]) -> [f64; 3] {
    let [w, x, y, z] = *q;
    let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
    let pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin();
    let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
    [roll, pitch, yaw].map(f64::to_degrees)
}

impl FloatingCsv {
    /// Create the file and write the header, or, continuing a run (`append`), open it at
    /// its end.
    pub fn open(path: &Path, append: bool) -> io::Result<FloatingCsv> {
        Ok(FloatingCsv {
            w: super::open_csv(path, FLOATING_HEADER, append)?,
        })
    }

    /// The rows of every body at time `t` \[T\] under `gravity` \[L/T^2\], flushed.
    pub fn write(&mut self, t: f64, gravity: [f32; 3], bodies: &[MfBody]) -> io::Result<()> {
        for b in bodies {
            let (c, q, v, w) = (b.centre, b.orientation, b.velocity, b.omega);
            let a = angles(&q);
            let g = gravity.map(|g| b.mass * g as f64);
            let (f, m, k, km) = (b.force, b.torque, b.contact, b.contact_torque);
            writeln!(
                self.w,
                "{t},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},\
                 {},{},{},{},{},{}",
                b.group,
                c[0],
                c[1],
                c[2],
                q[0],
                q[1],
                q[2],
                q[3],
                a[0],
                a[1],
                a[2],
                v[0],
                v[1],
                v[2],
                w[0],
                w[1],
                w[2],
                f[0],
                f[1],
                f[2],
                g[0],
                g[1],
                g[2],
                m[0],
                m[1],
                m[2],
                k[0],
                k[1],
                k[2],
                km[0],
                km[1],
                km[2]
            )?;
        }
        self.w.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_of_single_turns() {
        let half = |deg: f64| (0.5 * deg.to_radians()).sin_cos();
        let (s, c) = half(30.0);
        let a = angles(&[c, 0.0, 0.0, s]);
        assert!(
            (a[2] - 30.0).abs() < 1e-9 && a[0].abs() < 1e-9 && a[1].abs() < 1e-9,
            "{a:?}"
        );
        let (s, c) = half(-20.0);
        let a = angles(&[c, s, 0.0, 0.0]);
        assert!((a[0] + 20.0).abs() < 1e-9, "{a:?}");
        let (s, c) = half(10.0);
        let a = angles(&[c, 0.0, s, 0.0]);
        assert!((a[1] - 10.0).abs() < 1e-9, "{a:?}");
        assert_eq!(FLOATING_HEADER.split(',').count(), 33);
    }
}
