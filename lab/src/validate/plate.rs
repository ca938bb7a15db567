//! Gray, Monaghan & Swift (2001) oscillating cantilever plate (issue #6): a 2D plane-strain
//! plate L x H = 0.2 x 0.02 whose left L / 4 is held by a clamp (a driven solid with motion
//! zero, bonded to the plate: `same_body`), started with the first bending mode's velocity,
//! no gravity. The tip's y displacement against thin-plate (Euler-Bernoulli, plane strain)
//! theory: the period from zero crossings, the first-cycle amplitude V_f c0 / omega and the
//! decay per cycle. Parameters, theory and tolerances: `refdata/elastic_gray2001_oscillating_plate.json`.
//!
//! Our solid model: shear modulus G = E / (2 (1 + nu)) in the Jaumann rate, eq. (12), and
//! P = c_s^2 (rho - rho0) with c_s = sqrt(K / rho), K = E / (3 (1 - 2 nu)), so in plane
//! strain the plate bends with E / (1 - nu^2) as the theory assumes. The step size, eq. (19),
//! takes the longitudinal speed sqrt(c_s^2 + 4 G / (3 rho)) for solids (`params::sound_speed`):
//! 64.8 m/s here, not c_s = 57.0.
//!
//! The plate takes density diffusion inside the body (`[solid] density_diffusion = 0.02`, in
//! Antuono et al. 2010's form that leaves its bending's linear density alone): with the
//! artificial stress 0.3 that holds the fibres against the tensile instability, a
//! particle-scale (odd-even) pressure mode grows at H / dx = 32 and damped the plate by 0.43
//! per cycle; the diffusion keeps it down (docs/reference/accuracy.md, oscillating plate).
//!
//! Both solid formulations run (`[solid] formulation`): the paper's Jaumann rate with the
//! terms above, and the total-Lagrangian one (`meshfree_core::physics::tlsph`), which needs neither
//! the artificial stress nor the density diffusion (no tensile instability; its density is
//! rho0 / det F) and takes the hourglass control at its default. The issue's target for the
//! latter: the frequency within 2 % at H / dx = 8. Its rows are informational unless they
//! pass the same bounds. Measured (docs/reference/accuracy.md): total Lagrangian, reference
//! gradient exact for quadratic fields, period +9.6 % at H / dx = 4 (CPU), +4.0 %, +2.0 %,
//! +1.2 % at 8, 16, 32 (H200, 2026-11-27); the Jaumann rate +42.8 % at 4, +17.7 %, +7.6 %,
//! +6.5 % at 8, 16, 32. The 2 % target at 8 is not met yet.
//!
//! Quick tier: H / dx = 4 (coarse: the plate is soft and the clamp compliant), 2.5 periods,
//! regression bounds; the Jaumann period and amplitude informational (43 % and 37 % off,
//! 12 % and 8 % with a doubled shear modulus: no bound separates right from wrong there),
//! the total-Lagrangian rows checks. Full tier (GPU): H / dx = 8, 16, 32, 3.5 periods, the JSON's tolerances
//! on the finest, and the observed order of the period error.

use super::check::{convergence, Check, RunInfo};
use super::ctx::{Ctx, Sim, Tier};
use super::refdata::refdata;
use crate::plot::{plot, Figure, Series};
use meshfree_core::named::Named;
use meshfree_core::scene::scheme::SolidFormulation;

pub const NAME: &str = "plate";
pub const DESCRIPTION: &str = "Oscillating cantilever plate (Gray, Monaghan & Swift 2001), 2D plane strain, \
L = 0.2, H = 0.02, rho = 1000, E = 2 MPa, nu = 0.3975, left L/4 clamped, first-mode initial velocity with \
V_f = 0.01, no gravity: the tip's period against thin-plate theory (0.2540 s), its first-cycle amplitude \
against V_f c0 / omega and its decay per cycle.";
const SOURCE: &str =
    "thin-plate theory, Gray, Monaghan & Swift 2001 (refdata/elastic_gray2001_oscillating_plate.json)";

/// V_f of the initial velocity: the tip starts at V_f c0 (the JSON compares periods at
/// V_f <= 0.01, where the response is linear).
const V_F: f64 = 0.01;
/// k L of the first bending mode (the JSON's initial-condition formula).
const KL: f64 = 1.875;
/// Artificial viscosity (eq. (10)) and artificial stress (Gray et al. 2001).
const ALPHA: f64 = 0.1;
const ART_STRESS: f64 = 0.3;
/// delta of the density diffusion inside the body (`[solid] density_diffusion`).
pub const SOLID_DIFFUSION: f64 = 0.02;

/// The reference values read from the JSON.
pub struct Reference {
    pub l: f64,
    pub h: f64,
    pub rho: f64,
    pub g: f64,
    pub c0: f64,
    pub omega: f64,
    pub period: f64,
}

fn num(v: &serde_json::Value, path: &[&str]) -> f64 {
    let mut x = v;
    for k in path {
        x = &x[*k];
    }
    x.as_f64()
        .unwrap_or_else(|| panic!("{} missing in the plate reference", path.join(".")))
}

pub fn reference() -> Reference {
    let v: serde_json::Value =
        serde_json::from_str(refdata("elastic_gray2001_oscillating_plate.json"))
            .expect("plate reference JSON");
    Reference {
        l: num(&v, &["geometry", "L_m"]),
        h: num(&v, &["geometry", "H_thickness_m"]),
        rho: num(&v, &["material", "rho_kg_m3"]),
        g: num(&v, &["material", "G_Pa"]),
        c0: num(&v, &["material", "c0_m_s"]),
        omega: num(&v, &["theory", "omega_rad_s"]),
        period: num(&v, &["theory", "period_s"]),
    }
}

/// The scene at spacing `dx`: a clamp box x in [-L/4, 0] (driven, motion zero) and the
/// plate x in [0, L], both y in [-H/2, H/2], on one lattice.
pub fn scene_text(r: &Reference, dx: f64, t_end: f64, f: SolidFormulation) -> String {
    let solid_scheme = match f {
        SolidFormulation::Jaumann => {
            format!("artificial_stress = {ART_STRESS:e}\ndensity_diffusion = {SOLID_DIFFUSION:e}")
        }
        SolidFormulation::TotalLagrangian => "formulation = \"total-lagrangian\"".to_string(),
    };
    format!(
        r#"dimension = 2
name = "validate-plate"

[domain]
min = [{x0:e}, {y0:e}]
max = [{x1:e}, {y1:e}]

[discretisation]
spacing = {dx:e}

[time]
end = {t_end:e}
output_interval = {t_end:e}

[fluid]                 # no fluid particles; the table is required, alpha acts on solids too
density = {rho:e}
sound_speed = {c0:e}
alpha = {ALPHA:e}

[solid]
density = {rho:e}
sound_speed = {c0:e}    # c_s = sqrt(K / rho)
shear_modulus = {g:e}
{solid_scheme}

[[solids]]              # the clamp: held fixed, bonded to the plate
shape = "box"
min = [{xc:e}, {ylo:e}]
max = [0.0, {yhi:e}]
motion = [0.0, 0.0]

[[solids]]              # the plate
shape = "box"
min = [0.0, {ylo:e}]
max = [{l:e}, {yhi:e}]
"#,
        x0 = -0.5 * r.l,
        x1 = 1.5 * r.l,
        y0 = -r.l,
        y1 = r.l,
        rho = r.rho,
        c0 = r.c0,
        g = r.g,
        xc = -0.25 * r.l,
        ylo = -0.5 * r.h,
        yhi = 0.5 * r.h,
        l = r.l,
    )
}

/// The first mode's velocity shape, 1 at the tip (the JSON's formula over its Q):
/// [M (cos kx - cosh kx) - N (sin kx - sinh kx)] / Q.
pub fn mode_shape(x: f64, l: f64) -> f64 {
    let k = KL / l;
    let kl = KL;
    let m = kl.sin() + kl.sinh();
    let n = kl.cos() + kl.cosh();
    let q = 2.0 * (kl.cos() * kl.sinh() - kl.sin() * kl.cosh());
    (m * ((k * x).cos() - (k * x).cosh()) - n * ((k * x).sin() - (k * x).sinh())) / q
}

/// Times where `y` changes sign (linear interpolation).
fn zero_crossings(t: &[f64], y: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    for k in 1..y.len() {
        if (y[k - 1] > 0.0) != (y[k] > 0.0) && y[k] != y[k - 1] {
            out.push(t[k - 1] + (t[k] - t[k - 1]) * y[k - 1] / (y[k - 1] - y[k]));
        }
    }
    out
}

struct Outcome {
    dx: f64,
    /// (t, tip y displacement).
    series: Vec<(f64, f64)>,
    period: f64,
    amplitude: f64,
    /// 1 - (last positive peak / first)^(1 / cycles between them).
    decay: f64,
    mean_dt: f64,
    run: RunInfo,
}

pub fn simulate_tip(
    ctx: &Ctx,
    ratio: f64,
    cycles: f64,
    f: SolidFormulation,
) -> anyhow::Result<(f64, f64, f64, f64, f64)> {
    let r = reference();
    let o = simulate(ctx, &r, r.h / ratio, cycles * r.period, f)?;
    Ok((
        o.period,
        o.amplitude,
        o.decay,
        o.mean_dt,
        o.run.wall_seconds,
    ))
}

fn simulate(
    ctx: &Ctx,
    r: &Reference,
    dx: f64,
    t_end: f64,
    f: SolidFormulation,
) -> anyhow::Result<Outcome> {
    let scene = ctx.scene(&scene_text(r, dx, t_end, f), "validate:plate")?;
    let mut setup = scene.setup()?;
    // The initial velocity field of the first mode on the plate (group 1; the clamp is 0).
    let tip_x = setup
        .particles
        .iter()
        .filter(|q| q.group == 1)
        .map(|q| q.position[0])
        .fold(f32::MIN, f32::max);
    let mut tip = Vec::new();
    for q in setup.particles.iter_mut().filter(|q| q.group == 1) {
        q.velocity[1] = (V_F * r.c0 * mode_shape(q.position[0] as f64, r.l)) as f32;
        if q.position[0] > tip_x - 0.25 * dx as f32 {
            tip.push(q.id);
        }
    }
    anyhow::ensure!(!tip.is_empty(), "no tip particle at dx = {dx}");
    let y_tip = |ps: &[meshfree_core::physics::particle::Particle]| {
        tip.iter()
            .map(|&id| ps[id as usize].position[1] as f64)
            .sum::<f64>()
            / tip.len() as f64
    };
    let y0 = y_tip(&setup.particles);
    let resolution = format!("dx = {dx} (H / dx = {}), {}", (r.h / dx).round(), f.name());
    let mut sim = Sim::new(ctx, setup, scene.gates(), resolution)?;
    let samples = (t_end / (r.period / 100.0)).ceil() as usize;
    let mut series = vec![(0.0, 0.0)];
    for k in 1..=samples {
        sim.advance_to(t_end * k as f64 / samples as f64)?;
        let mut ps = sim.solver.particles();
        ps.sort_by_key(|q| q.id);
        series.push((sim.solver.time(), y_tip(&ps) - y0));
    }
    // From the first sample on: the start (y = 0 exactly) is not a crossing.
    let (t, y): (Vec<f64>, Vec<f64>) = series[1..].iter().copied().unzip();
    let cross = zero_crossings(&t, &y);
    anyhow::ensure!(
        cross.len() >= 3,
        "the tip crossed zero {} times by t = {t_end} (expected about {}): no oscillation",
        cross.len(),
        (2.0 * t_end / r.period) as usize
    );
    // Crossings every half period: the slope of a straight line through them.
    let n = cross.len() as f64;
    let mi = (n - 1.0) / 2.0;
    let mc = cross.iter().sum::<f64>() / n;
    let sxy: f64 = (cross.iter().enumerate())
        .map(|(i, c)| (i as f64 - mi) * (c - mc))
        .sum();
    let sxx: f64 = (0..cross.len()).map(|i| (i as f64 - mi).powi(2)).sum();
    let period = 2.0 * sxy / sxx;
    // Positive lobes: [0, c0], [c1, c2], [c3, c4], ...
    let lobe_max = |a: f64, b: f64| {
        series
            .iter()
            .filter(|s| s.0 >= a && s.0 <= b)
            .map(|s| s.1)
            .fold(f64::MIN, f64::max)
    };
    let mut peaks = vec![lobe_max(0.0, cross[0])];
    let mut k = 1;
    while k + 1 < cross.len() {
        peaks.push(lobe_max(cross[k], cross[k + 1]));
        k += 2;
    }
    let amplitude = peaks[0];
    let decay = if peaks.len() > 1 {
        1.0 - (peaks[peaks.len() - 1] / peaks[0]).powf(1.0 / (peaks.len() - 1) as f64)
    } else {
        f64::NAN
    };
    let mean_dt = sim.solver.time() / sim.solver.steps().max(1) as f64;
    Ok(Outcome {
        dx,
        series,
        period,
        amplitude,
        decay,
        mean_dt,
        run: sim.info(),
    })
}

pub fn run(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    let mut rows = run_formulation(ctx, SolidFormulation::Jaumann)?;
    // The total-Lagrangian rows: in the full tier informational unless they pass the same
    // bounds; in the quick tier checks with their own tolerances (a row that turns
    // informational when it fails is no check).
    let quick = ctx.tier == Tier::Quick;
    for row in run_formulation(ctx, SolidFormulation::TotalLagrangian)? {
        rows.push(if row.pass || quick {
            row
        } else {
            row.informational()
        });
    }
    Ok(rows)
}

/// The plate's rows with one solid formulation.
fn run_formulation(ctx: &Ctx, f: SolidFormulation) -> anyhow::Result<Vec<Check>> {
    let r = reference();
    let tl = f == SolidFormulation::TotalLagrangian;
    let name = f.name();
    let quick = ctx.tier == Tier::Quick;
    let (ratios, cycles): (&[f64], f64) = if quick {
        (&[4.0], 2.5)
    } else {
        (&[8.0, 16.0, 32.0], 3.5)
    };
    let amp_ref = V_F * r.c0 / r.omega;
    let mut outs = Vec::new();
    for &ratio in ratios {
        let o = simulate(ctx, &r, r.h / ratio, cycles * r.period, f)?;
        ctx.log(&format!(
            "{name}, H / dx = {ratio}: period {:.4} s, amplitude {:.5} m, decay {:.3} per cycle, mean dt {:.2e} s, {:.1} s",
            o.period, o.amplitude, o.decay, o.mean_dt, o.run.wall_seconds
        ));
        outs.push(o);
    }
    let fine = outs.last().expect("one run");
    let png = if tl {
        "plate-tip-total-lagrangian.png"
    } else {
        "plate-tip.png"
    };
    let t_max = fine.series.last().map_or(0.0, |s| s.0);
    let theory: Vec<(f64, f64)> = (0..=400)
        .map(|k| {
            let t = t_max * k as f64 / 400.0;
            (t, amp_ref * (r.omega * t).sin())
        })
        .collect();
    plot(
        &ctx.out_dir.join(png),
        &Figure {
            title: &format!(
                "Oscillating plate ({name}), H / dx = {}: tip y displacement",
                (r.h / fine.dx).round()
            ),
            x_label: "t [s]",
            y_label: "tip y [m]",
            log_x: false,
            log_y: false,
        },
        &[
            Series::line("SPH", fine.series.clone()),
            Series::line(
                format!(
                    "theory: (V_f c0 / omega) sin(omega t), T = {:.4} s",
                    r.period
                ),
                theory,
            ),
        ],
    )?;
    let run = &fine.run;
    let basis = if quick { "regression" } else { "literature" };
    let dt_note = format!(
        "mean dt {:.2e} s = {:.3} h / c_s: eq. (19) takes the longitudinal speed sqrt(c_s^2 + 4 G / (3 rho)) = {:.1} m/s, not c_s = {:.1}",
        fine.mean_dt,
        fine.mean_dt / (1.3 * fine.dx / r.c0),
        (r.c0 * r.c0 + 4.0 * r.g / (3.0 * r.rho)).sqrt(),
        r.c0
    );
    let period_err = |o: &Outcome| (o.period / r.period - 1.0).abs();
    let mut rows = vec![
        Check::within(
            NAME,
            "period from the tip's zero crossings: |T / T_theory - 1|",
            SOURCE,
            Some(r.period),
            fine.period,
            period_err(fine),
            match (quick, tl) {
                (true, false) => 0.5,
                (true, true) => 0.04,
                (false, _) => 0.10,
            },
            basis,
            run,
        )
        .with_plot(png)
        .with_note(if quick && tl {
            "H / dx = 4: measured +1.4 % (CPU 2026-12-05, H200 2026-11-28); 0.04 is 2.8 x that, a doubled shear \
             modulus shortens the period by about 30 %. The JSON recommends 5-10 % at V_f = 0.01"
        } else if quick {
            "informational at H / dx = 4: the coarse Jaumann plate is softer than thin-plate theory (period +43 % \
             here, CPU 2026-12-05 and H200 2026-11-28; +16 % at H / dx = 8), and a doubled shear modulus brings it \
             to +12 % (tests/perturbed.rs): no bound about the theory tells a right scheme from a wrong one at this \
             resolution (a halved one stops the oscillation, which fails the case). The JSON recommends 5-10 % at V_f = 0.01"
        } else {
            "10 %, the JSON's 5-10 %: thickness / length 0.1 (shear and rotary inertia) lowers the frequency by a few per cent"
        }),
        Check::within(
            NAME,
            "first-cycle tip amplitude: |A / (V_f c0 / omega) - 1|",
            SOURCE,
            Some(amp_ref),
            fine.amplitude,
            (fine.amplitude / amp_ref - 1.0).abs(),
            match (quick, tl) {
                (true, false) => 0.5,
                (true, true) => 0.04,
                (false, _) => 0.15,
            },
            basis,
            run,
        )
        .with_note(if quick && tl {
            "H / dx = 4: measured 0.015 (CPU 2026-12-05, H200 2026-11-28); 0.04 is 2.7 x that; A = v / omega moves \
             with the frequency. The JSON recommends 10-15 %"
        } else if quick {
            "informational at H / dx = 4: A = v / omega, the coarse plate's lower frequency raises it (+37 % here, \
             +14 % at 8), and a doubled shear modulus brings it to +8 % (tests/perturbed.rs). The JSON recommends 10-15 %"
        } else {
            "the JSON recommends 10-15 %"
        }),
        Check::within(
            NAME,
            "tip amplitude decay per cycle",
            "JSON: < 5 % per cycle with small artificial viscosity",
            Some(0.0),
            fine.decay,
            fine.decay,
            match (quick, tl) {
                (true, false) => 0.15,
                (true, true) => 0.0015,
                _ => 0.05,
            },
            basis,
            run,
        )
        .with_note(if tl {
            format!("total Lagrangian: alpha = {ALPHA}, hourglass control at its default, no artificial stress; {dt_note}{}",
                if quick { "; quick: 0.0015, 2.3 x the 0.00065 measured (CPU 2026-12-05, H100 2026-12-06); ten times the artificial viscosity gives 0.0023 (tests/perturbed.rs); the JSON's bound is 5 %" } else { "" })
        } else {
            format!("alpha = {ALPHA}, artificial stress {ART_STRESS}, density diffusion in the body {SOLID_DIFFUSION}; {dt_note}{}",
                if quick { "; quick: 0.15, 1.5 x the 0.102 measured (CPU 2026-12-05, H200 2026-11-28, H100 2026-12-06); five times the body's density diffusion gives 0.21 (tests/perturbed.rs)" } else { "" })
        }),
    ];
    if quick && !tl {
        // The coarse Jaumann plate's period and amplitude (see their notes).
        for row in rows.iter_mut().take(2) {
            *row = row.clone().informational();
        }
    }
    if tl {
        for row in rows.iter_mut() {
            row.quantity = format!("{} (total Lagrangian)", row.quantity);
        }
    }
    if outs.len() > 1 {
        let dx: Vec<f64> = outs.iter().map(|o| o.dx).collect();
        let runs: Vec<RunInfo> = outs.iter().map(|o| o.run.clone()).collect();
        rows.push(convergence(
            NAME,
            if tl {
                "the period error (total Lagrangian)"
            } else {
                "the period error"
            },
            &dx,
            &outs.iter().map(period_err).collect::<Vec<_>>(),
            &runs,
        ));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mode_shape_is_clamped_and_one_at_the_tip() {
        let l = 0.2;
        assert!(mode_shape(0.0, l).abs() < 1e-12);
        assert!(
            (mode_shape(l, l) - 1.0).abs() < 1e-3,
            "{}",
            mode_shape(l, l)
        );
        // Monotone along the plate.
        assert!(mode_shape(0.5 * l, l) > 0.0 && mode_shape(0.5 * l, l) < 1.0);
    }

    /// The period, amplitude and decay of both formulations at the H / dx of
    /// `MESHFREE_PLATE_RATIOS` (default "4,8"), 2.5 periods, on the CPU: a measurement
    /// (release build: `cargo test --release -p meshfree-lab --lib measure_plate --
    /// --ignored --nocapture`).
    #[test]
    #[ignore = "a measurement: minutes in a release build"]
    fn measure_plate() {
        use meshfree_core::backend::BackendChoice;
        let ratios: Vec<f64> = std::env::var("MESHFREE_PLATE_RATIOS")
            .unwrap_or_else(|_| "4,8".into())
            .split(',')
            .map(|s| s.trim().parse().expect("a number"))
            .collect();
        let out = std::env::temp_dir();
        let ctx = Ctx {
            tier: Tier::Quick,
            backend: BackendChoice::Cpu,
            courant: None,
            integrator: None,
            sets: &[],
            out_dir: &out,
            verbose: true,
            edit: None,
        };
        let r = reference();
        for f in [SolidFormulation::TotalLagrangian, SolidFormulation::Jaumann] {
            for &ratio in &ratios {
                let (period, amp, decay, dt, wall) = simulate_tip(&ctx, ratio, 2.5, f).unwrap();
                crate::note!(
                    "{} H/dx = {ratio}: period {period:.4} s ({:+.1} % of {:.4}), amplitude {amp:.5} m \
                     ({:+.1} % of {:.5}), decay {decay:.3} per cycle, mean dt {dt:.2e}, {wall:.0} s",
                    f.name(),
                    100.0 * (period / r.period - 1.0),
                    r.period,
                    100.0 * (amp / (V_F * r.c0 / r.omega) - 1.0),
                    V_F * r.c0 / r.omega
                );
            }
        }
    }

    #[test]
    fn zero_crossings_of_a_sine() {
        let t: Vec<f64> = (0..=1000).map(|k| k as f64 * 1e-3).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|t| (2.0 * std::f64::consts::PI * 3.0 * t).sin())
            .collect();
        let c = zero_crossings(&t[1..], &y[1..]);
        assert_eq!(c.len(), 5, "{c:?}");
        assert!((c[0] - 1.0 / 6.0).abs() < 1e-4);
    }
}
