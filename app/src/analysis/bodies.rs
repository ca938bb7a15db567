//! Rigid-body measures of elastic bodies (the particles of one solid group): centroid,
//! centroid velocity, angular velocity about the centroid, radius of gyration and size
//! (area in 2D, volume in 3D, the sum of m_i / rho_i). The run driver writes them to
//! `bodies.csv` (`output::bodies_csv`) and their extremes to `summary.json`.

use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};

use meshfree_core::physics::particle::{Kind, Particle};

/// One body at one instant. Vectors have three components (z = 0 in 2D).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    pub group: u32,
    /// Number of particles.
    pub n: usize,
    /// \[L\] mass-weighted centroid.
    pub centroid: [f32; 3],
    /// [L/T] velocity of the centroid (total momentum / total mass).
    pub velocity: [f32; 3],
    /// [1/T] angular velocity about the centroid, omega = I^-1 L with I the inertia tensor
    /// and L the angular momentum of the particles' velocities relative to the centroid's.
    /// In 2D only z: omega_z = L_z / I_z.
    pub omega: [f32; 3],
    /// \[L\] radius of gyration about the centroid, sqrt(sum m |x - c|^2 / sum m): grows
    /// where a body comes apart even though its size (below) does not.
    pub rg: f32,
    /// [L^d] sum of m_i / rho_i: the body's area (2D) or volume (3D).
    pub size: f32,
}

/// The measures of the particles of `group` (of any kind), or None where it has none.
/// `dim` is 2 or 3: in 2D only omega_z is computed.
pub fn body(particles: &[Particle], group: u32, dim: u32) -> Option<Body> {
    let b: Vec<&Particle> = particles.iter().filter(|p| p.group == group).collect();
    if b.is_empty() {
        return None;
    }
    let pos = |p: &Particle| DVec3::from_array(p.position.map(f64::from));
    let vel = |p: &Particle| DVec3::from_array(p.velocity.map(f64::from));
    let (mut m, mut mx, mut mv, mut size) = (0.0f64, DVec3::ZERO, DVec3::ZERO, 0.0f64);
    for p in &b {
        let mi = p.mass as f64;
        m += mi;
        mx += pos(p) * mi;
        mv += vel(p) * mi;
        size += mi / p.density as f64;
    }
    let (c, v) = (mx / m, mv / m);
    // Angular momentum L = sum m d x u and inertia tensor I = sum m (|d|^2 E - d d^T) about
    // the centroid, d = x - c, u = v - v_c.
    let (mut l, mut inertia, mut r2) = (DVec3::ZERO, DMat3::ZERO, 0.0f64);
    for p in &b {
        let mi = p.mass as f64;
        let d = pos(p) - c;
        let u = vel(p) - v;
        l += d.cross(u) * mi;
        let dd = d.length_squared();
        r2 += dd * mi;
        inertia += (DMat3::from_diagonal(DVec3::splat(dd))
            - DMat3::from_cols(d * d.x, d * d.y, d * d.z))
            * mi;
    }
    let omega = if dim == 2 {
        let iz = inertia.z_axis.z;
        DVec3::new(0.0, 0.0, if iz > 0.0 { l.z / iz } else { 0.0 })
    } else if inertia.determinant().abs() > 1e-12 * r2.powi(3).max(f64::MIN_POSITIVE) {
        inertia.inverse() * l
    } else {
        DVec3::ZERO // a single particle or a line of them: no rotation to speak of
    };
    Some(Body {
        group,
        n: b.len(),
        centroid: c.as_vec3().to_array(),
        velocity: v.as_vec3().to_array(),
        omega: omega.as_vec3().to_array(),
        rg: (r2 / m).sqrt() as f32,
        size: size as f32,
    })
}

/// Every solid group of `particles` (the elastic bodies, driven ones included), by group.
pub fn solid_groups(particles: &[Particle]) -> Vec<u32> {
    let mut g: Vec<u32> = particles
        .iter()
        .filter(|p| p.kind == Kind::Solid)
        .map(|p| p.group)
        .collect();
    g.sort_unstable();
    g.dedup();
    g
}

/// The extremes of one body over a run, for `summary.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodySummary {
    pub group: u32,
    pub particles: usize,
    /// [1/T] largest |omega| over the outputs.
    pub max_omega: f32,
    /// [-] largest |size / size at t = 0 - 1| over the outputs (area in 2D, volume in 3D).
    pub worst_size_change: f32,
    /// [-] largest |rg / rg at t = 0 - 1| over the outputs: the body's shape.
    pub worst_rg_change: f32,
}

/// Bodies followed over a run: the measures at t = 0 and the running extremes.
#[derive(Clone, Debug, Default)]
pub struct BodyTracker {
    dim: u32,
    start: Vec<Body>,
    summary: Vec<BodySummary>,
}

/// One output's row per body: the measures and the ratios to t = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyRow {
    pub body: Body,
    /// [-] size / size at t = 0.
    pub size_ratio: f32,
    /// [-] rg / rg at t = 0.
    pub rg_ratio: f32,
}

impl BodyTracker {
    /// Start from the particles at t = 0: every solid group is a body.
    pub fn new(particles: &[Particle], dim: u32) -> BodyTracker {
        let start: Vec<Body> = solid_groups(particles)
            .into_iter()
            .filter_map(|g| body(particles, g, dim))
            .collect();
        let summary = start
            .iter()
            .map(|b| BodySummary {
                group: b.group,
                particles: b.n,
                max_omega: 0.0,
                worst_size_change: 0.0,
                worst_rg_change: 0.0,
            })
            .collect();
        BodyTracker {
            dim,
            start,
            summary,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.start.is_empty()
    }

    /// The rows of one output, updating the extremes. A body whose particles are all gone
    /// has no row.
    pub fn sample(&mut self, particles: &[Particle]) -> Vec<BodyRow> {
        let mut rows = Vec::new();
        for (b0, s) in self.start.iter().zip(self.summary.iter_mut()) {
            let Some(b) = body(particles, b0.group, self.dim) else {
                continue;
            };
            let size_ratio = b.size / b0.size;
            let rg_ratio = if b0.rg > 0.0 { b.rg / b0.rg } else { 1.0 };
            let w = b.omega.iter().map(|c| c * c).sum::<f32>().sqrt();
            s.max_omega = s.max_omega.max(w);
            s.worst_size_change = s.worst_size_change.max((size_ratio - 1.0).abs());
            s.worst_rg_change = s.worst_rg_change.max((rg_ratio - 1.0).abs());
            rows.push(BodyRow {
                body: b,
                size_ratio,
                rg_ratio,
            });
        }
        rows
    }

    pub fn summaries(&self) -> Vec<BodySummary> {
        self.summary.clone()
    }

    /// Continue the extremes of a run from `summaries` (its `summaries` at a checkpoint).
    /// Err: they name other bodies than this tracker's.
    pub fn resume(&mut self, summaries: &[BodySummary]) -> Result<(), String> {
        let groups =
            |v: &[BodySummary]| v.iter().map(|b| (b.group, b.particles)).collect::<Vec<_>>();
        if groups(summaries) != groups(&self.summary) {
            return Err(format!(
                "its bodies (group, particles) {:?} are not the scene's {:?}",
                groups(summaries),
                groups(&self.summary)
            ));
        }
        self.summary = summaries.to_vec();
        Ok(())
    }
}
