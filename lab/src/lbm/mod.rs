//! A small D2Q9 lattice Boltzmann solver: the grid-based reference for the built-in vortex
//! streets (issue #23), kept out of the SPH core.
//!
//! Everything here is in lattice units (spacing 1, time step 1, rest density 1, sound speed
//! 1 / sqrt 3); `street.rs` maps a scene onto the lattice.
//!
//! - Collision: two-relaxation-time (TRT), Ginzburg, Verhaeghe & d'Humieres 2008 (Commun.
//!   Comput. Phys. 3, 427), the symmetric part relaxed at 1 / tau+ with nu = (tau+ - 1/2) / 3,
//!   the antisymmetric part at 1 / tau- from the "magic" Lambda = (tau+ - 1/2)(tau- - 1/2) =
//!   3 / 16, with which bounce-back puts a straight wall exactly halfway between nodes
//!   (Krueger et al., "The Lattice Boltzmann Method", 2017, sections 10.7 and 5.3.5).
//! - A uniform body force (acceleration `accel`, [lattice length / step^2]) by Guo, Zheng &
//!   Shi 2002 (Phys. Rev. E 65, 046308; Krueger et al. 6.3), split into its TRT parts, with the
//!   velocity u = (sum f c + F / 2) / rho.
//! - Streaming: pull, periodic in x and y.
//! - Walls: the cells whose centres lie inside the obstacle are solid; every link from a fluid
//!   cell into one gets the linear interpolated bounce-back of Bouzidi, Firdaouss &
//!   Lallemand 2001 (Phys. Fluids 13, 3452) with the wall's fraction q along the link
//!   (bisection of `inside`), halfway bounce-back where the second fluid node it needs is
//!   missing. The force on the obstacle is the momentum exchanged across those links (Ladd
//!   1994; Mei, Yu, Shyy & Luo 2002, Phys. Rev. E 65, 041203).
//! - A band of cells (`band`) has its velocity set: after collision its populations are the
//!   equilibrium at the prescribed velocity with the cell's own density.

pub mod street;

use rayon::prelude::*;

/// The D2Q9 velocities: rest, the four axes, the four diagonals.
pub const C: [[i32; 2]; 9] = [
    [0, 0],
    [1, 0],
    [0, 1],
    [-1, 0],
    [0, -1],
    [1, 1],
    [-1, 1],
    [-1, -1],
    [1, -1],
];
/// The weights of `C` (Krueger et al. table 3.3).
pub const W: [f64; 9] = [
    4.0 / 9.0,
    1.0 / 9.0,
    1.0 / 9.0,
    1.0 / 9.0,
    1.0 / 9.0,
    1.0 / 36.0,
    1.0 / 36.0,
    1.0 / 36.0,
    1.0 / 36.0,
];
/// The direction opposite to each of `C`.
pub const OPP: [usize; 9] = [0, 3, 4, 1, 2, 7, 8, 5, 6];
/// TRT's magic parameter (Ginzburg et al. 2008): walls exactly halfway under bounce-back.
pub const MAGIC: f64 = 3.0 / 16.0;

/// The second-order equilibrium f_i = w_i rho (1 + 3 c.u + 9/2 (c.u)^2 - 3/2 u^2).
pub fn equilibrium(rho: f64, u: [f64; 2]) -> [f64; 9] {
    let uu = u[0] * u[0] + u[1] * u[1];
    std::array::from_fn(|i| {
        let cu = C[i][0] as f64 * u[0] + C[i][1] as f64 * u[1];
        W[i] * rho * (1.0 + 3.0 * cu + 4.5 * cu * cu - 1.5 * uu)
    })
}

/// A link from a fluid cell into the obstacle: the population `dir` arriving at `cell`
/// would come from a solid cell; the wall lies at fraction `q` of the link from the cell.
#[derive(Clone, Copy, Debug)]
struct Link {
    cell: usize,
    dir: usize,
    q: f64,
    /// The fluid cell one step further from the wall (cell + c_dir), for q < 1/2.
    behind: Option<usize>,
}

/// The lattice: `nx` x `ny` cells, cell (i, j) centred at (i + 1/2, j + 1/2).
///
/// Populations are stored row by row and, within a row, direction by direction
/// (index (9 j + k) nx + i): streaming is then a shifted copy of whole rows, and the
/// collision runs along contiguous arrays. They hold the post-collision values f* between
/// steps.
pub struct Lattice {
    pub nx: usize,
    pub ny: usize,
    f: Vec<f64>,
    next: Vec<f64>,
    solid: Vec<bool>,
    solid_cells: Vec<usize>,
    links: Vec<Link>,
    omega_plus: f64,
    omega_minus: f64,
    /// [lattice length / step^2] The uniform acceleration of the next step (Guo forcing).
    pub accel: [f64; 2],
    /// The columns [band.0, band.1) whose velocity is set to `band_velocity`.
    pub band: (usize, usize),
    pub band_velocity: [f64; 2],
}

impl Lattice {
    /// At rest at density 1, kinematic viscosity `nu` \[lattice\], the cells whose centre
    /// satisfies `inside` solid.
    pub fn new(nx: usize, ny: usize, nu: f64, inside: impl Fn([f64; 2]) -> bool) -> Lattice {
        let tau_plus = 3.0 * nu + 0.5;
        let tau_minus = MAGIC / (tau_plus - 0.5) + 0.5;
        let centre = |c: usize| [(c % nx) as f64 + 0.5, (c / nx) as f64 + 0.5];
        let solid: Vec<bool> = (0..nx * ny).map(|c| inside(centre(c))).collect();
        let mut f = vec![0.0; 9 * nx * ny];
        let rest = equilibrium(1.0, [0.0; 2]);
        for (n, x) in f.iter_mut().enumerate() {
            *x = rest[(n / nx) % 9];
        }
        let mut lat = Lattice {
            nx,
            ny,
            next: f.clone(),
            f,
            solid_cells: (0..nx * ny).filter(|&c| solid[c]).collect(),
            solid,
            links: Vec::new(),
            omega_plus: 1.0 / tau_plus,
            omega_minus: 1.0 / tau_minus,
            accel: [0.0; 2],
            band: (0, 0),
            band_velocity: [0.0; 2],
        };
        for cell in (0..nx * ny).filter(|&c| !lat.solid[c]) {
            for dir in 1..9 {
                if !lat.solid[lat.neighbour(cell, OPP[dir])] {
                    continue;
                }
                // The wall crossing along x -> x - c_dir by bisection of `inside`
                // (unwrapped coordinates: the obstacle must not straddle the periodic edge).
                let x = centre(cell);
                let c = C[dir];
                let at = |s: f64| [x[0] - s * c[0] as f64, x[1] - s * c[1] as f64];
                let (mut lo, mut hi) = (0.0, 1.0);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if inside(at(mid)) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                let b = lat.neighbour(cell, dir);
                lat.links.push(Link {
                    cell,
                    dir,
                    q: 0.5 * (lo + hi),
                    behind: (!lat.solid[b]).then_some(b),
                });
            }
        }
        lat
    }

    /// The cell one step along C[dir] from `cell`, periodic.
    fn neighbour(&self, cell: usize, dir: usize) -> usize {
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        let i = (cell as i64 % nx + C[dir][0] as i64).rem_euclid(nx);
        let j = (cell as i64 / nx + C[dir][1] as i64).rem_euclid(ny);
        (j * nx + i) as usize
    }

    /// The index of population `k` of `cell` in `f` / `next`.
    #[inline]
    fn at(&self, cell: usize, k: usize) -> usize {
        let (j, i) = (cell / self.nx, cell % self.nx);
        (9 * j + k) * self.nx + i
    }

    pub fn is_solid(&self, i: usize, j: usize) -> bool {
        self.solid[j * self.nx + i]
    }

    /// Density and velocity of cell (i, j) before the last collision, which added the
    /// step's force F = rho a to the momentum: u = (sum f* c - F / 2) / rho (Guo et al.
    /// 2002); in the band its set velocity; (1, 0) in a solid cell.
    pub fn moments(&self, i: usize, j: usize) -> (f64, [f64; 2]) {
        let c = j * self.nx + i;
        if self.solid[c] {
            return (1.0, [0.0; 2]);
        }
        let f: [f64; 9] = std::array::from_fn(|k| self.f[self.at(c, k)]);
        let rho: f64 = f.iter().sum();
        if (self.band.0..self.band.1).contains(&i) {
            return (rho, self.band_velocity);
        }
        let m = |d: usize| (0..9).map(|k| f[k] * C[k][d] as f64).sum::<f64>();
        (
            rho,
            [
                m(0) / rho - 0.5 * self.accel[0],
                m(1) / rho - 0.5 * self.accel[1],
            ],
        )
    }

    /// Add `dv` times `weight` (of the cell's centre) to the velocity of every fluid cell,
    /// keeping the non-equilibrium part (f += feq(rho, u + w dv) - feq(rho, u)). Used once,
    /// to seed the shedding.
    pub fn kick(&mut self, weight: impl Fn([f64; 2]) -> f64, dv: [f64; 2]) {
        for c in (0..self.nx * self.ny).filter(|&c| !self.solid[c]) {
            let w = weight([(c % self.nx) as f64 + 0.5, (c / self.nx) as f64 + 0.5]);
            if w == 0.0 {
                continue;
            }
            let idx: [usize; 9] = std::array::from_fn(|k| self.at(c, k));
            let rho: f64 = idx.iter().map(|&n| self.f[n]).sum();
            let m = |d: usize| (0..9).map(|k| self.f[idx[k]] * C[k][d] as f64).sum::<f64>();
            let u = [m(0) / rho, m(1) / rho];
            let (a, b) = (
                equilibrium(rho, u),
                equilibrium(rho, [u[0] + w * dv[0], u[1] + w * dv[1]]),
            );
            for k in 0..9 {
                self.f[idx[k]] += b[k] - a[k];
            }
        }
    }

    /// One step: stream, bounce back at the obstacle, collide (TRT with the Guo force; the
    /// band set to its equilibrium). Returns the force on the obstacle [lattice: rho0 dx^3
    /// / dt^2 per unit depth], the momentum exchanged across the wall links.
    pub fn step(&mut self) -> [f64; 2] {
        self.stream();
        let force = self.bounce_back();
        self.collide();
        std::mem::swap(&mut self.f, &mut self.next);
        force
    }

    /// Pull streaming of the post-collision `f` into `next`, periodic: row j, direction k
    /// takes row j - c_ky shifted by c_kx (what comes from solid cells is replaced by
    /// `bounce_back`).
    fn stream(&mut self) {
        let (nx, ny, f) = (self.nx, self.ny, &self.f);
        self.next
            .par_chunks_mut(9 * nx)
            .enumerate()
            .for_each(|(j, row)| {
                for (k, dst) in row.chunks_exact_mut(nx).enumerate() {
                    let sj = (j as i64 - C[k][1] as i64).rem_euclid(ny as i64) as usize;
                    let src = &f[(9 * sj + k) * nx..(9 * sj + k + 1) * nx];
                    match C[k][0] {
                        0 => dst.copy_from_slice(src),
                        1 => {
                            dst[1..].copy_from_slice(&src[..nx - 1]);
                            dst[0] = src[nx - 1];
                        }
                        _ => {
                            dst[..nx - 1].copy_from_slice(&src[1..]);
                            dst[nx - 1] = src[0];
                        }
                    }
                }
            });
    }

    /// Bouzidi et al. 2001's linear interpolated bounce-back for a wall at rest, in the
    /// direction k arriving at x (the wall along -c_k at q; o = opposite of k, f* the
    /// post-collision populations):
    /// q < 1/2:  f_k(x) = 2q f*_o(x) + (1 - 2q) f*_o(x + c_k),
    /// q >= 1/2: f_k(x) = f*_o(x) / (2q) + (2q - 1) / (2q) f*_k(x).
    /// Momentum exchange (Mei et al. 2002): each link gives the obstacle
    /// c_o (f*_o(x) + f_k(x)).
    fn bounce_back(&mut self) -> [f64; 2] {
        let mut force = [0.0; 2];
        for l in &self.links {
            let (k, o) = (l.dir, OPP[l.dir]);
            let post = |cell: usize, d: usize| self.f[self.at(cell, d)];
            let fo = post(l.cell, o);
            let fk = match l.behind {
                Some(b) if l.q < 0.5 => 2.0 * l.q * fo + (1.0 - 2.0 * l.q) * post(b, o),
                None if l.q < 0.5 => fo,
                _ => fo / (2.0 * l.q) + (2.0 * l.q - 1.0) / (2.0 * l.q) * post(l.cell, k),
            };
            let n = self.at(l.cell, k);
            self.next[n] = fk;
            force[0] += C[o][0] as f64 * (fo + fk);
            force[1] += C[o][1] as f64 * (fo + fk);
        }
        force
    }

    /// TRT collision of `next` in place, row by row, with Guo's source for F = rho a:
    /// S_i = w_i [3 c.F + 9 (c.u)(c.F) - 3 u.F], its antisymmetric part 3 w_i c.F weighted
    /// by (1 - omega-/2), its symmetric part by (1 - omega+/2). The band's cells are then
    /// set to the equilibrium at the band's velocity with their density (which the
    /// collision keeps), the solid cells to rest (they receive populations from the fluid
    /// and never give any back).
    // `i` indexes the nine direction arrays of a row at once.
    #[allow(clippy::needless_range_loop)]
    fn collide(&mut self) {
        let (wp, wm, a, nx) = (self.omega_plus, self.omega_minus, self.accel, self.nx);
        let (band, ub) = (self.band, self.band_velocity);
        self.next.par_chunks_mut(9 * nx).for_each(|row| {
            let mut r: Vec<&mut [f64]> = row.chunks_exact_mut(nx).collect();
            for i in 0..nx {
                let f: [f64; 9] = std::array::from_fn(|k| r[k][i]);
                let rho: f64 = f.iter().sum();
                let mut m = [0.0; 2];
                for k in 1..9 {
                    m[0] += f[k] * C[k][0] as f64;
                    m[1] += f[k] * C[k][1] as f64;
                }
                let u = [m[0] / rho + 0.5 * a[0], m[1] / rho + 0.5 * a[1]];
                let eq = equilibrium(rho, u);
                let (fx, fy) = (rho * a[0], rho * a[1]);
                let uf = u[0] * fx + u[1] * fy;
                for k in 0..9 {
                    let o = OPP[k];
                    let (cx, cy) = (C[k][0] as f64, C[k][1] as f64);
                    let (cu, cf) = (cx * u[0] + cy * u[1], cx * fx + cy * fy);
                    let s_plus = W[k] * (9.0 * cu * cf - 3.0 * uf);
                    let s_minus = W[k] * 3.0 * cf;
                    let plus = 0.5 * (f[k] + f[o]) - 0.5 * (eq[k] + eq[o]);
                    let minus = 0.5 * (f[k] - f[o]) - 0.5 * (eq[k] - eq[o]);
                    r[k][i] = f[k] - wp * plus - wm * minus
                        + (1.0 - 0.5 * wp) * s_plus
                        + (1.0 - 0.5 * wm) * s_minus;
                }
            }
            for i in band.0..band.1 {
                let rho: f64 = (0..9).map(|k| r[k][i]).sum();
                let eq = equilibrium(rho, ub);
                for k in 0..9 {
                    r[k][i] = eq[k];
                }
            }
        });
        let rest = equilibrium(1.0, [0.0; 2]);
        for c in 0..self.solid_cells.len() {
            let cell = self.solid_cells[c];
            for (k, x) in rest.iter().enumerate() {
                let n = self.at(cell, k);
                self.next[n] = *x;
            }
        }
    }
}
