use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use crate::ViewerError;

/// An 8-bit RGBA image, rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes, RGBA, first row at the top.
    pub rgba: Vec<u8>,
}

impl Image {
    /// The RGBA value at `(x, y)`, `y = 0` at the top.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = ((y * self.width + x) * 4) as usize;
        [
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ]
    }

    /// Builds an image from rows read bottom to top (as `glReadPixels` gives them).
    pub(crate) fn from_gl_rows(width: u32, height: u32, bottom_up: &[u8]) -> Image {
        let row = width as usize * 4;
        let mut rgba = Vec::with_capacity(bottom_up.len());
        for r in bottom_up.chunks_exact(row).rev() {
            rgba.extend_from_slice(r);
        }
        Image {
            width,
            height,
            rgba,
        }
    }

    /// Reads a `width` x `height` RGBA image from `buffer` (`glow::BACK`,
    /// `glow::COLOR_ATTACHMENT0`, ...) of `framebuffer` (`None`: the window's).
    pub(crate) fn read_gl(
        gl: &glow::Context,
        framebuffer: Option<glow::Framebuffer>,
        buffer: u32,
        width: u32,
        height: u32,
    ) -> Image {
        use glow::HasContext;
        let mut px = vec![0u8; (width * height * 4) as usize];
        // SAFETY: plain GL calls on the caller's current context; `px` holds exactly
        // width x height RGBA bytes at pack alignment 1.
        unsafe {
            gl.bind_framebuffer(glow::READ_FRAMEBUFFER, framebuffer);
            gl.read_buffer(buffer);
            gl.pixel_store_i32(glow::PACK_ALIGNMENT, 1);
            gl.read_pixels(
                0,
                0,
                width as i32,
                height as i32,
                glow::RGBA,
                glow::UNSIGNED_BYTE,
                glow::PixelPackData::Slice(&mut px),
            );
        }
        Image::from_gl_rows(width, height, &px)
    }

    /// Writes the image as an RGBA PNG.
    pub fn save_png(&self, path: impl AsRef<Path>) -> Result<(), ViewerError> {
        let path = path.as_ref();
        if let Some(dir) = path.parent() {
            if !dir.as_os_str().is_empty() {
                std::fs::create_dir_all(dir)?;
            }
        }
        let file = BufWriter::new(File::create(path)?);
        let mut enc = png::Encoder::new(file, self.width, self.height);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().map_err(png_err)?;
        w.write_image_data(&self.rgba).map_err(png_err)?;
        w.finish().map_err(png_err)?;
        Ok(())
    }

    /// Reads an 8-bit RGB or RGBA PNG (as written by [`Image::save_png`]).
    pub fn load_png(path: impl AsRef<Path>) -> Result<Image, ViewerError> {
        let file = File::open(path)?;
        let mut dec = png::Decoder::new(std::io::BufReader::new(file));
        dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = dec.read_info().map_err(png_err)?;
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).map_err(png_err)?;
        buf.truncate(info.buffer_size());
        let rgba = match info.color_type {
            png::ColorType::Rgba => buf,
            png::ColorType::Rgb => buf
                .chunks_exact(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect(),
            png::ColorType::Grayscale => buf.iter().flat_map(|&g| [g, g, g, 255]).collect(),
            png::ColorType::GrayscaleAlpha => buf
                .chunks_exact(2)
                .flat_map(|p| [p[0], p[0], p[0], p[1]])
                .collect(),
            other => {
                return Err(ViewerError::Io(std::io::Error::other(format!(
                    "unsupported PNG colour type {other:?}"
                ))))
            }
        };
        Ok(Image {
            width: info.width,
            height: info.height,
            rgba,
        })
    }
}

fn png_err(e: impl std::fmt::Display) -> ViewerError {
    ViewerError::Io(std::io::Error::other(format!("PNG: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_round_trip_and_flip() {
        // 2x2, bottom-up rows: bottom row red, top row green.
        let bottom_up = [
            255, 0, 0, 255, 255, 0, 0, 255, 0, 255, 0, 255, 0, 255, 0, 255,
        ];
        let img = Image::from_gl_rows(2, 2, &bottom_up);
        assert_eq!(img.pixel(0, 0), [0, 255, 0, 255]);
        assert_eq!(img.pixel(1, 1), [255, 0, 0, 255]);
        let dir = std::env::temp_dir().join(format!("meshfree-viewer-png-{}", std::process::id()));
        let path = dir.join("t.png");
        img.save_png(&path).unwrap();
        let back = Image::load_png(&path).unwrap();
        assert_eq!(back, img);
        let _ = std::fs::remove_dir_all(dir);
    }
}
