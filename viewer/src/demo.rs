//! A small analytic [`LiveSource`] for trying the viewer without the solver:
//! a differentially rotating vortex of fluid particles with a rigid solid ring,
//! in a box of boundary particles (2D) or a cylinder over a floor (3D).

use std::f32::consts::TAU;

use crate::{kind, Field, FrameData, LiveSource, Status};

/// A rotating-vortex demo source.
#[derive(Debug, Clone)]
pub struct DemoSource {
    dim: u8,
    /// (kind, radius from the axis, start angle, axial coordinate) per particle.
    particles: Vec<(u8, f32, f32, f32)>,
    /// Fixed positions of the boundary particles.
    walls: Vec<[f32; 3]>,
    spacing: f32,
    domain_min: [f32; 3],
    domain_max: [f32; 3],
    time: f64,
    step: u64,
    /// Time step per `advance` step.
    pub dt: f64,
}

const RADIUS: f32 = 0.4;
const CENTER: f32 = 0.5;

fn angular_velocity(r: f32, kind: u8) -> f32 {
    if kind == kind::SOLID {
        1.0
    } else {
        // Fast in the middle ring, slower at the axis and the rim.
        6.0 * (r / RADIUS) * (1.0 - 0.7 * r / RADIUS) + 0.5
    }
}

impl DemoSource {
    /// A 2D vortex in the unit square; about `n * n * 0.6` particles.
    pub fn new_2d(n: usize) -> DemoSource {
        let n = n.max(4);
        let dx = 1.0 / n as f32;
        let mut particles = Vec::new();
        let mut walls = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let x = (i as f32 + 0.5) * dx - CENTER;
                let y = (j as f32 + 0.5) * dx - CENTER;
                let r = (x * x + y * y).sqrt();
                if r < RADIUS {
                    let k = if r > RADIUS - 2.0 * dx {
                        kind::SOLID
                    } else {
                        kind::FLUID
                    };
                    particles.push((k, r, y.atan2(x), 0.0));
                }
            }
        }
        for layer in 0..2 {
            let lo = -(layer as f32 + 0.5) * dx;
            let hi = 1.0 + (layer as f32 + 0.5) * dx;
            let m = n + 2 * layer + 1;
            for i in 0..m {
                let t = lo + i as f32 * dx;
                walls.extend([[t, lo, 0.0], [t, hi, 0.0], [lo, t + dx, 0.0], [hi, t, 0.0]]);
            }
        }
        DemoSource {
            dim: 2,
            particles,
            walls,
            spacing: dx,
            domain_min: [-2.0 * dx, -2.0 * dx, 0.0],
            domain_max: [1.0 + 2.0 * dx, 1.0 + 2.0 * dx, 0.0],
            time: 0.0,
            step: 0,
            dt: 2e-3,
        }
    }

    /// A 3D rotating cylinder (axis y) over a floor of boundary particles; `n` particles across.
    pub fn new_3d(n: usize) -> DemoSource {
        let n = n.max(4);
        let dx = 1.0 / n as f32;
        let mut particles = Vec::new();
        let mut walls = Vec::new();
        let layers = n / 2;
        for i in 0..n {
            for k in 0..n {
                let x = (i as f32 + 0.5) * dx - CENTER;
                let z = (k as f32 + 0.5) * dx - CENTER;
                let r = (x * x + z * z).sqrt();
                if r < RADIUS {
                    let kd = if r > RADIUS - 1.5 * dx {
                        kind::SOLID
                    } else {
                        kind::FLUID
                    };
                    for j in 0..layers {
                        particles.push((kd, r, z.atan2(x), (j as f32 + 0.5) * dx));
                    }
                }
                walls.push([x + CENTER, -0.5 * dx, z + CENTER]);
            }
        }
        DemoSource {
            dim: 3,
            particles,
            walls,
            spacing: dx,
            domain_min: [0.0, -dx, 0.0],
            domain_max: [1.0, layers as f32 * dx, 1.0],
            time: 0.0,
            step: 0,
            dt: 2e-3,
        }
    }

    fn position(&self, p: &(u8, f32, f32, f32)) -> [f32; 3] {
        let (k, r, a0, h) = *p;
        let a = a0 + angular_velocity(r, k) * self.time as f32;
        let (s, c) = (a % TAU).sin_cos();
        if self.dim == 2 {
            [CENTER + r * c, CENTER + r * s, 0.0]
        } else {
            [CENTER + r * c, h, CENTER + r * s]
        }
    }
}

impl LiveSource for DemoSource {
    fn advance(&mut self, steps: u32) -> Result<(), String> {
        self.step += steps as u64;
        self.time = self.step as f64 * self.dt;
        Ok(())
    }

    fn frame(&mut self, field: Field, out: &mut FrameData) {
        out.dim = self.dim;
        out.domain_min = self.domain_min;
        out.domain_max = self.domain_max;
        out.particle_radius = 0.5 * self.spacing;
        out.positions.clear();
        out.values.clear();
        out.kinds.clear();
        for p in &self.particles {
            let (k, r, _, _) = *p;
            let speed = angular_velocity(r, k) * r;
            out.positions.push(self.position(p));
            out.kinds.push(k);
            out.values.push(match field {
                Field::Speed => speed,
                Field::Pressure => 1000.0 * speed * speed,
                Field::Density => 1000.0 + 2.0 * speed * speed,
                Field::Kind => k as f32,
            });
        }
        for w in &self.walls {
            out.positions.push(*w);
            out.kinds.push(kind::BOUNDARY);
            out.values.push(match field {
                Field::Speed => 0.0,
                Field::Pressure => 0.0,
                Field::Density => 1000.0,
                Field::Kind => kind::BOUNDARY as f32,
            });
        }
    }

    fn status(&self) -> Status {
        Status {
            time: self.time,
            step: self.step,
            particles: self.particles.len() + self.walls.len(),
        }
    }

    fn reset(&mut self) -> Result<(), String> {
        self.time = 0.0;
        self.step = 0;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_consistent_and_buffer_is_reused() {
        for mut src in [DemoSource::new_2d(24), DemoSource::new_3d(10)] {
            let mut f = FrameData::default();
            src.frame(Field::Speed, &mut f);
            f.validate().unwrap();
            assert_eq!(f.len(), src.status().particles);
            let cap = f.positions.capacity();
            let ptr = f.positions.as_ptr();
            src.advance(10).unwrap();
            src.frame(Field::Pressure, &mut f);
            assert_eq!((f.positions.capacity(), f.positions.as_ptr()), (cap, ptr));
            assert_eq!(src.status().step, 10);
            src.reset().unwrap();
            assert_eq!(src.status().step, 0);
        }
    }
}
