//! Probes and free-surface gauges (`[[probes]]`, `[[gauges]]`): the host's part. The
//! fields at a point are interpolated by the backends (`Readback::sample_points`, on the
//! device on the GPU); a gauge is a line of such points whose colour (the fluid's kernel
//! sum sum_j W m_j / rho_j, eqs. (1)-(4), 1 inside the fluid and 1/2 at its free surface)
//! locates the surface here, as DualSPHysics' GaugeSWL does. `app/src/probes.rs` samples
//! them during a run into `probes.csv` and `gauges.csv`.

use crate::scene::format::Gauge;

/// The colour at the free surface [-]: half the kernel's support lies in the fluid.
pub const SURFACE_COLOUR: f32 = 0.5;

/// Where a gauge's line meets the free surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// \[L\] (z = 0 in 2D).
    pub position: [f64; 3],
    /// \[L\] from the line's start.
    pub distance: f64,
}

/// The points of the line `start` -> `end` (`dim` numbers each), both ends included, at
/// most `step` \[L\] apart and evenly spaced: ceil(length / step) + 1 of them.
pub fn line_points(start: &[f64], end: &[f64], step: f64, dim: usize) -> Vec<[f64; 3]> {
    let mut a = [0.0; 3];
    let mut b = [0.0; 3];
    a[..dim].copy_from_slice(&start[..dim]);
    b[..dim].copy_from_slice(&end[..dim]);
    let len = distance(&a, &b);
    let n = ((len / step) - 1e-9).ceil().max(1.0) as usize;
    (0..=n)
        .map(|k| {
            let s = k as f64 / n as f64;
            [0, 1, 2].map(|c| a[c] + s * (b[c] - a[c]))
        })
        .collect()
}

/// The points of gauge `g` in a scene of spacing `spacing` \[L\] (its `step`, default half the
/// spacing).
pub fn gauge_points(g: &Gauge, spacing: f64, dim: usize) -> Vec<[f64; 3]> {
    line_points(&g.start, &g.end, g.step.unwrap_or(0.5 * spacing), dim)
}

/// The free surface along a line of `points` whose colours are `colour`: the last point
/// with colour >= `SURFACE_COLOUR`, moved towards the next point by linear interpolation of
/// the colour between the two (where the next is below it); the line's end where the last
/// point is at or above it (the fluid reaches past the line); None where no point is (a dry
/// line).
pub fn surface(points: &[[f64; 3]], colour: &[f32]) -> Option<Surface> {
    let k = colour.iter().rposition(|&c| c >= SURFACE_COLOUR)?;
    let mut x = points[k];
    if let (Some(&c1), Some(next)) = (colour.get(k + 1), points.get(k + 1)) {
        let c0 = colour[k];
        // c0 >= 1/2 > c1: the crossing lies in [0, 1) of the way to the next point.
        let s = ((c0 - SURFACE_COLOUR) / (c0 - c1)) as f64;
        x = [0, 1, 2].map(|c| x[c] + s * (next[c] - x[c]));
    }
    Some(Surface {
        position: x,
        distance: distance(&points[0], &x),
    })
}

fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    (0..3).map(|c| (b[c] - a[c]).powi(2)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_points_include_both_ends_at_most_a_step_apart() {
        let p = line_points(&[0.0, 0.0], &[0.0, 1.0], 0.3, 2);
        assert_eq!(p.len(), 5); // ceil(1 / 0.3) = 4 intervals of 0.25
        assert_eq!(p[0], [0.0, 0.0, 0.0]);
        assert_eq!(p[4], [0.0, 1.0, 0.0]);
        assert!((p[1][1] - 0.25).abs() < 1e-12);
        // A whole number of steps gives exactly that many intervals.
        assert_eq!(line_points(&[0.0, 0.0], &[0.0, 1.0], 0.25, 2).len(), 5);
    }

    #[test]
    fn surface_interpolates_the_crossing_of_one_half() {
        let pts: Vec<[f64; 3]> = (0..5).map(|k| [0.0, k as f64, 0.0]).collect();
        // A low colour at the wall below does not count: the last point at or above 1/2.
        let s = surface(&pts, &[0.4, 1.0, 0.9, 0.3, 0.0]).unwrap();
        assert!((s.position[1] - (2.0 + 0.4 / 0.6)).abs() < 1e-6);
        assert!((s.distance - s.position[1]).abs() < 1e-12);
        assert_eq!(surface(&pts, &[0.0; 5]), None);
        let full = surface(&pts, &[1.0; 5]).unwrap();
        assert_eq!(full.position, [0.0, 4.0, 0.0]);
    }
}
