//! A clamped cantilever under its own weight (issue #20): a 2D plane-strain beam L x t =
//! 1 x 0.1 (quick tier 0.5 x 0.1) whose left end is held by a bonded clamp (a driven solid with motion zero, x in
//! [-0.3 L, 0]: 3 t, a whole number of spacings at every t / dx), gravity -y, started at rest. The steady tip
//! deflection against Euler-Bernoulli theory, w(x) = q x^2 (6 L^2 - 4 L x + x^2) / (24 E' I)
//! (w(L) = q L^4 / (8 E' I)), q = rho g t, I = t^3 / 12, E' = E / (1 - nu^2) in plane strain,
//! for E = 1e6, 1e8, 1e10 and 7e10 Pa (rho = 2700, nu = 0.3).
//!
//! What it tests: the response of a linear elastic beam scales as 1 / E, so w / w_theory
//! must not depend on E. A stiff solid's density change per step lies below f32's
//! resolution of rho (the ulp of 2700 is 2.4e-4, the root strain at E = 7e10 here 1e-8):
//! integrated in rho itself it rounded away, the pressure stayed zero and the beam came out
//! several times too soft (`SolidState::rho_dev` keeps the departure from rest instead).
//!
//! Material mapping (as `plate.rs`): shear modulus G = E / (2 (1 + nu)) in the Jaumann rate,
//! eq. (12), and P = c_s^2 (rho - rho0) with c_s = sqrt(K / rho), K = E / (3 (1 - 2 nu)),
//! so that in plane strain the beam bends with E' = E / (1 - nu^2).
//!
//! Gravity g = 0.01 m/s^2 keeps the softest beam linear (tip deflection 3.7e-3 L at E = 1e6);
//! the stiffest deflects 5.3e-8 m. f32 positions resolve that only near y = 0: the beam's
//! centreline lies on y = 0 and t / dx is odd, so that a row of particles sits on it, and the
//! tip is the centreline particle of the last column (its x, L - dx / 2, is where the theory
//! is taken). The run is undamped but for the artificial viscosity: started from rest, the
//! tip oscillates about the static deflection, which is the mean over whole periods of the
//! first mode (periods measured from the crossings of the mean; higher modes average out).
//! Every length of the problem is fixed but E, so the number of steps per period does not
//! depend on E (dt ~ h / c ~ 1 / sqrt(E), the period ~ 1 / sqrt(E)): a fixed number of
//! theoretical periods is run.
//!
//! Both solid formulations run (`[solid] formulation`): the paper's Jaumann rate and the
//! total-Lagrangian one (`meshfree_core::physics::tlsph`), each with its own rows.
//!
//! Quick tier: t / dx = 5 and L / t = 5 (CPU, seconds; a quarter of the steps per period of
//! L / t = 10): the total-Lagrangian ratio within 0.15 of the theory, the Jaumann ratio
//! informational (1.82 at this resolution, and 1.17 with a doubled shear modulus: no bound
//! about the theory separates right from wrong), and the key check that the ratio's spread
//! across E is round-off (1e-4). Full tier (GPU): t / dx = 5,
//! 9, 17, 5 % against the theory at every E on the finest, the spread, and the observed order
//! of the error at E = 7e10.

use super::check::{convergence, Check, RunInfo};
use super::ctx::{Ctx, Sim, Tier};
use crate::plot::{plot, Figure, Series};
use meshfree_core::named::Named;
use meshfree_core::scene::scheme::SolidFormulation;

pub const NAME: &str = "cantilever";
pub const DESCRIPTION: &str = "Cantilever under its own weight, 2D plane strain, L = 1, t = 0.1, rho = 2700, \
nu = 0.3, E = 1e6, 1e8, 1e10, 7e10 Pa, left end in a bonded clamp (0.3 L), g = 0.01 m/s^2, from rest: the tip's \
mean deflection over whole periods against Euler-Bernoulli theory q L^4 / (8 E' I), and its independence of E \
(f32 density of stiff solids).";
const SOURCE: &str =
    "Euler-Bernoulli beam theory, plane strain: w = q x^2 (6 L^2 - 4 L x + x^2) / (24 E' I)";

/// [L] length of the beam (full tier; the quick tier's is `L_QUICK`) and its thickness.
pub const L: f64 = 1.0;
pub const L_QUICK: f64 = 0.5;
pub const T: f64 = 0.1;
/// [M L^-2] density (aluminium), [-] Poisson's ratio, [L T^-2] gravity.
pub const RHO: f64 = 2700.0;
pub const NU: f64 = 0.3;
pub const G_ACC: f64 = 0.01;
/// [M L^-1 T^-2] Young's moduli.
pub const MODULI: [f64; 4] = [1e6, 1e8, 1e10, 7e10];
/// Artificial viscosity (eq. (10)).
const ALPHA: f64 = 0.1;

/// E' = E / (1 - nu^2), plane strain. [M L^-1 T^-2]
pub fn plane_strain_modulus(e: f64) -> f64 {
    e / (1.0 - NU * NU)
}

/// Euler-Bernoulli deflection [L] (positive down) at x of a cantilever of length L under
/// its own weight q = rho g t, with I = t^3 / 12 (per unit depth).
pub fn deflection(e: f64, l: f64, x: f64) -> f64 {
    let q = RHO * G_ACC * T;
    let i = T * T * T / 12.0;
    q * x * x * (6.0 * l * l - 4.0 * l * x + x * x) / (24.0 * plane_strain_modulus(e) * i)
}

/// The first bending mode's period [T] of the Euler-Bernoulli cantilever:
/// omega = 1.8751^2 sqrt(E' I / (rho t L^4)).
pub fn period(e: f64, l: f64) -> f64 {
    let i = T * T * T / 12.0;
    let omega = 1.875104f64.powi(2) * (plane_strain_modulus(e) * i / (RHO * T * l.powi(4))).sqrt();
    2.0 * std::f64::consts::PI / omega
}

/// (c_s, G) of E: c_s = sqrt(K / rho), K = E / (3 (1 - 2 nu)); G = E / (2 (1 + nu)).
pub fn material(e: f64) -> (f64, f64) {
    let k = e / (3.0 * (1.0 - 2.0 * NU));
    ((k / RHO).sqrt(), e / (2.0 * (1.0 + NU)))
}

/// The scene at spacing `dx` (t / dx odd: a row on y = 0) and modulus `e`: a clamp box
/// x in [-0.3 L, 0] (driven, motion zero; a whole number of spacings long, as a bonded clamp
/// must be) and the beam x in [0, L], y in [-t/2, t/2].
pub fn scene_text(e: f64, l: f64, dx: f64, t_end: f64, f: SolidFormulation) -> String {
    let (c_s, g) = material(e);
    let formulation = f.name();
    format!(
        r#"dimension = 2
name = "validate-cantilever"
gravity = [0.0, {gy:e}]

[domain]
min = [{x0:e}, {y0:e}]
max = [{x1:e}, {y1:e}]

[discretisation]
spacing = {dx:e}

[time]
end = {t_end:e}
output_interval = {t_end:e}

[fluid]                 # no fluid particles; the table is required, alpha acts on solids too
density = {RHO:e}
sound_speed = {c_s:e}
alpha = {ALPHA:e}

[solid]
density = {RHO:e}
sound_speed = {c_s:e}   # c_s = sqrt(K / rho)
shear_modulus = {g:e}
formulation = "{formulation}"

[[solids]]              # the clamp: held fixed, bonded to the beam
shape = "box"
min = [{xc:e}, {ylo:e}]
max = [0.0, {yhi:e}]
motion = [0.0, 0.0]

[[solids]]              # the beam
shape = "box"
min = [0.0, {ylo:e}]
max = [{l:e}, {yhi:e}]
"#,
        gy = -G_ACC,
        x0 = -3.0 * T - 0.5 * l,
        x1 = 1.5 * l,
        y0 = -0.5 * l,
        y1 = 0.5 * l,
        xc = -3.0 * T,
        ylo = -0.5 * T,
        yhi = 0.5 * T,
    )
}

/// Times where `y` crosses `m` (linear interpolation), with their direction (true: upward).
fn crossings(t: &[f64], y: &[f64], m: f64) -> Vec<(f64, bool)> {
    let mut out = Vec::new();
    for k in 1..y.len() {
        let (a, b) = (y[k - 1] - m, y[k] - m);
        if (a > 0.0) != (b > 0.0) && a != b {
            out.push((t[k - 1] + (t[k] - t[k - 1]) * a / (a - b), b > a));
        }
    }
    out
}

/// The mean of y(t) (piecewise linear through the samples) over [t0, t1].
fn mean_over(t: &[f64], y: &[f64], t0: f64, t1: f64) -> f64 {
    let at = |s: f64| {
        let k = t.partition_point(|&x| x < s).clamp(1, t.len() - 1);
        let f = (s - t[k - 1]) / (t[k] - t[k - 1]);
        y[k - 1] + f * (y[k] - y[k - 1])
    };
    let mut pts = vec![(t0, at(t0))];
    pts.extend(
        t.iter()
            .zip(y)
            .filter(|(s, _)| **s > t0 && **s < t1)
            .map(|(s, v)| (*s, *v)),
    );
    pts.push((t1, at(t1)));
    let area: f64 = pts
        .windows(2)
        .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
        .sum();
    area / (t1 - t0)
}

/// The static level of an oscillation about it: the mean over the whole periods between the
/// first and the last crossing of the mean in the first crossing's direction, iterated from
/// the plain mean. (level, measured period, periods averaged), None without a whole period.
pub fn whole_period_mean(t: &[f64], y: &[f64]) -> Option<(f64, f64, usize)> {
    let mut m = y.iter().sum::<f64>() / y.len() as f64;
    let mut out = None;
    for _ in 0..4 {
        let c = crossings(t, y, m);
        let first = *c.first()?;
        let same: Vec<f64> = c.iter().filter(|x| x.1 == first.1).map(|x| x.0).collect();
        let n = same.len().checked_sub(1).filter(|&n| n > 0)?;
        let (t0, t1) = (same[0], same[n]);
        m = mean_over(t, y, t0, t1);
        out = Some((m, (t1 - t0) / n as f64, n));
    }
    out
}

struct Outcome {
    e: f64,
    dx: f64,
    /// (t / T_theory, tip deflection / w_theory).
    series: Vec<(f64, f64)>,
    /// Tip deflection (positive down) [L] and its theory at the tip particle's x.
    w: f64,
    w_theory: f64,
    period: f64,
    periods: usize,
    run: RunInfo,
}

fn simulate(
    ctx: &Ctx,
    e: f64,
    l: f64,
    dx: f64,
    periods: f64,
    f: SolidFormulation,
) -> anyhow::Result<Outcome> {
    let t_ref = period(e, l);
    let t_end = periods * t_ref;
    let scene = ctx.scene(&scene_text(e, l, dx, t_end, f), "validate:cantilever")?;
    let setup = scene.setup()?;
    // The tip: the beam's (group 1) centreline particle of the last column.
    let beam = || setup.particles.iter().filter(|q| q.group == 1);
    let x_max = beam().map(|q| q.position[0]).fold(f32::MIN, f32::max);
    let tip = beam()
        .filter(|q| q.position[0] > x_max - 0.25 * dx as f32)
        .min_by(|a, b| a.position[1].abs().total_cmp(&b.position[1].abs()))
        .ok_or_else(|| anyhow::anyhow!("no tip particle at dx = {dx}"))?;
    anyhow::ensure!(
        (tip.position[1] as f64).abs() < 1e-6 * dx,
        "no particle on the centreline y = 0 (t / dx = {} must be odd)",
        T / dx
    );
    let (tip_id, tip_x, y0) = (tip.id, tip.position[0] as f64, tip.position[1] as f64);
    let w_theory = deflection(e, l, tip_x);
    let resolution = format!(
        "dx = {dx} (t / dx = {}, L / t = {}), {}",
        (T / dx).round(),
        l / T,
        f.name()
    );
    let mut sim = Sim::new(ctx, setup, scene.gates(), resolution)?;
    let samples = (periods * 100.0).ceil() as usize;
    let (mut t, mut y) = (Vec::new(), Vec::new());
    let mut series = Vec::new();
    for k in 1..=samples {
        sim.advance_to(t_end * k as f64 / samples as f64)?;
        let ps = sim.solver.particles();
        let q = ps
            .iter()
            .find(|q| q.id == tip_id)
            .ok_or_else(|| anyhow::anyhow!("the tip particle is gone"))?;
        let w = y0 - q.position[1] as f64;
        let now = sim.solver.time();
        t.push(now);
        y.push(w);
        series.push((now / t_ref, w / w_theory));
    }
    let (w, period, n) = whole_period_mean(&t, &y).ok_or_else(|| {
        anyhow::anyhow!(
            "E = {e:e}: the tip did not complete a period about its mean by t = {t_end:e} \
             (theory {t_ref:e} s)"
        )
    })?;
    Ok(Outcome {
        e,
        dx,
        series,
        w,
        w_theory,
        period,
        periods: n,
        run: sim.info(),
    })
}

pub fn run(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    let mut rows = Vec::new();
    for f in [SolidFormulation::Jaumann, SolidFormulation::TotalLagrangian] {
        rows.extend(run_formulation(ctx, f)?);
    }
    Ok(rows)
}

/// The rows of one solid formulation (`[solid] formulation`), labelled with it.
fn run_formulation(ctx: &Ctx, f: SolidFormulation) -> anyhow::Result<Vec<Check>> {
    let label = f.name();
    let quick = ctx.tier == Tier::Quick;
    // Whole theoretical periods run; the mean takes the whole measured ones in it.
    let (l, ratios, periods): (f64, &[f64], f64) = if quick {
        (L_QUICK, &[5.0], 2.0)
    } else {
        (L, &[5.0, 9.0, 17.0], 2.5)
    };
    let mut by_res: Vec<Vec<Outcome>> = Vec::new();
    for &ratio in ratios {
        let mut row = Vec::new();
        for &e in &MODULI {
            let o = simulate(ctx, e, l, T / ratio, periods, f)?;
            ctx.log(&format!(
                "{label}, t / dx = {ratio}, E = {e:e}: tip {:.4e} m, theory {:.4e} m, ratio {:.4}, period {:.4e} s \
                 (theory {:.4e}) over {} periods, {:.1} s",
                o.w,
                o.w_theory,
                o.w / o.w_theory,
                o.period,
                period(e, l),
                o.periods,
                o.run.wall_seconds
            ));
            row.push(o);
        }
        by_res.push(row);
    }
    let fine = by_res.last().expect("one resolution");
    let png = format!("cantilever-tip-{label}.png");
    let png = png.as_str();
    let mut series: Vec<Series> = fine
        .iter()
        .map(|o| Series::line(format!("E = {:e} Pa", o.e), o.series.clone()))
        .collect();
    series.push(Series::line(
        "theory (static)",
        vec![(0.0, 1.0), (periods, 1.0)],
    ));
    plot(
        &ctx.out_dir.join(png),
        &Figure {
            title: &format!(
                "Cantilever under its own weight, {label}, t / dx = {}: tip deflection / theory",
                (T / fine[0].dx).round()
            ),
            x_label: "t / T_theory",
            y_label: "w_tip / w_theory",
            log_x: false,
            log_y: false,
        },
        &series,
    )?;
    let basis = if quick { "regression" } else { "literature" };
    let ratio = |o: &Outcome| o.w / o.w_theory;
    let mut rows = Vec::new();
    for o in fine {
        let row = Check::within(
                NAME,
                &format!("{label}: tip deflection at E = {:e} Pa: |w / w_theory - 1|", o.e),
                SOURCE,
                Some(o.w_theory),
                o.w,
                (ratio(o) - 1.0).abs(),
                match (quick, f) {
                    (true, SolidFormulation::Jaumann) => 1.0,
                    (true, SolidFormulation::TotalLagrangian) => 0.15,
                    (false, _) => 0.05,
                },
                basis,
                &o.run,
            )
            .with_plot(png)
            .with_note(format!(
                "mean over {} measured periods of {:.4e} s (theory {:.4e} s); {}",
                o.periods,
                o.period,
                period(o.e, l),
                match (quick, f) {
                    (true, SolidFormulation::Jaumann) => {
                        "informational at t / dx = 5, L / t = 5: the coarse Jaumann beam is 1.82 x the \
                         theory at every E (CPU 2026-12-05, H100 2026-11-25; the kernel truncated at its \
                         faces, a compliant clamp, shear 4 % at L / t = 5), and a doubled shear modulus \
                         brings it to 1.17 (tests/perturbed.rs): no bound about the theory tells a right \
                         scheme from a wrong one at this resolution. The spread across E is checked; the \
                         full tier checks 5 % at t / dx = 17"
                    }
                    (true, SolidFormulation::TotalLagrangian) => {
                        "t / dx = 5, L / t = 5: measured 1.064 x the theory at every E (CPU 2026-12-05, \
                         H200 2026-11-28; 1.29 before the clamp's face, 1.64 before the reference \
                         gradient was made exact for quadratic fields); the plane-strain continuum \
                         itself is 1.037 x Euler-Bernoulli here (shear and the clamp face: \
                         lab/reference/cantilever_fem.py). 0.15 is 2.3 x the error; a doubled shear \
                         modulus gives 0.35 (tests/perturbed.rs)"
                    }
                    (false, _) => {
                        "the plane-strain continuum is 1.007 x Euler-Bernoulli at L / t = 10 (shear and the \
                         clamp face: lab/reference/cantilever_fem.py)"
                    }
                }
            ));
        rows.push(if quick && f == SolidFormulation::Jaumann {
            row.informational()
        } else {
            row
        });
    }
    let rs: Vec<f64> = fine.iter().map(ratio).collect();
    let mean = rs.iter().sum::<f64>() / rs.len() as f64;
    let spread = (rs.iter().cloned().fold(f64::MIN, f64::max)
        - rs.iter().cloned().fold(f64::MAX, f64::min))
        / mean;
    let last = &fine.last().expect("four moduli").run;
    rows.push(
        Check::within(
            NAME,
            &format!(
                "{label}: spread of w / w_theory across E = 1e6 ... 7e10 Pa: (max - min) / mean"
            ),
            "linear elasticity: w E is independent of E",
            Some(0.0),
            spread,
            spread,
            if quick { 1e-4 } else { 0.03 },
            "literature",
            last,
        )
        .with_note(format!(
            "ratios {}: a stiff solid whose density change per step rounds away in f32 comes out \
             several times softer{}",
            rs.iter()
                .map(|r| format!("{r:.4}"))
                .collect::<Vec<_>>()
                .join(", "),
            if quick {
                " (1.87 against 5.04 before rho_dev). Quick: 1e-4, 30 x the round-off-level spread \
                 measured (3.3e-6 Jaumann, 5.3e-7 total Lagrangian; CPU 2026-12-05, the H200 within \
                 10 % of it): a bound 1.5-3 x it would test the backend's summation order; a shear \
                 modulus 1.5 x off at the stiffest E alone gives 0.24 (tests/perturbed.rs)"
            } else {
                ""
            }
        )),
    );
    if by_res.len() > 1 {
        let stiff: Vec<&Outcome> = by_res.iter().map(|r| r.last().unwrap()).collect();
        let dx: Vec<f64> = stiff.iter().map(|o| o.dx).collect();
        let runs: Vec<RunInfo> = stiff.iter().map(|o| o.run.clone()).collect();
        rows.push(convergence(
            NAME,
            &format!("{label}: the tip deflection error at E = 7e10 Pa"),
            &dx,
            &stiff
                .iter()
                .map(|o| (ratio(o) - 1.0).abs())
                .collect::<Vec<_>>(),
            &runs,
        ));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn theory_at_the_tip_is_q_l4_over_8_ei() {
        let e = 7e10;
        let want = RHO * G_ACC * T * L.powi(4) / (8.0 * plane_strain_modulus(e) * T.powi(3) / 12.0);
        assert!((deflection(e, L, L) / want - 1.0).abs() < 1e-12);
        assert_eq!(deflection(e, L, 0.0), 0.0);
        // The softest beam stays linear: w / L well below 1 %.
        assert!(deflection(MODULI[0], L, L) / L < 5e-3);
    }

    #[test]
    fn material_gives_e_back() {
        let (c, g) = material(7e10);
        let k = RHO * c * c;
        let e = 9.0 * k * g / (3.0 * k + g);
        assert!((e / 7e10 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn whole_period_mean_of_an_oscillation_from_rest_is_its_level() {
        // y = w (1 - cos(omega t)), a 5 % faster second mode on top; the mean is w.
        let (w, tp) = (2.0, 0.3);
        let t: Vec<f64> = (1..=200).map(|k| k as f64 * 2.0 * tp / 200.0).collect();
        let y: Vec<f64> = t
            .iter()
            .map(|t| {
                let a = 2.0 * std::f64::consts::PI * t / tp;
                w * (1.0 - a.cos()) + 0.03 * w * (6.27 * a).sin()
            })
            .collect();
        let (m, p, n) = whole_period_mean(&t, &y).expect("a whole period");
        assert_eq!(n, 1);
        assert!((m / w - 1.0).abs() < 5e-3, "{m}");
        assert!((p / tp - 1.0).abs() < 1e-2, "{p}");
    }
}
