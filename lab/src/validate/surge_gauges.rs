//! The dam break's gauges, read off the particles: the water depth along the floor and the
//! surge front (`Depth`, `surge_front`), the water height at the back wall (`wall_height`)
//! and how high the surge rides over the floor (`surge_cushion`). Used by `dam_break` and
//! the stability sweep.

use meshfree_core::physics::kernel;
use meshfree_core::physics::params::SphParams;
use meshfree_core::physics::particle::{Kind, Particle};

/// The least water depth [-, of the column width] that counts as the surge: the front is
/// where the water thins below it. DualSPHysics' validation of Koshizuka & Oka's experiment
/// (`examples/main/01_DamBreak/CaseDambreakVal2D_Def.xml`: a 1 m wide column, the tip read
/// by a free-surface gauge, `Swl_z003`, along a line 0.03 m above the floor) counts the
/// water from 0.03 column widths deep; the experiments photographed the leading edge of the
/// surge, which a lone particle or a sheet one particle thick ahead of it is not
/// (docs/reference/accuracy.md, "Dam-break fronts run ahead of the experiments").
pub const FRONT_DEPTH: f64 = 0.03;

/// The water depth d(x) \[L\] over the floor, from the fluid particles: the fluid fraction
/// phi = sum_j V_j W(x - x_j) (V_j = m_j / rho_j [L^d], W the run's kernel [L^-d],
/// `kernel::w`) integrated along the vertical, d(x) = sum_j V_j K(x - x_j) with
/// K(s) = integral of W(sqrt(s^2 + t^2)) dt [L^-1] (2D; tabulated once). A layer of depth D
/// gives d = D whatever its height above the floor, so the dynamic walls' stand-off (the
/// sheet rides about a spacing above the floor particles) does not read as a dry floor,
/// as the colour at a fixed height near the floor does.
pub struct Depth {
    /// (x_j, V_j) of the fluid particles, binned by x in bins one support wide.
    bins: Vec<Vec<(f64, f64)>>,
    support: f64,
    /// K at s = support k / (len - 1).
    table: Vec<f64>,
}

impl Depth {
    pub fn new(p: &SphParams, ps: &[Particle]) -> Depth {
        let support = (2.0 * p.h) as f64;
        let mut bins: Vec<Vec<(f64, f64)>> = Vec::new();
        // Only water inside the domain counts: a blown-up state (a particle at 1e30 or NaN,
        // between two health checks) would otherwise ask for bins without end.
        for q in ps
            .iter()
            .filter(|q| q.kind == Kind::Fluid && in_domain(p, q))
        {
            let x = q.position[0] as f64;
            let k = (x / support).floor().max(0.0) as usize;
            if bins.len() <= k {
                bins.resize(k + 1, Vec::new());
            }
            bins[k].push((x, (q.mass / q.density) as f64));
        }
        // K(s) by the midpoint rule over t in [-support, support], 400 cells.
        let (n, m) = (200, 400);
        let dt = 2.0 * support / m as f64;
        let table = (0..=n)
            .map(|i| {
                let sx = support * i as f64 / n as f64;
                (0..m)
                    .map(|k| {
                        let t = -support + (k as f64 + 0.5) * dt;
                        kernel::w(p, sx.hypot(t) as f32) as f64 * dt
                    })
                    .sum()
            })
            .collect();
        Depth {
            bins,
            support,
            table,
        }
    }

    fn line_integral(&self, s: f64) -> f64 {
        let u = s.abs() / self.support * (self.table.len() - 1) as f64;
        let i = u.floor() as usize;
        if i + 1 >= self.table.len() {
            return 0.0;
        }
        let f = u - i as f64;
        self.table[i] * (1.0 - f) + self.table[i + 1] * f
    }

    /// d(x) \[L\].
    pub fn at(&self, x: f64) -> f64 {
        let k = (x / self.support).floor().max(0.0) as usize;
        let bins = self
            .bins
            .get(k.saturating_sub(1)..(k + 2).min(self.bins.len()));
        bins.into_iter()
            .flatten()
            .flatten()
            .map(|&(xj, v)| v * self.line_integral(x - xj))
            .sum()
    }
}

/// The surge front \[L\]: going from the back wall x = 0 along the floor in steps of dx / 4,
/// past any dry strip at the wall, the first x where the water depth (`Depth`) falls below
/// `min_depth` \[L\] (interpolated linearly), as DualSPHysics' gauge reads the first change
/// from water to none; a drop or a sheet thinner than `min_depth` ahead of the water is not
/// the front. 0 where no water is that deep.
pub fn surge_front(p: &SphParams, ps: &[Particle], min_depth: f64) -> f64 {
    assert!(min_depth > 0.0, "the front's depth must be positive");
    let depth = Depth::new(p, ps);
    let step = 0.25 * p.dx as f64;
    let end = ps
        .iter()
        .filter(|q| q.kind == Kind::Fluid && in_domain(p, q))
        .map(|q| q.position[0] as f64)
        .fold(0.0, f64::max)
        + 2.0 * p.h as f64;
    // A depth that is not a number (a particle's NaN volume) counts as dry: both scans end.
    let (mut x, mut prev) = (0.0, depth.at(0.0));
    while !at_least(prev, min_depth) {
        x += step;
        if x > end {
            return 0.0;
        }
        prev = depth.at(x);
    }
    while x <= end {
        let next = depth.at(x + step);
        if !at_least(next, min_depth) {
            return match next.is_nan() {
                true => x,
                false => x + (prev - min_depth) / (prev - next) * step,
            };
        }
        x += step;
        prev = next;
    }
    end
}

/// Whether `v` reaches `min`: false for NaN, so that a scan counts a blown-up value as dry.
fn at_least(v: f64, min: f64) -> bool {
    v.partial_cmp(&min).is_some_and(|o| o.is_ge())
}

/// Whether `q` lies inside the scene's domain (NaN does not).
fn in_domain(p: &SphParams, q: &Particle) -> bool {
    (0..2).all(|a| q.position[a] >= p.domain_min[a] && q.position[a] <= p.domain_max[a])
}

/// \[1\] The fluid fraction below which the back wall's gauge counts the wall as dry
/// (`wall_height`). One column of particles standing against the wall, the sparsest water
/// the wall can have, reads 0.44-0.54 there; no water within the support reads 0.
pub const WALL_DRY: f64 = 0.25;

/// The water height \[L\] at the back wall x = 0 (the floor at y = 0): the free surface of the
/// column standing on the floor there, read by a kernel gauge. The fluid fraction at (0, y),
/// phi(y) = sum_j V_j [W(x_j, y - y_j) + W(-x_j, y - y_j) + W(x_j, y + y_j) + W(-x_j, y + y_j)]
/// with V_j = m_j / rho_j [L^d] and W the run's kernel [L^-d] (`kernel::w`), the fluid mirrored
/// across the wall and the floor, is 1 inside the water and 1/2 at its surface. Going up from
/// the floor in steps of dx/10, the gauge reads the water as ending where phi first falls
/// below `WALL_DRY` (no water at the wall), and the height is the last place below that where
/// phi fell through 1/2 (interpolated linearly); 0 when phi(0) < 1/2.
///
/// Why two levels: a band of the column that stands off the wall or thins to one particle
/// column reads phi ~ 0.47 with water above it (the leapfrog's dam break at dx = 0.04,
/// T = 2.57, had one 1.5 dx below a surface 2 dx higher): 1/2 alone took that band for the
/// surface. A drop or a film left above a gap empties the support between, so phi falls
/// below `WALL_DRY` first and it is not counted. The colour-function gauge `tests/physics.rs`
/// used one spacing from the wall, one-sided, is now this one, mirrored so that it reads the
/// wall itself. It replaced a walk up the particles within 2 dx of the wall that stopped at
/// the first gap wider than 2 dx: measured from y = 0, a bottom particle lifted 2 dx off the
/// floor by the noise read as an empty wall (h = 0; docs/reference/accuracy.md, dam break).
pub fn wall_height(p: &SphParams, ps: &[Particle], dx: f64) -> f64 {
    let phi = wall_fraction(p, ps);
    // A fraction that is not a number (a particle's NaN volume) counts as empty, and the
    // gauge ends at the domain's top: the scan ends in a blown-up state too.
    let (mut y, mut prev) = (0.0, phi(0.0));
    if !at_least(prev, 0.5) {
        return 0.0;
    }
    let dy = 0.1 * dx;
    let top = p.domain_max[1] as f64;
    // The last height where phi fell through 1/2, while it has not come back above.
    let mut surface = None;
    while y < top {
        let next = phi(y + dy);
        if at_least(prev, 0.5) && !at_least(next, 0.5) {
            surface = Some(match next.is_nan() {
                true => y,
                false => y + (prev - 0.5) / (prev - next) * dy,
            });
        }
        if !at_least(next, WALL_DRY) {
            // phi < 1/2 is only reached through a crossing: `surface` holds it.
            return surface.unwrap_or(y);
        }
        if at_least(next, 0.5) {
            surface = None;
        }
        y += dy;
        prev = next;
    }
    top
}

/// phi(y) of `wall_height`: the fluid fraction \[1\] at (0, y), the fluid mirrored across the
/// back wall x = 0 and the floor y = 0.
pub fn wall_fraction(p: &SphParams, ps: &[Particle]) -> impl Fn(f64) -> f64 {
    let support = (2.0 * p.h) as f64;
    let near: Vec<(f64, f64, f64)> = ps
        .iter()
        .filter(|q| q.kind == Kind::Fluid && (q.position[0] as f64) < support)
        .map(|q| {
            (
                q.position[0] as f64,
                q.position[1] as f64,
                (q.mass / q.density) as f64,
            )
        })
        .collect();
    let p = *p;
    let w = move |x: f64, y: f64| kernel::w(&p, x.hypot(y) as f32) as f64;
    // x_j and -x_j are equally far from (0, y): the wall's mirror doubles the sum.
    move |y: f64| -> f64 {
        near.iter()
            .map(|&(x, yj, v)| 2.0 * v * (w(x, y - yj) + w(x, y + yj)))
            .sum()
    }
}

/// How high the surge rides over the floor \[dx\]: over bins 0.2 `w` wide from x = 1.2 `w`
/// to 0.4 `w` short of the front `front` \[L\] (its thin tip left out), the mean of each bin's
/// lowest water particle's height over the floor (y = 0), in spacings `dx`; NaN where the
/// surge covers no whole bin yet. Water lying on the floor's surface reads 0.5 (the
/// lattice's first row); dynamic walls hold a surge about a spacing higher (issue #56).
pub fn surge_cushion(ps: &[Particle], dx: f64, w: f64, front: f64) -> f64 {
    let (mut sum, mut n) = (0.0, 0);
    let mut x = 1.2 * w;
    while x + 0.2 * w <= front - 0.4 * w {
        let low = (ps.iter())
            .filter(|q| q.kind == Kind::Fluid)
            .filter(|q| (q.position[0] as f64) >= x && (q.position[0] as f64) < x + 0.2 * w)
            .map(|q| q.position[1] as f64)
            .fold(f64::INFINITY, f64::min);
        if low.is_finite() {
            sum += low / dx;
            n += 1;
        }
        x += 0.2 * w;
    }
    if n == 0 {
        f64::NAN
    } else {
        sum / n as f64
    }
}
