//! A periodic vortex street on the lattice, set up as the SPH scenes set it up: both axes
//! periodic (a row of cylinders one channel height apart), the mean flow held by an inflow
//! band whose velocity is set to U ramp(t), the fluid outside the band accelerated with the
//! ramp's mean-flow increase (the SPH kick's uniform body force, core/src/backend/cpu/
//! integrate.rs), the same smooth ramp r(t) = (1 - cos(pi t / t_r)) / 2 (`smooth_ramp`, the
//! shape of the SPH band's `ramp_share`), Re = U D / nu. Scene units in, `ForceSample`s in
//! scene time out, so that `validate::cylinder::summary_for` analyses them as it does an SPH
//! run's forces.csv.

use super::Lattice;
use meshfree_core::backend::cpu::smooth_ramp;
use meshfree_core::measure::monitor::ForceSample;

/// A street in scene units (any consistent units; the built-ins' are dimensionless).
#[derive(Clone, Debug)]
pub struct Street {
    pub name: &'static str,
    pub re: f64,
    /// \[L\] the periodic box, x along the flow.
    pub length: f64,
    pub height: f64,
    /// \[L\] the cylinder's diameter and centre.
    pub diameter: f64,
    pub centre: [f64; 2],
    /// \[L\] the inflow band: cells with centre x in [band.0, band.1).
    pub band: (f64, f64),
    /// [L/T] the band's velocity (along x).
    pub u: f64,
    /// \[T\] the start's ramp (0: impulsive).
    pub ramp: f64,
    /// \[T\] the end of the run.
    pub t_end: f64,
    /// \[T\] the force record's interval.
    pub sample: f64,
}

/// The default lattice speed of U: Mach U / c_s = 0.17 (the SPH scenes run at 0.1), the
/// usual choice for cylinder benchmarks (Krueger et al. 2017); its compressibility error
/// (~Ma^2) is measured against 0.05 in docs/journal/2026-11-28-street-reference.md.
pub const U_LATTICE: f64 = 0.1;
/// \[U\] The seed of the shedding: a cross-flow velocity of this peak given once, at the end
/// of the ramp, in a Gaussian exp(-r^2 / w^2) of width w = D / 4 one diameter behind the
/// cylinder's rear (where `validate::cylinder::kick` puts its own, of width D / 2). The
/// lattice's mirror-symmetric start would otherwise wait for round-off to break the
/// symmetry; the SPH scenes' particle noise does it for them.
pub const KICK: f64 = 0.1;

/// `scenes/vortex-street-re140.toml`: 20 x 8, D = 2 at (8, 4), U = 15, band [0, 1),
/// ramp 2 D / U, to t = 20, forces every 0.02.
pub fn re140() -> Street {
    Street {
        name: "vortex-street-re140",
        re: 140.0,
        length: 20.0,
        height: 8.0,
        diameter: 2.0,
        centre: [8.0, 4.0],
        band: (0.0, 1.0),
        u: 15.0,
        ramp: 4.0 / 15.0,
        t_end: 20.0,
        sample: 0.02,
    }
}

/// `scenes/vortex-street-re105.toml`: 20.7 x 6, D = 2 at (8, 3), otherwise as `re140`.
pub fn re105() -> Street {
    Street {
        name: "vortex-street-re105",
        re: 105.0,
        length: 20.7,
        height: 6.0,
        centre: [8.0, 3.0],
        ..re140()
    }
}

/// `validate`'s cylinder (lab/src/validate/cylinder.rs): Re 100, 40 x 24 (blockage 0.083),
/// D = 2 at (10, 12), U = 1, the band [29, 30) (10 D upstream across the periodic end),
/// ramp 2 D / U, to t U / D = 120, forces every 0.125 D / U.
pub fn validate_cylinder() -> Street {
    Street {
        name: "validate-cylinder",
        re: 100.0,
        length: 40.0,
        height: 24.0,
        diameter: 2.0,
        centre: [10.0, 12.0],
        band: (29.0, 30.0),
        u: 1.0,
        ramp: 4.0,
        t_end: 240.0,
        sample: 0.25,
    }
}

/// A finished run: the force record and what it cost.
#[derive(Clone, Debug)]
pub struct StreetRun {
    /// Lattice cells across the diameter.
    pub d_cells: usize,
    pub nx: usize,
    pub ny: usize,
    /// \[L\] the box as the lattice holds it (nx and ny are rounded to whole cells).
    pub length: f64,
    pub height: f64,
    pub steps: usize,
    pub samples: Vec<ForceSample>,
    pub wall_seconds: f64,
}

impl Street {
    /// Run at `d_cells` lattice cells per diameter, U at `u_lattice` (lattice units).
    pub fn run(&self, d_cells: usize, u_lattice: f64) -> StreetRun {
        let started = std::time::Instant::now();
        let dx = self.diameter / d_cells as f64;
        let (nx, ny) = (
            (self.length / dx).round() as usize,
            (self.height / dx).round() as usize,
        );
        // Lattice units: length dx, time dt = u_lattice dx / U.
        let dt = u_lattice * dx / self.u;
        let nu = u_lattice * d_cells as f64 / self.re;
        let (xc, yc, r) = (
            self.centre[0] / dx,
            self.centre[1] / dx,
            0.5 * d_cells as f64,
        );
        let mut lat = Lattice::new(nx, ny, nu, |p| {
            (p[0] - xc).powi(2) + (p[1] - yc).powi(2) < r * r
        });
        // Columns whose centre (i + 1/2) dx lies in the band.
        let first = |x: f64| (x / dx - 0.5).ceil().max(0.0) as usize;
        lat.band = (first(self.band.0), first(self.band.1));
        let steps = (self.t_end / dt).round() as usize;
        let every = (self.sample / dt).round().max(1.0) as usize;
        let q = 0.5 * u_lattice * u_lattice * d_cells as f64;
        let q_scene = 0.5 * self.u * self.u * self.diameter;
        let mut samples = vec![ForceSample {
            t: 0.0,
            force: [0.0; 3],
            cd: 0.0,
            cl: 0.0,
        }];
        let mut kicked = false;
        let mut sum = [0.0; 2];
        for n in 0..steps {
            let (t0, t1) = (n as f64 * dt, (n + 1) as f64 * dt);
            let (r0, r1) = (smooth_ramp(self.ramp, t0), smooth_ramp(self.ramp, t1));
            lat.band_velocity = [u_lattice * r1, 0.0];
            lat.accel = [u_lattice * (r1 - r0), 0.0];
            if !kicked && t0 >= self.ramp {
                let (x0, w) = (xc + 1.5 * d_cells as f64, 0.25 * d_cells as f64);
                lat.kick(
                    |p| (-((p[0] - x0).powi(2) + (p[1] - yc).powi(2)) / (w * w)).exp(),
                    [0.0, KICK * u_lattice],
                );
                kicked = true;
            }
            let f = lat.step();
            sum[0] += f[0];
            sum[1] += f[1];
            // The sample: the force averaged over its interval (takes out the lattice's
            // acoustic ripple; the box filter keeps 99.9 % of the shedding's amplitude at
            // 37 samples a period).
            if (n + 1) % every == 0 {
                let (cd, cl) = (sum[0] / every as f64 / q, sum[1] / every as f64 / q);
                samples.push(ForceSample {
                    t: t1,
                    force: [cd * q_scene, cl * q_scene, 0.0],
                    cd,
                    cl,
                });
                sum = [0.0; 2];
            }
        }
        StreetRun {
            d_cells,
            nx,
            ny,
            length: nx as f64 * dx,
            height: ny as f64 * dx,
            steps,
            samples,
            wall_seconds: started.elapsed().as_secs_f64(),
        }
    }
}
