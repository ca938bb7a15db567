//! Body-force-driven Poiseuille flow starting from rest (Morris, Fox & Zhu 1997, Sec. 4).
//!
//! A channel between no-slip plates at y = 0 and y = L (scene walls of shape "box", dynamic
//! wall particles), periodic in x, driven by the body force F (`gravity = [F, 0]`), with the
//! laminar viscosity of Morris et al. (`fluid.viscosity`) and no artificial viscosity. The
//! plates enter the laminar term with Morris et al.'s extrapolated wall velocity
//! (`[boundary] no_slip = "morris"`, cap 4: `MORRIS`); the walls at their own zero velocity
//! and Morris's cap 1.5, both of which slip by O(dx), are reported alongside at the finest
//! resolution (informational). The
//! reference is the series solution
//! v(y, t) = F/(2 nu) y (L - y) - sum_n 4 F L^2 / (nu pi^3 (2n+1)^3) sin((2n+1) pi y / L)
//!           exp(-(2n+1)^2 pi^2 nu t / L^2),
//! checked here against the tabulated profiles of
//! `refdata/analytic_poiseuille_couette_startup_profiles.csv` before use. Parameters are
//! Morris's: L = 1 mm, nu = 1e-6 m^2/s, F = 2e-4 m/s^2, v_max = F L^2 / (8 nu) = 2.5e-5 m/s.

use super::check::{convergence, Check, RunInfo};
use super::ctx::{Ctx, Sim, Tier};
use super::refdata::{csv_rows, refdata};
use crate::plot::{plot, Figure, Series};
use meshfree_core::physics::particle::Kind;

pub const NAME: &str = "poiseuille";
pub const DESCRIPTION: &str =
    "Poiseuille start-up between plates 1 mm apart, periodic in x, body force 2e-4 m/s^2, \
nu = 1e-6 m^2/s (Morris, Fox & Zhu 1997), c0 = 10 v_max, laminar viscosity only, Morris's \
extrapolated wall velocity: velocity-profile L2 error / v_max against the series solution at \
t = 0.0225-1 s.";
const SOURCE: &str = "series solution, Morris, Fox & Zhu 1997 (refdata/analytic_poiseuille_couette_startup*.{json,csv})";

const L: f64 = 1e-3;
const NU: f64 = 1e-6;
const F: f64 = 2e-4;
const VMAX: f64 = F * L * L / (8.0 * NU);

/// The series solution (Morris et al. 1997), 200 terms (t > 0) or the steady profile.
pub fn exact(y: f64, t: f64) -> f64 {
    let steady = F / (2.0 * NU) * y * (L - y);
    if !t.is_finite() {
        return steady;
    }
    let pi = std::f64::consts::PI;
    let sum: f64 = (0..200)
        .map(|n| {
            let k = (2 * n + 1) as f64;
            4.0 * F * L * L / (NU * pi.powi(3) * k.powi(3))
                * (k * pi * y / L).sin()
                * (-k * k * pi * pi * NU * t / (L * L)).exp()
        })
        .sum();
    steady - sum
}

/// How the plates enter the laminar viscosity (`[boundary] no_slip`, `no_slip_beta_max`).
#[derive(Clone, Copy, Debug)]
pub struct Walls {
    pub no_slip: &'static str,
    pub beta_max: f64,
}

/// The walls of the checks: Morris et al.'s extrapolated wall velocity with the cap of
/// beta = 1 + d_B / d_A at 4, which the lattice never reaches within the support (the first
/// fluid row, d_A = dx/2, meets wall rows at d_B = dx/2 and 3 dx/2: beta = 2 and 4), so the
/// cap only guards fluid particles that come closer to the plates than the lattice.
pub const MORRIS: Walls = Walls {
    no_slip: "morris",
    beta_max: 4.0,
};
/// Morris et al.'s own cap, 1.5: it binds on every wall pair of the first fluid row, whose
/// wall particles then take -v_A / 2 instead of -v_A and -3 v_A, and a slip of O(dx) stays.
pub const MORRIS_CAP_1_5: Walls = Walls {
    no_slip: "morris",
    beta_max: 1.5,
};
/// The walls at their own (zero) velocity: the scheme before Morris's extrapolation.
pub const WALL_VELOCITY: Walls = Walls {
    no_slip: "wall-velocity",
    beta_max: 1.5,
};

/// The scene at `n` particles across the channel (dx = L / n), the channel L long, with
/// the plates `walls`.
pub fn scene_text(n: usize, walls: Walls) -> String {
    let dx = L / n as f64;
    let wall = 3.0 * dx;
    let c0 = 10.0 * VMAX;
    format!(
        r#"dimension = 2
name = "validate-poiseuille"
gravity = [{F:e}, 0.0]                 # the driving body force

[domain]
min = [0.0, {ymin:e}]
max = [{L:e}, {ymax:e}]
periodic = [true, false]

[discretisation]
spacing = {dx:e}
h_factor = 1.3
kernel = "cubic-spline"

[time]
end = 1.0
output_interval = 0.01

[fluid]
density = 1000.0
sound_speed = {c0:e}
density_form = "continuity"
alpha = 0.0
viscosity = {NU:e}

[boundary]
strength = {strength:e}                # a safety net only: no force pushes fluid at the plates
wall_coupling = "dynamic"
no_slip = "{no_slip}"
no_slip_beta_max = {beta_max:?}

[[fluid_blocks]]
min = [0.0, 0.0]
max = [{L:e}, {L:e}]

[[walls]]                              # lower plate
shape = "box"
min = [0.0, {wlo:e}]
max = [{L:e}, 0.0]

[[walls]]                              # upper plate
shape = "box"
min = [0.0, {L:e}]
max = [{L:e}, {whi:e}]
"#,
        ymin = -wall - 2.0 * dx,
        ymax = L + wall + 2.0 * dx,
        strength = 50.0 * F,
        no_slip = walls.no_slip,
        beta_max = walls.beta_max,
        wlo = -wall,
        whi = L + wall,
    )
}

/// The profile table's times (s) and rows (t, y, vx).
fn table() -> Vec<(f64, f64, f64)> {
    csv_rows(refdata("analytic_poiseuille_couette_startup_profiles.csv"))
        .into_iter()
        .map(|r| {
            let t = if r[0] == "inf" {
                f64::INFINITY
            } else {
                r[0].parse().unwrap()
            };
            (t, r[1].parse().unwrap(), r[2].parse().unwrap())
        })
        .collect()
}

struct Outcome {
    n: usize,
    /// (t, L2 error / v_max, Linf error / v_max)
    errors: Vec<(f64, f64, f64)>,
    /// (t, [(y / L, mean vx / v_max) per particle row])
    profiles: Vec<(f64, Vec<(f64, f64)>)>,
    run: RunInfo,
}

/// The resolution label of a run: "L / n", with the walls where they are not `MORRIS`.
fn label(n: usize, walls: Walls) -> String {
    if walls.no_slip == MORRIS.no_slip && walls.beta_max == MORRIS.beta_max {
        format!("L / {n}")
    } else if walls.no_slip != MORRIS.no_slip {
        format!("L / {n}, no_slip = {}", walls.no_slip)
    } else {
        format!(
            "L / {n}, no_slip = {}, beta_max = {}",
            walls.no_slip, walls.beta_max
        )
    }
}

fn simulate(ctx: &Ctx, n: usize, walls: Walls, times: &[f64]) -> anyhow::Result<Outcome> {
    let scene = ctx.scene(&scene_text(n, walls), "validate:poiseuille")?;
    let setup = scene.setup()?;
    let dx = L / n as f64;
    let label = label(n, walls);
    let mut sim = Sim::new(ctx, setup, scene.gates(), label)?;
    let mut out = Outcome {
        n,
        errors: Vec::new(),
        profiles: Vec::new(),
        run: sim.info(),
    };
    for &t in times {
        sim.advance_to(t)?;
        let t_now = sim.solver.time();
        let ps = sim.solver.particles();
        let (mut sq, mut inf, mut count) = (0.0, 0.0f64, 0usize);
        let mut rows = vec![(0.0, 0usize); n];
        for q in ps.iter().filter(|q| q.kind == Kind::Fluid) {
            let (y, u) = (q.position[1] as f64, q.velocity[0] as f64);
            let e = (u - exact(y, t_now)) / VMAX;
            sq += e * e;
            inf = inf.max(e.abs());
            count += 1;
            let k = ((y / dx).floor().max(0.0) as usize).min(n - 1);
            rows[k].0 += u;
            rows[k].1 += 1;
        }
        out.errors.push((t, (sq / count as f64).sqrt(), inf));
        let prof = rows
            .iter()
            .enumerate()
            .filter(|(_, r)| r.1 > 0)
            .map(|(k, r)| ((k as f64 + 0.5) * dx / L, r.0 / r.1 as f64 / VMAX))
            .collect();
        out.profiles.push((t, prof));
    }
    out.run = sim.info();
    Ok(out)
}

pub fn run(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    // The series as coded must reproduce the tabulated profiles.
    let tab = table();
    let dev = tab
        .iter()
        .map(|&(t, y, v)| (exact(y, t) - v).abs() / VMAX)
        .fold(0.0, f64::max);
    anyhow::ensure!(
        dev < 1e-3,
        "the series differs from the refdata table by {dev} v_max"
    );

    let quick = ctx.tier == Tier::Quick;
    let times: &[f64] = if quick {
        &[0.0225, 0.045, 0.1125, 0.225]
    } else {
        &[0.0225, 0.045, 0.1125, 0.225, 0.5, 1.0]
    };
    let ns: &[usize] = if quick { &[20] } else { &[10, 20, 40] };
    let mut outs = Vec::new();
    for &n in ns {
        let o = simulate(ctx, n, MORRIS, times)?;
        ctx.log(&format!(
            "L/{n}: L2 errors {:?}, {:.1} s",
            o.errors
                .iter()
                .map(|e| format!("{:.4}", e.1))
                .collect::<Vec<_>>(),
            o.run.wall_seconds
        ));
        outs.push(o);
    }
    let fine = outs.last().expect("one run");
    let png = "poiseuille.png";
    let mut s = Vec::new();
    for (t, prof) in &fine.profiles {
        let reference = tab
            .iter()
            .filter(|r| (r.0 - t).abs() < 1e-9)
            .map(|r| (r.1 / L, r.2 / VMAX))
            .collect();
        s.push(Series::line(format!("series t = {t} s"), reference));
        s.push(Series::points(format!("SPH t = {t} s"), prof.clone()));
    }
    plot(
        &ctx.out_dir.join(png),
        &Figure {
            title: &format!("Poiseuille start-up, L/{}: vx(y), row means", fine.n),
            x_label: "y / L",
            y_label: "vx / v_max",
            log_y: false,
            log_x: false,
        },
        &s,
    )?;
    let r = &fine.run;
    let (t_worst, l2_worst, _) =
        fine.errors
            .iter()
            .copied()
            .fold((0.0, 0.0, 0.0), |a, e| if e.1 >= a.1 { e } else { a });
    let l2_early = fine
        .errors
        .iter()
        .filter(|e| e.0 <= 0.045 + 1e-9)
        .map(|e| e.1)
        .fold(0.0, f64::max);
    let mut rows = vec![Check::within(
        NAME,
        "velocity profile L2 error / v_max, worst over t = 0.0225-0.045 s (start-up)",
        SOURCE,
        Some(0.0),
        l2_early,
        l2_early,
        if quick { 0.005 } else { 0.05 },
        if quick { "regression" } else { "literature" },
        r,
    )
    .with_plot(png)
    .with_note(if quick {
        "L / 20: measured 0.0016 (CPU 2026-12-05, H200 2026-11-28): 0.005 is 3 x that, ten times below the refdata's 5 % \
         for transient profiles, which a doubled viscosity meets (0.048; tests/perturbed.rs)"
    } else {
        "5 %: the refdata recommendation for transient profiles"
    })];
    let t_last = fine.errors.last().map(|e| e.0).unwrap_or(0.0);
    rows.push(Check::within(
        NAME,
        &format!("velocity profile L2 error / v_max, worst over t = 0.0225-{t_last} s"),
        SOURCE,
        Some(0.0),
        l2_worst,
        l2_worst,
        // Quick tier: L/20 to 0.225 s measured 0.0030 with Morris's walls (0.082 without):
        // 0.008 is 2.7 x that, below the 0.030 of Morris's own cap 1.5.
        if quick { 0.008 } else { 0.05 },
        if quick { "regression" } else { "literature" },
        r,
    )
    .with_plot(png)
    .with_note(format!(
        "worst at t = {t_worst} s; {}5 % is the refdata recommendation for transient profiles (Morris et al. show figure-level agreement, no norm); errors per time: {}",
        if quick {
            "quick: 0.008 = 2.7 x the 0.0030 measured (CPU 2026-12-05, H200 2026-11-28), below the walls at \
             Morris's cap 1.5 (0.030) and at their own velocity (0.082); a doubled viscosity gives 0.29; "
        } else {
            ""
        },
        fine.errors.iter().map(|e| format!("t = {}: L2 {:.4}, Linf {:.4}", e.0, e.1, e.2)).collect::<Vec<_>>().join("; ")
    )));
    if let Some(&(t, l2, linf)) = fine.errors.iter().find(|e| e.0 >= 1.0) {
        rows.push(
            Check::within(
                NAME,
                "near-steady profile (t = 1 s = L^2/nu) Linf error / v_max",
                SOURCE,
                Some(0.0),
                linf,
                linf,
                0.02,
                "literature",
                r,
            )
            .with_note(format!("t = {t} s, L2 {l2:.4}; 2 % is the refdata recommendation for the steady profile with 20-40 particles across")),
        );
    }
    // The other wall schemes at the finest resolution of the tier, informational: the walls
    // at their own (zero) velocity (before Morris's extrapolation) and Morris's cap 1.5.
    for (walls, what) in [
        (
            WALL_VELOCITY,
            "walls at their own velocity (no_slip = \"wall-velocity\")",
        ),
        (MORRIS_CAP_1_5, "Morris walls with his cap beta_max = 1.5"),
    ] {
        let o = simulate(ctx, fine.n, walls, times)?;
        ctx.log(&format!(
            "{}: L2 errors {:?}, {:.1} s",
            label(o.n, walls),
            o.errors
                .iter()
                .map(|e| format!("{:.4}", e.1))
                .collect::<Vec<_>>(),
            o.run.wall_seconds
        ));
        let &(t, l2, linf) = o.errors.last().expect("one time");
        rows.push(
            Check::within(
                NAME,
                &format!("{what}: Linf error / v_max at t = {t} s"),
                SOURCE,
                Some(0.0),
                linf,
                linf,
                0.02,
                "literature",
                &o.run,
            )
            .informational()
            .with_note(format!(
                "informational: another wall scheme, shown beside the checked one (Morris's, cap 4); L2 {l2:.4}; errors per time: {}",
                o.errors
                    .iter()
                    .map(|e| format!("t = {}: L2 {:.4}, Linf {:.4}", e.0, e.1, e.2))
                    .collect::<Vec<_>>()
                    .join("; ")
            )),
        );
    }
    if outs.len() > 1 {
        let dx: Vec<f64> = outs.iter().map(|o| L / o.n as f64).collect();
        let runs: Vec<RunInfo> = outs.iter().map(|o| o.run.clone()).collect();
        let at = |o: &Outcome, t: f64| {
            o.errors
                .iter()
                .find(|e| e.0 == t)
                .map(|e| e.1)
                .unwrap_or(f64::NAN)
        };
        rows.push(convergence(
            NAME,
            "the L2 profile error at t = 0.225 s",
            &dx,
            &outs.iter().map(|o| at(o, 0.225)).collect::<Vec<_>>(),
            &runs,
        ));
        rows.push(convergence(
            NAME,
            "the L2 profile error at t = 1 s",
            &dx,
            &outs.iter().map(|o| at(o, 1.0)).collect::<Vec<_>>(),
            &runs,
        ));
    }
    Ok(rows)
}
