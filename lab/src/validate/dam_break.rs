//! Dam break: the surge front and the water height at the back wall of a collapsing column.
//!
//! References (both in `refdata/`, with their sources in the file headers):
//! * Martin & Moyce (1952), square column n^2 = 1: surge front x/a and residual height
//!   h/a at the wall against T = t sqrt(g/a) (`dambreak_martin_moyce_n1_surge_and_height.csv`).
//! * Koshizuka & Oka (1996), column L wide and 2L high: surge front Z/L against
//!   T = t sqrt(2 g / L), two independent digitisations of the experiment
//!   (`dambreak_koshizuka_oka_1996_surge_front.csv`).
//!
//! Time origin: T = 0 when the gate is removed, in both cases and both experiments. The
//! front is where the water thins below 0.03 column widths (`surge_front`, `FRONT_DEPTH`),
//! not the rightmost particle: the SPH surge ends in a sheet one or two particles thick that
//! lengthens as dx falls. SPH fronts still run ahead of the experiments; published WCSPH
//! fronts lie within about 10-15 % of them, and the two digitisations of Koshizuka & Oka
//! differ by up to 10 % late in the run. The tolerance is 15 %.

use super::check::{convergence, Check, RunInfo};
use super::ctx::{Ctx, Sim, Tier};
use super::refdata::{csv_rows, refdata};
pub use super::surge_gauges::{
    surge_cushion, surge_front, wall_fraction, wall_height, Depth, FRONT_DEPTH, WALL_DRY,
};
use crate::plot::{plot, Figure, Series};

pub const NAME: &str = "dam-break";
pub const DESCRIPTION: &str =
    "2D dam break in a closed tank (dynamic walls with their density held at >= rho0, \
c0 = 10 sqrt(2 g H), alpha = 0.02, XSPH 0.5; the gate is removed at t = 0, the time origin of \
both experiments): surge front (where the water thins below 0.03 column widths) vs Martin & Moyce \
(1952, square column) and Koshizuka & Oka (1996, column 1 x 2), water height at the back wall vs \
Martin & Moyce.";
const MM: &str = "Martin & Moyce 1952 (refdata/dambreak_martin_moyce_n1_surge_and_height.csv)";
const KO: &str = "Koshizuka & Oka 1996 experiment, two digitisations (refdata/dambreak_koshizuka_oka_1996_surge_front.csv)";

/// A column `w` wide and `h` high at the left of a closed tank `len` x `tank_h`, dynamic walls.
pub fn scene_text(dx: f64, w: f64, h: f64, len: f64, tank_h: f64) -> String {
    scene_text_walls(dx, [w, h, len, tank_h], "dynamic")
}

/// `scene_text` with `[boundary] wall_coupling = walls` ("dynamic" or "mdbc").
pub fn scene_text_walls(dx: f64, geo: [f64; 4], walls: &str) -> String {
    let [w, h, len, tank_h] = geo;
    let g = 9.81;
    let c0 = 10.0 * (2.0 * g * h).sqrt();
    let strength = 5.0 * g * h / dx;
    let margin = 3.0 * dx + 0.04;
    format!(
        r#"dimension = 2
name = "validate-dam-break"
gravity = [0.0, -{g}]

[domain]
min = [-{margin}, -{margin}]
max = [{xmax}, {ymax}]

[discretisation]
spacing = {dx}
h_factor = 1.3
kernel = "cubic-spline"

[time]
end = 2.0
output_interval = 0.02

[fluid]
density = 1000.0
sound_speed = {c0}
density_form = "continuity"
alpha = 0.02
xsph = 0.5

[boundary]
strength = {strength}
wall_coupling = "{walls}"
wall_density_floor = true

[[fluid_blocks]]
min = [0.0, 0.0]
max = [{w}, {h}]
hydrostatic = true

[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [{len}, {tank_h}]
layers = 3
open_top = false

[[walls]]
shape = "box"
min = [{w}, 0.0]
max = [{gate_x}, {gate_h}]
remove_at = 0.0
"#,
        xmax = len + margin,
        ymax = tank_h + margin,
        gate_x = w + 3.0 * dx,
        gate_h = 1.5 * h,
    )
}

/// Martin & Moyce's surge front (T = t sqrt(g/a), x/a) for the square column, where it is
/// compared: from T = 0.8 (before, it depends on how the gate opens) to `t_end`, while
/// x/a < 3.8 (the far wall of the 4 a tank).
pub fn martin_moyce_front(t_end: f64) -> Vec<(f64, f64)> {
    series(
        "dambreak_martin_moyce_n1_surge_and_height.csv",
        "surge_front",
    )
    .into_iter()
    .filter(|&(t, x)| t >= 0.8 && x < 3.8 && t <= t_end)
    .collect()
}

fn series(file: &str, key: &str) -> Vec<(f64, f64)> {
    csv_rows(refdata(file))
        .into_iter()
        .filter(|r| r[0] == key)
        .map(|r| (r[1].parse().unwrap(), r[2].parse().unwrap()))
        .collect()
}

/// Front x and wall height h (in column widths) and the surge's cushion (`cushion`, in
/// spacings) at the given normalised times.
struct Track {
    times: Vec<f64>,
    front: Vec<f64>,
    height: Vec<f64>,
    cushion: Vec<f64>,
    run: RunInfo,
}

/// Run a column `w` x `h` in a tank `len` x `tank_h`, sampling at normalised times `ts`
/// (t = T / t_scale).
fn simulate(
    ctx: &Ctx,
    dx: f64,
    geo: [f64; 4],
    t_scale: f64,
    ts: &[f64],
    walls: &str,
) -> anyhow::Result<Track> {
    let w = geo[0];
    let scene = ctx.scene(&scene_text_walls(dx, geo, walls), "validate:dam-break")?;
    let setup = scene.setup()?;
    let params = setup.params;
    let mut sim = Sim::new(ctx, setup, scene.gates(), format!("dx = {dx}"))?;
    let mut tr = Track {
        times: Vec::new(),
        front: Vec::new(),
        height: Vec::new(),
        cushion: Vec::new(),
        run: sim.info(),
    };
    let mut ts = ts.to_vec();
    ts.sort_by(f64::total_cmp);
    ts.dedup();
    for &t_norm in &ts {
        sim.advance_to(t_norm / t_scale)?;
        let ps = sim.solver.particles();
        let front = surge_front(&params, &ps, FRONT_DEPTH * w);
        let height = wall_height(&params, &ps, dx);
        tr.times.push(t_norm);
        tr.front.push(front / w);
        tr.height.push(height / w);
        tr.cushion.push(surge_cushion(&ps, dx, w, front));
    }
    tr.run = sim.info();
    Ok(tr)
}

impl Track {
    fn at(&self, v: &[f64], t: f64) -> f64 {
        let i = self
            .times
            .iter()
            .position(|&x| (x - t).abs() < 1e-9)
            .expect("sampled time");
        v[i]
    }
}

/// Worst relative error of `sim` against `reference` points: (error, T, sim, ref).
fn worst(tr: &Track, v: &[f64], reference: &[(f64, f64)]) -> (f64, f64, f64, f64) {
    let mut w = (0.0f64, f64::NAN, f64::NAN, f64::NAN);
    for &(t, r) in reference {
        let s = tr.at(v, t);
        let e = (s - r).abs() / r;
        if e >= w.0 {
            w = (e, t, s, r);
        }
    }
    w
}

pub fn run(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    let quick = ctx.tier == Tier::Quick;
    let g = 9.81f64;
    // Martin & Moyce: a = 1 column in a 4 x 2 tank. The front is compared from T = 0.8
    // (before, it depends on how the gate opens) until it nears the far wall (x/a < 3.8);
    // the wall height until the reflected wave returns (T <= 4.3; the quick tier stops at
    // T = 2.5).
    let t_mm_end = if quick { 2.5 } else { 4.3 };
    let mm_front = martin_moyce_front(t_mm_end);
    let mm_height: Vec<(f64, f64)> = series(
        "dambreak_martin_moyce_n1_surge_and_height.csv",
        "residual_height_at_wall",
    )
    .into_iter()
    .filter(|&(t, _)| t > 0.0 && t <= t_mm_end)
    .collect();
    // Koshizuka & Oka: L = 0.5 column, 1.0 high, in a 4L = 2 long tank 1.5 high; front
    // compared from T = 0.75 while Z/L < 3.8.
    let ko_text = refdata("dambreak_koshizuka_oka_1996_surge_front.csv");
    let ko_exp: Vec<(f64, f64)> = csv_rows(ko_text)
        .into_iter()
        .filter(|r| r[0].starts_with("KO1996_exp"))
        .map(|r| (r[1].parse().unwrap(), r[2].parse().unwrap()))
        .filter(|&(t, z): &(f64, f64)| t >= 0.75 && z < 3.8)
        .collect();
    let ko_mps = series(
        "dambreak_koshizuka_oka_1996_surge_front.csv",
        "KO1996_MPS_simulation_pysph",
    );

    let mm_dx: &[f64] = if quick { &[0.04] } else { &[0.04, 0.02, 0.01] };
    let ko_dx: &[f64] = if quick {
        &[0.025]
    } else {
        &[0.025, 0.0125, 0.00625]
    };
    let mut mm_runs = Vec::new();
    let mut mm_ts: Vec<f64> = mm_front.iter().chain(&mm_height).map(|p| p.0).collect();
    mm_ts.extend((1..=(t_mm_end * 10.0) as usize).map(|i| i as f64 * 0.1));
    for &dx in mm_dx {
        let tr = simulate(
            ctx,
            dx,
            [1.0, 1.0, 4.0, 2.0],
            (g / 1.0).sqrt(),
            &mm_ts,
            "dynamic",
        )?;
        ctx.log(&format!(
            "Martin & Moyce dx = {dx}: {:.1} s",
            tr.run.wall_seconds
        ));
        mm_runs.push(tr);
    }
    // mDBC walls (issue #56) beside the dynamic ones, at the finest square-column spacing.
    let mm_mdbc = {
        let dx = *mm_dx.last().expect("one spacing");
        let tr = simulate(ctx, dx, [1.0, 1.0, 4.0, 2.0], g.sqrt(), &mm_ts, "mdbc")?;
        ctx.log(&format!(
            "Martin & Moyce dx = {dx}, mDBC walls: {:.1} s",
            tr.run.wall_seconds
        ));
        tr
    };
    let mut ko_runs = Vec::new();
    for &dx in ko_dx {
        let mut ts: Vec<f64> = ko_exp.iter().map(|p| p.0).collect();
        let t_end = ko_exp.iter().map(|p| p.0).fold(0.0, f64::max);
        ts.extend((1..=(t_end * 10.0) as usize).map(|i| i as f64 * 0.1));
        let tr = simulate(
            ctx,
            dx,
            [0.5, 1.0, 2.0, 1.5],
            (2.0 * g / 0.5).sqrt(),
            &ts,
            "dynamic",
        )?;
        ctx.log(&format!(
            "Koshizuka & Oka dx = {dx}: {:.1} s",
            tr.run.wall_seconds
        ));
        ko_runs.push(tr);
    }

    // Plots: every resolution against the references.
    let png_front = "dam-break-front.png";
    let png_height = "dam-break-height.png";
    let mut s = vec![Series::points("Martin & Moyce 1952", mm_front.clone())];
    for tr in &mm_runs {
        let pts = curve(&tr.times, &tr.front);
        s.push(Series::line(
            format!("SPH square column, {}", tr.run.resolution),
            pts,
        ));
    }
    s.push(Series::line(
        format!("SPH square column, {}, mDBC walls", mm_mdbc.run.resolution),
        curve(&mm_mdbc.times, &mm_mdbc.front),
    ));
    s.push(Series::points(
        "Koshizuka & Oka 1996 (exp.)",
        ko_exp.clone(),
    ));
    s.push(Series::line(
        "Koshizuka & Oka MPS",
        ko_mps.into_iter().filter(|p| p.1 < 4.0).collect(),
    ));
    for tr in &ko_runs {
        let pts = curve(&tr.times, &tr.front);
        s.push(Series::line(
            format!("SPH 1 x 2 column, {}", tr.run.resolution),
            pts,
        ));
    }
    plot(
        &ctx.out_dir.join(png_front),
        &Figure {
            title: "Dam break: surge front",
            x_label: "T = t sqrt(g/a)  (K&O: t sqrt(2g/L))",
            y_label: "front x / a  (K&O: Z / L)",
            log_y: false,
            log_x: false,
        },
        &s,
    )?;
    let mut s = vec![Series::points("Martin & Moyce 1952", mm_height.clone())];
    for tr in &mm_runs {
        let pts = curve(&tr.times, &tr.height);
        s.push(Series::line(format!("SPH, {}", tr.run.resolution), pts));
    }
    s.push(Series::line(
        format!("SPH, {}, mDBC walls", mm_mdbc.run.resolution),
        curve(&mm_mdbc.times, &mm_mdbc.height),
    ));
    plot(
        &ctx.out_dir.join(png_height),
        &Figure {
            title: "Dam break: water height at the back wall",
            x_label: "T = t sqrt(g/a)",
            y_label: "h / a",
            log_y: false,
            log_x: false,
        },
        &s,
    )?;

    let mm = mm_runs.last().expect("one run");
    let ko = ko_runs.last().expect("one run");
    let basis = if quick { "regression" } else { "literature" };
    let (e, t, sim, r) = worst(mm, &mm.front, &mm_front);
    let (eh, th, simh, rh) = worst(mm, &mm.height, &mm_height);
    let (ek, tk, simk, rk) = worst(ko, &ko.front, &ko_exp);
    let mut rows = vec![
        Check::within(NAME, "surge front x/a, max relative error (square column)", MM, Some(r), sim, e, 0.15, "literature", &mm.run)
            .with_plot(png_front)
            .with_note(format!("worst at T = {t}; compared for 0.8 <= T <= {t_mm_end} while x/a < 3.8; front = where the water depth falls below 0.03 a (surge_front); 15 %: published WCSPH fronts lie 10-15 % from the experiment")),
        Check::within(NAME, "surge front Z/L, max relative error (1 x 2 column)", KO, Some(rk), simk, ek, if quick { 0.25 } else { 0.15 }, basis, &ko.run)
            .with_plot(png_front)
            .with_note(format!("worst at T = {tk}; both experimental digitisations (they differ by up to 10 % late in the run), T >= 0.75 while Z/L < 3.8; L = 0.5 m; front = where the water depth falls below 0.03 L")),
        Check::within(NAME, "water height at the back wall h/a, max relative error", MM, Some(rh), simh, eh, if quick { 0.15 } else { 0.10 }, basis, &mm.run)
            .with_plot(png_height)
            .with_note(format!("worst at T = {th}; height = kernel gauge at the wall, the last phi = 1/2 below the first dry point, phi < 1/4 (wall_height); the reference times carry the digitisation error (the heights were read at fixed ordinates); 10 % is our reading of published SPH comparisons, not a published bound")),
    ];
    if quick {
        // The quick tier's margins (CPU release, 2026-12-05): front 0.105 against 0.15 (a
        // literature bound, 1.4 x), the 1 x 2 column 0.184 against 0.25 (1.4 x), the height
        // 0.060 against 0.15 (2.5 x; 25 particles across the column resolve the kernel gauge).
        // Halved gravity (the time scale sqrt(a / g) then wrong by sqrt 2) fails all three
        // (0.22, 0.27, 0.23; tests/perturbed.rs).
        for row in rows.iter_mut() {
            let margin = row.tolerance / row.error;
            row.note = format!("{}; quick tier: margin {margin:.1} x", row.note);
        }
    }
    rows.extend(mdbc_rows(mm, &mm_mdbc, &mm_front, &mm_height, quick));
    if mm_runs.len() > 1 {
        let errs = |runs: &[Track],
                    v: &dyn Fn(&Track) -> &Vec<f64>,
                    reference: &[(f64, f64)]|
         -> Vec<f64> {
            runs.iter()
                .map(|tr| worst(tr, v(tr), reference).0)
                .collect()
        };
        let infos = |runs: &[Track]| runs.iter().map(|t| t.run.clone()).collect::<Vec<_>>();
        let note = "the reference is an experiment, so the error need not vanish as dx -> 0";
        rows.push(
            convergence(
                NAME,
                "the surge-front error vs Martin & Moyce",
                mm_dx,
                &errs(&mm_runs, &|t| &t.front, &mm_front),
                &infos(&mm_runs),
            )
            .with_note_append(note)
            .informational(),
        );
        rows.push(
            convergence(
                NAME,
                "the surge-front error vs Koshizuka & Oka",
                ko_dx,
                &errs(&ko_runs, &|t| &t.front, &ko_exp),
                &infos(&ko_runs),
            )
            .with_note_append(note)
            .informational(),
        );
        rows.push(
            convergence(
                NAME,
                "the wall-height error vs Martin & Moyce",
                mm_dx,
                &errs(&mm_runs, &|t| &t.height, &mm_height),
                &infos(&mm_runs),
            )
            .with_note_append(note)
            .informational(),
        );
    }
    Ok(rows)
}

/// The mDBC walls' rows beside the dynamic walls' run `dynamic` at the same spacing: the
/// front and the back-wall height (reported) and the surge's cushion (checked against half a
/// spacing's lattice row; the dynamic walls' reported).
fn mdbc_rows(
    dynamic: &Track,
    mdbc: &Track,
    front: &[(f64, f64)],
    height: &[(f64, f64)],
    quick: bool,
) -> Vec<Check> {
    let basis = if quick { "regression" } else { "literature" };
    // The surge's cushion, mean over T in [1.2, 2] (the surge runs from 1.2 a to 2.4 a).
    let cushion = |tr: &Track| {
        let v: Vec<f64> = (tr.times.iter().zip(&tr.cushion))
            .filter(|(t, c)| (1.2..=2.0).contains(*t) && c.is_finite())
            .map(|(_, c)| *c)
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let (c_m, c_d) = (cushion(mdbc), cushion(dynamic));
    let (e, t, sim, r) = worst(mdbc, &mdbc.front, front);
    let (eh, th, simh, rh) = worst(mdbc, &mdbc.height, height);
    let (e_d, _, _, _) = worst(dynamic, &dynamic.front, front);
    let (eh_d, _, _, _) = worst(dynamic, &dynamic.height, height);
    const ISSUE: &str = "the lattice's first row, 0.5 dx over the floor (issue #56)";
    vec![
        Check::within(NAME, "surge front x/a, max relative error (square column), mDBC walls", MM, Some(r), sim, e, 0.15, basis, &mdbc.run)
            .with_plot("dam-break-front.png")
            .informational()
            .with_note(format!("worst at T = {t}; reported beside the dynamic walls' {e_d:.3} at the same spacing")),
        Check::within(NAME, "water height at the back wall h/a, max relative error, mDBC walls", MM, Some(rh), simh, eh, if quick { 0.15 } else { 0.10 }, basis, &mdbc.run)
            .with_plot("dam-break-height.png")
            .informational()
            .with_note(format!("worst at T = {th}; the dynamic walls' {eh_d:.3} at the same spacing. Reported, not checked: late in the collapse (T > 2) the water's column next to the back wall stands about a spacing off it above mid-height under mDBC, and the gauge at the wall reads it low (2026-12-07, dx = 0.04: 0.22 against 0.06; issue #56)")),
        Check::within(NAME, "the surge's lowest water over the floor [dx], mDBC walls", ISSUE, Some(0.5), c_m, c_m, if quick { 0.9 } else { 0.6 }, "regression", &mdbc.run)
            .with_note(format!("mean over T in [1.2, 2] of each 0.2 a bin's lowest water particle, from x = 1.2 a to 0.4 a short of the front (surge_cushion); the dynamic walls': {c_d:.2} dx")),
        Check::within(NAME, "the surge's lowest water over the floor [dx], dynamic walls", ISSUE, Some(0.5), c_d, c_d, 0.6, "regression", &dynamic.run)
            .informational()
            .with_note("as the mDBC walls' row; dynamic walls hold the surge about a spacing off the floor"),
    ]
}

impl Check {
    fn with_note_append(mut self, more: &str) -> Check {
        if !self.note.is_empty() {
            self.note.push_str("; ");
        }
        self.note.push_str(more);
        self
    }
}

/// (time, value) points of a run's curve.
fn curve(times: &[f64], values: &[f64]) -> Vec<(f64, f64)> {
    times.iter().copied().zip(values.iter().copied()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use meshfree_core::physics::particle::{Kind, Particle};
    use meshfree_core::scene::Scene;

    /// A block of water `depth` deep on the floor from x = 0 to `x1`, on a lattice of `dx`.
    fn block(dx: f64, x1: f64, depth: f64, y0: f64) -> Vec<Particle> {
        let (nx, ny) = ((x1 / dx).round() as usize, (depth / dx).round() as usize);
        let mut ps = Vec::new();
        for i in 0..nx {
            for j in 0..ny {
                ps.push(water(dx, (i as f64 + 0.5) * dx, y0 + (j as f64 + 0.5) * dx));
            }
        }
        ps
    }

    fn water(dx: f64, x: f64, y: f64) -> Particle {
        Particle {
            kind: Kind::Fluid,
            position: [x as f32, y as f32, 0.0],
            density: 1000.0,
            mass: (1000.0 * dx * dx) as f32,
            ..Default::default()
        }
    }

    #[test]
    fn the_front_is_where_the_water_thins_below_the_depth_not_the_last_particle() {
        let dx = 0.02;
        let scene = Scene::from_toml(&scene_text(dx, 1.0, 1.0, 4.0, 2.0), "test").unwrap();
        let p = scene.setup().unwrap().params;
        let support = 2.0 * p.h as f64;
        // A column 0.2 deep to x = 1, then a sheet one particle thick riding a spacing above
        // the floor to x = 2 (the dynamic walls' stand-off), then a lone drop at x = 3.
        let mut ps = block(dx, 1.0, 0.2, 0.0);
        ps.extend(block(dx, 1.0, dx, 0.5 * dx).into_iter().map(|mut q| {
            q.position[0] += 1.0;
            q
        }));
        ps.push(water(dx, 3.0, 0.01));
        let depth = Depth::new(&p, &ps);
        // The depth integral reads the column and the sheet whatever their height.
        assert!(
            (depth.at(0.5) / 0.2 - 1.0).abs() < 0.02,
            "{}",
            depth.at(0.5)
        );
        assert!((depth.at(1.5) / dx - 1.0).abs() < 0.05, "{}", depth.at(1.5));
        let front = surge_front(&p, &ps, FRONT_DEPTH);
        assert!(front > 1.0 && front < 1.0 + support, "front {front}");
        // A shallower threshold takes the sheet in, and still not the drop.
        let sheet = surge_front(&p, &ps, 0.5 * dx);
        assert!(sheet > 2.0 - dx && sheet < 2.0 + support, "sheet {sheet}");
        // Water that has left a dry strip at the back wall still has its front.
        let shifted: Vec<Particle> = (ps.iter().copied())
            .map(|mut q| {
                q.position[0] += 0.5;
                q
            })
            .collect();
        let front_shifted = surge_front(&p, &shifted, FRONT_DEPTH);
        assert!(
            (front_shifted - front - 0.5).abs() < 1e-3,
            "{front_shifted} vs {front}"
        );
        assert_eq!(surge_front(&p, &[], FRONT_DEPTH), 0.0);
    }

    /// The back wall's gauge sees through a band of the column that has thinned at the wall
    /// (phi between `WALL_DRY` and 1/2) and does not count a drop or a film above a gap.
    #[test]
    fn the_wall_height_sees_through_a_thin_band_and_not_above_a_gap() {
        let dx = 0.02;
        let scene = Scene::from_toml(&scene_text(dx, 1.0, 1.0, 4.0, 2.0), "test").unwrap();
        let p = scene.setup().unwrap().params;
        let support = 2.0 * p.h as f64;
        let column = block(dx, 0.4, 0.4, 0.0);
        let full = wall_height(&p, &column, dx);
        assert!((full - 0.4).abs() < 0.5 * dx, "{full}");
        // Two rows of the column, 0.3 up, keep one particle in three within the support.
        let band = |q: &Particle| (q.position[1] as f64 - 0.3).abs() < dx;
        let thinned: Vec<Particle> = (column.iter().enumerate())
            .filter(|(i, q)| !(band(q) && (q.position[0] as f64) < support && i % 3 != 0))
            .map(|(_, q)| *q)
            .collect();
        let phi = wall_fraction(&p, &thinned);
        let dip = (0..=40)
            .map(|k| phi(0.27 + 0.002 * k as f64))
            .fold(f64::INFINITY, f64::min);
        // The case this gauge is for: 1/2 alone would stop in the band.
        assert!(dip > WALL_DRY && dip < 0.5, "the band reads {dip}");
        let height = wall_height(&p, &thinned, dx);
        assert!((height - full).abs() < 0.1 * dx, "{height} vs {full}");
        // A drop at the wall, and a film along it, above a gap wider than the support.
        let mut above = column.clone();
        above.push(water(dx, 0.5 * dx, 0.4 + 1.5 * support));
        above.extend(block(dx, 0.1, 3.0 * dx, 0.4 + 3.0 * support));
        let height = wall_height(&p, &above, dx);
        assert!((height - full).abs() < 0.1 * dx, "{height} vs {full}");
        // With no gap, water on top of the column counts.
        let mut taller = column;
        taller.extend(block(dx, 0.1, 3.0 * dx, 0.4));
        let height = wall_height(&p, &taller, dx);
        assert!(height > full + 2.0 * dx, "{height} vs {full}");
    }

    /// A state caught between two health checks of a blow-up (a particle flung to 1e30, one
    /// at NaN, a NaN volume) still has a front, and the scan ends: it hung the stability
    /// map of the forward Euler with the summation density.
    #[test]
    fn a_blown_up_state_has_a_front_and_the_scan_ends() {
        let dx = 0.02;
        let scene = Scene::from_toml(&scene_text(dx, 1.0, 1.0, 4.0, 2.0), "test").unwrap();
        let p = scene.setup().unwrap().params;
        let mut ps = block(dx, 1.0, 0.2, 0.0);
        let clean = surge_front(&p, &ps, FRONT_DEPTH);
        ps.push(water(dx, 1e30, 0.1));
        ps.push(water(dx, f64::NAN, 0.1));
        assert_eq!(surge_front(&p, &ps, FRONT_DEPTH), clean);
        // Only water far away, no column: no front.
        assert_eq!(surge_front(&p, &ps[ps.len() - 2..], FRONT_DEPTH), 0.0);
        let mut nan = water(dx, 0.5, 0.1);
        nan.density = f32::NAN;
        ps.push(nan);
        let front = surge_front(&p, &ps, FRONT_DEPTH);
        assert!((0.0..=1.0 + 2.0 * p.h as f64).contains(&front), "{front}");
        // The back wall's gauge, with a NaN volume beside the wall, ends too.
        let mut wall = block(dx, 0.2, 0.2, 0.0);
        wall[0].density = f32::NAN;
        let height = wall_height(&p, &wall, dx);
        assert!((0.0..=0.2).contains(&height), "{height}");
    }
}
