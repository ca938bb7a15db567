//! Hydrostatic tank: water at rest in an open tank keeps p = rho0 g (H - y) and stays put.
//!
//! Reference: hydrostatics with the Tait equation of state (Monaghan 1994; Batchelor 1967),
//! `refdata/analytic_hydrostatic_and_still_water.json`, which recommends interior pressure
//! within 2 % of rho0 g H, one kernel radius away from walls and the free surface.

use super::plot::{plot, Figure, Series};
use super::{convergence, Check, Ctx, RunInfo, Sim, Tier};
use crate::particle::Kind;
use crate::scene::Scene;

pub const NAME: &str = "hydrostatic-tank";
pub const DESCRIPTION: &str =
    "Water 1 x 1 at rest in an open 2D tank (dynamic walls, Tait EOS, c0 = 45): \
time-averaged pressure vs rho0 g depth, particle drift and residual speed after t = 1.";
const SOURCE: &str = "hydrostatics, Tait EOS (refdata/analytic_hydrostatic_and_still_water.json)";

/// The scene, at spacing `dx` (the wall strength C0 = 5 g H / r0 follows dx).
pub fn scene_text(dx: f64) -> String {
    let strength = 5.0 * 9.81 * 1.0 / dx;
    let margin = 3.0 * dx + 0.05;
    format!(
        r#"dimension = 2
name = "validate-hydrostatic"
gravity = [0.0, -9.81]

[domain]
min = [-{margin}, -{margin}]
max = [{xmax}, 1.3]

[discretisation]
spacing = {dx}
h_factor = 1.3
kernel = "cubic-spline"

[time]
end = 1.0
output_interval = 0.05

[fluid]
density = 1000.0
sound_speed = 45.0
density_form = "continuity"
alpha = 0.02

[boundary]
strength = {strength}
wall_coupling = "dynamic"

[[fluid_blocks]]
min = [0.0, 0.0]
max = [1.0, 1.0]
hydrostatic = true

[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [1.0, 1.2]
layers = 3
open_top = true
"#,
        xmax = 1.0 + margin
    )
}

/// Settle to T_AVG0, then average pressure over [T_AVG0, T_END] (about five acoustic
/// periods 2 H / c0 = 0.044 s), since a weakly compressible column keeps ringing.
const T_AVG0: f64 = 0.8;
const T_END: f64 = 1.0;
const SAMPLES: usize = 20;

struct Outcome {
    dx: f64,
    /// Max over two-spacing layers of |mean p - rho g depth| / (rho0 g H).
    layer_err: f64,
    /// RMS over interior particles of (p - rho g depth) / (rho0 g H).
    rms_err: f64,
    drift_over_dx: f64,
    speed_over_ugh: f64,
    /// (depth / H, p / (rho0 g H)) per fluid particle, time-averaged.
    profile: Vec<(f64, f64)>,
    run: RunInfo,
}

fn simulate(ctx: &Ctx, dx: f64) -> anyhow::Result<Outcome> {
    let scene = Scene::from_toml(&scene_text(dx), "validate:hydrostatic-tank")?;
    let setup = scene.setup()?;
    let p = setup.params;
    let start = setup.particles.clone();
    let mut sim = Sim::new(ctx, setup, scene.gates(), format!("dx = {dx}"))?;
    sim.advance_to(T_AVG0)?;
    let mut mean_p = vec![0.0f64; start.len()];
    for k in 1..=SAMPLES {
        sim.advance_to(T_AVG0 + (T_END - T_AVG0) * k as f64 / SAMPLES as f64)?;
        for (m, q) in mean_p.iter_mut().zip(sim.solver.particles()) {
            *m += q.pressure as f64 / SAMPLES as f64;
        }
    }
    let end = sim.solver.particles();
    let d = sim.solver.diagnostics();
    let (g, rho0, h_col) = (-p.gravity[1] as f64, p.rho0 as f64, 1.0f64);
    let scale = rho0 * g * h_col;
    let support = p.support as f64;
    let drift = start
        .iter()
        .zip(&end)
        .filter(|(a, _)| a.kind == Kind::Fluid)
        .map(|(a, b)| {
            ((a.position[0] - b.position[0]) as f64).hypot((a.position[1] - b.position[1]) as f64)
        })
        .fold(0.0, f64::max);
    let top = end
        .iter()
        .filter(|q| q.kind == Kind::Fluid)
        .map(|q| q.position[1] as f64)
        .fold(f64::MIN, f64::max)
        + 0.5 * dx;
    let mut layers: std::collections::BTreeMap<i64, (f64, f64, usize)> = Default::default();
    let (mut sq, mut n) = (0.0, 0usize);
    let mut profile = Vec::new();
    for (q, &pm) in end.iter().zip(&mean_p) {
        if q.kind != Kind::Fluid {
            continue;
        }
        let (x, y) = (q.position[0] as f64, q.position[1] as f64);
        let depth = top - y;
        profile.push((depth / h_col, pm / scale));
        let near_wall = x < support || x > 1.0 - support || y < support;
        if depth < support || near_wall {
            continue;
        }
        let want = rho0 * g * depth;
        sq += ((pm - want) / scale).powi(2);
        n += 1;
        let e = layers.entry((depth / (2.0 * dx)) as i64).or_default();
        e.0 += pm;
        e.1 += want;
        e.2 += 1;
    }
    anyhow::ensure!(n > 0, "no interior particle at dx = {dx}");
    let layer_err = layers
        .values()
        .map(|(got, want, c)| (got - want).abs() / *c as f64 / scale)
        .fold(0.0, f64::max);
    Ok(Outcome {
        dx,
        layer_err,
        rms_err: (sq / n as f64).sqrt(),
        drift_over_dx: drift / dx,
        speed_over_ugh: d.max_speed as f64 / (g * h_col).sqrt(),
        profile,
        run: sim.info(),
    })
}

pub fn run(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    let dxs: &[f64] = match ctx.tier {
        Tier::Quick => &[0.05],
        Tier::Full => &[0.05, 0.025, 0.0125],
    };
    let mut outs = Vec::new();
    for &dx in dxs {
        let o = simulate(ctx, dx)?;
        ctx.log(&format!(
            "dx = {dx}: layer error {:.4}, rms {:.4}, drift {:.3} dx, speed {:.4} sqrt(gH), {:.1} s",
            o.layer_err, o.rms_err, o.drift_over_dx, o.speed_over_ugh, o.run.wall_seconds
        ));
        outs.push(o);
    }
    let fine = outs.last().expect("one run");
    let png = "hydrostatic-tank.png";
    let depth_max = fine.profile.iter().map(|p| p.0).fold(0.0, f64::max);
    plot(
        &ctx.out_dir.join(png),
        &Figure {
            title: &format!(
                "Hydrostatic tank, dx = {}: pressure averaged over t = 0.8-1.0",
                fine.dx
            ),
            x_label: "depth / H",
            y_label: "p / (rho0 g H)",
            log_y: false,
            log_x: false,
        },
        &[
            Series::points("SPH particles", fine.profile.clone()),
            Series::line("rho0 g depth", vec![(0.0, 0.0), (depth_max, depth_max)]),
        ],
    )?;
    let quick = ctx.tier == Tier::Quick;
    let r = &fine.run;
    let mut rows = vec![
        Check::within(
            NAME,
            "interior pressure: max layer-mean error / (rho0 g H)",
            SOURCE,
            Some(0.0),
            fine.layer_err,
            fine.layer_err,
            if quick { 0.03 } else { 0.02 },
            if quick { "regression" } else { "literature" },
            r,
        )
        .with_plot(png)
        .with_note("layers 2 dx thick, one support radius (2h) from walls and free surface; 0.02 is the refdata recommendation"),
        Check::within(
            NAME,
            "interior pressure: RMS particle error / (rho0 g H)",
            SOURCE,
            Some(0.0),
            fine.rms_err,
            fine.rms_err,
            if quick { 0.05 } else { 0.02 },
            if quick { "regression" } else { "literature" },
            r,
        ),
        Check::within(
            NAME,
            "max particle drift after t = 1 / dx",
            "rest (expected settling g H^2 / (2 c0^2) = H / 400)",
            Some(0.0),
            fine.drift_over_dx,
            fine.drift_over_dx,
            0.5,
            "regression",
            r,
        ),
        Check::within(
            NAME,
            "max speed at t = 1 / sqrt(g H)",
            "rest (refdata: < 0.01 after t = 20 sqrt(H/g) = 6.4, longer than this run)",
            Some(0.0),
            fine.speed_over_ugh,
            fine.speed_over_ugh,
            0.05,
            "regression",
            r,
        ),
    ];
    if outs.len() > 1 {
        let dx: Vec<f64> = outs.iter().map(|o| o.dx).collect();
        let runs: Vec<RunInfo> = outs.iter().map(|o| o.run.clone()).collect();
        rows.push(convergence(
            NAME,
            "the RMS pressure error",
            &dx,
            &outs.iter().map(|o| o.rms_err).collect::<Vec<_>>(),
            &runs,
        ));
    }
    Ok(rows)
}
