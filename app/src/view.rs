//! The binary's viewer glue: `meshfree view` and `meshfree render`. It lives in the binary,
//! not the library, so that the solver library never depends on GL; the `viewer` feature
//! (on by default) brings in the `meshfree-viewer` crate.

use std::path::Path;

use anyhow::Context;
use meshfree::cli::{RenderArgs, ShownField, ViewArgs};
use meshfree::output::{write_vtu, RunStatus, RunSummary, Timing};
use meshfree_core::backend::create;
use meshfree_core::frame;
use meshfree_core::scene::format::OutputFormat;
use meshfree_core::scene::{Counts, Overrides, Scene};
use meshfree_core::solver::{Diagnostics, Shown, Snapshot, Solver};
use meshfree_core::step::Stepper;
use meshfree_viewer::{Field, FrameData, LiveSource, RenderOptions, Status, ViewOptions};

fn field(f: ShownField) -> Field {
    match f {
        ShownField::Speed => Field::Speed,
        ShownField::Pressure => Field::Pressure,
        ShownField::Density => Field::Density,
        ShownField::Kind => Field::Kind,
    }
}

/// A running scene as the viewer sees it: the solver plus the scene's gates.
struct Live {
    scene: Scene,
    backend: meshfree_core::backend::BackendChoice,
    solver: Box<dyn Solver>,
    stepper: Stepper,
    time: f64,
    snapshot: Snapshot,
}

impl Live {
    fn new(scene: Scene, backend: meshfree_core::backend::BackendChoice) -> anyhow::Result<Live> {
        let setup = scene.setup()?;
        let solver = create(backend, setup)?;
        let info = solver.info();
        eprintln!(
            "{}: {} particles on {} ({})",
            scene.name(),
            solver.len(),
            info.backend,
            info.device
        );
        let stepper = Stepper::new(scene.gates());
        Ok(Live {
            scene,
            backend,
            solver,
            stepper,
            time: 0.0,
            snapshot: Snapshot::default(),
        })
    }

    /// Step until `t_end` [T], opening gates on time and checking health.
    fn advance_to(&mut self, t_end: f64) -> Result<(), String> {
        self.stepper
            .advance_to(self.solver.as_mut(), t_end)
            .map_err(|e| e.to_string())?;
        self.time = self.solver.time();
        Ok(())
    }
}

/// The solver's quantity for a viewer field.
fn shown(f: Field) -> Shown {
    match f {
        Field::Speed => Shown::Speed,
        Field::Pressure => Shown::Pressure,
        Field::Density => Shown::Density,
        Field::Kind => Shown::Kind,
    }
}

impl LiveSource for Live {
    fn advance(&mut self, steps: u32) -> Result<(), String> {
        self.stepper
            .advance_steps(self.solver.as_mut(), steps.into())
            .map_err(|e| e.to_string())?;
        self.time = self.solver.time();
        Ok(())
    }

    /// One read-back per drawn frame, into buffers reused from frame to frame.
    fn frame(&mut self, f: Field, out: &mut FrameData) {
        let p = *self.solver.params();
        out.dim = p.dim as u8;
        out.domain_min = p.domain_min;
        out.domain_max = p.domain_max;
        if p.dim == 2 {
            out.domain_min[2] = 0.0;
            out.domain_max[2] = 0.0;
        }
        out.particle_radius = 0.5 * p.dx;
        self.snapshot.positions = std::mem::take(&mut out.positions);
        self.snapshot.values = std::mem::take(&mut out.values);
        self.snapshot.kinds = std::mem::take(&mut out.kinds);
        self.solver.snapshot(shown(f), &mut self.snapshot);
        out.positions = std::mem::take(&mut self.snapshot.positions);
        out.values = std::mem::take(&mut self.snapshot.values);
        out.kinds = std::mem::take(&mut self.snapshot.kinds);
    }

    fn status(&self) -> Status {
        Status {
            time: self.time,
            step: self.solver.steps(),
            particles: self.solver.len(),
        }
    }

    fn reset(&mut self) -> Result<(), String> {
        *self = Live::new(self.scene.clone(), self.backend).map_err(|e| format!("{e:#}"))?;
        Ok(())
    }
}

/// `meshfree view`: the live window; on close, the final particles and summary.json.
pub fn view(a: ViewArgs) -> anyhow::Result<()> {
    let mut scene = Scene::load(&a.scene)?;
    if let Some(dx) = a.spacing {
        scene = scene.with_spacing(dx)?;
    }
    if a.paper_exact {
        scene = scene.with_paper_exact()?;
    }
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| Path::new("out").join(scene.name()));
    let mut live = Live::new(scene.clone(), a.backend)?;
    let started = std::time::Instant::now();
    let dim = live.solver.params().dim;
    let opts = ViewOptions {
        title: format!("meshfree: {}", scene.name()),
        field: field(a.field),
        steps_per_frame: a.steps_per_frame,
        hide_boundary: dim == 3,
        screenshot_dir: out.clone(),
        ..Default::default()
    };
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    meshfree_viewer::run_window(&mut live, opts)?;
    // The window closed: write where the run got to.
    let particles = live.solver.particles();
    let vtu = out.join("final.vtu");
    let fields = scene.file.output.fields(live.solver.has_solids());
    let d: Diagnostics = live.solver.diagnostics();
    let frame = frame::FrameData::from_particles(&particles, fields, d.step, d.time);
    let bytes = write_vtu(&vtu, &frame, fields, false)
        .with_context(|| format!("writing {}", vtu.display()))?;
    let info = live.solver.info();
    let wall = started.elapsed().as_secs_f64();
    let summary = RunSummary {
        scene: scene.name().to_string(),
        scene_source: scene.origin(),
        dimension: scene.file.dimension,
        backend: info.backend,
        device: info.device,
        particles: Counts::of(&particles),
        steps: d.step,
        simulated_time: d.time,
        wall_seconds: wall,
        particle_steps_per_second: particles.len() as f64 * d.step as f64 / wall.max(1e-9),
        outputs: 1,
        output_dir: out.display().to_string(),
        output_format: OutputFormat::Vtu,
        output_bytes: bytes,
        timing: Timing {
            total_seconds: wall,
            ..Default::default()
        },
        fluid_clusters: None,
        voids: None,
        final_diagnostics: Some(d),
        status: RunStatus::Completed,
        fault: None,
        interrupted_by: None,
        fault_frame: None,
        monitors: Vec::new(),
        bodies: Vec::new(),
        checkpoint_time: None,
        resumed_from: Vec::new(),
    };
    let path = out.join("summary.json");
    std::fs::write(&path, serde_json::to_string_pretty(&summary)?)
        .with_context(|| format!("writing {}", path.display()))?;
    println!(
        "window closed at t = {:.4}; wrote {} and {}",
        summary.simulated_time,
        vtu.display(),
        path.display()
    );
    Ok(())
}

/// `meshfree render`: PNG without a display, at a time or as a sequence.
pub fn render(a: RenderArgs) -> anyhow::Result<()> {
    let mut scene = Scene::load(&a.scene)?;
    if let Some(dx) = a.spacing {
        scene = scene.with_spacing(dx)?;
    }
    if a.paper_exact {
        scene = scene.with_paper_exact()?;
    }
    if a.t_end.is_some() {
        scene = scene.with_overrides(&Overrides {
            t_end: a.t_end,
            output_interval: None,
        })?;
    }
    let mut live = Live::new(scene.clone(), a.backend)?;
    let f = field(a.field);
    let dim = live.solver.params().dim;
    let mut renderer = meshfree_viewer::HeadlessRenderer::new()?;
    let mut frame = FrameData::default();
    let mut shoot = |live: &mut Live, path: Option<&Path>| -> anyhow::Result<()> {
        live.frame(f, &mut frame);
        let opts = RenderOptions {
            width: a.size.0,
            height: a.size.1,
            field: f,
            hide_kinds: [false, false, dim == 3 && !a.show_boundary],
            overlay: vec![format!("{}  t = {:.3}", scene.name(), live.time)],
            ..Default::default()
        };
        let image = renderer.render(&frame, &opts)?;
        if let Some(path) = path {
            image
                .save_png(path)
                .with_context(|| format!("writing {}", path.display()))?;
            println!("wrote {} (t = {:.4})", path.display(), live.time);
        }
        Ok(())
    };
    let stem = a.out.with_extension("");
    let numbered = |k: u32| std::path::PathBuf::from(format!("{}_{k:04}.png", stem.display()));
    if a.figures {
        let moments = figure_moments(&scene);
        std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
        let end = scene.file.time.end;
        for &t in &moments {
            if t > end + 1e-12 {
                println!("skipping t = {t}: past the end time {end}");
                continue;
            }
            live.advance_to(t).map_err(anyhow::Error::msg)?;
            let path = a.out.join(format!("{}_t{t:.2}.png", scene.name()));
            shoot(&mut live, Some(&path))?;
        }
        return Ok(());
    }
    match (a.frames, a.steps_per_frame) {
        (Some(n), Some(k)) => {
            // Timed: K solver steps, then one snapshot and render, N times.
            let (mut solve, mut draw) = (0.0f64, 0.0f64);
            for f in 0..n {
                let t0 = std::time::Instant::now();
                live.advance(k).map_err(anyhow::Error::msg)?;
                live.time = live.solver.time(); // waits for the GPU
                let t1 = std::time::Instant::now();
                // Only the last frame is written: PNG encoding is no part of a viewer's cost.
                shoot(&mut live, (f + 1 == n).then(|| numbered(f)).as_deref())?;
                draw += t1.elapsed().as_secs_f64();
                solve += (t1 - t0).as_secs_f64();
            }
            println!(
                "timing: {} particles, {n} frames of {k} steps: {:.1} frames/s, solver {:.3} ms/step, \
                 drawing {:.1} ms/frame, solver slow-down from drawing {:.1} %",
                live.solver.len(),
                n as f64 / (solve + draw),
                1e3 * solve / (n as f64 * k as f64),
                1e3 * draw / n as f64,
                100.0 * draw / solve
            );
        }
        (Some(n), None) => {
            let n = n.max(1);
            let t_end = scene.file.time.end;
            for f in 0..n {
                let t = if n == 1 {
                    0.0
                } else {
                    t_end * f as f64 / (n - 1) as f64
                };
                live.advance_to(t).map_err(anyhow::Error::msg)?;
                shoot(&mut live, Some(&numbered(f)))?;
            }
        }
        _ => {
            live.advance_to(a.at.unwrap_or(0.0))
                .map_err(anyhow::Error::msg)?;
            shoot(&mut live, Some(&a.out))?;
        }
    }
    Ok(())
}

/// The scene's `time.figures`; without them, five moments from the start to the end time
/// (said on stderr).
fn figure_moments(scene: &Scene) -> Vec<f64> {
    let f = &scene.file.time.figures;
    if !f.is_empty() {
        return f.clone();
    }
    let end = scene.file.time.end;
    let m: Vec<f64> = (0..5).map(|k| end * k as f64 / 4.0).collect();
    eprintln!(
        "{}: no `time.figures` in the scene; rendering at {m:?}",
        scene.name()
    );
    m
}
