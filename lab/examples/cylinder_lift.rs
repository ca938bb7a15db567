//! Issue #23's diagnosis of the cylinder's weak lift: runs `validate`'s cylinder
//! (`cylinder::simulate`, Re 100, kicked) in variants of the confined scheme, one after
//! another, and writes each run's force history (`<name>.csv`: t U / D, Cd, Cl) and its
//! statistics over the second half (`cylinder::summary`: St, mean Cd, the rms lift in the
//! band around St; and the raw rms Cl), and the smoothed lift's rms per quarter of the
//! record, which shows whether the shedding has saturated; and the void metric every
//! `cylinder::VOID_EVERY_UD` (`meshfree_core::voids`).
//!
//! `cargo run --release -p meshfree-lab --example cylinder_lift -- OUT_DIR BACKEND
//! NAME:D_OVER_DX:T_END_UD:VARIANT ...`, VARIANT one of `confined` (validate's scheme),
//! `morris` (and Morris's no-slip walls), `bg3` (background pressure 3 q), or both
//! (`morris-bg3`).

use meshfree_core::backend::BackendChoice;
use meshfree_core::monitor::MonitorSummary;
use meshfree_core::scene::Scene;
use meshfree_core::scheme::NoSlip;
use meshfree_lab::validate::cylinder::{self, confined, D, H, KICK, SAMPLE_UD, U};
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
        out_dir: &out,
        verbose: true,
    };
    for spec in &args[2..] {
        let f: Vec<&str> = spec.split(':').collect();
        let (name, dod, t_end, variant) = (f[0], f[1].parse::<f64>()?, f[2].parse::<f64>()?, f[3]);
        let edit = move |s: &mut Scene| {
            confined(s);
            if variant.contains("morris") {
                if let Some(b) = s.file.boundary.as_mut() {
                    b.no_slip = NoSlip::Morris;
                }
            }
            if variant.contains("bg3") {
                s.file.fluid.background_pressure = 3.0 * 0.5 * U * U;
            }
        };
        let (samples, run, voids) =
            cylinder::simulate(&ctx, dod, 100.0, t_end, SAMPLE_UD, KICK, &edit, true)?;
        let mut csv = std::fs::File::create(out.join(format!("{name}.csv")))?;
        writeln!(csv, "t_ud,cd,cl")?;
        for s in &samples {
            writeln!(csv, "{:.4},{:.6},{:.6}", s.t * U / D, s.cd, s.cl)?;
        }
        let raw = MonitorSummary::of(name, 0, &samples, U, D, D / H);
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
    }
    Ok(())
}
