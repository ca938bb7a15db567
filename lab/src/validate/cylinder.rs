//! Flow past a circular cylinder at Re = 100 with a small blockage (issue #6): a periodic
//! 40 x 24 channel (blockage D / H = 0.083) held at U by an inflow band, Re set by the
//! Morris viscosity. Strouhal number (DFT peak of the lift, `meshfree_core::measure::monitor`) against
//! Roshko (1954) and Williamson (1988), mean drag against the published Re 100 values
//! (refdata/cylinder_flow_reference.json, cylinder_strouhal_vs_Re.csv).
//!
//! Quick tier: D / dx = 5, t U / D = 3 (about 10 s on the CPU): the drag only, a regression
//! bound 1.5 x today's error (no Strouhal number: nothing sheds by t U / D = 3). Full tier (for the GPU, about 1e10 particle-steps): D / dx = 5, 10, 20 to
//! t U / D = 120, each started with a small antisymmetric kick (`kick`) so the shedding
//! starts within t U / D ~ 30 instead of growing from round-off; St and Cd at every
//! resolution, the finest against the literature, and the observed order of convergence
//! of both (`check::convergence`). `cylinder_onset.rs` reuses `simulate` at other Re.
//!
//! The full tier also measures the void metric (`meshfree_core::measure::voids`: empty cells of
//! side dx in the fluid region, the largest empty circle in dx) from a read-back every
//! `VOID_EVERY_UD`, and compares St, Cd and the rms lift with the unconfined values after
//! the blockage correction of Allen & Vincenti (1944) (`blockage_epsilon`).
//!
//! Both cases run the confined-flow scheme (`confined`): particle shifting 0.2, a
//! background pressure of 2 q, Morris's no-slip walls and a start ramped over 2 D / U (6 q,
//! dynamic walls and an impulsive start until 2026-11-28). Without shifting and a background
//! pressure the near wake tears where its pressure goes
//! negative and the disordered particles dissipate like a fluid of about twice the
//! viscosity: at D / dx = 20 the lift was a fifth of the expected one and the onset sweep
//! could not tell Re 35 from Re 70 (docs/reference/accuracy.md, "Cylinder, Re 100"). The speed-vs-accuracy
//! chart keeps the solver's defaults.

use super::check::{convergence, Check, RunInfo};
use super::ctx::{Ctx, Sim, Tier};
use super::refdata::{csv_rows, refdata};
use crate::plot::{plot, Figure, Series};
use meshfree_core::measure::monitor::{band_rms, BluffBody, Coefficients, ForceSample, BAND_REL};
use meshfree_core::measure::voids::{VoidMeter, VoidSummary};
use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::scheme::NoSlip;
use meshfree_core::scene::Scene;

pub const NAME: &str = "cylinder";
pub const DESCRIPTION: &str = "Flow past a cylinder, Re = 100, D = 2, U = 1, rho0 = 1, c0 = 10, periodic \
40 x 24 channel (blockage 0.083) held at U by an inflow band, laminar viscosity nu = U D / Re, no artificial \
viscosity, summation density, the band 10 D upstream of the cylinder, particle shifting 0.2, background pressure 2 q, Morris's no-slip walls and a start ramped over \
2 D / U (confined flow): Strouhal number and mean drag against Roshko / Williamson and published Re 100 \
values, and (full tier) St, Cd and rms Cl corrected for the blockage (Allen & Vincenti 1944) and the largest void in the \
wake; full tier at D / dx = 5, 10, 20 with the observed order of convergence.";

pub const RE: f64 = 100.0;
pub const U: f64 = 1.0;
pub const D: f64 = 2.0;
pub const H: f64 = 24.0;
/// [L] the cylinder's centre.
const XC: f64 = 10.0;
const YC: f64 = H / 2.0;

/// Full tier: the resolutions D / dx (40 and 24 are multiples of each dx) and the run
/// length t U / D (about 40 % start-up and growth, then ~8 shedding periods of 6 D / U).
const FULL_D_OVER_DX: [f64; 3] = [5.0, 10.0, 20.0];
const FULL_T_END_UD: f64 = 120.0;
/// Full tier: lift samples every 0.125 D / U (~48 per shedding period).
pub const SAMPLE_UD: f64 = 0.125;
/// Full tier: the kick's peak cross-flow speed, as a fraction of U.
pub const KICK: f64 = 0.2;
/// [-] The particle shifting coefficient of the cylinder cases (`[fluid] shifting`).
pub const SHIFTING: f64 = 0.2;
/// [rho0 U^2 / 2] The background pressure of the cylinder cases (`[fluid]
/// background_pressure`): above the wake's lowest pressure (Cp ~ -1.5 behind the cylinder,
/// lower in the shed vortices' cores). 6 q until 2026-11-28 damped the shedding (rms Cl_u
/// -57 %); 2 q keeps voids under 2 dx with the ramped start (`RAMP_UD`), where an
/// impulsive start tears the fluid at the shoulders (potential flow's Cp = -3; issue #23,
/// docs/journal/2026-11-27-wake.md).
pub const BACKGROUND_PRESSURE_Q: f64 = 2.0;
/// [D / U] The start's ramp (`[inflow] ramp`): the fluid from rest to U over this time.
pub const RAMP_UD: f64 = 2.0;

/// The confined-flow scheme the cylinder cases run with: particle shifting, a background
/// pressure (no free surface here), Morris's no-slip walls (the zero-velocity dynamic
/// walls' partial slip under-drags by ~8 %) and a ramped start.
pub fn confined(s: &mut Scene) {
    s.file.fluid.shifting = SHIFTING;
    s.file.fluid.background_pressure = BACKGROUND_PRESSURE_Q * 0.5 * s.file.fluid.density * U * U;
    if let Some(b) = s.file.boundary.as_mut() {
        b.no_slip = NoSlip::Morris;
    }
    if let Some(i) = s.file.inflow.as_mut() {
        i.ramp = RAMP_UD * D / U;
    }
}

/// [D] How far upstream of the cylinder's centre the inflow band ends, across the periodic
/// end (the band [29, 30) of the 40-long channel, the cylinder at x = 10, 9.5 D of wake
/// before the band). With the band 4.5 D upstream (until 2026-11-28) it held the flow at U
/// where the cylinder still slows it, and St_u read +5.6 % (2 q, Morris walls, ramped);
/// 10 D upstream, +3.6 %, and 60 long, +2.8 % (issue #23).
pub const BAND_UPSTREAM_D: f64 = 10.0;
/// [L] the channel's length.
const L: f64 = 40.0;

/// The scene at spacing `dx` (40 and 24 must be multiples of it) and Reynolds number `re`.
pub fn scene_text(dx: f64, t_end: f64, re: f64) -> String {
    format!(
        r#"dimension = 2
name = "validate-cylinder"

[domain]
min = [0.0, 0.0]
max = [{L}, {H}]
periodic = [true, true]

[discretisation]
spacing = {dx:e}

[time]
end = {t_end:e}
output_interval = 1.0

[fluid]
density = 1.0
sound_speed = 10.0
density_form = "summation"
viscosity = {nu:e}

[boundary]
strength = {c0:e}
wall_coupling = "dynamic"

[[fluid_blocks]]
min = [0.0, 0.0]
max = [{L}, {H}]
velocity = [{U}, 0.0]

[[walls]]
shape = "cylinder"
center = [{XC}, {YC}]
radius = {r}
layers = 3

[inflow]
axis = "x"
min = {band_min:e}
max = {band_max:e}
velocity = [{U}, 0.0]
"#,
        nu = U * D / re,
        c0 = 5.0 * 0.5 * U * U / dx,
        r = D / 2.0,
        band_min = XC - BAND_UPSTREAM_D * D + L - 1.0,
        band_max = XC - BAND_UPSTREAM_D * D + L,
    )
}

/// The scene `simulate` starts from, before its `edit`: at `D / dx`, `re` and to
/// `t_end_ud` (in D / U).
pub fn scene(d_over_dx: f64, re: f64, t_end_ud: f64) -> anyhow::Result<Scene> {
    let text = scene_text(D / d_over_dx, t_end_ud * D / U, re);
    Ok(Scene::from_toml(&text, "validate:cylinder")?)
}

/// An antisymmetric start: the fluid gets a cross-flow velocity
/// v = amplitude U exp(-|x - x0|^2 / (D / 2)^2), x0 one diameter behind the cylinder's
/// rear on the wake axis. v is even in y - yc, the symmetry of the shedding mode (the
/// mirror-symmetric steady wake has v odd), so the kick seeds the mode that grows above
/// Re_c and decays below it, instead of waiting for round-off to break the symmetry.
pub fn kick(particles: &mut [meshfree_core::physics::particle::Particle], amplitude: f64) {
    let (x0, y0, w) = (XC + 1.5 * D, YC, 0.5 * D);
    for p in particles.iter_mut().filter(|p| p.kind == Kind::Fluid) {
        let r2 = (p.position[0] as f64 - x0).powi(2) + (p.position[1] as f64 - y0).powi(2);
        p.velocity[1] = (amplitude * U * (-r2 / (w * w)).exp()) as f32;
    }
}

/// Full tier: the void metric every this many D / U (a read-back of the particles each).
pub const VOID_EVERY_UD: f64 = 1.0;

/// Run the cylinder at `D / dx` and `re` to `t_end_ud` (in D / U), with the kick
/// `kick_amplitude` (0: none), sampling the force every `sample_ud` (in D / U); the scene
/// is changed by `edit` (and revalidated) first. With `voids`, also the void metric every
/// `VOID_EVERY_UD` (its read-backs count in the wall time).
#[allow(clippy::too_many_arguments)]
pub fn simulate(
    ctx: &Ctx,
    d_over_dx: f64,
    re: f64,
    t_end_ud: f64,
    sample_ud: f64,
    kick_amplitude: f64,
    edit: &dyn Fn(&mut Scene),
    voids: bool,
) -> anyhow::Result<(Vec<ForceSample>, RunInfo, Option<VoidSummary>)> {
    let mut scene = scene(d_over_dx, re, t_end_ud)?;
    edit(&mut scene);
    scene.revalidate()?;
    ctx.perturb(&mut scene)?;
    let group = scene.wall_group(0);
    let mut setup = scene.setup()?;
    if kick_amplitude != 0.0 {
        kick(&mut setup.particles, kick_amplitude);
    }
    let meter = voids.then(|| VoidMeter::new(&scene.file, &setup.particles));
    let mut void_summary = meter.as_ref().map(|m| VoidSummary {
        region_cells: m.region_cells(),
        ..VoidSummary::default()
    });
    let mut sim = Sim::new(
        ctx,
        setup,
        scene.gates(),
        format!("Re {re}, D / dx = {d_over_dx}"),
    )?;
    let q = 0.5 * 1.0 * U * U * D;
    let mut samples = Vec::new();
    let n = (t_end_ud / sample_ud).round() as usize;
    let void_every = (VOID_EVERY_UD / sample_ud).round().max(1.0) as usize;
    for k in 0..=n {
        sim.advance_to(k as f64 * sample_ud * D / U)?;
        if let (Some(m), Some(sum)) = (&meter, void_summary.as_mut()) {
            if k % void_every == 0 {
                let t = sim.solver.time();
                sum.add(m.measure(&sim.solver.particles(), t));
            }
        }
        let f = sim.solver.wall_forces(&[group])[0];
        samples.push(ForceSample {
            t: sim.solver.time(),
            force: f,
            cd: f[0] / q,
            cl: f[1] / q,
        });
    }
    let run = sim.info();
    ctx.log(&format!(
        "Re {re}, D / dx = {d_over_dx}: {} particles, {:.1} s",
        run.particles, run.wall_seconds
    ));
    if let Some(v) = &void_summary {
        ctx.log(&format!(
            "  voids: largest {:.2} dx at t U / D = {:.1}, empty cells max {:.4} mean {:.4}",
            v.largest_void_dx,
            v.largest_void_time * U / D,
            v.max_empty_fraction,
            v.mean_empty_fraction
        ));
    }
    Ok((samples, run, void_summary))
}

/// Allen & Vincenti's (1944) blockage correction of a 2D body in a closed channel (as in
/// Barlow, Rae & Pope, Low-Speed Wind Tunnel Testing, 1999, ch. 10): the flow past the
/// body is faster than U by epsilon = solid blockage + wake blockage,
/// eps = (pi^2 / 12) (D / H)^2 + (D / H) Cd / 4 (the first the doublet's images at every
/// H, the same row of images a periodic channel has). The unconfined equivalents are then
/// St_u = St / (1 + eps) (the frequency unchanged) and Cd_u = Cd / (1 + eps)^2, rms Cl_u =
/// rms Cl / (1 + eps)^2 (the dynamic pressure). Meant for small blockage (here 0.083:
/// eps = 0.034).
pub fn blockage_epsilon(blockage: f64, cd: f64) -> f64 {
    std::f64::consts::PI.powi(2) / 12.0 * blockage * blockage + blockage * cd / 4.0
}

/// The maximum void the wake may show (issue #23): 2 dx, one missing particle.
pub const MAX_VOID_DX: f64 = 2.0;

/// The centred moving average of `x` over `2 half + 1` samples (fewer at the ends): it
/// takes out the sample-to-sample SPH force noise (acoustic waves of the weakly
/// compressible start; rms Cl ~0.5 sample to sample at D / dx = 5) and keeps the shedding
/// (~48 samples a period at `SAMPLE_UD`).
pub fn smooth(x: &[f64], half: usize) -> Vec<f64> {
    (0..x.len())
        .map(|i| {
            let (a, b) = (i.saturating_sub(half), (i + half + 1).min(x.len()));
            x[a..b].iter().sum::<f64>() / (b - a) as f64
        })
        .collect()
}

/// Half-width of the smoothing of the lift before its DFT and rms, in samples of
/// `SAMPLE_UD`: 9 samples = 1.125 D / U, which keeps 95 % of the amplitude at St 0.165
/// (sin(pi St w) / (pi St w)) and takes out the force noise.
pub const SMOOTH_HALF: usize = 4;

/// The monitor summary (second half): St the DFT peak of the lift smoothed by `smooth`
/// (which takes out the force noise, rms Cl ~0.5 sample to sample at D / dx = 5), the rms lift that of
/// the raw lift within `BAND_REL` of the shedding frequency (`band_rms`, as
/// `MonitorSummary::of` takes it about the raw lift's own peak), mean Cd and Cl those of
/// the record. The rms of
/// the smoothed lift, used until 2026-11-27, was low by the moving average's gain
/// at St (0.93 at St 0.18: issue #23) and high by the noise the average lets through
/// (raw rms Cl 0.24 when the shedding's is 0.12, D / dx = 20); without a dominant
/// frequency the rms stays that of the smoothed lift.
pub fn summary(samples: &[ForceSample]) -> Coefficients {
    summary_for(samples, U, D, H)
}

/// `summary` of any cylinder's force record (e.g. a built-in vortex street's forces.csv):
/// reference speed `u`, diameter `d`, periodic spacing (channel height) `h`, samples at even
/// intervals. The lift is smoothed over the same span in D / U as `summary`'s
/// (2 `SMOOTH_HALF` + 1 samples of `SAMPLE_UD`: the half-width scaled to the record's
/// sample interval, at least 1 sample).
pub fn summary_for(samples: &[ForceSample], u: f64, d: f64, h: f64) -> Coefficients {
    let interval_ud = match samples {
        [a, .., b] => (b.t - a.t) / (samples.len() - 1) as f64 * u / d,
        _ => SAMPLE_UD,
    };
    let half = ((SMOOTH_HALF as f64 * SAMPLE_UD / interval_ud).round() as usize).max(1);
    let raw: Vec<f64> = samples.iter().map(|s| s.cl).collect();
    let smoothed: Vec<ForceSample> = samples
        .iter()
        .zip(smooth(&raw, half))
        .map(|(s, cl)| ForceSample { cl, ..*s })
        .collect();
    let body = BluffBody {
        velocity: u,
        length: d,
        blockage_ratio: d / h,
    };
    let mut s = Coefficients::of(&smoothed, body);
    if let Some(st) = s.strouhal {
        let (t, cl): (Vec<f64>, Vec<f64>) = samples
            .iter()
            .filter(|x| x.t >= s.window_start)
            .map(|x| (x.t, x.cl))
            .unzip();
        s.rms_cl = band_rms(&t, &cl, st * u / d, BAND_REL);
    }
    s
}

/// Cd and Cl against t U / D for t U / D >= `from_ud`, one pair of series per labelled
/// run, both smoothed by `smooth` with half-width `half` (0: raw).
pub fn force_series(runs: &[(String, &[ForceSample])], from_ud: f64, half: usize) -> Vec<Series> {
    let suffix = if half > 0 { " (smoothed)" } else { "" };
    let mut out = Vec::new();
    for (label, samples) in runs {
        let cd: Vec<f64> = samples.iter().map(|x| x.cd).collect();
        let cl: Vec<f64> = samples.iter().map(|x| x.cl).collect();
        for (name, y) in [("Cd", smooth(&cd, half)), ("Cl", smooth(&cl, half))] {
            out.push(Series::line(
                format!("{name} {label}{suffix}"),
                samples
                    .iter()
                    .zip(y)
                    .filter(|(x, _)| x.t * U / D >= from_ud)
                    .map(|(x, y)| (x.t * U / D, y))
                    .collect(),
            ));
        }
    }
    out
}

// Published mean Cd at Re 100 (Liu et al. 1998 1.35, Park et al. 1998 1.33, Braza
// et al. 1986 1.364): the reference file's band 1.31-1.37, centre 1.34.
pub const CD_REF: f64 = 1.34;
/// The published rms lift at Re 100 (amplitude 0.33-0.34 / sqrt 2, the reference file's
/// band 0.226-0.247).
pub const CL_RMS_REF: f64 = 0.235;
const CD_SOURCE: &str = "Re 100 mean Cd 1.31-1.37 (Liu, Zheng & Sung 1998; Park, Kwon & Choi 1998; refdata/cylinder_flow_reference.json)";

/// Roshko's and Williamson's St at `re` from refdata/cylinder_strouhal_vs_Re.csv.
pub fn strouhal_fits(re: u32) -> (f64, f64) {
    let row = csv_rows(refdata("cylinder_strouhal_vs_Re.csv"))
        .into_iter()
        .find(|r| r[0] == re.to_string())
        .unwrap_or_else(|| panic!("Re {re} in cylinder_strouhal_vs_Re.csv"));
    (
        row[1].parse().expect("Roshko St"),
        row[2].parse().expect("Williamson St"),
    )
}

/// For `meshfree chart`: |St / St_Williamson(100) - 1| of a kicked run at `D / dx` to
/// `t_end_ud`, the scene changed by `edit`; an error when the lift shows no shedding.
pub fn strouhal_error(
    ctx: &Ctx,
    d_over_dx: f64,
    t_end_ud: f64,
    edit: &dyn Fn(&mut Scene),
) -> anyhow::Result<(f64, RunInfo)> {
    let (samples, run, _) = simulate(ctx, d_over_dx, RE, t_end_ud, SAMPLE_UD, KICK, edit, false)?;
    let s = summary(&samples);
    let st = s
        .strouhal
        .ok_or_else(|| anyhow::anyhow!("no shedding: the lift has no dominant frequency"))?;
    Ok(((st / strouhal_fits(100).1 - 1.0).abs(), run))
}

pub fn run(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    if ctx.tier == Tier::Quick {
        return quick(ctx);
    }
    let (roshko, williamson) = strouhal_fits(100);
    let mut rows = Vec::new();
    let mut all: Vec<(Vec<ForceSample>, RunInfo, Coefficients)> = Vec::new();
    let mut voids: Vec<VoidSummary> = Vec::new();
    for &n in &FULL_D_OVER_DX {
        let (samples, run, v) =
            simulate(ctx, n, RE, FULL_T_END_UD, SAMPLE_UD, KICK, &confined, true)?;
        let s = summary(&samples);
        ctx.log(&format!("{s}"));
        all.push((samples, run, s));
        voids.push(v.unwrap_or_default());
    }
    let png = "cylinder.png";
    let labelled: Vec<(String, &[ForceSample])> = FULL_D_OVER_DX
        .iter()
        .zip(&all)
        .map(|(n, a)| (format!("D/dx {n}"), a.0.as_slice()))
        .collect();
    plot(
        &ctx.out_dir.join(png),
        &Figure {
            title: "Flow past a cylinder, Re = 100: smoothed drag and lift, t U / D >= 5",
            x_label: "t U / D",
            y_label: "Cd, Cl",
            log_x: false,
            log_y: false,
        },
        &force_series(&labelled, 5.0, SMOOTH_HALF),
    )?;
    // Every resolution reported; the finest checked against the literature.
    let last = all.len() - 1;
    for (k, (_, run, s)) in all.iter().enumerate() {
        let st = s.strouhal.unwrap_or(f64::NAN);
        let finest = k == last;
        let window = s.window_start * U / D;
        // The unconfined equivalents (Allen & Vincenti 1944).
        let eps = blockage_epsilon(D / H, s.mean_cd);
        let st_u = st / (1.0 + eps);
        let cd_u = s.mean_cd / (1.0 + eps).powi(2);
        let cl_u = s.rms_cl / (1.0 + eps).powi(2);
        let corrected =
            format!("corrected for blockage 0.083 (Allen & Vincenti 1944: eps = {eps:.4})");
        let mark = |row: Check, note: &str| {
            if finest {
                row.with_note(note.to_string())
            } else {
                row.informational()
                    .with_note("a coarser resolution of the study")
            }
        };
        for (name, st_ref) in [("Roshko 1954", roshko), ("Williamson 1988", williamson)] {
            let row = Check::within(
                NAME,
                &format!("Strouhal number (DFT of the smoothed lift, t U / D >= {window:.0}) vs {name}: |St / St_fit - 1|"),
                &format!("{name} fit at Re 100 (refdata/cylinder_strouhal_vs_Re.csv)"),
                Some(st_ref),
                st,
                (st / st_ref - 1.0).abs(),
                0.10,
                "literature",
                run,
            )
            .with_plot(png);
            rows.push(mark(row, "10 %: the reference file recommends 5 % for blockage < 5 % and D / dx >= 40; here 0.083 and 20"));
        }
        let row = Check::within(
            NAME,
            &format!("St {corrected} vs Williamson 1988: |St_u / 0.1643 - 1|"),
            "Williamson 1988 fit at Re 100 (refdata/cylinder_strouhal_vs_Re.csv); issue #23's target 5 %",
            Some(williamson),
            st_u,
            (st_u / williamson - 1.0).abs(),
            0.05,
            "literature",
            run,
        );
        rows.push(mark(row, "issue #23: 5 % after the blockage correction"));
        let row = Check::within(
            NAME,
            &format!("mean Cd over t U / D >= {window:.0}: |Cd / 1.34 - 1|"),
            CD_SOURCE,
            Some(CD_REF),
            s.mean_cd,
            (s.mean_cd / CD_REF - 1.0).abs(),
            0.15,
            "literature",
            run,
        );
        rows.push(mark(row, "the reference file recommends 10 % at blockage < 5 %; blockage 0.083 raises Cd by a few per cent"));
        let row = Check::within(
            NAME,
            &format!("mean Cd {corrected}: |Cd_u / 1.34 - 1|"),
            CD_SOURCE,
            Some(CD_REF),
            cd_u,
            (cd_u / CD_REF - 1.0).abs(),
            0.10,
            "literature",
            run,
        );
        rows.push(mark(row, "issue #23: 10 % after the blockage correction"));
        let row = Check::within(
            NAME,
            &format!("rms Cl (the raw lift within [0.5, 1.5] of the shedding frequency) over t U / D >= {window:.0} {corrected}: |rms Cl_u / 0.235 - 1|"),
            "Re 100 Cl amplitude 0.32-0.35, rms 0.23-0.25 (Liu, Zheng & Sung 1998; Park, Kwon & Choi 1998; refdata/cylinder_flow_reference.json)",
            Some(CL_RMS_REF),
            cl_u,
            (cl_u / CL_RMS_REF - 1.0).abs(),
            0.10,
            "literature",
            run,
        );
        rows.push(mark(
            row,
            &format!("issue #23: 10 %; uncorrected rms Cl {:.4}", s.rms_cl),
        ));
        let v = &voids[k];
        let row = Check::within(
            NAME,
            &format!(
                "largest void over the run (empty circle centred in the fluid region, every {VOID_EVERY_UD} D / U), in dx"
            ),
            "issue #23: no void larger than 2 dx (one missing particle reads 2.0, a square lattice 1.41)",
            Some(0.0),
            v.largest_void_dx,
            v.largest_void_dx,
            MAX_VOID_DX,
            "regression",
            run,
        );
        rows.push(mark(
            row,
            &format!("at t U / D = {:.1}", v.largest_void_time * U / D),
        ));
        rows.push(
            Check::within(
                NAME,
                "largest share of the fluid region's cells (side dx) with no particle (reported)",
                "a square lattice: 0",
                Some(0.0),
                v.max_empty_fraction,
                v.max_empty_fraction,
                0.2,
                "regression",
                run,
            )
            .informational()
            .with_note(format!("mean over the run {:.4}", v.mean_empty_fraction)),
        );
    }
    // Observed order against the published values: informational, since the limit of this
    // configuration (blockage 0.083, a periodic channel) is not the unconfined value.
    let dxs: Vec<f64> = FULL_D_OVER_DX.iter().map(|n| D / n).collect();
    let runs: Vec<RunInfo> = all.iter().map(|a| a.1.clone()).collect();
    let st_err: Vec<f64> = all
        .iter()
        .map(|a| (a.2.strouhal.unwrap_or(f64::NAN) / williamson - 1.0).abs())
        .collect();
    let cd_err: Vec<f64> = all
        .iter()
        .map(|a| (a.2.mean_cd / CD_REF - 1.0).abs())
        .collect();
    let note = "against the unconfined literature value; blockage 0.083 shifts the limit by a few per cent, so informational";
    for (quantity, errors) in [
        ("|St / St_Williamson - 1|", &st_err),
        ("|Cd / 1.34 - 1|", &cd_err),
    ] {
        let row = convergence(NAME, quantity, &dxs, errors, &runs);
        let errs = row.note.clone();
        rows.push(row.informational().with_note(format!("{errs}; {note}")));
    }
    Ok(rows)
}

/// D / dx = 5 to t U / D = 3, no kick: the start-up drag, a regression bound.
fn quick(ctx: &Ctx) -> anyhow::Result<Vec<Check>> {
    let (samples, run, _) = simulate(ctx, 5.0, RE, 3.0, 0.05, 0.0, &confined, false)?;
    let body = BluffBody {
        velocity: U,
        length: D,
        blockage_ratio: D / H,
    };
    let s = Coefficients::of(&samples, body);
    // Only what is checked: at t U / D = 3 the wake has not started to shed, so the lift's
    // "Strouhal number" would be noise (the full tier measures it to t U / D = 120).
    ctx.log(&format!(
        "mean Cd {:.4} over t U / D >= {:.1}, {:.1} s",
        s.mean_cd,
        s.window_start * U / D,
        run.wall_seconds
    ));
    let png = "cylinder.png";
    plot(
        &ctx.out_dir.join(png),
        &Figure {
            title: "Flow past a cylinder, Re = 100: drag and lift",
            x_label: "t U / D",
            y_label: "Cd, Cl",
            log_x: false,
            log_y: false,
        },
        &force_series(&[("D/dx 5".into(), &samples)], 0.0, 0),
    )?;
    // The ramped start's drag, early: a regression bound 1.5 x today's error (the start-up
    // drag is not the shedding mean of the reference, so no claim of accuracy).
    let err = (s.mean_cd / CD_REF - 1.0).abs();
    Ok(vec![Check::within(
        NAME,
        &format!(
            "mean Cd over t U / D in [{:.1}, 3] (start-up): |Cd / 1.34 - 1|",
            s.window_start * U / D
        ),
        CD_SOURCE,
        Some(CD_REF),
        s.mean_cd,
        err,
        0.16,
        "regression",
        &run,
    )
    .with_plot(png)
    .with_note(
        "D / dx = 5, before shedding starts: the drag only (no Strouhal number: nothing sheds by t U / D = 3). \
         0.16 is 1.5 x the 0.106 measured on the CPU (2026-12-05; 0.066 on the H200, 2026-11-28): 1.13 < Cd < 1.55; \
         a doubled viscosity gives 0.22, a halved sound speed 0.49, a halved inflow velocity 0.74 (tests/perturbed.rs)",
    )])
}
