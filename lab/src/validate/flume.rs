//! Regular waves in a flume (issue #57): the built-in `flume-2d` (a piston paddle, H = 0.05,
//! T = 1.2 in 0.3 of water: kd = 1.065, a damping zone over the last 2 m) at three
//! spacings, H / dx = 2.5, 5 and 10. At gauges 1, 2 and 3 m from the paddle, the mean
//! crest-to-trough height of the waves between zero up-crossings over 6 <= t <= 12 (after
//! the 2.4 s ramp and the waves' arrival at the group velocity, 1.1 m/s) against the
//! target H of first-order wave-maker theory (Biesel's transfer function gives the stroke),
//! and their mean period against T. The tolerances: 5 % in height, 1 % in period.
//! Full tier only: each run is 10 periods of 5,000 to 72,000 particles.

use super::check::{Check, RunInfo};
use super::ctx::{Ctx, Sim, Tier};
use meshfree_core::measure::probe::{gauge_points, surface};

pub const NAME: &str = "flume";
pub const DESCRIPTION: &str = "Regular waves from a piston paddle (flume-2d: H = 0.05, T = 1.2, depth 0.3, \
kd = 1.065, damping zone over the last 2 m): wave height and period at 1, 2 and 3 m against the target of \
first-order wave-maker theory, at H / dx = 2.5, 5, 10.";
const SOURCE: &str =
    "target wave of linear wave-maker theory (Biesel; Dean & Dalrymple 1991 sec. 6.2)";

const TEXT: &str = include_str!("../../../scenes/flume-2d.toml");
/// \[L\], \[T\], \[L\] the built-in's wave.
const H: f64 = 0.05;
const T: f64 = 1.2;
const DEPTH: f64 = 0.3;
/// \[T\] the record the heights are taken over, and the sampling interval.
const FROM: f64 = 6.0;
const END: f64 = 12.0;
const EVERY: f64 = 0.02;

/// Mean height and period of the waves between zero up-crossings of eta(t) (its mean
/// taken off), and how many.
fn waves(series: &[(f64, f64)]) -> (f64, f64, usize) {
    let n = series.len().max(1) as f64;
    let mean = series.iter().map(|s| s.1).sum::<f64>() / n;
    let ups: Vec<f64> = series
        .windows(2)
        .filter(|w| w[0].1 - mean < 0.0 && w[1].1 - mean >= 0.0)
        .map(|w| {
            let (a, b) = (w[0].1 - mean, w[1].1 - mean);
            w[0].0 + (w[1].0 - w[0].0) * (-a) / (b - a)
        })
        .collect();
    let mut heights = Vec::new();
    for w in ups.windows(2) {
        let inside = series
            .iter()
            .filter(|s| s.0 >= w[0] && s.0 < w[1])
            .map(|s| s.1);
        let (lo, hi) = inside.fold((f64::MAX, f64::MIN), |(l, h), e| (l.min(e), h.max(e)));
        heights.push(hi - lo);
    }
    let k = heights.len();
    if k == 0 {
        return (f64::NAN, f64::NAN, 0);
    }
    let period = (ups[k] - ups[0]) / k as f64;
    (heights.iter().sum::<f64>() / k as f64, period, k)
}

/// The free surface's elevation above `depth` \[L\] at each of the scene's gauges (2D,
/// vertical lines), sampled every `span[2]` from `span[0]` to `span[1]` \[T\]: (t, eta) per
/// gauge; a dry moment leaves no sample.
pub(super) fn surface_series(
    sim: &mut Sim,
    scene: &meshfree_core::scene::Scene,
    [from, end, every]: [f64; 3],
    depth: f64,
) -> anyhow::Result<Vec<Vec<(f64, f64)>>> {
    let dx = scene.file.discretisation.spacing;
    let lines: Vec<Vec<[f64; 3]>> = (scene.file.gauges.iter())
        .map(|g| gauge_points(g, dx, 2))
        .collect();
    let points: Vec<[f32; 3]> = (lines.iter())
        .flat_map(|l| l.iter().map(|p| p.map(|x| x as f32)))
        .collect();
    let mut eta: Vec<Vec<(f64, f64)>> = vec![Vec::new(); lines.len()];
    let mut samples = Vec::new();
    let mut t = from;
    sim.advance_to(t)?;
    while t <= end + 1e-9 {
        sim.solver.sample_points(&points, false, &mut samples);
        let mut at = 0;
        for (k, line) in lines.iter().enumerate() {
            let colour: Vec<f32> = samples[at..at + line.len()]
                .iter()
                .map(|s| s.colour)
                .collect();
            if let Some(s) = surface(line, &colour) {
                eta[k].push((sim.solver.time(), s.position[1] - depth));
            }
            at += line.len();
        }
        t += every;
        sim.advance_to(t)?;
    }
    Ok(eta)
}

struct Outcome {
    dx: f64,
    /// Per gauge: its x, the mean height and period, and how many waves.
    gauges: Vec<(f64, f64, f64, usize)>,
    run: RunInfo,
}

fn simulate(ctx: &Ctx, dx: f64) -> anyhow::Result<Outcome> {
    let text = TEXT.replace("spacing = 0.01 ", &format!("spacing = {dx} "));
    anyhow::ensure!(text != TEXT || dx == 0.01, "flume-2d's spacing line moved");
    let scene = ctx.scene(&text, "validate:flume")?;
    let setup = scene.setup()?;
    let mut sim = Sim::new(
        ctx,
        setup,
        scene.gates(),
        format!("dx = {dx} (H / dx = {})", H / dx),
    )?;
    let eta = surface_series(&mut sim, &scene, [FROM, END, EVERY], DEPTH)?;
    let gauges = (scene.file.gauges.iter().zip(&eta))
        .map(|(g, e)| {
            let (h, p, n) = waves(e);
            (g.start[0], h, p, n)
        })
        .collect();
    Ok(Outcome {
        dx,
        gauges,
        run: sim.info(),
    })
}

pub fn run(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    let dxs: &[f64] = match ctx.tier {
        Tier::Quick => &[0.02],
        Tier::Full => &[0.02, 0.01, 0.005],
    };
    let mut rows = Vec::new();
    let finest = *dxs.last().expect("one spacing");
    for &dx in dxs {
        let o = simulate(ctx, dx)?;
        for &(x, h, p, n) in &o.gauges {
            ctx.log(&format!(
                "dx = {}: gauge at x = {x}: H = {h:.4} ({:+.1} %), T = {p:.4} ({:+.2} %) over {n} waves, {:.1} s",
                o.dx,
                100.0 * (h / H - 1.0),
                100.0 * (p / T - 1.0),
                o.run.wall_seconds
            ));
            let checked = |c: Check| {
                if dx == finest {
                    c
                } else {
                    c.informational()
                }
            };
            rows.push(checked(
                Check::within(
                    NAME,
                    &format!("wave height at x = {x} m: |H / H_target - 1|"),
                    SOURCE,
                    Some(H),
                    h,
                    (h / H - 1.0).abs(),
                    0.05,
                    "literature",
                    &o.run,
                )
                .with_note("5 %: the issue's tolerance (#57); the height falls along the flume"),
            ));
            rows.push(checked(
                Check::within(
                    NAME,
                    &format!("wave period at x = {x} m: |T / T_paddle - 1|"),
                    SOURCE,
                    Some(T),
                    p,
                    (p / T - 1.0).abs(),
                    0.01,
                    "literature",
                    &o.run,
                )
                .with_note("1 %: the issue's tolerance (#57)"),
            ));
        }
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::waves;

    #[test]
    fn waves_of_a_sine_have_its_height_and_period() {
        let s: Vec<(f64, f64)> = (0..600)
            .map(|i| {
                let t = i as f64 * 0.02;
                (
                    t,
                    0.01 + 0.025 * (2.0 * std::f64::consts::PI * t / 1.2 + 0.3).sin(),
                )
            })
            .collect();
        let (h, p, n) = waves(&s);
        assert!(n >= 8, "{n}");
        assert!((h - 0.05).abs() < 0.001, "{h}");
        assert!((p - 1.2).abs() < 0.002, "{p}");
    }
}
