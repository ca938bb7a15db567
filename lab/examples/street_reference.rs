//! Issue #23: the grid-based reference for the built-in vortex streets. Runs the lattice
//! Boltzmann street (`meshfree_lab::lbm::street`) of each named case at each resolution,
//! analyses its force record with the SPH streets' code (`validate::cylinder::summary_for`:
//! St the DFT peak of the smoothed lift, mean Cd, the lift's band rms, over the second half
//! of the record, t = 10-20 for the built-ins) and writes the JSON (per case: Re, blockage,
//! the runs, the change between the two finest, the command).
//!
//! `cargo run --release -p meshfree-lab --example street_reference -- \
//!     [--cases re140,re105,validate] [--d 20,30,40] [--out docs/data/street-reference.json] [--t-end T] [--u-lattice 0.1] [--re RE]`
//!
//! `--re` replaces each case's Reynolds number (the viscosity follows; the geometry and U
//! stay): the sensitivity of the statistics to Re.
//!
//! `validate` (the validate cylinder's geometry at Re 100, blockage 0.083) is also compared
//! with Williamson's St and, after Allen & Vincenti's correction, the unconfined Cd 1.34 and
//! rms lift 0.235.

use meshfree_lab::lbm::street::{re105, re140, validate_cylinder, Street, KICK, U_LATTICE};
use meshfree_lab::validate::cylinder::{
    blockage_epsilon, strouhal_fits, summary_for, CD_REF, CL_RMS_REF,
};
use serde_json::json;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |key: &str, default: &str| -> String {
        args.iter()
            .position(|a| a == key)
            .and_then(|i| args.get(i + 1).cloned())
            .unwrap_or_else(|| default.to_string())
    };
    let cases = value("--cases", "re140,re105");
    let ds: Vec<usize> = value("--d", "20,30,40")
        .split(',')
        .map(|d| d.parse())
        .collect::<Result<_, _>>()?;
    let out = value("--out", "docs/data/street-reference.json");
    let u_lattice: f64 = value("--u-lattice", &U_LATTICE.to_string()).parse()?;
    let mut results = Vec::new();
    for case in cases.split(',') {
        let mut street: Street = match case {
            "re140" => re140(),
            "re105" => re105(),
            "validate" => validate_cylinder(),
            other => anyhow::bail!("unknown case {other} (re140, re105, validate)"),
        };
        if let Some(t) = args.iter().position(|a| a == "--t-end") {
            street.t_end = args[t + 1].parse()?;
        }
        if let Some(r) = args.iter().position(|a| a == "--re") {
            street.re = args[r + 1].parse()?;
        }
        let (u, d) = (street.u, street.diameter);
        let mut runs = Vec::new();
        let mut stats = Vec::new();
        for &dc in &ds {
            let run = street.run(dc, u_lattice);
            let s = summary_for(&run.samples, u, d, run.height);
            let st = s.strouhal.unwrap_or(f64::NAN);
            eprintln!(
                "{} D = {dc}: {} x {} cells, {} steps, {:.1} s; window t >= {:.2}: St {st:.4}, mean Cd {:.4}, rms Cl (band) {:.4}, mean Cl {:.4}",
                street.name, run.nx, run.ny, run.steps, run.wall_seconds, s.window_start, s.mean_cd, s.rms_cl, s.mean_cl
            );
            stats.push((st, s.mean_cd, s.rms_cl));
            let mut row = json!({
                "d_cells": dc,
                "cells": [run.nx, run.ny],
                "length": run.length,
                "height": run.height,
                "steps": run.steps,
                "window_start": s.window_start,
                "samples": run.samples.len(),
                "strouhal": st,
                "mean_cd": s.mean_cd,
                "mean_cl": s.mean_cl,
                "rms_cl_band": s.rms_cl,
                "wall_seconds": run.wall_seconds,
            });
            if case == "validate" {
                let eps = blockage_epsilon(d / run.height, s.mean_cd);
                let st_ref = strouhal_fits(100).1;
                let (st_u, cd_u, cl_u) = (
                    st / (1.0 + eps),
                    s.mean_cd / (1.0 + eps).powi(2),
                    s.rms_cl / (1.0 + eps).powi(2),
                );
                eprintln!(
                    "  eps {eps:.4}: St_u {st_u:.4} ({:+.1} % vs Williamson {st_ref}), Cd_u {cd_u:.4} ({:+.1} % vs {CD_REF}), rms Cl_u {cl_u:.4} ({:+.1} % vs {CL_RMS_REF})",
                    100.0 * (st_u / st_ref - 1.0),
                    100.0 * (cd_u / CD_REF - 1.0),
                    100.0 * (cl_u / CL_RMS_REF - 1.0)
                );
                row["unconfined"] = json!({
                    "eps": eps, "strouhal": st_u, "mean_cd": cd_u, "rms_cl": cl_u,
                    "strouhal_williamson": st_ref, "cd_ref": CD_REF, "rms_cl_ref": CL_RMS_REF,
                });
            }
            runs.push(row);
        }
        // The change from the second finest to the finest, relative to the finest.
        let change = match stats.as_slice() {
            [.., a, b] => json!({
                "strouhal": a.0 / b.0 - 1.0,
                "mean_cd": a.1 / b.1 - 1.0,
                "rms_cl_band": a.2 / b.2 - 1.0,
            }),
            _ => serde_json::Value::Null,
        };
        results.push(json!({
            "scene": street.name,
            "re": street.re,
            "blockage": street.diameter / street.height,
            "u": u,
            "diameter": d,
            "centre": street.centre,
            "band": [street.band.0, street.band.1],
            "ramp": street.ramp,
            "t_end": street.t_end,
            "sample_interval": street.sample,
            "runs": runs,
            "second_finest_vs_finest": change,
        }));
        write(&out, &args, u_lattice, &results)?;
    }
    Ok(())
}

/// The JSON document of the cases so far (written after each case).
fn write(
    out: &str,
    args: &[String],
    u_lattice: f64,
    results: &[serde_json::Value],
) -> anyhow::Result<()> {
    let doc = json!({
        "what": "Lattice Boltzmann (D2Q9, TRT at Lambda 3/16, Bouzidi bounce-back, momentum-exchange force) reference for the periodic vortex streets: St, mean Cd and band rms Cl by validate::cylinder::summary_for over the record's second half",
        "command": format!("cargo run --release -p meshfree-lab --example street_reference -- {}", args.join(" ")),
        "u_lattice": u_lattice,
        "kick": KICK,
        "cases": results,
    });
    if let Some(dir) = std::path::Path::new(&out).parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(out, serde_json::to_string_pretty(&doc)? + "\n")?;
    eprintln!("wrote {out}");
    Ok(())
}
