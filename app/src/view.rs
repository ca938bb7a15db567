//! The binary's viewer glue: `meshfree view` and `meshfree render`. It lives in the binary,
//! not the library, so that the solver library never depends on GL; the `viewer` feature
//! (on by default) brings in the `meshfree-viewer` crate.

use std::path::Path;

use anyhow::Context;
use meshfree::cli::{RenderArgs, ViewArgs};
use meshfree::output::files::SUMMARY;
use meshfree::output::{write_vtu, Compression, RunStatus, RunSummary, Timing};
use meshfree_core::backend::{create, Layout};
use meshfree_core::interop::{GlBuffers, GlSplat};
use meshfree_core::physics::params::SphParams;
use meshfree_core::scene::format::{OutputFormat, Wall};
use meshfree_core::scene::{Counts, Overrides, Scene};
use meshfree_core::solver::frame;
use meshfree_core::solver::step::Stepper;
use meshfree_core::solver::{Diagnostics, Shown, Snapshot, Solver};
use meshfree_viewer::{
    DeviceFrame, Field, FrameData, LiveSource, Outline, Panel, ParticleBuffers, RenderOptions,
    SplatView, Status, ViewOptions,
};

/// The viewer's field for the solver's quantity (the viewer knows nothing of the solver;
/// the registry is `Shown`).
pub(crate) fn field(f: Shown) -> Field {
    match f {
        Shown::Speed => Field::Speed,
        Shown::Pressure => Field::Pressure,
        Shown::Density => Field::Density,
        Shown::Kind => Field::Kind,
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
    /// The walls drawn as outlines in 3D, with the time each is removed at (gates).
    outlines: WallLines,
    /// Whether to offer the viewer a fill of its vertex buffers on the GPU
    /// (`Readback::gl_interop`); cleared where the backend refuses (its first error is said).
    device_fill: bool,
}

/// What the 3D viewer draws of the standing walls, each with the time it is removed at
/// (gates): boxes by their outline, walls from surface files by their edges.
#[derive(Debug, Default)]
pub(crate) struct WallLines {
    pub boxes: Vec<(Outline, Option<f64>)>,
    pub surfaces: Vec<(Vec<Segment>, Option<f64>)>,
}

/// A drawn edge: from, to \[L\].
pub(crate) type Segment = [[f32; 3]; 2];

/// [edges] a surface with more edges is drawn by its feature edges alone
/// (`Surface::edges`).
const MAX_EDGES: usize = 200_000;

/// The scene's walls for the 3D viewer (`WallLines`): its box walls (containers by their
/// inside, obstacles and gates) and its mesh walls. Driven and floating walls move, and
/// cylinders are no boxes: left out (`b` shows their particles).
pub(crate) fn wall_lines(scene: &Scene) -> WallLines {
    if scene.file.dimension != 3 {
        return WallLines::default();
    }
    let surfaces = (scene.file.walls.iter())
        .filter(|w| w.motion().is_none() && w.floating().is_none())
        .filter_map(|w| {
            let o = w.outline()?;
            let edges = o.loaded.get()?.edges(MAX_EDGES);
            let edges = edges.iter().map(|e| e.map(|p| p.map(|x| x as f32)));
            Some((edges.collect(), w.remove_at()))
        })
        .collect();
    WallLines {
        boxes: wall_outlines(scene),
        surfaces,
    }
}

/// The box walls of a 3D scene.
fn wall_outlines(scene: &Scene) -> Vec<(Outline, Option<f64>)> {
    let corner = |v: &[f64]| -> [f32; 3] { std::array::from_fn(|i| v[i] as f32) };
    scene
        .file
        .walls
        .iter()
        .filter(|w| w.motion().is_none() && w.floating().is_none())
        .filter_map(|w| match w {
            Wall::BoxContainer { min, max, .. } | Wall::Box { min, max, .. } => Some((
                Outline {
                    min: corner(min),
                    max: corner(max),
                },
                w.remove_at(),
            )),
            Wall::Segment { .. }
            | Wall::Cylinder { .. }
            | Wall::Mesh { .. }
            | Wall::Polygon { .. } => None,
        })
        .collect()
}

impl Live {
    fn new(scene: Scene, backend: meshfree_core::backend::BackendChoice) -> anyhow::Result<Live> {
        let setup = scene.setup()?;
        let solver = create(backend, Layout::One, setup)?;
        let info = solver.info();
        meshfree::errln!(
            "{}: {} particles on {} ({})",
            scene.name(),
            solver.len(),
            info.backend,
            info.device
        );
        let stepper = Stepper::new(scene.gates()).with_end(scene.file.time.end);
        Ok(Live {
            outlines: wall_lines(&scene),
            scene,
            backend,
            solver,
            stepper,
            time: 0.0,
            snapshot: Snapshot::default(),
            device_fill: true,
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
pub(crate) fn shown(f: Field) -> Shown {
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
        self.frame_meta(out);
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
        let device_fill = self.device_fill;
        *self = Live::new(self.scene.clone(), self.backend).map_err(|e| format!("{e:#}"))?;
        self.device_fill = device_fill;
        Ok(())
    }

    /// The CUDA backend's CUDA-OpenGL interop (`Readback::gl_interop`); `None` on the CPU, or
    /// where the buffers cannot be registered (say, an EGL display on another GPU than
    /// CUDA's): then this and every later frame are uploaded from snapshots.
    fn fill_buffers(
        &mut self,
        f: Field,
        hide_kinds: [bool; 3],
        fixed_range: bool,
        buffers: &ParticleBuffers,
        splat: Option<&SplatView>,
        out: &mut FrameData,
    ) -> Option<Result<DeviceFrame, String>> {
        if !self.device_fill {
            return None;
        }
        let gl = GlBuffers {
            positions: buffers.positions,
            values: buffers.values,
            kinds: buffers.kinds,
            capacity: buffers.capacity,
        };
        let hidden = (0..3).fold(0u8, |m, k| m | (u8::from(hide_kinds[k]) << k));
        let splat = splat.map(|v| GlSplat {
            buffer: v.buffer,
            width: v.width,
            height: v.height,
            view: v.view,
            ray: v.ray,
            radius: v.radius,
            first: v.first,
            count: v.count,
            hidden: v.hidden,
        });
        let r =
            self.solver
                .gl_interop()?
                .fill_gl(&gl, shown(f), hidden, fixed_range, splat.as_ref());
        match r {
            Ok(g) => {
                self.frame_meta(out);
                Some(Ok(DeviceFrame {
                    count: g.count,
                    kinds: g.kinds,
                    range: g.range,
                    splat: g.splat,
                }))
            }
            Err(e) => {
                meshfree::errln!("drawing from host copies of the particles: {e}");
                self.device_fill = false;
                None
            }
        }
    }
}

impl Live {
    /// The frame's dimension, domain and drawn radius.
    fn frame_meta(&self, out: &mut FrameData) {
        frame_meta(self.solver.params(), self.time, &self.outlines, out);
    }
}

/// A frame's dimension, domain, drawn radius and the wall outlines and edges standing at `t`
/// \[T\] (gates leave the picture when they are removed): for the live solver and for a
/// recorded run alike.
pub(crate) fn frame_meta(p: &SphParams, t: f64, walls: &WallLines, out: &mut FrameData) {
    let standing = |removed: &Option<f64>| removed.is_none_or(|r| t < r);
    out.dim = p.dim as u8;
    out.domain_min = p.domain_min;
    out.domain_max = p.domain_max;
    if p.dim == 2 {
        out.domain_min[2] = 0.0;
        out.domain_max[2] = 0.0;
    }
    out.particle_radius = 0.5 * p.dx;
    out.outlines.clear();
    out.outlines.extend(
        (walls.boxes.iter())
            .filter(|(_, removed)| standing(removed))
            .map(|(o, _)| *o),
    );
    out.edges.clear();
    for (edges, _) in walls.surfaces.iter().filter(|(_, r)| standing(r)) {
        out.edges.extend_from_slice(edges);
    }
}

/// The window's error; without a display (where the window's error names a path inside
/// winit), the way on: the headless renderer (issue #51).
pub(crate) fn window_error(e: meshfree_viewer::ViewerError) -> anyhow::Error {
    let unset = |v| std::env::var_os(v).is_none_or(|s| s.is_empty());
    let headless = unset("DISPLAY") && unset("WAYLAND_DISPLAY");
    if headless {
        anyhow::anyhow!(
            "no display (neither DISPLAY nor WAYLAND_DISPLAY is set): use `meshfree render` \
             for images without one"
        )
    } else {
        e.into()
    }
}

/// `meshfree view` of a scene: the live window; on close, the final particles and
/// summary.json. (A run's directory is `view_run`'s: `main.rs` tells them apart.)
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
        surface: a.surface,
        screenshot_dir: out.clone(),
        screenshot_after_frames: a.capture(),
        ..Default::default()
    };
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    meshfree_viewer::run_window(&mut live, opts).map_err(window_error)?;
    // The window closed: write where the run got to.
    let particles = live.solver.particles();
    let vtu = out.join("final.vtu");
    let fields = scene.file.output.fields(&particles);
    let d: Diagnostics = live.solver.diagnostics();
    let frame = frame::FrameData::from_particles(&particles, fields, d.step, d.time);
    let bytes = write_vtu(&vtu, &frame, fields, Compression::Raw)
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
        writer_mb_per_second: None,
        output_advice: None,
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
        error: None,
        // What `run --overwrite` may remove here later (output::files).
        files: vec!["final.vtu".into(), SUMMARY.into()],
        fault_frame: None,
        monitors: Vec::new(),
        bodies: Vec::new(),
        open_boundaries: Vec::new(),
        checkpoint_time: None,
        resumed_from: Vec::new(),
    };
    // Written as a run writes it: renamed into place, never through a planted link.
    let path = out.join(SUMMARY);
    (summary.write(&path)).with_context(|| format!("writing {}", path.display()))?;
    meshfree::outln!(
        "window closed at t = {:.4}; wrote {} and {}",
        summary.simulated_time,
        vtu.display(),
        path.display()
    )?;
    Ok(())
}

/// `meshfree render` of a scene: PNG without a display, at a time or as a sequence. (A
/// run's directory is `view_run`'s: `main.rs` tells them apart.)
pub fn render(a: RenderArgs) -> anyhow::Result<()> {
    let (Some(out), None) = (a.out.clone(), &a.movie) else {
        return Err(meshfree::bad_input::BadInput(format!(
            "--movie encodes a finished run's frames: run the scene (`meshfree run {}`), then \
             `meshfree render DIR --movie VIDEO`, or write PNGs here with --frames N --out",
            a.scene
        ))
        .into());
    };
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
    meshfree::errln!("headless OpenGL: {}", renderer.gl_renderer());
    let device = !a.host_copy;
    // The panel's rates: solver steps and drawn frames per second since the last image.
    let mut pace = (
        std::time::Instant::now(),
        live.solver.steps(),
        0.0f64,
        0.0f64,
    );
    let steps_per_frame = a.steps_per_frame.unwrap_or(0);
    let opts = |live: &Live| RenderOptions {
        width: a.size.0,
        height: a.size.1,
        field: f,
        range: a.range,
        hide_kinds: [false, false, dim == 3 && !a.show_boundary],
        overlay: vec![format!("{}  t = {:.3}", scene.name(), live.time)],
        surface: a.surface,
        ..Default::default()
    };
    // Draws the current state (the pixels read back only where a PNG is written); returns
    // whether the vertex buffers were filled on the GPU.
    let mut shoot = |live: &mut Live, path: Option<&Path>| -> anyhow::Result<bool> {
        let status = live.status();
        let panel = a.panel.then(|| {
            let dt = pace.0.elapsed().as_secs_f64().max(1e-9);
            if pace.1 != status.step {
                pace.2 = (status.step - pace.1) as f64 / dt;
                pace.3 = 1.0 / dt;
            }
            pace = (std::time::Instant::now(), status.step, pace.2, pace.3);
            Panel {
                status,
                paused: false,
                steps_per_frame,
                steps_per_second: pace.2,
                frames_per_second: pace.3,
                show_help: false,
                timeline: None,
            }
        });
        let o = RenderOptions {
            panel,
            ..opts(live)
        };
        let (image, on_device) = renderer.render_source(live, &o, device, path.is_some())?;
        if let (Some(path), Some(image)) = (path, image) {
            image
                .save_png(path)
                .with_context(|| format!("writing {}", path.display()))?;
            let from = match (on_device, renderer.drew_splat()) {
                (true, true) => {
                    "vertex buffers filled on the GPU, spheres from the GPU's visibility splat"
                }
                (true, false) => "vertex buffers filled on the GPU",
                _ => "a host copy",
            };
            meshfree::outln!(
                "wrote {} (t = {:.4}, drawn from {from})",
                path.display(),
                live.time
            )?;
        }
        Ok(on_device)
    };
    let stem = out.with_extension("");
    let numbered = |k: u32| std::path::PathBuf::from(format!("{}_{k:04}.png", stem.display()));
    if a.figures {
        let moments = figure_moments(&scene);
        std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
        let end = scene.file.time.end;
        for &t in &moments {
            if t > end + 1e-12 {
                meshfree::outln!("skipping t = {t}: past the end time {end}")?;
                continue;
            }
            live.advance_to(t).map_err(anyhow::Error::msg)?;
            let path = out.join(format!("{}_t{t:.2}.png", scene.name()));
            shoot(&mut live, Some(&path))?;
        }
        return Ok(());
    }
    match (a.frames, a.steps_per_frame) {
        (Some(n), Some(k)) => {
            // Timed: K solver steps, then one frame drawn (finished, not read back: a window
            // does not read its pixels), N times; the last one is written as PNG.
            let bytes = |live: &Live| live.solver.device_to_host_bytes();
            // Seconds of each frame's solving and drawing.
            let (mut solves, mut draws) = (Vec::new(), Vec::new());
            let (mut step_bytes, mut draw_bytes) = (0u64, 0u64);
            let mut on_device = false;
            for f in 0..n {
                let b0 = bytes(&live);
                let t0 = std::time::Instant::now();
                live.advance(k).map_err(anyhow::Error::msg)?;
                live.time = live.solver.time(); // waits for the GPU
                let t1 = std::time::Instant::now();
                let b1 = bytes(&live);
                let last = f + 1 == n;
                on_device = shoot(&mut live, None)?;
                draws.push(t1.elapsed().as_secs_f64());
                solves.push((t1 - t0).as_secs_f64());
                // Bytes from the second frame on: the first opens the scene's gates, whose
                // removals read the state back once.
                if let (Some(b0), Some(b1), Some(b2), true) = (b0, b1, bytes(&live), f > 0) {
                    step_bytes += b1 - b0;
                    draw_bytes += b2 - b1;
                }
                if last {
                    // PNG encoding and the pixels' read-back are no part of a viewer's cost.
                    shoot(&mut live, Some(&numbered(f)))?;
                }
            }
            // GPU time per pass over the frames above (their timer queries, read late).
            let passes: Vec<GpuPass> = renderer
                .take_pass_times()
                .into_iter()
                .map(|p| GpuPass {
                    pass: p.name,
                    ms: p.ms,
                })
                .collect();
            // The ceiling: the same sprites drawn again from the buffers as they are (the
            // sprites' raster, also where the frames came from the GPU's visibility splat).
            let o = RenderOptions {
                sprites_only: true,
                ..opts(&live)
            };
            let t0 = std::time::Instant::now();
            for _ in 0..n {
                renderer.redraw(&o, false)?;
            }
            let still = t0.elapsed().as_secs_f64();
            let later = n.saturating_sub(1).max(1) as f64;
            let per_frame = |b: u64| bytes(&live).map(|_| b as f64 / later);
            let ms = |v: &[f64]| v.iter().map(|s| 1e3 * s).collect::<Vec<f64>>();
            let t = FrameTiming {
                particles: live.solver.len(),
                frames: n,
                steps_per_frame: k,
                path: if on_device { "device" } else { "host copy" },
                all: FrameRates::of(&solves, &draws, k),
                static_drawing_ms_per_frame: 1e3 * still / n as f64,
                steady: (n > 1).then(|| FrameRates::of(&solves[1..], &draws[1..], k)),
                first_frame_ms: (1e3 * solves[0], 1e3 * draws[0]),
                frame_solver_ms: ms(&solves),
                frame_drawing_ms: ms(&draws),
                d2h_bytes_per_frame_drawing: per_frame(draw_bytes),
                d2h_bytes_per_frame_stepping: per_frame(step_bytes),
                size: a.size,
                gpu_passes_ms: passes,
            };
            meshfree::outln!("{}", t.line())?;
            if let Some(s) = &t.steady {
                meshfree::outln!(
                    "steady (frames after the first): {:.1} frames/s, solver {:.3} ms/step, \
                     drawing {:.2} ms/frame, slow-down {:.1} % (the solver alone: {:.1} \
                     frames/s); the first frame: solver {:.1} ms, drawing {:.1} ms",
                    s.frames_per_second,
                    s.solver_ms_per_step,
                    s.drawing_ms_per_frame,
                    s.solver_slowdown_percent,
                    s.solver_bound_frames_per_second,
                    t.first_frame_ms.0,
                    t.first_frame_ms.1
                )?;
            }
            if !t.gpu_passes_ms.is_empty() {
                let list: Vec<String> = t
                    .gpu_passes_ms
                    .iter()
                    .map(|p| format!("{} {:.2}", p.pass, p.ms))
                    .collect();
                meshfree::outln!("gpu ms per frame by pass: {}", list.join(", "))?;
            }
            meshfree::outln!("timing-json: {}", serde_json::to_string(&t)?)?;
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
            shoot(&mut live, Some(&out))?;
        }
    }
    Ok(())
}

/// Rates over some frames of `render --frames N --steps-per-frame K`.
#[derive(serde::Serialize)]
struct FrameRates {
    frames_per_second: f64,
    solver_ms_per_step: f64,
    /// Filling (or reading back and uploading) and drawing one frame, to its finish.
    drawing_ms_per_frame: f64,
    /// Drawing time over solver time for the same frames.
    solver_slowdown_percent: f64,
    /// The frames per second the solver alone allows at K steps a frame (free drawing):
    /// the GPU runs a frame's drawing after its steps, not under them.
    solver_bound_frames_per_second: f64,
}

impl FrameRates {
    /// From the frames' solving and drawing seconds, `k` steps each.
    fn of(solves: &[f64], draws: &[f64], k: u32) -> FrameRates {
        let (solve, draw) = (solves.iter().sum::<f64>(), draws.iter().sum::<f64>());
        let n = solves.len().max(1) as f64;
        FrameRates {
            frames_per_second: n / (solve + draw),
            solver_ms_per_step: 1e3 * solve / (n * k.max(1) as f64),
            drawing_ms_per_frame: 1e3 * draw / n,
            solver_slowdown_percent: 100.0 * draw / solve,
            solver_bound_frames_per_second: n / solve,
        }
    }
}

/// What `render --frames N --steps-per-frame K` measured.
#[derive(serde::Serialize)]
struct FrameTiming {
    particles: usize,
    frames: u32,
    steps_per_frame: u32,
    /// "device" (the vertex buffers filled on the GPU) or "host copy".
    path: &'static str,
    /// Over all N frames (the first one's set-up included: the gates' removal, the CUDA
    /// graph's capture, the modules' loading, the buffers' registration, the first draw).
    #[serde(flatten)]
    all: FrameRates,
    /// Drawing the same sprites again from the buffers as they are: the ceiling.
    static_drawing_ms_per_frame: f64,
    /// Over the frames after the first: a viewer's running cost.
    steady: Option<FrameRates>,
    /// The first frame's solving and drawing [ms].
    first_frame_ms: (f64, f64),
    /// Each frame's solving and drawing [ms].
    frame_solver_ms: Vec<f64>,
    frame_drawing_ms: Vec<f64>,
    /// Bytes read back from the device per frame by the drawing and by the stepping
    /// (`Solver::device_to_host_bytes`), over the frames after the first (which opens the
    /// scene's gates: a removal reads the state back once); `None` on the CPU.
    d2h_bytes_per_frame_drawing: Option<f64>,
    d2h_bytes_per_frame_stepping: Option<f64>,
    size: (u32, u32),
    /// Mean GPU time per frame of each drawing pass (`GL_TIME_ELAPSED` queries), in order:
    /// the particles, and with `--surface` the surface's sprites, thickness mipmaps, blur
    /// passes and shading. Empty where the GL has no timer queries.
    gpu_passes_ms: Vec<GpuPass>,
}

/// One drawing pass's mean GPU time per frame.
#[derive(serde::Serialize)]
struct GpuPass {
    pass: &'static str,
    ms: f64,
}

impl FrameTiming {
    fn line(&self) -> String {
        let bytes = |b: Option<f64>| b.map_or("-".to_string(), |b| format!("{b:.0}"));
        format!(
            "timing: {} particles at {}x{}, {} frames of {} steps, {}: {:.1} frames/s, solver \
             {:.3} ms/step, drawing {:.2} ms/frame (static-buffer drawing {:.2} ms/frame, \
             {:.2}x), solver slow-down from drawing {:.1} %, device-to-host bytes per frame: \
             {} drawing, {} stepping",
            self.particles,
            self.size.0,
            self.size.1,
            self.frames,
            self.steps_per_frame,
            self.path,
            self.all.frames_per_second,
            self.all.solver_ms_per_step,
            self.all.drawing_ms_per_frame,
            self.static_drawing_ms_per_frame,
            self.all.drawing_ms_per_frame / self.static_drawing_ms_per_frame.max(1e-9),
            self.all.solver_slowdown_percent,
            bytes(self.d2h_bytes_per_frame_drawing),
            bytes(self.d2h_bytes_per_frame_stepping),
        )
    }
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
    meshfree::errln!(
        "{}: no `time.figures` in the scene; rendering at {m:?}",
        scene.name()
    );
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_rates_split_a_frame_into_its_steps_and_its_drawing() {
        // Two frames of 10 steps: 16 ms of steps and 1 ms of drawing each.
        let r = FrameRates::of(&[0.016, 0.016], &[0.001, 0.001], 10);
        assert!((r.frames_per_second - 1.0 / 0.017).abs() < 1e-9);
        assert!((r.solver_ms_per_step - 1.6).abs() < 1e-9);
        assert!((r.drawing_ms_per_frame - 1.0).abs() < 1e-9);
        assert!((r.solver_slowdown_percent - 6.25).abs() < 1e-9);
        assert!((r.solver_bound_frames_per_second - 62.5).abs() < 1e-9);
    }

    #[test]
    fn the_3d_dam_break_shows_its_tank_and_loses_its_gate() {
        let scene = Scene::load("dam-break-3d").unwrap();
        let o = wall_outlines(&scene);
        assert_eq!(o.len(), 2, "{o:?}");
        assert_eq!(
            o[0],
            (
                Outline {
                    min: [0.0, 0.0, 0.0],
                    max: [3.0, 1.6, 0.48]
                },
                None
            )
        );
        assert_eq!(o[1].1, Some(0.0), "the gate goes at t = 0");
        // The frame carries the tank only: the gate is removed at the start.
        let mut live = Live::new(scene, meshfree_core::backend::BackendChoice::Cpu).unwrap();
        let mut frame = FrameData::default();
        live.frame(Field::Speed, &mut frame);
        assert_eq!(frame.outlines, vec![o[0].0]);
        // 2D scenes have none.
        let flat = wall_lines(&Scene::load("dam-break-2d").unwrap());
        assert!(flat.boxes.is_empty() && flat.surfaces.is_empty());
    }

    #[test]
    fn the_cow_is_drawn_by_its_edges() {
        let scene = Scene::load("cow-dam-break-3d").unwrap();
        let lines = wall_lines(&scene);
        assert_eq!(lines.boxes.len(), 2);
        assert_eq!(lines.surfaces.len(), 1);
        // A closed surface of 5,856 triangles has 8,784 edges, inside the cow's box.
        let (edges, removed) = &lines.surfaces[0];
        assert_eq!((edges.len(), *removed), (8784, None));
        assert!(edges.iter().flatten().all(|p| p[0] > 1.79 && p[0] < 2.32));
        let mut live = Live::new(scene, meshfree_core::backend::BackendChoice::Cpu).unwrap();
        let mut frame = FrameData::default();
        live.frame(Field::Speed, &mut frame);
        assert_eq!(frame.edges.len(), 8784);
    }
}
