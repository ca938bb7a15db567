//! `meshfree compare A B`: match the particles of two particle CSV files (ours, CPU vs GPU,
//! or another code's export in the same columns) by id or by nearest position, and report
//! per-field error norms and the worst particles.

use std::collections::HashMap;
use std::path::Path;

use serde::Serialize;

use crate::nearest::NearestIndex;
use crate::output::read_particles_csv;
use meshfree_core::physics::particle::Particle;

/// How particles of A find their partner in B.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum MatchBy {
    /// The same id (both files from the same scene).
    #[default]
    Id,
    /// The nearest particle of B to each particle of A (different codes).
    Position,
}

/// Error norms of one field over the matched pairs (A - B).
#[derive(Clone, Debug, Serialize)]
pub struct FieldError {
    pub field: String,
    /// max |a - b|
    pub max_abs: f64,
    /// sqrt(mean (a - b)^2)
    pub rms: f64,
    /// ||a - b||_2 / ||b||_2 (0 where b is all zero)
    pub rel_l2: f64,
    /// The id (in A) of the pair with the largest |a - b|.
    pub worst_id: u32,
}

#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    pub matched: usize,
    pub only_in_a: usize,
    pub only_in_b: usize,
    pub fields: Vec<FieldError>,
    /// (id in A, id in B, distance) of the pairs farthest apart, worst first.
    pub worst_positions: Vec<(u32, u32, f64)>,
}

type Getter = fn(&Particle) -> f64;

const FIELDS: [(&str, Getter); 9] = [
    ("x", |p| p.position[0] as f64),
    ("y", |p| p.position[1] as f64),
    ("z", |p| p.position[2] as f64),
    ("vx", |p| p.velocity[0] as f64),
    ("vy", |p| p.velocity[1] as f64),
    ("vz", |p| p.velocity[2] as f64),
    ("speed", |p| p.speed() as f64),
    ("density", |p| p.density as f64),
    ("pressure", |p| p.pressure as f64),
];

fn distance(a: &Particle, b: &Particle) -> f64 {
    (0..3)
        .map(|k| (a.position[k] as f64 - b.position[k] as f64).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Pairs (index in a, index in b).
fn pairs(a: &[Particle], b: &[Particle], by: MatchBy) -> Vec<(usize, usize)> {
    match by {
        MatchBy::Id => {
            let index: HashMap<u32, usize> = b.iter().enumerate().map(|(k, p)| (p.id, k)).collect();
            a.iter()
                .enumerate()
                .filter_map(|(i, p)| index.get(&p.id).map(|&k| (i, k)))
                .collect()
        }
        MatchBy::Position => {
            let index = NearestIndex::new(b.iter().map(|p| p.position.map(f64::from)).collect());
            a.iter()
                .enumerate()
                .filter_map(|(i, p)| {
                    index
                        .nearest(&p.position.map(f64::from))
                        .map(|(k, _)| (i, k))
                })
                .collect()
        }
    }
}

pub fn compare(a: &[Particle], b: &[Particle], by: MatchBy, worst: usize) -> Comparison {
    let pairs = pairs(a, b, by);
    let fields = FIELDS
        .iter()
        .map(|(name, get)| {
            let (mut max_abs, mut sum2, mut ref2, mut worst_id) = (0.0f64, 0.0f64, 0.0f64, 0u32);
            for &(i, k) in &pairs {
                let d = get(&a[i]) - get(&b[k]);
                if d.abs() > max_abs {
                    max_abs = d.abs();
                    worst_id = a[i].id;
                }
                sum2 += d * d;
                ref2 += get(&b[k]).powi(2);
            }
            let n = pairs.len().max(1) as f64;
            FieldError {
                field: name.to_string(),
                max_abs,
                rms: (sum2 / n).sqrt(),
                rel_l2: if ref2 > 0.0 {
                    (sum2 / ref2).sqrt()
                } else {
                    0.0
                },
                worst_id,
            }
        })
        .collect();
    let mut far: Vec<(u32, u32, f64)> = pairs
        .iter()
        .map(|&(i, k)| (a[i].id, b[k].id, distance(&a[i], &b[k])))
        .collect();
    far.sort_by(|x, y| y.2.total_cmp(&x.2));
    far.truncate(worst);
    let matched = pairs.len();
    Comparison {
        matched,
        only_in_a: a.len() - matched,
        only_in_b: b.len().saturating_sub(matched),
        fields,
        worst_positions: far,
    }
}

/// Read both files and compare them.
pub fn compare_files(a: &Path, b: &Path, by: MatchBy, worst: usize) -> Result<Comparison, String> {
    let pa = read_particles_csv(a)?;
    let pb = read_particles_csv(b)?;
    Ok(compare(&pa, &pb, by, worst))
}
