//! Issue #23's diagnosis of the cylinder's weak lift: runs `validate`'s cylinder
//! (`cylinder::simulate`, Re 100, kicked) in variants of the confined scheme, one after
//! another, and writes each run's force history (`<name>.csv`: t U / D, Cd, Cl) and its
//! statistics over the second half (`cylinder::summary`: St, mean Cd, the rms lift in the
//! band around St; and the raw rms Cl), and the smoothed lift's rms per quarter of the
//! record, which shows whether the shedding has saturated; and the void metric every
//! `cylinder::VOID_EVERY_UD` (`meshfree_core::measure::voids`).
//!
//! `cargo run --release -p meshfree-lab --example cylinder_lift -- OUT_DIR BACKEND
//! NAME:D_OVER_DX:T_END_UD:VARIANT ...`, VARIANT `confined` (validate's scheme) or
//! tokens joined by `-` that change it: `morris` (Morris's no-slip walls), `bgX`
//! (background pressure X q, e.g. `bg1.5`), `hY` (the channel Y high instead of 24: the
//! blockage D / Y; the cylinder keeps its place, the y axis being periodic), `lX` (the
//! channel X long instead of 40, the 1-long inflow band moved to end 10 D upstream of the
//! cylinder, across the periodic end, leaving X - 21 of wake behind the cylinder's centre),
//! `rX` (a start ramped over X D / U, `[inflow] ramp`: the fluid from rest).
//!
//! Per run it also prints the blockage-corrected St, Cd and rms Cl (Allen & Vincenti, as
//! `validate`) against issue #23's targets, and `SCORE name s`, s the largest of
//! |St_u / St_W - 1| / 0.05, |Cd_u / 1.34 - 1| / 0.10, |Cl_u / 0.235 - 1| / 0.10 and
//! largest void / 2 dx: s <= 1 meets every target.

use meshfree_core::backend::BackendChoice;
use meshfree_core::measure::monitor::{BluffBody, Coefficients};
use meshfree_core::scene::scheme::NoSlip;
use meshfree_core::scene::Scene;
use meshfree_lab::validate::cylinder::{
    self, blockage_epsilon, confined, CD_REF, CL_RMS_REF, D, KICK, MAX_VOID_DX, SAMPLE_UD, U,
};
use meshfree_lab::validate::{Ctx, Tier};
use std::io::Write;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = std::path::PathBuf::from(&args[0]);
    std::fs::create_dir_all(&out)?;
    let backend = match args[1].as_str() {
        "cuda" => BackendChoice::Cuda,
        _ => BackendChoice::Cpu,
    };
    let ctx = Ctx {
        tier: Tier::Full,
        backend,
        courant: None,
        integrator: None,
        sets: &[],
        out_dir: &out,
        verbose: true,
        edit: None,
    };
    for spec in &args[2..] {
        let f: Vec<&str> = spec.split(':').collect();
        let (name, dod, t_end, variant) = (f[0], f[1].parse::<f64>()?, f[2].parse::<f64>()?, f[3]);
        let edit = move |s: &mut Scene| {
            confined(s);
            for token in variant.split('-') {
                let num = |prefix: &str| token.strip_prefix(prefix)?.parse::<f64>().ok();
                if token == "morris" {
                    if let Some(b) = s.file.boundary.as_mut() {
                        b.no_slip = NoSlip::Morris;
                    }
                } else if let Some(q) = num("bg") {
                    s.file.fluid.background_pressure = q * 0.5 * s.file.fluid.density * U * U;
                } else if let Some(h) = num("h") {
                    s.file.domain.max[1] = h;
                    s.file.fluid_blocks[0].max[1] = h;
                } else if let Some(l) = num("l") {
                    // The band [b - 1, b) ends 10 D upstream of the cylinder (at x = 10)
                    // across the periodic end: b = l + 10 - 10 D.
                    let b = l + 10.0 - 10.0 * D;
                    s.file.domain.max[0] = l;
                    s.file.fluid_blocks[0].max[0] = l;
                    if let Some(i) = s.file.inflow.as_mut() {
                        (i.min, i.max) = (b - 1.0, b);
                    }
                } else if let Some(r) = num("r") {
                    if let Some(i) = s.file.inflow.as_mut() {
                        i.ramp = r * D / U;
                    }
                } else if token != "confined" {
                    panic!("unknown variant token {token}");
                }
            }
        };
        let h = {
            let mut s = Scene::from_toml(&cylinder::scene_text(D / dod, 1.0, 100.0), "h")?;
            edit(&mut s);
            s.file.domain.max[1] - s.file.domain.min[1]
        };
        let (samples, run, voids) =
            cylinder::simulate(&ctx, dod, 100.0, t_end, SAMPLE_UD, KICK, &edit, true)?;
        let mut csv = std::fs::File::create(out.join(format!("{name}.csv")))?;
        writeln!(csv, "t_ud,cd,cl")?;
        for s in &samples {
            writeln!(csv, "{:.4},{:.6},{:.6}", s.t * U / D, s.cd, s.cl)?;
        }
        let body = BluffBody {
            velocity: U,
            length: D,
            blockage_ratio: D / h,
        };
        let raw = Coefficients::of(&samples, body);
        let smooth = cylinder::summary(&samples);
        let cl = cylinder::smooth(
            &samples.iter().map(|s| s.cl).collect::<Vec<_>>(),
            cylinder::SMOOTH_HALF,
        );
        let n = cl.len();
        let quarters: Vec<String> = (0..4)
            .map(|q| {
                let w = &cl[q * n / 4..(q + 1) * n / 4];
                let m = w.iter().sum::<f64>() / w.len() as f64;
                let r = (w.iter().map(|x| (x - m).powi(2)).sum::<f64>() / w.len() as f64).sqrt();
                format!("{r:.4}")
            })
            .collect();
        let v = voids.unwrap_or_default();
        println!(
            "VOIDS {name}: largest {:.2} dx at t U / D = {:.1}, empty cells max {:.4} mean {:.4}",
            v.largest_void_dx,
            v.largest_void_time * U / D,
            v.max_empty_fraction,
            v.mean_empty_fraction
        );
        println!(
            "RESULT {name} D/dx {dod} t_end {t_end} {variant}: {} particles, {:.1} s; St {:.4}, mean Cd {:.4}, rms Cl raw {:.4} band {:.4}, mean Cl {:.4}; smoothed rms by quarter {}",
            run.particles,
            run.wall_seconds,
            smooth.strouhal.unwrap_or(f64::NAN),
            smooth.mean_cd,
            raw.rms_cl,
            smooth.rms_cl,
            smooth.mean_cl,
            quarters.join(" ")
        );
        let eps = blockage_epsilon(D / h, smooth.mean_cd);
        let st_u = smooth.strouhal.unwrap_or(f64::NAN) / (1.0 + eps);
        let cd_u = smooth.mean_cd / (1.0 + eps).powi(2);
        let cl_u = smooth.rms_cl / (1.0 + eps).powi(2);
        let williamson = cylinder::strouhal_fits(100).1;
        let errs = [
            st_u / williamson - 1.0,
            cd_u / CD_REF - 1.0,
            cl_u / CL_RMS_REF - 1.0,
        ];
        println!(
            "CORRECTED {name}: D/H {:.4}, eps {eps:.4}; St_u {st_u:.4} ({:+.1} %), Cd_u {cd_u:.4} ({:+.1} %), rms Cl_u {cl_u:.4} ({:+.1} %)",
            D / h,
            100.0 * errs[0],
            100.0 * errs[1],
            100.0 * errs[2]
        );
        let score = [
            errs[0].abs() / 0.05,
            errs[1].abs() / 0.10,
            errs[2].abs() / 0.10,
            v.largest_void_dx / MAX_VOID_DX,
        ]
        .into_iter()
        .map(|x| if x.is_nan() { f64::INFINITY } else { x })
        .fold(0.0, f64::max);
        println!("SCORE {name} {score:.3}");
    }
    Ok(())
}
