use std::fmt;

/// Everything the viewer can fail with.
#[derive(Debug)]
pub enum ViewerError {
    /// No EGL library or no usable EGL device (headless rendering impossible here).
    NoEglDevice(String),
    /// Creating the window, the GL display, context or surface failed.
    Window(String),
    /// A GL call, shader compilation or framebuffer setup failed.
    Gl(String),
    /// The source returned an error.
    Source(String),
    /// A [`crate::FrameData`] is inconsistent.
    InvalidFrame(String),
    /// Writing or encoding an image failed.
    Io(std::io::Error),
}

impl fmt::Display for ViewerError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ViewerError::NoEglDevice(m) => write!(f, "no EGL device for headless rendering: {m}"),
            ViewerError::Window(m) => write!(f, "window/GL setup failed: {m}"),
            ViewerError::Gl(m) => write!(f, "OpenGL error: {m}"),
            ViewerError::Source(m) => write!(f, "simulation source error: {m}"),
            ViewerError::InvalidFrame(m) => write!(f, "invalid frame data: {m}"),
            ViewerError::Io(e) => write!(f, "I/O error: {e}"),
        }
    }
}

impl std::error::Error for ViewerError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ViewerError::Io(e) => Some(e),
            _ => None,
        }
    }
}

impl From<std::io::Error> for ViewerError {
    fn from(e: std::io::Error) -> Self {
        ViewerError::Io(e)
    }
}

/// A GL call's failure as a `ViewerError::Gl`.
pub(crate) fn gl_err(m: impl Into<String>) -> ViewerError {
    ViewerError::Gl(m.into())
}
