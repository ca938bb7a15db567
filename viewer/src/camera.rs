use glam::{Mat4, Vec3};

/// Which camera to draw with.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Camera {
    /// Frame the domain: [`OrthoCamera`] for 2D frames, [`OrbitCamera`] for 3D.
    #[default]
    Auto,
    /// Orthographic camera looking down −z (2D).
    Ortho(OrthoCamera),
    /// Perspective orbit camera (3D), y up.
    Orbit(OrbitCamera),
}

/// Orthographic pan/zoom camera looking down −z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrthoCamera {
    /// World point at the middle of the view.
    pub center: [f32; 2],
    /// Half the visible world height.
    pub half_height: f32,
}

/// Perspective camera orbiting `target`, y up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    /// Point looked at.
    pub target: [f32; 3],
    /// Eye distance from `target`.
    pub distance: f32,
    /// Angle about the y axis, radians (0 looks down −z).
    pub yaw: f32,
    /// Elevation, radians (positive looks down from above).
    pub pitch: f32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

/// View and projection matrices ready for the shaders.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Matrices {
    pub view: Mat4,
    pub proj: Mat4,
    pub ortho: bool,
}

fn domain(min: [f32; 3], max: [f32; 3]) -> (Vec3, Vec3) {
    let (a, b) = (Vec3::from(min), Vec3::from(max));
    (a.min(b), a.max(b))
}

impl OrthoCamera {
    /// Fits the domain (plus `margin` world units) into a view of the given aspect (width / height).
    pub fn fit(domain_min: [f32; 3], domain_max: [f32; 3], margin: f32, aspect: f32) -> Self {
        let (lo, hi) = domain(domain_min, domain_max);
        let c = (lo + hi) * 0.5;
        let half = (hi - lo) * 0.5 + Vec3::splat(margin.max(0.0));
        let half_height = (half.y.max(half.x / aspect.max(1e-6)) * 1.05).max(1e-6);
        OrthoCamera {
            center: [c.x, c.y],
            half_height,
        }
    }

    /// Moves the view by a mouse drag of `(dx, dy)` pixels in a viewport `viewport_h` pixels high.
    pub fn pan_pixels(&mut self, dx: f32, dy: f32, viewport_h: f32) {
        let s = 2.0 * self.half_height / viewport_h.max(1.0);
        self.center[0] -= dx * s;
        self.center[1] += dy * s;
    }

    /// Zooms in (`factor` < 1) or out (`factor` > 1).
    pub fn zoom(&mut self, factor: f32) {
        self.half_height = (self.half_height * factor).max(1e-9);
    }

    pub(crate) fn matrices(&self, aspect: f32) -> Matrices {
        let hh = self.half_height;
        let hw = hh * aspect;
        let depth = 1.0e3 * hh.max(1.0);
        Matrices {
            view: Mat4::from_translation(Vec3::new(-self.center[0], -self.center[1], 0.0)),
            proj: Mat4::orthographic_rh_gl(-hw, hw, -hh, hh, -depth, depth),
            ortho: true,
        }
    }
}

impl OrbitCamera {
    /// A three-quarter view from above whose distance is the least at which all eight corners
    /// of the box (plus `margin` world units) lie inside a view of the given aspect (width /
    /// height), with 4 % to spare: the box fills the frame.
    pub fn fit(domain_min: [f32; 3], domain_max: [f32; 3], margin: f32, aspect: f32) -> Self {
        let (lo, hi) = domain(domain_min, domain_max);
        let c = (lo + hi) * 0.5;
        let half = (hi - lo) * 0.5 + Vec3::splat(margin.max(0.0));
        let fov_y = 40f32.to_radians();
        let mut cam = OrbitCamera {
            target: c.to_array(),
            distance: 1.0,
            yaw: 35f32.to_radians(),
            pitch: 25f32.to_radians(),
            fov_y,
        };
        // The view's axes: `back` points from the target to the eye.
        let back = Vec3::from(cam.eye()) - c;
        let right = Vec3::Y.cross(back).normalize();
        let up = back.cross(right);
        let ty = (fov_y * 0.5).tan();
        let tx = ty * aspect.max(1e-6);
        let mut d = 0f32;
        for i in 0..8 {
            let s = Vec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            );
            let p = s * half;
            // A corner at depth (d - z) in front of the eye is inside when |x| <= tx (d - z).
            let z = p.dot(back);
            d = d
                .max(z + p.dot(right).abs() / tx)
                .max(z + p.dot(up).abs() / ty);
        }
        cam.distance = (1.04 * d).max(1e-6);
        cam
    }

    /// Where the world point `p` lands in the view (normalised device coordinates: x and y
    /// in -1..1 inside the view, y up), or `None` behind the eye.
    pub fn project(&self, p: [f32; 3], aspect: f32) -> Option<[f32; 2]> {
        let m = self.matrices(aspect);
        let c = m.proj * m.view * Vec3::from(p).extend(1.0);
        (c.w > 0.0).then(|| [c.x / c.w, c.y / c.w])
    }

    /// Eye position in world space.
    pub fn eye(&self) -> [f32; 3] {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        (Vec3::from(self.target) + self.distance * Vec3::new(cp * sy, sp, cp * cy)).to_array()
    }

    /// Turns the camera by a mouse drag of `(dx, dy)` pixels.
    pub fn rotate_pixels(&mut self, dx: f32, dy: f32) {
        self.yaw -= dx * 0.01;
        self.pitch = (self.pitch + dy * 0.01).clamp(-1.55, 1.55);
    }

    /// Moves the target in the view plane by a drag of `(dx, dy)` pixels in a viewport `viewport_h` high.
    pub fn pan_pixels(&mut self, dx: f32, dy: f32, viewport_h: f32) {
        let m = self.matrices(1.0).view.inverse();
        let right = m.x_axis.truncate();
        let up = m.y_axis.truncate();
        let s = 2.0 * self.distance * (self.fov_y * 0.5).tan() / viewport_h.max(1.0);
        let t = Vec3::from(self.target) - right * dx * s + up * dy * s;
        self.target = t.to_array();
    }

    /// Moves closer (`factor` < 1) or farther (`factor` > 1).
    pub fn zoom(&mut self, factor: f32) {
        self.distance = (self.distance * factor).max(1e-9);
    }

    pub(crate) fn matrices(&self, aspect: f32) -> Matrices {
        let eye = Vec3::from(self.eye());
        let up = if self.pitch.abs() > 1.5 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        Matrices {
            view: Mat4::look_at_rh(eye, Vec3::from(self.target), up),
            proj: Mat4::perspective_rh_gl(
                self.fov_y,
                aspect.max(1e-6),
                self.distance * 1e-2,
                self.distance * 1e2,
            ),
            ortho: false,
        }
    }
}

impl Camera {
    /// Replaces [`Camera::Auto`] with the camera that frames the domain.
    pub fn resolve(
        &self,
        dim: u8,
        domain_min: [f32; 3],
        domain_max: [f32; 3],
        margin: f32,
        aspect: f32,
    ) -> Camera {
        match self {
            Camera::Auto if dim == 3 => {
                Camera::Orbit(OrbitCamera::fit(domain_min, domain_max, margin, aspect))
            }
            Camera::Auto => Camera::Ortho(OrthoCamera::fit(domain_min, domain_max, margin, aspect)),
            other => *other,
        }
    }

    pub(crate) fn matrices(
        &self,
        dim: u8,
        domain_min: [f32; 3],
        domain_max: [f32; 3],
        margin: f32,
        aspect: f32,
    ) -> Matrices {
        match self.resolve(dim, domain_min, domain_max, margin, aspect) {
            Camera::Ortho(c) => c.matrices(aspect),
            Camera::Orbit(c) => c.matrices(aspect),
            Camera::Auto => unreachable!("resolved"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ndc(m: &Matrices, p: [f32; 3]) -> Vec3 {
        let c = m.proj * m.view * Vec3::from(p).extend(1.0);
        c.truncate() / c.w
    }

    #[test]
    fn ortho_fit_puts_domain_inside_view() {
        let cam = OrthoCamera::fit([0.0, 0.0, 0.0], [2.0, 1.0, 0.0], 0.0, 1.5);
        let m = cam.matrices(1.5);
        for p in [[0.0, 0.0, 0.0], [2.0, 1.0, 0.0], [2.0, 0.0, 0.0]] {
            let q = ndc(&m, p);
            assert!(q.x.abs() <= 1.0 && q.y.abs() <= 1.0, "{p:?} -> {q:?}");
        }
        let c = ndc(&m, [1.0, 0.5, 0.0]);
        assert!(c.x.abs() < 1e-5 && c.y.abs() < 1e-5);
    }

    #[test]
    fn orbit_fit_puts_domain_corners_inside_view() {
        let (lo, hi) = ([0.0, 0.0, 0.0], [1.0, 2.0, 0.5]);
        let cam = OrbitCamera::fit(lo, hi, 0.0, 0.75);
        let m = cam.matrices(0.75);
        for i in 0..8 {
            let p = [
                if i & 1 == 0 { lo[0] } else { hi[0] },
                if i & 2 == 0 { lo[1] } else { hi[1] },
                if i & 4 == 0 { lo[2] } else { hi[2] },
            ];
            let q = ndc(&m, p);
            assert!(
                q.x.abs() <= 1.0 && q.y.abs() <= 1.0 && q.z.abs() <= 1.0,
                "{p:?} -> {q:?}"
            );
        }
    }

    #[test]
    fn pan_and_zoom() {
        let mut c = OrthoCamera {
            center: [0.0, 0.0],
            half_height: 1.0,
        };
        c.pan_pixels(50.0, 0.0, 100.0);
        assert!((c.center[0] + 1.0).abs() < 1e-6);
        c.zoom(0.5);
        assert!((c.half_height - 0.5).abs() < 1e-6);
        let mut o = OrbitCamera::fit([0.0; 3], [1.0; 3], 0.0, 1.0);
        let d = o.distance;
        o.zoom(2.0);
        assert!((o.distance - 2.0 * d).abs() < 1e-5);
        o.rotate_pixels(0.0, 1e6);
        assert!(o.pitch <= 1.55);
    }
}
