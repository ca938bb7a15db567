//! The live window: winit 0.30 `ApplicationHandler`, glutin 0.32 context
//! through glutin-winit 0.5's `DisplayBuilder`, and the shared renderer.

use std::ffi::CStr;
use std::num::NonZeroU32;
use std::path::PathBuf;
use std::time::Instant;

use glow::HasContext;
use glutin::config::{Config, ConfigTemplateBuilder, GlConfig};
use glutin::context::{
    ContextApi, ContextAttributesBuilder, GlProfile, NotCurrentGlContext, PossiblyCurrentContext,
    Version,
};
use glutin::display::{GetGlDisplay, GlDisplay};
use glutin::surface::{GlSurface, Surface, SwapInterval, WindowSurface};
use glutin_winit::{DisplayBuilder, GlWindow};
use raw_window_handle::HasWindowHandle;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use crate::renderer::Renderer;
use crate::{Camera, Field, FrameData, Image, LiveSource, RenderOptions, Status, ViewerError};

/// Settings of the live window.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewOptions {
    /// Window title.
    pub title: String,
    /// Initial inner size in pixels.
    pub width: u32,
    /// Initial inner size in pixels.
    pub height: u32,
    /// Field to colour by at start (`f` cycles).
    pub field: Field,
    /// Solver steps per drawn frame at start (`+` / `-` change it).
    pub steps_per_frame: u32,
    /// Start paused.
    pub paused: bool,
    /// Start with boundary particles hidden (`b` toggles).
    pub hide_boundary: bool,
    /// Start with the key list shown (`h` toggles).
    pub show_help: bool,
    /// Where `p` writes screenshots.
    pub screenshot_dir: PathBuf,
    /// After this many drawn frames, write a screenshot to this path and close
    /// the window (for tests and scripted captures).
    pub screenshot_after_frames: Option<(u32, PathBuf)>,
    /// Wait for vertical sync when swapping.
    pub vsync: bool,
    /// Starting camera; [`Camera::Auto`] frames the domain.
    pub camera: Camera,
}

impl Default for ViewOptions {
    fn default() -> Self {
        ViewOptions {
            title: "meshfree".into(),
            width: 1280,
            height: 800,
            field: Field::Speed,
            steps_per_frame: 1,
            paused: false,
            hide_boundary: false,
            show_help: false,
            screenshot_dir: PathBuf::from("."),
            screenshot_after_frames: None,
            vsync: true,
            camera: Camera::Auto,
        }
    }
}

const HELP: [&str; 11] = [
    "space  pause / run",
    ". n    single step",
    "r      reset",
    "+ -    steps per frame",
    "f      next field",
    "b      hide boundary",
    "p      screenshot",
    "c      reset camera",
    "h      this help",
    "q esc  quit",
    "mouse  drag, wheel zoom",
];

/// Opens the live window and runs `source` in its render loop until the window
/// is closed (returns `Ok(())`), or a screenshot requested by
/// [`ViewOptions::screenshot_after_frames`] is written.
///
/// Only one call per process is possible (winit allows one event loop). On
/// Linux it may be called from any thread.
pub fn run_window(source: &mut dyn LiveSource, opts: ViewOptions) -> Result<(), ViewerError> {
    #[allow(unused_mut)]
    let mut builder = EventLoop::builder();
    #[cfg(all(
        unix,
        not(any(target_os = "macos", target_os = "ios", target_os = "android"))
    ))]
    {
        use winit::platform::x11::EventLoopBuilderExtX11;
        builder.with_any_thread(true);
    }
    let event_loop = builder
        .build()
        .map_err(|e| ViewerError::Window(format!("event loop: {e}")))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App::new(source, opts);
    event_loop
        .run_app(&mut app)
        .map_err(|e| ViewerError::Window(format!("event loop: {e}")))?;
    match app.error.take() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

struct Gfx {
    renderer: Renderer,
    gl: glow::Context,
    // Drop order: surface, then context, then window.
    surface: Surface<WindowSurface>,
    context: PossiblyCurrentContext,
    window: Window,
}

#[derive(Default)]
struct Drag {
    cursor: Option<(f64, f64)>,
    left: bool,
    other: bool,
}

/// What a key asks of the window beyond [`Controls`]' own state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum KeyAction {
    None,
    Close,
    Reset,
    Screenshot,
    ResetCamera,
}

/// The keyboard-driven state of the live window.
#[derive(Debug, Clone, PartialEq)]
struct Controls {
    field: Field,
    steps_per_frame: u32,
    paused: bool,
    single_step: bool,
    hide_boundary: bool,
    show_help: bool,
}

impl Controls {
    fn on_key(&mut self, key: Key<&str>) -> KeyAction {
        match key {
            Key::Named(NamedKey::Space) => self.paused = !self.paused,
            Key::Named(NamedKey::Escape) => return KeyAction::Close,
            Key::Character(c) => match c {
                " " => self.paused = !self.paused,
                "." | "n" | "N" => {
                    self.paused = true;
                    self.single_step = true;
                }
                "r" | "R" => return KeyAction::Reset,
                "+" | "=" => self.steps_per_frame = (self.steps_per_frame * 2).min(1 << 16),
                "-" | "_" => self.steps_per_frame = (self.steps_per_frame / 2).max(1),
                "f" | "F" => self.field = self.field.next(),
                "b" | "B" => self.hide_boundary = !self.hide_boundary,
                "p" | "P" => return KeyAction::Screenshot,
                "h" | "H" | "?" => self.show_help = !self.show_help,
                "c" | "C" => return KeyAction::ResetCamera,
                "q" | "Q" => return KeyAction::Close,
                _ => {}
            },
            _ => {}
        }
        KeyAction::None
    }
}

struct App<'a> {
    source: &'a mut dyn LiveSource,
    opts: ViewOptions,
    gfx: Option<Gfx>,
    frame: FrameData,
    ctl: Controls,
    camera: Camera,
    last_dim: u8,
    drag: Drag,
    frames: u64,
    screenshot: bool,
    message: Option<(String, Instant)>,
    rate_t0: Instant,
    rate_frames: u32,
    rate_steps: u64,
    rate_step0: u64,
    fps: f64,
    sps: f64,
    error: Option<ViewerError>,
}

fn win_err(e: impl std::fmt::Display) -> ViewerError {
    ViewerError::Window(e.to_string())
}

fn pick_config(configs: Box<dyn Iterator<Item = Config> + '_>) -> Config {
    let all: Vec<Config> = configs.collect();
    let score = |c: &Config| {
        (c.depth_size() >= 24) as u32 * 4
            + (c.num_samples() == 0) as u32 * 2
            + (c.alpha_size() == 8) as u32
    };
    let best = all.iter().map(score).max().unwrap_or(0);
    all.into_iter()
        .find(|c| score(c) == best)
        .expect("glutin offers at least one config")
}

impl<'a> App<'a> {
    fn new(source: &'a mut dyn LiveSource, opts: ViewOptions) -> App<'a> {
        let now = Instant::now();
        App {
            ctl: Controls {
                field: opts.field,
                steps_per_frame: opts.steps_per_frame.max(1),
                paused: opts.paused,
                single_step: false,
                hide_boundary: opts.hide_boundary,
                show_help: opts.show_help,
            },
            camera: opts.camera,
            source,
            opts,
            gfx: None,
            frame: FrameData::default(),
            last_dim: 0,
            drag: Drag::default(),
            frames: 0,
            screenshot: false,
            message: None,
            rate_t0: now,
            rate_frames: 0,
            rate_steps: 0,
            rate_step0: 0,
            fps: 0.0,
            sps: 0.0,
            error: None,
        }
    }

    fn create_gfx(&self, event_loop: &ActiveEventLoop) -> Result<Gfx, ViewerError> {
        let attrs = Window::default_attributes()
            .with_title(self.opts.title.clone())
            .with_inner_size(PhysicalSize::new(
                self.opts.width.max(64),
                self.opts.height.max(64),
            ));
        let template = ConfigTemplateBuilder::new().with_depth_size(24);
        let (window, config) = DisplayBuilder::new()
            .with_window_attributes(Some(attrs))
            .build(event_loop, template, pick_config)
            .map_err(win_err)?;
        let window = window.ok_or_else(|| win_err("no window was created"))?;
        let handle = window.window_handle().map_err(win_err)?.as_raw();
        let display = config.display();
        let mut context = None;
        let mut last = String::new();
        for version in [Some(Version::new(3, 3)), None] {
            let ca = ContextAttributesBuilder::new()
                .with_context_api(ContextApi::OpenGl(version))
                .with_profile(GlProfile::Core)
                .build(Some(handle));
            // SAFETY: the config and the window handle come from this display.
            match unsafe { display.create_context(&config, &ca) } {
                Ok(c) => {
                    context = Some(c);
                    break;
                }
                Err(e) => last = e.to_string(),
            }
        }
        let context =
            context.ok_or_else(|| win_err(format!("creating an OpenGL context: {last}")))?;
        let sattrs = window
            .build_surface_attributes(Default::default())
            .map_err(win_err)?;
        // SAFETY: the surface attributes come from this window.
        let surface =
            unsafe { display.create_window_surface(&config, &sattrs) }.map_err(win_err)?;
        let context = context.make_current(&surface).map_err(win_err)?;
        let interval = if self.opts.vsync {
            SwapInterval::Wait(NonZeroU32::MIN)
        } else {
            SwapInterval::DontWait
        };
        // Not every driver lets us choose; drawing works either way.
        let _ = surface.set_swap_interval(&context, interval);
        // SAFETY: the context is current on this thread.
        let gl = unsafe {
            glow::Context::from_loader_function_cstr(|s: &CStr| display.get_proc_address(s))
        };
        // SAFETY: the context is current on this thread.
        unsafe {
            eprintln!(
                "meshfree-viewer: OpenGL {} on {}",
                gl.get_parameter_string(glow::VERSION),
                gl.get_parameter_string(glow::RENDERER)
            );
        }
        let renderer = Renderer::new(&gl)?;
        window.request_redraw();
        Ok(Gfx {
            renderer,
            gl,
            surface,
            context,
            window,
        })
    }

    fn say(&mut self, m: impl Into<String>) {
        let m = m.into();
        eprintln!("meshfree-viewer: {m}");
        self.message = Some((m, Instant::now()));
    }

    fn advance(&mut self, steps: u32) {
        if let Err(e) = self.source.advance(steps) {
            self.ctl.paused = true;
            self.say(format!("solver error, paused: {e}"));
        }
    }

    fn overlay(&self, st: &Status) -> Vec<String> {
        let mut lines = vec![
            format!("t {:.5}  step {}", st.time, st.step),
            format!("particles {}", st.particles),
            format!(
                "{}  steps/frame {}  steps/s {:.0}  fps {:.1}",
                if self.ctl.paused { "PAUSED" } else { "running" },
                self.ctl.steps_per_frame,
                self.sps,
                self.fps
            ),
        ];
        if self.ctl.hide_boundary {
            lines.push("boundary hidden".into());
        }
        if let Some((m, t)) = &self.message {
            if t.elapsed().as_secs_f32() < 4.0 {
                lines.push(m.clone());
            }
        }
        if self.ctl.show_help {
            lines.push(String::new());
            lines.extend(HELP.iter().map(|s| s.to_string()));
        } else {
            lines.push("h: keys".into());
        }
        lines
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_none() {
            return;
        }
        if !self.ctl.paused {
            self.advance(self.ctl.steps_per_frame);
        } else if self.ctl.single_step {
            self.advance(1);
        }
        self.ctl.single_step = false;
        // The particles: filled on the GPU where the source can (device_fill.rs), else uploaded.
        let hide_kinds = [false, false, self.ctl.hide_boundary];
        let gfx = self.gfx.as_mut().expect("checked above");
        let range = match crate::device_fill::prepare(
            &mut gfx.renderer,
            &gfx.gl,
            &mut *self.source,
            self.ctl.field,
            hide_kinds,
            None,
            true,
            &mut self.frame,
        ) {
            Ok((range, _)) => range,
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
                return;
            }
        };
        if self.frame.dim != self.last_dim {
            self.last_dim = self.frame.dim;
            self.camera = self.opts.camera;
        }
        let st = self.source.status();
        self.update_rates(&st);
        let overlay = self.overlay(&st);
        let gfx = self.gfx.as_mut().expect("checked above");
        let size = gfx.window.inner_size();
        let (w, h) = (size.width.max(1), size.height.max(1));
        let opts = RenderOptions {
            width: w,
            height: h,
            field: self.ctl.field,
            range,
            camera: self.camera,
            hide_kinds,
            colorbar: true,
            overlay,
            ..RenderOptions::default()
        };
        let info = gfx.renderer.draw(&gfx.gl, &self.frame, &opts);
        self.camera = info.camera;
        self.frames += 1;

        let auto_shot = match &self.opts.screenshot_after_frames {
            Some((n, path)) if self.frames >= u64::from(*n) => Some(path.clone()),
            _ => None,
        };
        if self.screenshot || auto_shot.is_some() {
            self.screenshot = false;
            let img = read_back(&gfx.gl, w, h);
            let path = auto_shot.clone().unwrap_or_else(|| {
                self.opts
                    .screenshot_dir
                    .join(format!("meshfree-{:08}-{}.png", st.step, self.frames))
            });
            match img.save_png(&path) {
                Ok(()) => self.say(format!("saved {}", path.display())),
                Err(e) => {
                    self.say(format!("screenshot failed: {e}"));
                    if auto_shot.is_some() {
                        self.error = Some(e);
                    }
                }
            }
        }
        let gfx = self.gfx.as_mut().expect("checked above");
        if let Err(e) = gfx.surface.swap_buffers(&gfx.context) {
            self.error = Some(win_err(format!("swap buffers: {e}")));
            event_loop.exit();
            return;
        }
        if auto_shot.is_some() {
            event_loop.exit();
        }
    }

    fn update_rates(&mut self, st: &Status) {
        if self.rate_frames == 0 && self.rate_steps == 0 {
            self.rate_step0 = st.step;
        }
        self.rate_frames += 1;
        self.rate_steps = st.step.saturating_sub(self.rate_step0).max(1);
        let dt = self.rate_t0.elapsed().as_secs_f64();
        if dt >= 0.5 {
            self.fps = self.rate_frames as f64 / dt;
            self.sps = st.step.saturating_sub(self.rate_step0) as f64 / dt;
            self.rate_t0 = Instant::now();
            self.rate_frames = 0;
            self.rate_steps = 0;
        }
    }

    fn key(&mut self, key: Key<&str>, event_loop: &ActiveEventLoop) {
        match self.ctl.on_key(key) {
            KeyAction::None => {}
            KeyAction::Close => self.close(event_loop),
            KeyAction::Screenshot => self.screenshot = true,
            KeyAction::ResetCamera => self.camera = self.opts.camera,
            KeyAction::Reset => {
                if let Err(e) = self.source.reset() {
                    self.ctl.paused = true;
                    self.say(format!("reset failed: {e}"));
                } else {
                    self.say("reset");
                }
            }
        }
    }

    fn mouse_moved(&mut self, x: f64, y: f64) {
        let prev = self.drag.cursor.replace((x, y));
        let Some((px, py)) = prev else { return };
        let (dx, dy) = ((x - px) as f32, (y - py) as f32);
        let h = self
            .gfx
            .as_ref()
            .map_or(1, |g| g.window.inner_size().height) as f32;
        match &mut self.camera {
            Camera::Ortho(c) if self.drag.left || self.drag.other => c.pan_pixels(dx, dy, h),
            Camera::Orbit(c) if self.drag.left => c.rotate_pixels(dx, dy),
            Camera::Orbit(c) if self.drag.other => c.pan_pixels(dx, dy, h),
            _ => {}
        }
    }

    fn zoom(&mut self, factor: f32) {
        match &mut self.camera {
            Camera::Ortho(c) => c.zoom(factor),
            Camera::Orbit(c) => c.zoom(factor),
            Camera::Auto => {}
        }
    }

    fn close(&mut self, event_loop: &ActiveEventLoop) {
        self.release_gfx();
        event_loop.exit();
    }

    fn release_gfx(&mut self) {
        if let Some(g) = self.gfx.take() {
            g.renderer.destroy(&g.gl);
        }
    }
}

fn read_back(gl: &glow::Context, w: u32, h: u32) -> Image {
    let mut img = Image::read_gl(gl, None, glow::BACK, w, h);
    for p in img.rgba.chunks_exact_mut(4) {
        p[3] = 255;
    }
    img
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.create_gfx(event_loop) {
            Ok(g) => self.gfx = Some(g),
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => self.close(event_loop),
            WindowEvent::Resized(size) => {
                if let Some(g) = &self.gfx {
                    if let (Some(w), Some(h)) =
                        (NonZeroU32::new(size.width), NonZeroU32::new(size.height))
                    {
                        g.surface.resize(&g.context, w, h);
                    }
                    g.window.request_redraw();
                }
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                self.key(event.logical_key.as_ref(), event_loop);
            }
            WindowEvent::CursorMoved { position, .. } => self.mouse_moved(position.x, position.y),
            WindowEvent::CursorLeft { .. } => self.drag.cursor = None,
            WindowEvent::MouseInput { state, button, .. } => {
                let down = state == ElementState::Pressed;
                match button {
                    MouseButton::Left => self.drag.left = down,
                    MouseButton::Right | MouseButton::Middle => self.drag.other = down,
                    _ => {}
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let y = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                self.zoom(0.9f32.powf(y));
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(g) = &self.gfx {
            g.window.request_redraw();
        }
    }

    fn exiting(&mut self, _event_loop: &ActiveEventLoop) {
        self.release_gfx();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_drive_the_controls() {
        let mut c = Controls {
            field: Field::Speed,
            steps_per_frame: 1,
            paused: false,
            single_step: false,
            hide_boundary: false,
            show_help: false,
        };
        assert_eq!(c.on_key(Key::Named(NamedKey::Space)), KeyAction::None);
        assert!(c.paused);
        c.on_key(Key::Character(" "));
        assert!(!c.paused);
        c.on_key(Key::Character("."));
        assert!(c.paused && c.single_step);
        c.single_step = false;
        c.on_key(Key::Character("n"));
        assert!(c.single_step);
        for _ in 0..3 {
            c.on_key(Key::Character("+"));
        }
        assert_eq!(c.steps_per_frame, 8);
        c.on_key(Key::Character("-"));
        assert_eq!(c.steps_per_frame, 4);
        for _ in 0..10 {
            c.on_key(Key::Character("-"));
        }
        assert_eq!(c.steps_per_frame, 1);
        let fields: Vec<Field> = (0..4)
            .map(|_| {
                c.on_key(Key::Character("f"));
                c.field
            })
            .collect();
        assert_eq!(
            fields,
            [Field::Pressure, Field::Density, Field::Kind, Field::Speed]
        );
        c.on_key(Key::Character("b"));
        assert!(c.hide_boundary);
        c.on_key(Key::Character("h"));
        assert!(c.show_help);
        assert_eq!(c.on_key(Key::Character("r")), KeyAction::Reset);
        assert_eq!(c.on_key(Key::Character("p")), KeyAction::Screenshot);
        assert_eq!(c.on_key(Key::Character("c")), KeyAction::ResetCamera);
        assert_eq!(c.on_key(Key::Character("q")), KeyAction::Close);
        assert_eq!(c.on_key(Key::Named(NamedKey::Escape)), KeyAction::Close);
        assert_eq!(c.on_key(Key::Character("z")), KeyAction::None);
    }
}
