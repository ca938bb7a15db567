//! The plots' text: the embedded font, and a drawing backend that sets each glyph at its
//! side bearing.
//!
//! plotters' `ab_glyph` text (0.3.7, `FontDataInternal::draw`) starts each glyph's ink at
//! the pen and drops the glyph's left side bearing. In the monospaced font the narrow glyphs
//! ('.', '1') then sit at the left of their cells, so a tick label "1.0" read "1. 0" and
//! "0.1" read "0. 1". `Typeset` wraps a backend and draws the text of `FAMILY` itself, with
//! the bearing; plotters still measures and anchors it (its widths were right: they add the
//! advances), and every other drawing goes to the wrapped backend.

use std::sync::OnceLock;

use ab_glyph::{point, Font, FontRef, ScaleFont};
use plotters::style::FontStyle;
use plotters_backend::{
    text_anchor::{HPos, VPos},
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSansMono.ttf");
pub(crate) const FAMILY: &str = "sans-serif";

pub(crate) fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // Registering a valid embedded font cannot fail; if it did, text is just missing.
        let _ = plotters::style::register_font(FAMILY, FontStyle::Normal, FONT);
    });
}

/// The embedded font for drawing (None if it did not parse: plotters then draws, or fails
/// to find the font, as without `Typeset`).
fn font() -> Option<&'static FontRef<'static>> {
    static PARSED: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    PARSED
        .get_or_init(|| FontRef::try_from_slice(FONT).ok())
        .as_ref()
}

/// The coverage of each pixel of `text` at `size` px, as (x, y, coverage) from the pen's
/// start: each glyph at the pen plus its side bearing (where plotters drops the bearing),
/// the pen moved by the advances and kerning, and the baseline at y = size / 2 as plotters
/// puts it (so labels stand where they stood; only the glyphs' x changed).
fn glyph_pixels(font: &FontRef, size: f32, text: &str, mut pixel: impl FnMut(i32, i32, f32)) {
    let scaled = font.as_scaled(size);
    let mut pen = 0.0f32;
    let mut prev = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            pen += scaled.kern(p, id);
        }
        prev = Some(id);
        if let Some(outline) = font.outline_glyph(id.with_scale_and_position(size, point(pen, 0.0)))
        {
            let b = outline.px_bounds();
            let (x0, y0) = (b.min.x as i32, (size / 2.0 + b.min.y) as i32);
            outline.draw(|x, y, a| pixel(x0 + x as i32, y0 + y as i32, a));
        }
        pen += scaled.h_advance(id);
    }
}

/// A drawing backend whose text of `FAMILY` is drawn by `glyph_pixels`.
pub(crate) struct Typeset<DB>(pub DB);

impl<DB: DrawingBackend> DrawingBackend for Typeset<DB> {
    type ErrorType = DB::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.blit_bitmap(pos, size, src)
    }

    /// plotters' own `draw_text` (anchor, rotation, clipping to the backend), with the
    /// glyphs from `glyph_pixels`.
    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let font = match font() {
            Some(f) if style.family().as_str() == FAMILY => f,
            _ => return self.0.draw_text(text, style, pos),
        };
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let ((min_x, min_y), (max_x, max_y)) = style
            .layout_box(text)
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let (width, height) = (max_x - min_x, max_y - min_y);
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let trans = style.transform();
        let (w, h) = self.get_size();
        let mut result = Ok(());
        glyph_pixels(font, style.size() as f32, text, |x, y, a| {
            let (x, y) = trans.transform(x + dx - min_x, y + dy - min_y);
            let (x, y) = (pos.0 + x, pos.1 + y);
            if result.is_ok() && x >= 0 && x < w as i32 && y >= 0 && y < h as i32 {
                result = self.0.draw_pixel((x, y), color.mix(a as f64));
            }
        });
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::coord::ranged1d::ValueFormatter;
    use plotters::prelude::*;

    /// The column ranges [first, last] holding ink of `text` drawn at 15 px (the tick
    /// labels' size) by `Typeset` over a bitmap.
    fn ink_columns(text: &str) -> Vec<(usize, usize)> {
        register_font();
        let (w, h) = (80usize, 30usize);
        let mut buf = vec![255u8; w * h * 3];
        {
            let mut b = Typeset(BitMapBackend::with_buffer(&mut buf, (w as u32, h as u32)));
            let style = TextStyle::from((FAMILY, 15).into_font()).color(&BLACK);
            b.draw_text(text, &style, (4, 4)).unwrap();
            b.present().unwrap();
        }
        let inked = |x: usize| (0..h).any(|y| buf[(y * w + x) * 3] < 160);
        let mut runs: Vec<(usize, usize)> = Vec::new();
        for x in (0..w).filter(|&x| inked(x)) {
            match runs.last_mut() {
                Some(r) if r.1 + 1 == x => r.1 = x,
                _ => runs.push((x, x)),
            }
        }
        runs
    }

    #[test]
    fn tick_labels_read_without_a_gap_after_the_point() {
        // The log axes' labels are plotters' `{:?}` of the tick: the text was right ...
        type Log = plotters::coord::combinators::LogCoord<f64>;
        assert_eq!(<Log as ValueFormatter<f64>>::format(&1.0), "1.0");
        assert_eq!(<Log as ValueFormatter<f64>>::format(&0.1), "0.1");
        // ... its glyphs were not: the point sits midway between its neighbours, in the
        // middle of its cell, where plotters' drawing put it at the left of its cell (gaps
        // of 2 and 8 px around it in "1.0"; in "0.1" it touched the 0).
        for text in ["1.0", "0.1"] {
            let runs = ink_columns(text);
            assert_eq!(runs.len(), 3, "{text}: {runs:?}");
            let before = runs[1].0 - runs[0].1;
            let after = runs[2].0 - runs[1].1;
            assert!(before.abs_diff(after) <= 2, "{text}: {runs:?}");
        }
    }
}
