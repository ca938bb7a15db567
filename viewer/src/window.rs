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

use crate::panel::{Controls, Outcome};
use crate::renderer::{Renderer, Slider};
use crate::{
    Action, Camera, Field, FrameData, Image, LiveSource, Panel, RenderOptions, Seek, Status,
    ViewerError,
};

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
    /// Starting camera; [`Camera::Auto`] frames the domain (3D: the outlines).
    pub camera: Camera,
    /// Start with the fluid drawn as a surface (3D; `s` toggles).
    pub surface: bool,
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
            surface: false,
        }
    }
}

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
    /// The left button went down on a recorded run's time slider: moving seeks.
    seeking: bool,
}

/// The action of a key press.
fn key_action(key: Key<&str>) -> Option<Action> {
    match key {
        Key::Named(NamedKey::Space) => Some(Action::Pause),
        Key::Named(NamedKey::Escape) => Some(Action::Close),
        Key::Named(NamedKey::ArrowRight) => Some(Action::Step),
        Key::Named(NamedKey::ArrowLeft) => Some(Action::Back),
        Key::Named(NamedKey::Home) => Some(Action::First),
        Key::Named(NamedKey::End) => Some(Action::Last),
        Key::Character(c) => Action::for_key(c),
        _ => None,
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
    /// The colour range and the panel's rows of the last drawn frame.
    range: (f32, f32),
    panel_rows: Vec<([f32; 4], Action)>,
    /// A recorded run's time slider as last drawn.
    slider: Option<Slider>,
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
                hide_kinds: [false, false, opts.hide_boundary],
                outlines: true,
                surface: opts.surface,
                range: None,
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
            range: (0.0, 1.0),
            panel_rows: Vec::new(),
            slider: None,
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
        // 4.0 first, as headless.rs asks.
        for version in [Some(Version::new(4, 0)), Some(Version::new(3, 3)), None] {
            let ca = ContextAttributesBuilder::new()
                .with_context_api(ContextApi::OpenGl(version))
                .with_profile(GlProfile::Core)
                .build(Some(handle));
            // SAFETY: the raw window handle is `window`'s, which is alive and outlives the
            // context (`Gfx` drops it last); the config comes from this display.
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
        // SAFETY: the surface attributes hold `window`'s raw handle, alive and outliving
        // the surface (`Gfx` drops the surface first, the window last).
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
        let tex_buffer = crate::splat::tex_buffer_fn(|s| display.get_proc_address(s));
        let renderer = Renderer::new(&gl, tex_buffer)?;
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

    /// Lines over the panel: a message of the last few seconds.
    fn overlay(&self) -> Vec<String> {
        match &self.message {
            Some((m, t)) if t.elapsed().as_secs_f32() < 4.0 => vec![m.clone()],
            _ => Vec::new(),
        }
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
        let hide_kinds = self.ctl.hide_kinds;
        let gfx = self.gfx.as_mut().expect("checked above");
        let range = match crate::device_fill::prepare(
            &mut gfx.renderer,
            &gfx.gl,
            &mut *self.source,
            self.ctl.field,
            hide_kinds,
            self.ctl.range,
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
        let overlay = self.overlay();
        let panel = Panel {
            status: st,
            paused: self.ctl.paused,
            steps_per_frame: self.ctl.steps_per_frame,
            steps_per_second: self.sps,
            frames_per_second: self.fps,
            show_help: self.ctl.show_help,
            timeline: self.source.timeline(),
        };
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
            surface: self.ctl.surface,
            outlines: self.ctl.outlines,
            panel: Some(panel),
            ..RenderOptions::default()
        };
        let info = gfx.renderer.draw(&gfx.gl, &self.frame, &opts);
        self.camera = info.camera;
        self.range = info.range;
        self.panel_rows = info.panel_rows;
        self.slider = info.slider;
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

    /// Does what a key or a click on the panel asks.
    fn act(&mut self, action: Action, event_loop: &ActiveEventLoop) {
        match self.ctl.apply(action, self.range) {
            Outcome::None => {}
            Outcome::Close => self.close(event_loop),
            Outcome::Screenshot => self.screenshot = true,
            Outcome::ResetCamera => self.camera = self.opts.camera,
            Outcome::Seek(to) => self.seek(to),
            Outcome::Reset => {
                if let Err(e) = self.source.reset() {
                    self.ctl.paused = true;
                    self.say(format!("reset failed: {e}"));
                } else {
                    self.say("reset");
                }
            }
        }
    }

    /// Shows another frame of a recorded run; a live run says it goes forward only.
    fn seek(&mut self, to: Seek) {
        let Some(tl) = self.source.timeline() else {
            self.say("a live run goes forward only: `meshfree view DIR` plays a finished run's frames back and forth");
            return;
        };
        let k = tl.target(to);
        if k != tl.frame {
            if let Err(e) = self.source.seek(k) {
                self.say(format!("cannot show frame {}: {e}", k + 1));
            }
        }
    }

    /// Seeks to the slider's fraction under the cursor, where the cursor is on it (or a drag
    /// started on it); whether it was.
    fn slide(&mut self) -> bool {
        let (Some(s), Some((x, y))) = (self.slider, self.drag.cursor) else {
            return false;
        };
        match s.fraction(x as f32, y as f32, self.drag.seeking) {
            Some(f) => {
                self.ctl.paused = true;
                self.seek(Seek::Fraction(f));
                true
            }
            None => false,
        }
    }

    /// The panel row under the cursor.
    fn panel_hit(&self) -> Option<Action> {
        let (x, y) = self.drag.cursor?;
        let (x, y) = (x as f32, y as f32);
        self.panel_rows
            .iter()
            .find(|([rx, ry, rw, rh], _)| x >= *rx && x < rx + rw && y >= *ry && y < ry + rh)
            .map(|(_, a)| *a)
    }

    fn mouse_moved(&mut self, x: f64, y: f64) {
        let prev = self.drag.cursor.replace((x, y));
        if self.drag.seeking {
            self.slide();
            return;
        }
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
                if let Some(a) = key_action(event.logical_key.as_ref()) {
                    self.act(a, event_loop);
                }
            }
            WindowEvent::CursorMoved { position, .. } => self.mouse_moved(position.x, position.y),
            WindowEvent::CursorLeft { .. } => self.drag.cursor = None,
            WindowEvent::MouseInput { state, button, .. } => {
                let down = state == ElementState::Pressed;
                // A click on a panel row does its action and starts no drag.
                if down && button == MouseButton::Left {
                    if let Some(a) = self.panel_hit() {
                        self.act(a, event_loop);
                        return;
                    }
                    // A press on a recorded run's slider seeks, and its drag too.
                    if self.slide() {
                        self.drag.seeking = true;
                        return;
                    }
                }
                if !down && button == MouseButton::Left {
                    self.drag.seeking = false;
                }
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
    fn keys_name_actions() {
        assert_eq!(key_action(Key::Named(NamedKey::Space)), Some(Action::Pause));
        assert_eq!(
            key_action(Key::Named(NamedKey::Escape)),
            Some(Action::Close)
        );
        assert_eq!(key_action(Key::Character("s")), Some(Action::Surface));
        assert_eq!(key_action(Key::Character("z")), None);
        assert_eq!(key_action(Key::Named(NamedKey::Tab)), None);
        assert_eq!(
            key_action(Key::Named(NamedKey::ArrowLeft)),
            Some(Action::Back)
        );
        assert_eq!(
            key_action(Key::Named(NamedKey::ArrowRight)),
            Some(Action::Step)
        );
        assert_eq!(key_action(Key::Named(NamedKey::Home)), Some(Action::First));
        assert_eq!(key_action(Key::Named(NamedKey::End)), Some(Action::Last));
    }

    #[test]
    fn the_slider_maps_a_click_to_a_fraction_of_the_run() {
        let s = Slider {
            x: 10.0,
            width: 100.0,
            y: 200.0,
            height: 20.0,
        };
        assert_eq!(s.fraction(10.0, 210.0, false), Some(0.0));
        assert_eq!(s.fraction(60.0, 210.0, false), Some(0.5));
        assert_eq!(s.fraction(115.0, 205.0, false), Some(1.0));
        assert_eq!(s.fraction(60.0, 150.0, false), None, "above the band");
        assert_eq!(s.fraction(300.0, 210.0, false), None, "past the track");
        // A drag that started on it goes on anywhere, clamped.
        assert_eq!(s.fraction(300.0, 10.0, true), Some(1.0));
        assert_eq!(s.fraction(-50.0, 10.0, true), Some(0.0));
    }
}
