//! Plane Poiseuille flow between an inlet and an outlet (issue #55): water enters a 2D
//! channel H = 0.1 high through an inlet at a mean U = 0.5 (a parabolic profile,
//! `[[open_boundaries]] profile`), flows 0.5 along it at Re = U H / nu = 5 between plates
//! and leaves through an outlet; no periodic axis. The plates are mDBC walls (`wall_coupling
//! = "mdbc"`, English et al. 2022) that enter the laminar viscosity with Morris, Fox & Zhu's
//! extrapolated velocity (`no_slip = "morris"`). Dynamic walls hold the fluid off by most of
//! a spacing (the first row's mean height 0.83 dx at H/20, none in it at their own
//! velocity): the profile 10.5-14 % off at H/20, against 1.9 % on mDBC walls
//! (docs/journal/2026-12-07-inlet-profile.md).
//!
//! Analytic (the developed flow): u(y) = 6 U eta (1 - eta), eta = y / H, and dp/dx = -12 rho
//! nu U / H^2 = -6000 Pa/m. Measured over the last flow-through time, every 0.1: the
//! pressure's slope (a line fitted to the fluid's pressure over x in [0.05, 0.35]) and the
//! profile's L2 error relative to u_max = 1.5 U over the lattice's rows, each row's error
//! the mean of u - u(y) over its fluid at x in [0.3, 0.45] and the samples; and the mass that left against the
//! mass that came in from the end of the first flow-through time on (core/tests/open.rs
//! checks that the particle count changes by exactly what came in less what left).
//! Issue #55's tolerances: the profile within 1 %, the pressure drop within 2 %, the fluxes
//! within 0.5 %; the quick tier runs H/10, whose rows are regression bounds.

use super::check::{line_fit, Check, RunInfo};
use super::ctx::{Ctx, Sim, Tier};
use meshfree_core::physics::particle::{Kind, Particle};

pub const NAME: &str = "open-channel";
pub const DESCRIPTION: &str = "Plane Poiseuille flow at Re 5 between an inlet (parabolic, mean \
0.5 m/s) and an outlet, H = 0.1, 0.5 long, no periodic axis, mDBC plates with Morris's no-slip: pressure \
drop, velocity profile and the fluxes in and out against the analytic developed flow.";
const SOURCE: &str =
    "plane Poiseuille flow, u = 6 U y (H - y) / H^2, dp/dx = -12 rho nu U / H^2 (issue #55)";

/// \[L\] the channel's height and length, \[L/T\] the mean velocity, \[L^2/T\] nu, \[M/L^3\].
const H: f64 = 0.1;
const LENGTH: f64 = 0.5;
const U: f64 = 0.5;
const NU: f64 = 0.01;
const RHO: f64 = 1000.0;

/// \[M/(L^2 T^2)\] the developed flow's pressure gradient, -12 rho nu U / H^2.
fn slope_exact() -> f64 {
    -12.0 * RHO * NU * U / (H * H)
}

/// The scene at spacing `dx`, to time `end`.
pub fn scene_text(dx: f64, end: f64) -> String {
    let depth = 4.0 * dx;
    let rows = 3.0 * dx;
    format!(
        r#"dimension = 2
name = "validate-open-channel"

[domain]
min = [-{left}, -{below}]
max = [{right}, {above}]

[discretisation]
spacing = {dx}

[time]
end = {end}
output_interval = 0.25

[fluid]
density = {RHO}
sound_speed = 10.0
viscosity = {NU}
alpha = 0.0
xsph = 0.0

[boundary]
strength = 1.0
wall_coupling = "mdbc"
wall_density_floor = true
no_slip = "morris"

[[fluid_blocks]]
min = [0.0, 0.0]
max = [{LENGTH}, {H}]
velocity = [{U}, 0.0]

[[walls]]
shape = "box"
min = [-{left}, -{rows}]
max = [{right}, 0.0]

[[walls]]
shape = "box"
min = [-{left}, {H}]
max = [{right}, {lid}]

[[open_boundaries]]
kind = "inlet"
min = [-{depth}, 0.0]
max = [0.0, {H}]
normal = [1.0, 0.0]
velocity = [{U}, 0.0]
profile = "parabolic"

[[open_boundaries]]
kind = "outlet"
min = [{LENGTH}, 0.0]
max = [{outlet}, {H}]
normal = [-1.0, 0.0]
"#,
        left = depth + 2.0 * dx,
        below = rows + dx,
        right = LENGTH + 2.0 * depth + 2.0 * dx,
        above = H + rows + dx,
        lid = H + rows,
        outlet = LENGTH + depth,
    )
}

/// What one run measured.
struct Outcome {
    dx: f64,
    /// \[Pa/m\] the pressure's slope, averaged over the samples.
    slope: f64,
    /// \[-\] the profile's L2 error / u_max, root mean square over the samples.
    profile_l2: f64,
    /// \[-\] mass out / mass in over the measured span, less 1.
    flux_balance: f64,
    run: RunInfo,
}

fn fluid(v: &[Particle]) -> impl Iterator<Item = &Particle> {
    v.iter().filter(|q| q.kind == Kind::Fluid)
}

fn run_one(ctx: &Ctx, dx: f64, end: f64) -> anyhow::Result<Outcome> {
    let scene = ctx.scene(&scene_text(dx, end), "validate-open-channel")?;
    let setup = scene.setup()?;
    let n0 = fluid(&setup.particles).count() as i64;
    let mut sim = Sim::new(ctx, setup, Vec::new(), format!("dx = H/{:.0}", H / dx))?;
    // The fluxes from the end of the first flow-through time (the start's acoustic
    // transient long gone) to the end; the flow over the last one.
    let through = LENGTH / U;
    sim.advance_to(through)?;
    let start = sim.solver.open_tally();
    let from = end - through;
    sim.advance_to(from)?;
    // Per row of the lattice across the channel (width dx), over the samples: the sums of
    // each particle's velocity, of its y and of its velocity less the analytic one at its y,
    // and the count; the profile their means (particle noise averaged out).
    let rows = (H / dx).round() as usize;
    let (mut sum, mut ys, mut off, mut count) = (
        vec![0.0f64; rows],
        vec![0.0f64; rows],
        vec![0.0f64; rows],
        vec![0usize; rows],
    );
    let exact = |y: f64| 6.0 * U * (y / H) * (1.0 - y / H);
    let mut slopes = Vec::new();
    let samples = 10;
    for k in 1..=samples {
        sim.advance_to(from + through * k as f64 / samples as f64)?;
        let v = sim.solver.particles();
        let pts: Vec<(f64, f64)> = fluid(&v)
            .filter(|q| (0.05..0.35).contains(&(q.position[0] as f64)))
            .map(|q| (q.position[0] as f64, q.pressure as f64))
            .collect();
        slopes.push(line_fit(&pts).map_or(f64::NAN, |(s, _)| s));
        for q in fluid(&v).filter(|q| (0.3..0.45).contains(&(q.position[0] as f64))) {
            let r = (q.position[1] as f64 / dx).floor();
            if (0.0..rows as f64).contains(&r) {
                let (r, y, u) = (r as usize, q.position[1] as f64, q.velocity[0] as f64);
                sum[r] += u;
                ys[r] += y;
                off[r] += u - exact(y);
                count[r] += 1;
            }
        }
    }
    // L2 over the rows of the mean of u - u(y), relative to u_max.
    let squares: Vec<f64> = (0..rows)
        .filter(|&r| count[r] > 0)
        .map(|r| (off[r] / count[r] as f64).powi(2))
        .collect();
    let profile_l2 = (squares.iter().sum::<f64>() / squares.len().max(1) as f64).sqrt() / (1.5 * U);
    let mean =
        |a: &[f64], r: usize, scale: f64| format!("{:.3}", a[r] / count[r].max(1) as f64 / scale);
    let column = |a: &[f64], scale: f64| {
        (0..rows)
            .map(|r| mean(a, r, scale))
            .collect::<Vec<_>>()
            .join(" ")
    };
    ctx.log(&format!(
        "dx = {dx}, by row from the floor: u / u_max {}; y / dx {}",
        column(&sum, 1.5 * U),
        column(&ys, dx)
    ));
    let end_tally = sim.solver.open_tally();
    let mass_in = end_tally[0].mass_in - start[0].mass_in;
    let mass_out = end_tally[1].mass_out - start[1].mass_out;
    let v = sim.solver.particles();
    // Particles are made only as an inlet's buffer particle joins the fluid (`count_in`)
    // and removed only at a boundary (`count_out`, either kind).
    let net: i64 = end_tally
        .iter()
        .map(|t| t.count_in as i64 - t.count_out as i64)
        .sum();
    let count_gap = fluid(&v).count() as i64 - n0 - net;
    let slope = slopes.iter().sum::<f64>() / slopes.len() as f64;
    ctx.log(&format!(
        "dx = {dx}: dp/dx {slope:.0} Pa/m, profile L2 {profile_l2:.4} of u_max, mass in {mass_in:.3} \
         out {mass_out:.3} kg/m from t = {through} to {end}, count gap {count_gap}"
    ));
    Ok(Outcome {
        dx,
        slope,
        profile_l2,
        flux_balance: mass_out / mass_in - 1.0,
        run: sim.info(),
    })
}

pub fn run(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    // Quick: H/10 over two flow-through times; measured (CPU, 2026-12-07): dp/dx 6.4 % low,
    // the profile 3.9 %, the fluxes 0.4 % apart (a row at each end is 4 % of that span: the
    // quick tier reports it, checks it not). Full: H/20 over four (the issue's 20 are for a
    // GPU), the issue's tolerances.
    let (dx, end, basis, tol) = match ctx.tier {
        Tier::Quick => (H / 10.0, 2.0 * LENGTH / U, "regression", [0.15, 0.08, 0.1]),
        Tier::Full => (
            H / 20.0,
            4.0 * LENGTH / U,
            "literature",
            [0.02, 0.01, 0.005],
        ),
    };
    let o = run_one(ctx, dx, end)?;
    let exact = slope_exact();
    let note = format!(
        "over the last flow-through time (the profile: each row's mean over 10 samples), dx = {}",
        o.dx
    );
    let span = end - LENGTH / U;
    let flux = Check::within(
        NAME,
        "mass out / mass in - 1",
        "mass conservation",
        Some(0.0),
        o.flux_balance,
        o.flux_balance.abs(),
        tol[2],
        basis,
        &o.run,
    )
    .with_note(format!(
        "from t = {} to {end}; a row of particles at each end is {:.2} % of it",
        LENGTH / U,
        100.0 * 2.0 * dx / (U * span)
    ));
    Ok(vec![
        Check::within(
            NAME,
            "pressure gradient dp/dx [Pa/m]",
            SOURCE,
            Some(exact),
            o.slope,
            (o.slope / exact - 1.0).abs(),
            tol[0],
            basis,
            &o.run,
        )
        .with_note(note.clone()),
        Check::within(
            NAME,
            "velocity profile L2 error / u_max, x in [0.3, 0.45]",
            SOURCE,
            Some(0.0),
            o.profile_l2,
            o.profile_l2,
            tol[1],
            basis,
            &o.run,
        )
        .with_note(note),
        match ctx.tier {
            Tier::Quick => flux.informational(),
            Tier::Full => flux,
        },
    ])
}
