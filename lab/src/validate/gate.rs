//! Antoci, Gallati & Sibilla (2007) elastic gate (issue #6): a water column 0.1 wide and
//! 0.14 high held by a rubber gate 0.005 thick whose upper part is clamped (a driven solid,
//! bonded to the gate: `same_body`) and whose lower 0.079 is free; at t = 0 the water pushes
//! the free end open. The free end's x and y displacement against the experiment (digitised
//! from Ng et al. 2020, `refdata/fsi_antoci2007_elastic_gate.csv`) and the published SPH
//! results (Khayyer et al. 2018, Yang et al. 2012, Ng et al. 2020: the band drawn in the
//! plot). Parameters and tolerances: `refdata/fsi_antoci2007_elastic_gate.json`.
//!
//! Material: rho_s = 1100, E = 11.96 MPa, nu = 0.4, the set Antoci et al. identified for the
//! rubber and that Ng et al. 2020 use in the comparison the curves come from (SPHinXsys
//! takes 7.8 MPa with nu = 0.47; the peak displacement is first-order sensitive to E). Our
//! solid: G = E / (2 (1 + nu)), P = c_s^2 (rho - rho0) with c_s = sqrt(K / rho),
//! K = E / (3 (1 - 2 nu)).
//!
//! The free length is rounded to the particle lattice (the clamp must sit on the gate's
//! lattice): 0.079 +- dx / 2.
//!
//! The gate meets the water only (`[solid] wall_contact = false`, as SPHinXsys's
//! test_2d_elastic_gate): its free end starts on the floor and rises as it bends, so the
//! floor never pushes on it, while a body's continuity over the floor's wall particles read
//! the foot leaving them as a dilatation and blew the 4-across gate up at 0.016 s
//! (docs/reference/accuracy.md). The tank is closed (a lid at its 0.16 m): the outflow's run-up on the
//! far wall otherwise throws water out of the domain's top.
//!
//! Artificial viscosity alpha = 0.1 (eq. (10), every pair, water and gate): at 0.02 a
//! particle-scale wobble of the gate grows from its foot at 8 across (its speed 1.4-1.7x per
//! ms from t ~ 7 ms, at 4 across it stays at noise level), reaches the root by 20 ms and
//! blows the run up at 0.026 s; the term's damping per pair scales with h, so it halves with
//! every halving of dx. 0.05 and 0.1 both run to 0.4 s (docs/reference/accuracy.md has both).
//!
//! Both solid formulations run (`[solid] formulation`): the paper's Jaumann rate with the
//! artificial stress above, and the total-Lagrangian one (`meshfree_core::physics::tlsph`, no
//! artificial stress, the hourglass control at its default); the latter's rows are
//! informational unless they pass the same bounds.
//!
//! Quick tier: two particles across the gate (dx = 2.5 mm) to t = 0.02 s (about 50 s on 2
//! CPU cores in the debug profile): it checks that the gate stays bonded to its clamp, and
//! reports (informational) that it bends downstream, by no more than twice the experiment's
//! displacement at that time (interpolated from the start): two particles cannot resolve
//! bending (halved gravity and a doubled shear modulus stay inside those bounds). Full tier (GPU): 2, 4 and 8 particles across to t = 0.4 s: peak x and
//! its time, RMS of x(t) against the experiment, peak y, and the observed order of the RMS.

use super::check::{convergence, Check, RunInfo};
use super::ctx::{Ctx, Sim, Tier};
use super::refdata::{csv_rows, refdata};
use crate::plot::{plot, Figure, Series};
use meshfree_core::named::Named;
use meshfree_core::physics::particle::Particle;
use meshfree_core::scene::scheme::SolidFormulation;

pub const NAME: &str = "gate";
pub const DESCRIPTION: &str = "Elastic gate (Antoci, Gallati & Sibilla 2007): water 0.1 x 0.14 behind a rubber \
gate 0.005 thick, free length 0.079, clamped above, rho_s = 1100, E = 11.96 MPa, nu = 0.4, gravity 9.81, \
dynamic walls: the free end's x and y displacement vs time to 0.4 s against the experiment and published SPH.";
const SOURCE: &str =
    "Antoci, Gallati & Sibilla 2007 experiment (refdata/fsi_antoci2007_elastic_gate.csv, .json)";
const EXP: &str = "experiment_Antoci2007";
const SPH: [&str; 3] = [
    "SPH_Khayyer2018_ISPH-SPH",
    "SPH-FEM_Yang2012",
    "SPH-VCPM_Ng2020",
];

const WATER_W: f64 = 0.1;
const WATER_H: f64 = 0.14;
const FREE_LEN: f64 = 0.079;
const THICK: f64 = 0.005;
const TANK_L: f64 = 0.2;
const TANK_H: f64 = 0.16;
const RHO_S: f64 = 1100.0;
const E: f64 = 11.96e6;
const NU: f64 = 0.4;
const G: f64 = 9.81;

/// The lattice-rounded free length at spacing `dx`.
fn free_length(dx: f64) -> f64 {
    (FREE_LEN / dx).round() * dx
}

/// The scene at spacing `dx` (the gate's thickness must be a multiple of it).
pub fn scene_text(dx: f64, t_end: f64, f: SolidFormulation) -> String {
    let solid_scheme = match f {
        SolidFormulation::Jaumann => "artificial_stress = 0.3\n\
             artificial_stress_from = \"deviatoric\" # at 4 across the whole stress's form drives an odd-even mode (docs/reference/accuracy.md)",
        SolidFormulation::TotalLagrangian => "formulation = \"total-lagrangian\" # no artificial stress: free of the tensile instability",
    };
    let shear = E / (2.0 * (1.0 + NU));
    let bulk = E / (3.0 * (1.0 - 2.0 * NU));
    // Fluid c0 = 10 sqrt(2 g H): Mach 0.1 for the fastest water.
    let c0 = 10.0 * (2.0 * G * WATER_H).sqrt();
    let strength = 5.0 * G * WATER_H / dx;
    let margin = 3.0 * dx + 0.01;
    format!(
        r#"dimension = 2
name = "validate-gate"
gravity = [0.0, -{G}]

[domain]
min = [-{margin:e}, -{margin:e}]
max = [{xmax:e}, {ymax:e}]

[discretisation]
spacing = {dx:e}

[time]
end = {t_end:e}
output_interval = {t_end:e}

[fluid]
density = 1000.0
sound_speed = {c0:e}
alpha = 0.1                   # 0.02 leaves a particle-scale mode of the gate undamped at 8 across (docs/reference/accuracy.md)
xsph = 0.5
density_diffusion = 0.1

[solid]
density = {RHO_S:e}
sound_speed = {cs:e}          # sqrt(K / rho_s), K = E / (3 (1 - 2 nu))
shear_modulus = {shear:e}     # E / (2 (1 + nu))
wall_contact = false          # the gate meets the water only, not the floor it starts on
{solid_scheme}

[boundary]
strength = {strength:e}
wall_coupling = "dynamic"

[[fluid_blocks]]
min = [0.0, 0.0]
max = [{WATER_W:e}, {WATER_H:e}]
hydrostatic = true

[[solids]]                    # the clamp: holds the gate above its free length and the water
shape = "box"
min = [{WATER_W:e}, {lf:e}]
max = [{gx:e}, {TANK_H:e}]
motion = [0.0, 0.0]

[[solids]]                    # the gate's free part, touching the floor
shape = "box"
min = [{WATER_W:e}, 0.0]
max = [{gx:e}, {lf:e}]

[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [{TANK_L:e}, {TANK_H:e}]
layers = 3
open_top = false              # a lid: the outflow's run-up on the far wall stays in the tank
"#,
        cs = (bulk / RHO_S).sqrt(),
        lf = free_length(dx),
        gx = WATER_W + THICK,
        xmax = TANK_L + margin,
        ymax = 2.0 * TANK_H,
    )
}

/// (t, value) points.
type Curve = Vec<(f64, f64)>;

/// A digitised series of the CSV: (t, displacement), in time order.
fn series(name: &str, component: &str) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = csv_rows(refdata("fsi_antoci2007_elastic_gate.csv"))
        .into_iter()
        .filter(|r| r[0] == name && r[1] == component)
        .map(|r| (r[2].parse().unwrap(), r[3].parse().unwrap()))
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    v
}

/// The experiment's series with the start, (0, 0) (the gate starts at rest, undeflected),
/// for interpolation before its first point at 0.04 s.
fn experiment(component: &str) -> Vec<(f64, f64)> {
    let mut v = series(EXP, component);
    if v[0].0 > 0.0 {
        v.insert(0, (0.0, 0.0));
    }
    v
}

/// Linear interpolation in a time series (clamped at its ends).
fn interp(s: &[(f64, f64)], t: f64) -> f64 {
    if t <= s[0].0 {
        return s[0].1;
    }
    for w in s.windows(2) {
        if t <= w[1].0 {
            let f = (t - w[0].0) / (w[1].0 - w[0].0);
            return w[0].1 + f * (w[1].1 - w[0].1);
        }
    }
    s[s.len() - 1].1
}

/// The published SPH band: (lower, upper) envelope of the three SPH series on `ts` within
/// the times all three cover.
fn sph_band(component: &str, ts: &[f64]) -> (Curve, Curve) {
    let all: Vec<Vec<(f64, f64)>> = SPH.iter().map(|n| series(n, component)).collect();
    let t0 = all.iter().map(|s| s[0].0).fold(f64::MIN, f64::max);
    let t1 = all
        .iter()
        .map(|s| s[s.len() - 1].0)
        .fold(f64::MAX, f64::min);
    let (mut lo, mut hi) = (Vec::new(), Vec::new());
    for &t in ts.iter().filter(|&&t| t >= t0 && t <= t1) {
        let v: Vec<f64> = all.iter().map(|s| interp(s, t)).collect();
        lo.push((t, v.iter().copied().fold(f64::MAX, f64::min)));
        hi.push((t, v.iter().copied().fold(f64::MIN, f64::max)));
    }
    (lo, hi)
}

struct Outcome {
    dx: f64,
    /// (t, x, y) of the free end's displacement.
    series: Vec<(f64, f64, f64)>,
    /// Largest displacement of a gate particle next to the clamp, over the run / dx.
    root_slip: f64,
    run: RunInfo,
}

fn simulate(ctx: &Ctx, dx: f64, t_end: f64, f: SolidFormulation) -> anyhow::Result<Outcome> {
    let scene = ctx.scene(&scene_text(dx, t_end, f), "validate:gate")?;
    let setup = scene.setup()?;
    // Groups: 0 the water, 1 the clamp, 2 the gate.
    let gate: Vec<&Particle> = setup.particles.iter().filter(|q| q.group == 2).collect();
    anyhow::ensure!(!gate.is_empty(), "no gate particle at dx = {dx}");
    let y_min = gate.iter().map(|q| q.position[1]).fold(f32::MAX, f32::min);
    let y_max = gate.iter().map(|q| q.position[1]).fold(f32::MIN, f32::max);
    let row = |y: f32| -> Vec<u32> {
        (gate.iter())
            .filter(|q| (q.position[1] - y).abs() < 0.25 * dx as f32)
            .map(|q| q.id)
            .collect()
    };
    let (tip, root) = (row(y_min), row(y_max));
    let start = setup.particles.clone();
    let mean = |ps: &[Particle], ids: &[u32], a: usize| {
        ids.iter()
            .map(|&id| ps[id as usize].position[a] as f64)
            .sum::<f64>()
            / ids.len() as f64
    };
    let (x0, y0) = (mean(&start, &tip, 0), mean(&start, &tip, 1));
    let mut sim = Sim::new(
        ctx,
        setup,
        scene.gates(),
        format!(
            "dx = {dx} ({} across the gate), {}",
            (THICK / dx).round(),
            f.name()
        ),
    )?;
    let samples = (t_end / 0.004).round().max(1.0) as usize;
    let mut out = vec![(0.0, 0.0, 0.0)];
    let mut root_slip = 0.0f64;
    for k in 1..=samples {
        sim.advance_to(t_end * k as f64 / samples as f64)?;
        let mut ps = sim.solver.particles();
        ps.sort_by_key(|q| q.id);
        let t = sim.solver.time();
        out.push((t, mean(&ps, &tip, 0) - x0, mean(&ps, &tip, 1) - y0));
        for &id in &root {
            let (a, b) = (&start[id as usize], &ps[id as usize]);
            let d = ((a.position[0] - b.position[0]) as f64)
                .hypot((a.position[1] - b.position[1]) as f64);
            root_slip = root_slip.max(d / dx);
        }
    }
    Ok(Outcome {
        dx,
        series: out,
        root_slip,
        run: sim.info(),
    })
}

/// RMS over the experiment's points in (0, t_end] of x_sim - x_exp. [m]
fn rms_x(o: &Outcome, exp: &[(f64, f64)]) -> f64 {
    let sim: Vec<(f64, f64)> = o.series.iter().map(|s| (s.0, s.1)).collect();
    let t_end = sim.last().map_or(0.0, |s| s.0);
    let pts: Vec<f64> = (exp.iter())
        .filter(|e| e.0 > 0.0 && e.0 <= t_end)
        .map(|e| interp(&sim, e.0) - e.1)
        .collect();
    (pts.iter().map(|d| d * d).sum::<f64>() / pts.len().max(1) as f64).sqrt()
}

fn draw(ctx: &Ctx, o: &Outcome, png: &str, component: &str, k: usize) -> anyhow::Result<()> {
    let ts: Vec<f64> = (0..=200).map(|i| 0.4 * i as f64 / 200.0).collect();
    let (lo, hi) = sph_band(component, &ts);
    let sim: Vec<(f64, f64)> = (o.series.iter())
        .map(|s| (s.0, if k == 1 { s.1 } else { s.2 }))
        .collect();
    plot(
        &ctx.out_dir.join(png),
        &Figure {
            title: &format!(
                "Elastic gate, {} particles across: free end {component}",
                (THICK / o.dx).round()
            ),
            x_label: "t [s]",
            y_label: &format!("{component} displacement [m]"),
            log_x: false,
            log_y: false,
        },
        &[
            Series::line("SPH (meshfree)", sim),
            Series::points("experiment (Antoci et al. 2007)", series(EXP, component)),
            Series::line("published SPH band, low", lo),
            Series::line("published SPH band, high", hi),
        ],
    )
}

pub fn run(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    let mut rows = run_formulation(ctx, SolidFormulation::Jaumann)?;
    // The total-Lagrangian rows: informational unless they pass the same bounds. A run that
    // stops at the coarsest resolution is one informational row: the Jaumann rows stand.
    match run_formulation(ctx, SolidFormulation::TotalLagrangian) {
        Ok(tl) => {
            // In the quick tier a checked row stays a check (informational when it fails
            // is no check).
            let quick = ctx.tier == Tier::Quick;
            for mut row in tl {
                row.quantity = format!("{} (total Lagrangian)", row.quantity);
                rows.push(if row.pass || quick {
                    row
                } else {
                    row.informational()
                });
            }
        }
        Err(e) => {
            ctx.log(&format!("total-lagrangian: stopped: {e:#}"));
            let mut row = rows.first().cloned().expect("the Jaumann rows");
            row.quantity = "the coarsest run reaches its end time (total Lagrangian)".into();
            row.source = "completes".into();
            (row.reference, row.measured, row.error, row.tolerance) =
                (None, f64::NAN, f64::NAN, 0.0);
            row.pass = false;
            row.plot = None;
            (row.resolution, row.particles, row.wall_seconds) =
                ("the coarsest of the tier".into(), 0, 0.0);
            row.note = format!("{e:#}");
            rows.push(row.informational());
        }
    }
    Ok(rows)
}

/// The gate's rows with one solid formulation.
fn run_formulation(ctx: &Ctx, f: SolidFormulation) -> anyhow::Result<Vec<Check>> {
    let quick = ctx.tier == Tier::Quick;
    let tag = match f {
        SolidFormulation::Jaumann => "",
        SolidFormulation::TotalLagrangian => "-total-lagrangian",
    };
    let (across, t_end): (&[f64], f64) = if quick {
        (&[2.0], 0.02)
    } else {
        (&[2.0, 4.0, 8.0], 0.4)
    };
    let exp_x = experiment("x");
    let mut outs: Vec<Outcome> = Vec::new();
    // A run that stops (after a coarser one finished) is a failed row of its own, and the
    // accuracy rows come from the finest run that reached t_end: a blow-up at 8 across
    // does not hide what 2 and 4 across measured.
    let mut stopped: Vec<Check> = Vec::new();
    for &n in across {
        let t0 = std::time::Instant::now();
        let o = match simulate(ctx, THICK / n, t_end, f) {
            Ok(o) => o,
            Err(e) if !outs.is_empty() => {
                ctx.log(&format!("{}, {n} across: stopped: {e:#}", f.name()));
                let info = RunInfo {
                    resolution: format!("dx = {} ({n} across the gate)", THICK / n),
                    particles: 0,
                    wall_seconds: t0.elapsed().as_secs_f64(),
                    info: outs[0].run.info.clone(),
                };
                stopped.push(
                    Check::within(
                        NAME,
                        &format!("{n} across runs to t = {t_end} s"),
                        "completes",
                        None,
                        f64::NAN,
                        f64::NAN,
                        0.0,
                        "regression",
                        &info,
                    )
                    .with_note(format!("{e:#}")),
                );
                break;
            }
            Err(e) => return Err(e),
        };
        let last = o.series.last().copied().unwrap_or_default();
        ctx.log(&format!(
            "{}, {n} across: free end at t = {:.3}: x {:.4}, y {:.4}; root slip {:.3} dx; {:.1} s",
            f.name(),
            last.0,
            last.1,
            last.2,
            o.root_slip,
            o.run.wall_seconds
        ));
        outs.push(o);
    }
    let fine = outs.last().expect("one run");
    let (png_x, png_y) = (format!("gate-x{tag}.png"), format!("gate-y{tag}.png"));
    let (png_x, png_y) = (png_x.as_str(), png_y.as_str());
    draw(ctx, fine, png_x, "x", 1)?;
    draw(ctx, fine, png_y, "y", 2)?;
    let run = &fine.run;
    let (t_last, x_last, _) = fine.series.last().copied().unwrap_or_default();
    let x_exp_last = interp(&exp_x, t_last);
    let mut rows = vec![Check::within(
        NAME,
        "gate stays bonded: largest displacement of the row next to the clamp / dx",
        "bonded clamp (the root row moves with the clamp's edge only)",
        Some(0.0),
        fine.root_slip,
        fine.root_slip,
        if quick { 0.03 } else { 0.5 },
        "regression",
        run,
    )
    .with_note(
        "an unbonded gate slides off its clamp by many dx. Quick: 0.03, 3.3 x the 0.0092 measured with the \
         Jaumann rate (0.0039 total Lagrangian; CPU 2026-12-05, H200 2026-11-28): the root row moves only \
         elastically, by 1 % of dx; neither a doubled shear modulus (0.009) nor halved gravity (0.004) moves \
         it, only a clamp that starts to let go (not shown by tests/perturbed.rs). Full tier: half a spacing",
    )];
    if quick {
        // Downstream, and no more than twice the experiment's at that time: the right
        // direction and order, not an accuracy claim at two particles across.
        rows.push(
            Check::within(
                NAME,
                &format!("free end x at t = {t_last:.2} s bends downstream: |x / x_exp - 1|"),
                SOURCE,
                Some(x_exp_last),
                x_last,
                if x_last > 0.0 {
                    (x_last / x_exp_last - 1.0).abs()
                } else {
                    f64::INFINITY
                },
                1.0,
                "regression",
                run,
            )
            .with_plot(png_x)
            .with_note(
                "informational: two particles across the 5 mm gate at t = 0.02 s resolve neither load nor \
                 stiffness: halved gravity gives 0.77, a doubled shear modulus 0.45 (today 0.50 Jaumann, 0.36 total \
                 Lagrangian), all inside 0 < x < 2 x_exp (x_exp interpolated between the start and the first \
                 measured point at 0.04 s); the full tier compares the curves",
            )
            .informational(),
        );
        return Ok(rows);
    }
    let v: serde_json::Value =
        serde_json::from_str(refdata("fsi_antoci2007_elastic_gate.json")).expect("gate JSON");
    let peak_ref = |c: &str, k: &str| {
        v["peaks_from_digitised_curves"][format!("{EXP}_{c}")][k]
            .as_f64()
            .expect("peak in the gate JSON")
    };
    let (x_peak_ref, t_peak_ref, y_peak_ref) = (
        peak_ref("x", "max_m"),
        peak_ref("x", "t_at_max_s"),
        peak_ref("y", "max_m"),
    );
    let peak = |k: usize| {
        (fine.series.iter())
            .map(|s| (s.0, if k == 1 { s.1 } else { s.2 }))
            .fold((0.0, f64::MIN), |a, b| if b.1 > a.1 { b } else { a })
    };
    let (t_peak, x_peak) = peak(1);
    let (_, y_peak) = peak(2);
    let rms: Vec<f64> = outs.iter().map(|o| rms_x(o, &exp_x) / x_peak_ref).collect();
    rows.push(
        Check::within(
            NAME,
            "peak x of the free end: |x_max / x_max,exp - 1|",
            SOURCE,
            Some(x_peak_ref),
            x_peak,
            (x_peak / x_peak_ref - 1.0).abs(),
            0.20,
            "literature",
            run,
        )
        .with_plot(png_x)
        .with_note("the JSON: published SPH peaks lie 8-16 % below the measured one"),
    );
    rows.push(
        Check::within(
            NAME,
            "time of the peak x: |t - 0.15| (the JSON's window 0.10-0.20 s)",
            SOURCE,
            Some(t_peak_ref),
            t_peak,
            (t_peak - 0.15).abs(),
            0.05,
            "literature",
            run,
        )
        .with_note("the experiment's curve is sampled every 0.04 s: its time of peak is known to +-0.02-0.04 s"),
    );
    rows.push(
        Check::within(
            NAME,
            "RMS of x(t) - x_exp(t) over 0-0.4 s / measured peak x",
            SOURCE,
            Some(0.0),
            rms[rms.len() - 1],
            rms[rms.len() - 1],
            0.20,
            "literature",
            run,
        )
        .with_plot(png_x),
    );
    rows.push(
        Check::within(
            NAME,
            "peak y of the free end: |y_max / y_max,exp - 1|",
            SOURCE,
            Some(y_peak_ref),
            y_peak,
            (y_peak / y_peak_ref - 1.0).abs(),
            0.30,
            "literature",
            run,
        )
        .with_plot(png_y)
        .with_note("the JSON: published SPH y peaks lie 13-24 % below the measured one"),
    );
    let dx: Vec<f64> = outs.iter().map(|o| o.dx).collect();
    let runs: Vec<RunInfo> = outs.iter().map(|o| o.run.clone()).collect();
    // Against an experiment the error need not vanish with dx: reported, never failing.
    rows.push(
        convergence(
            NAME,
            "the RMS of x(t) against the experiment",
            &dx,
            &rms,
            &runs,
        )
        .informational(),
    );
    rows.extend(stopped);
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_series_and_band() {
        let x = series(EXP, "x");
        assert_eq!(x.len(), 9);
        assert!((interp(&x, 0.16062) - 0.046386).abs() < 1e-9);
        let ts: Vec<f64> = (0..=40).map(|i| 0.01 * i as f64).collect();
        let (lo, hi) = sph_band("x", &ts);
        assert!(!lo.is_empty() && lo.len() == hi.len());
        assert!(lo.iter().zip(&hi).all(|(a, b)| a.1 <= b.1));
    }

    #[test]
    fn free_length_sits_on_the_lattice() {
        for n in [2.0, 4.0, 8.0] {
            let dx = THICK / n;
            let l = free_length(dx);
            assert!((l - FREE_LEN).abs() <= 0.5 * dx + 1e-12, "{l}");
            assert!(((l / dx) - (l / dx).round()).abs() < 1e-9);
        }
    }
}
