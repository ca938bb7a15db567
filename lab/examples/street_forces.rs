//! Issue #23: the statistics of a built-in vortex street's run (`meshfree run
//! vortex-street-re1{40,05}`) by `validate`'s cylinder analysis (`cylinder::summary_for`:
//! St the DFT peak of the smoothed lift, mean Cd, the band rms of the raw lift, over the
//! second half of the record), the Allen & Vincenti blockage correction as `validate`
//! (`cylinder::blockage_epsilon`) against Williamson's St at the scene's Re
//! (refdata/cylinder_strouhal_vs_Re.csv) and the derived unconfined Cd and rms lift of
//! refdata/cylinder_flow_reference.json, and the run's largest void and wall time
//! (summary.json).
//!
//! `cargo run --release -p meshfree-lab --example street_forces -- RUN_DIR ...`, each
//! RUN_DIR a run's output (scene.toml, forces.csv, summary.json).

use meshfree_core::measure::monitor::ForceSample;
use meshfree_core::scene::Scene;
use meshfree_lab::validate::cylinder::{blockage_epsilon, strouhal_fits, summary_for};
use std::path::Path;

/// (Re, mean Cd, rms Cl) of the unconfined flow, the centres of the bands of
/// refdata/cylinder_flow_reference.json ("derived": Cd 1.33-1.35 and 1.32-1.34, the lift
/// amplitude 0.35-0.37 and 0.45-0.50, rms = amplitude / sqrt 2).
const REFERENCES: [(u32, f64, f64); 2] = [(105, 1.34, 0.255), (140, 1.33, 0.336)];

fn main() -> anyhow::Result<()> {
    for dir in std::env::args().skip(1) {
        let dir = Path::new(&dir);
        let scene = Scene::from_file(dir.join("scene.toml"))?;
        let f = &scene.file;
        let m = &f.monitors[0];
        let (u, d) = (m.reference_velocity.unwrap(), m.reference_length.unwrap());
        let h = f.domain.max[1] - f.domain.min[1];
        let re = (u * d / f.fluid.viscosity).round() as u32;
        let text = std::fs::read_to_string(dir.join("forces.csv"))?;
        let samples: Vec<ForceSample> = text
            .lines()
            .skip(1)
            .map(|l| {
                let v: Vec<f64> = l
                    .split(',')
                    .map(|x| x.parse().unwrap_or(f64::NAN))
                    .collect();
                ForceSample {
                    t: v[0],
                    force: [v[1], v[2], v[3]],
                    cd: v[4],
                    cl: v[5],
                }
            })
            .collect();
        let s = summary_for(&samples, u, d, h);
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json"))?)?;
        let voids = &json["voids"];
        let st = s.strouhal.unwrap_or(f64::NAN);
        let eps = blockage_epsilon(d / h, s.mean_cd);
        let (st_u, cd_u, cl_u) = (
            st / (1.0 + eps),
            s.mean_cd / (1.0 + eps).powi(2),
            s.rms_cl / (1.0 + eps).powi(2),
        );
        let st_ref = strouhal_fits(re).1;
        let (_, cd_ref, cl_ref) =
            REFERENCES
                .iter()
                .find(|r| r.0 == re)
                .copied()
                .unwrap_or((re, f64::NAN, f64::NAN));
        let pct = |x: f64, r: f64| 100.0 * (x / r - 1.0);
        println!(
            "{}: Re {re}, D/H {:.3}, {} particles, {} steps, wall {:.2} s; window t >= {:.2} ({} samples in all); \
             largest void {:.3} dx at t = {:.2}, empty cells max {:.4} mean {:.4}; \
             St {st:.4}, mean Cd {:.4}, rms Cl (band) {:.4}; eps {eps:.3}: St_u {st_u:.4} ({:+.1} % vs {st_ref}), \
             Cd_u {cd_u:.4} ({:+.1} % vs {cd_ref}), rms Cl_u {cl_u:.4} ({:+.1} % vs {cl_ref})",
            dir.display(),
            d / h,
            json["particles"]["total"],
            json["steps"],
            json["wall_seconds"].as_f64().unwrap_or(f64::NAN),
            s.window_start,
            samples.len(),
            voids["largest_void_dx"].as_f64().unwrap_or(f64::NAN),
            voids["largest_void_time"].as_f64().unwrap_or(f64::NAN),
            voids["max_empty_fraction"].as_f64().unwrap_or(f64::NAN),
            voids["mean_empty_fraction"].as_f64().unwrap_or(f64::NAN),
            s.mean_cd,
            s.rms_cl,
            pct(st_u, st_ref),
            pct(cd_u, cd_ref),
            pct(cl_u, cl_ref),
        );
    }
    Ok(())
}
