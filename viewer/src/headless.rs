//! Headless rendering: EGL on a device (`EGL_EXT_platform_device`), no
//! display server, a surfaceless OpenGL core context (4.0, else 3.3), and an FBO.

use std::ffi::CStr;

use glow::HasContext;
use glutin::api::egl::context::PossiblyCurrentContext;
use glutin::api::egl::device::Device;
use glutin::api::egl::display::Display;
use glutin::config::{Api, ConfigSurfaceTypes, ConfigTemplateBuilder};
use glutin::context::{ContextApi, ContextAttributesBuilder, GlProfile, Version};
use glutin::prelude::*;

use crate::renderer::Renderer;
use crate::{FrameData, Image, LiveSource, PassTime, RenderOptions, ViewerError};

/// A reusable headless renderer: one EGL context and FBO for many frames.
///
/// Not `Send`: use it on the thread that made it.
pub struct HeadlessRenderer {
    renderer: Renderer,
    fbo: Option<(
        glow::Framebuffer,
        glow::Renderbuffer,
        glow::Renderbuffer,
        u32,
        u32,
    )>,
    gl: glow::Context,
    gl_renderer: String,
    /// The last `render_source` frame (its vectors empty where the source filled the
    /// buffers on the GPU) and colour range, for `redraw`.
    source_frame: FrameData,
    source_range: Option<(f32, f32)>,
    /// Whether the last draw took its spheres from the source's visibility splat.
    splat: bool,
    // Declared last so they drop after the GL objects are deleted in `Drop`.
    _context: PossiblyCurrentContext,
    _display: Display,
}

impl std::fmt::Debug for HeadlessRenderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HeadlessRenderer")
            .field("gl_renderer", &self.gl_renderer)
            .finish()
    }
}

fn make_context(device: &Device) -> Result<(Display, PossiblyCurrentContext), String> {
    // SAFETY: no raw display handle is passed (glutin asks only that one given be valid);
    // the device comes from `Device::query_devices`.
    let display = unsafe { Display::with_device(device, None) }.map_err(|e| e.to_string())?;
    let template = ConfigTemplateBuilder::new()
        .with_surface_type(ConfigSurfaceTypes::empty())
        .with_api(Api::OPENGL)
        .build();
    // SAFETY: the template has no native window.
    let config = unsafe { display.find_configs(template) }
        .map_err(|e| e.to_string())?
        .next()
        .ok_or("no EGL config without surface")?;
    let mut last = String::new();
    // 4.0 first, then 3.3 (all the viewer needs): NVIDIA gives the version asked for, Mesa
    // its highest.
    for version in [Some(Version::new(4, 0)), Some(Version::new(3, 3)), None] {
        let attrs = ContextAttributesBuilder::new()
            .with_context_api(ContextApi::OpenGl(version))
            .with_profile(GlProfile::Core)
            .build(None);
        // SAFETY: the attributes carry no raw window handle (`build(None)`), the one thing
        // glutin asks to be valid; config comes from this display.
        match unsafe { display.create_context(&config, &attrs) } {
            Ok(ctx) => {
                let ctx = ctx.make_current_surfaceless().map_err(|e| e.to_string())?;
                return Ok((display, ctx));
            }
            Err(e) => last = e.to_string(),
        }
    }
    Err(format!("creating an OpenGL core context failed: {last}"))
}

impl HeadlessRenderer {
    /// Opens the first EGL device that gives an OpenGL core context (4.0, else 3.3).
    pub fn new() -> Result<HeadlessRenderer, ViewerError> {
        let devices: Vec<Device> = Device::query_devices()
            .map_err(|e| ViewerError::NoEglDevice(format!("querying EGL devices: {e}")))?
            .collect();
        if devices.is_empty() {
            return Err(ViewerError::NoEglDevice("EGL lists no devices".into()));
        }
        let mut errors = Vec::new();
        for device in &devices {
            let name = device
                .name()
                .or(device.vendor())
                .unwrap_or("unnamed device");
            match make_context(device) {
                Ok((display, context)) => {
                    // SAFETY: the context is current on this thread (`make_context` made it
                    // so), and the loader is its display's, so every function loaded is that
                    // context's.
                    let gl = unsafe {
                        glow::Context::from_loader_function_cstr(|s: &CStr| {
                            display.get_proc_address(s)
                        })
                    };
                    // SAFETY: the context rule (renderer.rs): `gl` was just loaded from the
                    // context current on this thread; the strings are queried, no object
                    // named.
                    let gl_renderer = unsafe {
                        format!(
                            "{} ({})",
                            gl.get_parameter_string(glow::RENDERER),
                            gl.get_parameter_string(glow::VERSION)
                        )
                    };
                    let tex_buffer = crate::splat::tex_buffer_fn(|s| display.get_proc_address(s));
                    let renderer = Renderer::new(&gl, tex_buffer)?;
                    return Ok(HeadlessRenderer {
                        renderer,
                        fbo: None,
                        gl,
                        gl_renderer,
                        source_frame: FrameData::default(),
                        source_range: None,
                        splat: false,
                        _context: context,
                        _display: display,
                    });
                }
                Err(e) => errors.push(format!("{name}: {e}")),
            }
        }
        Err(ViewerError::NoEglDevice(errors.join("; ")))
    }

    /// `GL_RENDERER (GL_VERSION)` of the context, e.g. `llvmpipe (...) (4.5 (Core Profile) Mesa ...)`.
    pub fn gl_renderer(&self) -> &str {
        &self.gl_renderer
    }

    fn target(&mut self, w: u32, h: u32) -> Result<glow::Framebuffer, ViewerError> {
        let gl = &self.gl;
        if let Some((fbo, _, _, fw, fh)) = self.fbo {
            if (fw, fh) == (w, h) {
                return Ok(fbo);
            }
        }
        // SAFETY: the context rule (renderer.rs): `self.gl` is loaded from `_context`,
        // current on this thread since `new` (`HeadlessRenderer` is not `Send`); the old
        // FBO and renderbuffers are this renderer's, deleted once (taken out of `self.fbo`).
        // w and h are at most 16384 (the callers' check), so the casts to i32 keep them.
        unsafe {
            if let Some((fbo, c, d, _, _)) = self.fbo.take() {
                gl.delete_framebuffer(fbo);
                gl.delete_renderbuffer(c);
                gl.delete_renderbuffer(d);
            }
            let fbo = gl.create_framebuffer().map_err(ViewerError::Gl)?;
            let color = gl.create_renderbuffer().map_err(ViewerError::Gl)?;
            let depth = gl.create_renderbuffer().map_err(ViewerError::Gl)?;
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(color));
            gl.renderbuffer_storage(glow::RENDERBUFFER, glow::RGBA8, w as i32, h as i32);
            gl.bind_renderbuffer(glow::RENDERBUFFER, Some(depth));
            gl.renderbuffer_storage(
                glow::RENDERBUFFER,
                glow::DEPTH_COMPONENT24,
                w as i32,
                h as i32,
            );
            gl.bind_renderbuffer(glow::RENDERBUFFER, None);
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
            gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0,
                glow::RENDERBUFFER,
                Some(color),
            );
            gl.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::DEPTH_ATTACHMENT,
                glow::RENDERBUFFER,
                Some(depth),
            );
            let status = gl.check_framebuffer_status(glow::FRAMEBUFFER);
            if status != glow::FRAMEBUFFER_COMPLETE {
                return Err(ViewerError::Gl(format!(
                    "framebuffer incomplete: 0x{status:x}"
                )));
            }
            self.fbo = Some((fbo, color, depth, w, h));
            Ok(fbo)
        }
    }

    /// Renders `frame` and reads the pixels back.
    pub fn render(
        &mut self,
        frame: &FrameData,
        opts: &RenderOptions,
    ) -> Result<Image, ViewerError> {
        let (w, h) = (opts.width, opts.height);
        if w == 0 || h == 0 || w > 16384 || h > 16384 {
            return Err(ViewerError::Gl(format!("bad image size {w}x{h}")));
        }
        let fbo = self.target(w, h)?;
        self.renderer.upload(&self.gl, frame)?;
        let gl = &self.gl;
        // SAFETY: the context rule (renderer.rs), as in `target`: fbo is this renderer's,
        // just made complete there.
        unsafe {
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
            gl.draw_buffers(&[glow::COLOR_ATTACHMENT0]);
        }
        self.renderer.draw(gl, frame, opts);
        let img = Image::read_gl(gl, Some(fbo), glow::COLOR_ATTACHMENT0, w, h);
        // SAFETY: the context rule (renderer.rs): binding the default framebuffer (none,
        // in a surfaceless context) and reading the error flag name no object.
        unsafe {
            gl.bind_framebuffer(glow::FRAMEBUFFER, None);
            let err = gl.get_error();
            if err != glow::NO_ERROR {
                return Err(ViewerError::Gl(format!(
                    "GL error 0x{err:x} while rendering"
                )));
            }
        }
        Ok(img)
    }
}

impl HeadlessRenderer {
    /// Renders `source`'s current state coloured by `opts.field`: its particles written into
    /// the vertex buffers on the GPU where `device` allows and the source offers it
    /// ([`LiveSource::fill_buffers`]), else [`LiveSource::frame`] uploaded. With `read` the
    /// pixels come back as an [`Image`]; without, the frame is only finished (`glFinish`),
    /// as a window would show it. Returns the image and whether the GPU fill ran.
    pub fn render_source(
        &mut self,
        source: &mut dyn LiveSource,
        opts: &RenderOptions,
        device: bool,
        read: bool,
    ) -> Result<(Option<Image>, bool), ViewerError> {
        let (range, on_device) = crate::device_fill::prepare(
            &mut self.renderer,
            &self.gl,
            source,
            opts.field,
            opts.hide_kinds,
            opts.range,
            device,
            &mut self.source_frame,
        )?;
        self.source_range = range;
        Ok((self.redraw(opts, read)?, on_device))
    }

    /// Draws the particles of the last [`HeadlessRenderer::render_source`] again, from the
    /// vertex buffers as they are (nothing uploaded or filled: the drawing's own cost).
    pub fn redraw(
        &mut self,
        opts: &RenderOptions,
        read: bool,
    ) -> Result<Option<Image>, ViewerError> {
        let (w, h) = (opts.width, opts.height);
        if w == 0 || h == 0 || w > 16384 || h > 16384 {
            return Err(ViewerError::Gl(format!("bad image size {w}x{h}")));
        }
        let fbo = self.target(w, h)?;
        let opts = RenderOptions {
            range: self.source_range,
            ..opts.clone()
        };
        let gl = &self.gl;
        // SAFETY: the context rule (renderer.rs), as in `target`: fbo is this renderer's,
        // just made complete there.
        unsafe {
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
            gl.draw_buffers(&[glow::COLOR_ATTACHMENT0]);
        }
        self.splat = self.renderer.draw(gl, &self.source_frame, &opts).splat;
        let img = if read {
            Some(Image::read_gl(gl, Some(fbo), glow::COLOR_ATTACHMENT0, w, h))
        } else {
            // SAFETY: the context rule (renderer.rs); glFinish takes no arguments.
            unsafe { gl.finish() };
            None
        };
        // SAFETY: the context rule (renderer.rs): binding the default framebuffer (none,
        // in a surfaceless context) and reading the error flag name no object.
        unsafe {
            gl.bind_framebuffer(glow::FRAMEBUFFER, None);
            let err = gl.get_error();
            if err != glow::NO_ERROR {
                return Err(ViewerError::Gl(format!(
                    "GL error 0x{err:x} while rendering"
                )));
            }
        }
        Ok(img)
    }
}

impl HeadlessRenderer {
    /// Whether the last frame drawn took its spheres from the source's visibility splat
    /// (made with the fill for the view drawn before: from the second frame of a view on).
    pub fn drew_splat(&self) -> bool {
        self.splat
    }

    /// The mean GPU time of each pass (the particles, the surface's passes) over the
    /// frames drawn since the last call, as far as their timer queries have been read;
    /// the measuring starts again. Empty where the context has no timer queries.
    pub fn take_pass_times(&mut self) -> Vec<PassTime> {
        self.renderer.take_pass_times(&self.gl)
    }
}

impl Drop for HeadlessRenderer {
    fn drop(&mut self) {
        self.renderer.destroy(&self.gl);
        if let Some((fbo, c, d, _, _)) = self.fbo.take() {
            // SAFETY: the context rule (renderer.rs): the context is still current (the
            // `_context` field drops after this), and the FBO and renderbuffers are this
            // renderer's, deleted once (taken out of `self.fbo`).
            unsafe {
                self.gl.delete_framebuffer(fbo);
                self.gl.delete_renderbuffer(c);
                self.gl.delete_renderbuffer(d);
            }
        }
    }
}

/// Renders one frame headless (EGL device, no display) and returns the image.
///
/// Makes a new EGL context each call; use [`HeadlessRenderer`] for many frames.
/// Returns [`ViewerError::NoEglDevice`] where no EGL device is usable.
pub fn render_headless(frame: &FrameData, opts: &RenderOptions) -> Result<Image, ViewerError> {
    HeadlessRenderer::new()?.render(frame, opts)
}
