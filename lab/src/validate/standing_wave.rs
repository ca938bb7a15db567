//! A linear standing gravity wave (issue #57): one wavelength L = 1.77 of water 0.3 deep
//! in a tank periodic along x (kd = 1.065, the flume's), started at rest with the surface
//! eta = a cos(k x), a = 0.015 (ka = 0.053), over a dynamic floor. Linear theory: the
//! surface oscillates at omega^2 = g k tanh(k d) (T = 1.1998 s; the second-order shift of
//! a standing wave at this ka and kd is under 0.1 %, Tadjbakhsh & Keller 1960), and without
//! viscosity it keeps its amplitude.
//!
//! Measured from 0.3 s on by 16 gauges along the wavelength: the surface's projection on
//! cos(k x) is the mode's amplitude, free of the other wavenumbers the start excites; a
//! damped cosine fitted to it gives the period, against linear theory, and the amplitude's
//! decay rate (informational: its inviscid value is 0). The plain
//! pressure gradient of eq. (7) makes the wave 4-7 % fast at every spacing and damps it
//! (docs/journal/2026-12-07-waves.md); `[fluid] gradient_correction` takes both away. The
//! corrected runs are checked (1 %: issue #57's period tolerance), the plain ones are
//! reported beside them. The correction runs on the CPU backend only, so the case does.

use super::check::{Check, RunInfo};
use super::ctx::{Ctx, Sim, Tier};
use super::flume::surface_series;
use meshfree_core::backend::BackendChoice;

pub const NAME: &str = "standing-wave";
pub const DESCRIPTION: &str = "Linear standing wave, one wavelength 1.77 of water 0.3 deep, periodic, \
amplitude 0.015 (kd = 1.065, ka = 0.053): period against omega^2 = g k tanh(k d) and the amplitude's \
decay rate, with and without [fluid] gradient_correction (CPU backend).";
const SOURCE: &str = "linear wave theory, omega^2 = g k tanh(k d) (Dean & Dalrymple 1991 sec. 3.3)";

/// \[L\] wavelength, depth and amplitude.
const L: f64 = 1.77;
const DEPTH: f64 = 0.3;
const A: f64 = 0.015;
/// \[L/T^2\]
const G: f64 = 9.81;
/// \[T\] the record's start (after the start's pressure transient) and sampling interval.
const FROM: f64 = 0.3;
const EVERY: f64 = 0.01;

/// Gauges evenly along the wavelength: the mode's amplitude is the surface's projection
/// on cos(k x), free of the other wavenumbers the start excites.
const GAUGES: usize = 16;

/// \[L\] gauge `i`'s x.
fn gauge_x(i: usize) -> f64 {
    (i as f64 + 0.5) * L / GAUGES as f64
}

/// \[T\] The linear period, 2 pi / sqrt(g k tanh(k d)).
pub fn linear_period() -> f64 {
    let k = 2.0 * std::f64::consts::PI / L;
    2.0 * std::f64::consts::PI / (G * k * (k * DEPTH).tanh()).sqrt()
}

/// The scene at spacing `dx`, the correction on or off.
pub fn scene_text(dx: f64, corrected: bool) -> String {
    let n = 90;
    let surface: Vec<String> = (0..=n)
        .rev()
        .map(|i| {
            let x = L * i as f64 / n as f64;
            let y = DEPTH + A * (2.0 * std::f64::consts::PI * x / L).cos();
            format!("[{x:.6}, {y:.6}]")
        })
        .collect();
    format!(
        r#"dimension = 2
name = "validate-standing-wave"
gravity = [0.0, -{G}]

[domain]
min = [0.0, -0.1]
max = [{L}, 0.6]
periodic = [true, false]

[discretisation]
spacing = {dx}
h_factor = 1.3
kernel = "wendland-c2"

[time]
end = 100.0
output_interval = 1.0
courant = 0.4
integrator = "leapfrog"

[fluid]
density = 1000.0
sound_speed = 17.0
gamma = 7.0
density_form = "continuity"
alpha = 0.01
density_diffusion = 0.1
density_diffusion_form = "fourtakas"
gradient_correction = {corrected}

[boundary]
strength = 294.3
wall_coupling = "dynamic"
wall_density_floor = true
hydrostatic_walls = true

[[fluid_blocks]]
min = [0.0, 0.0]
max = [{L}, {top}]
hydrostatic = true
inside = {{ points = [[0.0, 0.0], [{L}, 0.0], {surface}] }}

[[walls]]
shape = "box"
min = [0.0, {floor}]
max = [{L}, 0.0]

{gauges}"#,
        top = DEPTH + A,
        floor = -3.0 * dx,
        surface = surface.join(", "),
        gauges = (0..GAUGES)
            .map(|i| {
                let x = gauge_x(i);
                format!(
                    "[[gauges]]\nname = \"g{i}\"\nstart = [{x}, 0.1]\nend = [{x}, 0.5]\ninterval = {EVERY}\n\n"
                )
            })
            .collect::<String>(),
    )
}

/// The damped oscillation c + e^(-lambda t) (a cos(omega t) + b sin(omega t)) nearest in
/// least squares to `series` (t, m): (omega \[1/T\], lambda \[1/T\]), searched over omega
/// within 15 % of `omega0` and lambda in [-0.5, 2], on a grid refined twice about the best.
pub fn damped_fit(series: &[(f64, f64)], omega0: f64) -> (f64, f64) {
    let residual = |omega: f64, lambda: f64| -> f64 {
        // Normal equations of the three basis functions.
        let mut m = [[0.0f64; 3]; 3];
        let mut r = [0.0f64; 3];
        let basis = |t: f64| {
            let e = (-lambda * t).exp();
            [1.0, e * (omega * t).cos(), e * (omega * t).sin()]
        };
        for &(t, y) in series {
            let f = basis(t);
            for a in 0..3 {
                r[a] += f[a] * y;
                for b in 0..3 {
                    m[a][b] += f[a] * f[b];
                }
            }
        }
        let Some(c) = solve3(m, r) else {
            return f64::INFINITY;
        };
        series
            .iter()
            .map(|&(t, y)| {
                let f = basis(t);
                (y - c[0] * f[0] - c[1] * f[1] - c[2] * f[2]).powi(2)
            })
            .sum()
    };
    let (mut best, mut span) = ((omega0, 0.0), (0.15 * omega0, 1.25));
    let mut centre = (omega0, 0.75);
    for _ in 0..3 {
        let mut least = f64::INFINITY;
        for i in -40..=40 {
            for j in -40..=40 {
                let w = centre.0 + span.0 * i as f64 / 40.0;
                let l = centre.1 + span.1 * j as f64 / 40.0;
                let e = residual(w, l);
                if e < least {
                    (least, best) = (e, (w, l));
                }
            }
        }
        centre = best;
        span = (span.0 / 20.0, span.1 / 20.0);
    }
    best
}

/// The solution of the 3 x 3 system m x = r (Cramer's rule); None where m is singular.
fn solve3(m: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(m);
    if d.abs() < 1e-300 {
        return None;
    }
    let mut x = [0.0; 3];
    for (c, xc) in x.iter_mut().enumerate() {
        let mut mc = m;
        for row in 0..3 {
            mc[row][c] = r[row];
        }
        *xc = det(mc) / d;
    }
    Some(x)
}

struct Outcome {
    /// \[T\] the mode's period.
    period: f64,
    /// \[1/T\] the amplitude's decay rate: minus the slope of ln(height) against time.
    decay: f64,
    run: RunInfo,
}

fn simulate(ctx: &Ctx, dx: f64, corrected: bool, end: f64) -> anyhow::Result<Outcome> {
    let scene = ctx.scene(&scene_text(dx, corrected), "validate:standing-wave")?;
    let setup = scene.setup()?;
    let label = if corrected { "corrected" } else { "plain" };
    let mut sim = Sim::new(
        ctx,
        setup,
        scene.gates(),
        format!("dx = {dx} (d / dx = {}), {label}", DEPTH / dx),
    )?;
    let eta = surface_series(&mut sim, &scene, [FROM, end, EVERY], DEPTH)?;
    // The mode's amplitude at each sample where every gauge saw the surface.
    let k = 2.0 * std::f64::consts::PI / L;
    let n = eta.iter().map(|e| e.len()).min().unwrap_or(0);
    anyhow::ensure!(
        eta.iter().all(|e| e.len() == n) && n > 100,
        "a gauge missed the surface"
    );
    let mode: Vec<(f64, f64)> = (0..n)
        .map(|s| {
            let m: f64 = (eta.iter().enumerate())
                .map(|(i, e)| e[s].1 * (k * gauge_x(i)).cos())
                .sum();
            (eta[0][s].0, 2.0 * m / GAUGES as f64)
        })
        .collect();
    let (omega, decay) = damped_fit(&mode, 2.0 * std::f64::consts::PI / linear_period());
    Ok(Outcome {
        period: 2.0 * std::f64::consts::PI / omega,
        decay,
        run: sim.info(),
    })
}

pub fn run(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    let cpu = Ctx {
        backend: BackendChoice::Cpu,
        ..*ctx
    };
    // (spacing, corrected, end time)
    let runs: &[(f64, bool, f64)] = match ctx.tier {
        Tier::Quick => &[(0.02, true, 3.0)],
        Tier::Full => &[
            (0.02, false, 6.0),
            (0.02, true, 6.0),
            (0.01, false, 6.0),
            (0.01, true, 6.0),
        ],
    };
    let t = linear_period();
    let mut rows = Vec::new();
    for &(dx, corrected, end) in runs {
        let o = simulate(&cpu, dx, corrected, end)?;
        ctx.log(&format!(
            "{}: T = {:.4} ({:+.2} % of linear {t:.4}), amplitude decay {:.3} /s, {:.1} s",
            o.run.resolution,
            o.period,
            100.0 * (o.period / t - 1.0),
            o.decay,
            o.run.wall_seconds
        ));
        let label = if corrected { "corrected" } else { "plain" };
        let period = Check::within(
            NAME,
            &format!("period, {label} gradient: |T / T_linear - 1|"),
            SOURCE,
            Some(t),
            o.period,
            (o.period / t - 1.0).abs(),
            0.01,
            "literature",
            &o.run,
        )
        .with_note("1 %: issue #57's period tolerance");
        rows.push(if corrected {
            period
        } else {
            period.informational()
        });
        rows.push(
            Check::within(
                NAME,
                &format!("amplitude decay rate [1/s], {label} gradient"),
                "inviscid linear theory: 0",
                Some(0.0),
                o.decay,
                o.decay.abs(),
                0.1,
                "literature",
                &o.run,
            )
            .with_note("informational: artificial viscosity alpha = 0.01 and the spacing set it")
            .informational(),
        );
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_linear_period_is_the_flumes_wave() {
        // kd = 1.065 at T = 1.2 (flume-2d's wave, its wavelength 1.77).
        assert!((super::linear_period() - 1.1998).abs() < 5e-4);
    }

    #[test]
    fn the_fit_finds_a_damped_oscillations_frequency_and_rate() {
        let s: Vec<(f64, f64)> = (0..400)
            .map(|i| {
                let t = 0.3 + 0.01 * i as f64;
                let noise = 0.0005 * ((i * 7919) % 13) as f64 / 13.0;
                (
                    t,
                    0.001 + 0.015 * (-0.08 * t).exp() * (5.5 * t + 0.4).cos() + noise,
                )
            })
            .collect();
        let (omega, lambda) = super::damped_fit(&s, 5.2);
        assert!((omega - 5.5).abs() < 0.005, "{omega}");
        assert!((lambda - 0.08).abs() < 0.01, "{lambda}");
    }
}
