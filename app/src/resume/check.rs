//! A checkpoint is input like a scene (issue #52): before a resume touches a file, every
//! field of the run's part that names a file or feeds an arithmetic is checked, so that a
//! damaged or crafted `checkpoint.bin` (with a valid checksum) is refused, naming the
//! field, instead of reaching outside the run's directory or wrapping a count.
//!
//! A file it names must be one the run itself writes (`output::files`): the writer's CSVs,
//! a force monitor of the run's scene, the probes' and gauges' CSVs, the frames below its
//! frame count. Times are finite and not negative, intervals positive, counts bounded
//! by the steps taken (at most one output per step, and one at t = 0 and at a blow-up).

use std::collections::HashSet;

use super::Resume;
use crate::output::files::{self, BODIES, CLUSTERS, DIAGNOSTICS, GAUGES, PROBES, VOIDS};

/// Steps beyond this (2^53, where an f64 stops counting them exactly) are no real run's.
const MAX_STEPS: u64 = 1 << 53;

/// The first field of `r` that no run could have written, and why.
pub(super) fn check(r: &Resume) -> Result<(), String> {
    let clock = r.solver.clock();
    let run = &r.run;
    time("time", clock.time)?;
    if clock.steps > MAX_STEPS {
        return Err(format!("steps = {} is beyond any run", clock.steps));
    }
    if !(clock.dt.is_finite() && clock.dt >= 0.0) {
        return Err(format!("dt = {} is not a step size", clock.dt));
    }
    time("t_end", run.t_end)?;
    if !(run.output_interval.is_finite() && run.output_interval > 0.0) {
        return Err(format!(
            "output_interval = {} is not a positive time",
            run.output_interval
        ));
    }
    time("next_output", run.next_output)?;
    if let Some(t) = run.next_checkpoint {
        time("next_checkpoint", t)?;
    }
    for &t in run
        .monitors
        .next
        .iter()
        .chain(&run.probes.probes)
        .chain(&run.probes.gauges)
    {
        time("a monitor's or probe's next sample", t)?;
    }
    for &(_, t) in &run.stepper.pending_gates {
        time("a gate's opening", t)?;
    }
    for &t in &run.resumed_from {
        time("resumed_from", t)?;
    }
    let w = &run.writer;
    if w.frames as u64 > clock.steps.saturating_add(2) {
        return Err(format!(
            "writer.frames = {} outputs in {} steps",
            w.frames, clock.steps
        ));
    }
    for (t, file) in &w.series {
        time("a particles.pvd entry", *t)?;
        if files::frame_index(file).is_none_or(|i| i >= w.frames) {
            return Err(format!(
                "particles.pvd's entry `{file}` is not one of the run's {} frames",
                w.frames
            ));
        }
    }
    let f = &r.scene.file;
    // The monitors' part holds the force monitors' files, `floating.csv` and
    // `open_boundaries.csv` (`monitors::Monitors::state`), each where the scene has them.
    let monitors: Vec<String> = (f.monitors.iter())
        .map(|m| files::monitor_file(&m.name))
        .chain(
            f.walls
                .iter()
                .any(|w| w.floating().is_some())
                .then(|| files::FLOATING.to_string()),
        )
        .chain((!f.open_boundaries.is_empty()).then(|| files::OPEN_BOUNDARIES.to_string()))
        .collect();
    let parts = [
        (
            "writer",
            &w.files,
            vec![DIAGNOSTICS, CLUSTERS, VOIDS, BODIES],
        ),
        (
            "monitors",
            &run.monitors.files,
            monitors.iter().map(String::as_str).collect(),
        ),
        ("probes", &run.probes.files, vec![PROBES, GAUGES]),
    ];
    let mut seen = HashSet::new();
    for (part, listed, allowed) in parts {
        for (name, _) in listed.iter() {
            if !allowed.contains(&name.as_str()) || !seen.insert(name.as_str()) {
                return Err(format!(
                    "the {part}' file `{name}` is not one the run writes (or is listed twice)"
                ));
            }
        }
    }
    Ok(())
}

/// A simulated time [T]: finite and not negative.
fn time(field: &str, t: f64) -> Result<(), String> {
    if t.is_finite() && t >= 0.0 {
        Ok(())
    } else {
        Err(format!("{field} = {t} is not a time of a run"))
    }
}
