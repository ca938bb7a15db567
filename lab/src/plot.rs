//! PNG plots of simulation vs reference (plotters, bitmap backend only). Text is drawn with
//! an embedded DejaVu Sans Mono (`assets/fonts`, Bitstream Vera licence) through ab_glyph
//! (`text.rs`: plotters measures it, `Typeset` places its glyphs), so no system font or
//! fontconfig is needed.

mod text;

use std::path::Path;

use plotters::prelude::*;

pub(crate) use text::{register_font, Typeset, FAMILY};

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    Line,
    Points,
}

/// One curve or point set.
#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
}

impl Series {
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.into(),
            points,
            style: Style::Line,
        }
    }

    pub fn points(label: impl Into<String>, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: label.into(),
            points,
            style: Style::Points,
        }
    }
}

/// Axes and labels of one figure.
#[derive(Clone, Debug, Default)]
pub struct Figure<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    /// Log scale on y (every y must be positive).
    pub log_y: bool,
    /// Log scale on x (every x must be positive).
    pub log_x: bool,
}

fn range(v: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in v.filter(|x| x.is_finite() && (!log || *x > 0.0)) {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if log {
        // Whole decades, so that the axis has labelled ticks (plotters labels powers of 10).
        let lo = 10f64.powf((lo / 1.2).log10().floor());
        let hi = 10f64.powf((hi * 1.2).log10().ceil());
        return (lo, hi);
    }
    let pad = if hi > lo { 0.05 * (hi - lo) } else { 0.5 };
    (lo - pad, hi + pad)
}

/// Distinct colours, in order; a figure with more series reuses them from the start.
const COLORS: [RGBColor; 20] = [
    RGBColor(200, 30, 30),
    RGBColor(30, 80, 200),
    RGBColor(20, 140, 40),
    RGBColor(160, 60, 180),
    RGBColor(230, 130, 0),
    RGBColor(0, 0, 0),
    RGBColor(0, 160, 170),
    RGBColor(140, 90, 40),
    RGBColor(240, 80, 160),
    RGBColor(120, 120, 120),
    RGBColor(255, 170, 170),
    RGBColor(120, 170, 255),
    RGBColor(130, 220, 110),
    RGBColor(210, 160, 230),
    RGBColor(250, 200, 90),
    RGBColor(90, 60, 20),
    RGBColor(110, 230, 220),
    RGBColor(60, 0, 110),
    RGBColor(180, 180, 0),
    RGBColor(0, 90, 70),
];

/// Above this many series the legend moves out of the plot, into a column on its right, so
/// that it covers no data (the speed-against-accuracy charts carry up to 20).
const LEGEND_INSIDE_MAX: usize = 8;
/// [px] width of that column.
const LEGEND_WIDTH: u32 = 340;

/// The legend as a column of its own (`side`): each series' marker or line and its label,
/// in the series' colours, from the top.
fn legend_column<DB: DrawingBackend>(
    side: &DrawingArea<DB, plotters::coord::Shift>,
    series: &[Series],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    for (i, s) in series.iter().enumerate() {
        let c = COLORS[i % COLORS.len()];
        let y = 40 + 22 * i as i32;
        match s.style {
            Style::Line => {
                side.draw(&PathElement::new(vec![(8, y), (28, y)], c.stroke_width(2)))?
            }
            Style::Points => side.draw(&Circle::new((18, y), 4, c.filled()))?,
        }
        side.draw(&Text::new(s.label.as_str(), (36, y - 8), (FAMILY, 15)))?;
    }
    Ok(())
}

/// Draw `series` into a 900 x 600 PNG at `path` (wider by `LEGEND_WIDTH` where the legend
/// stands beside the plot).
pub fn plot(path: &Path, fig: &Figure, series: &[Series]) -> anyhow::Result<()> {
    register_font();
    let all = || series.iter().flat_map(|s| s.points.iter());
    let (x0, x1) = range(all().map(|p| p.0), fig.log_x);
    let (y0, y1) = range(all().map(|p| p.1), fig.log_y);
    let outside = series.len() > LEGEND_INSIDE_MAX;
    let width = 900 + if outside { LEGEND_WIDTH } else { 0 };
    let root = Typeset(BitMapBackend::new(path, (width, 600))).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| anyhow::anyhow!("plot {}: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (area, side) = root.split_horizontally(900);
    if outside {
        legend_column(&side, series).map_err(|e| err(&e))?;
    }
    let mut builder = ChartBuilder::on(&area);
    builder
        .caption(fig.title, (FAMILY, 22))
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(80);
    macro_rules! draw {
        ($chart:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_desc(fig.x_label)
                .y_desc(fig.y_label)
                .label_style((FAMILY, 15))
                .axis_desc_style((FAMILY, 17))
                .light_line_style(RGBColor(235, 235, 235))
                .draw()
                .map_err(|e| err(&e))?;
            for (i, s) in series.iter().enumerate() {
                let c = COLORS[i % COLORS.len()];
                match s.style {
                    Style::Line => chart
                        .draw_series(LineSeries::new(s.points.iter().copied(), c.stroke_width(2)))
                        .map_err(|e| err(&e))?
                        .label(s.label.as_str())
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                        }),
                    Style::Points => chart
                        .draw_series(s.points.iter().map(|&p| Circle::new(p, 3, c.filled())))
                        .map_err(|e| err(&e))?
                        .label(s.label.as_str())
                        .legend(move |(x, y)| Circle::new((x + 10, y), 4, c.filled())),
                };
            }
            if !outside {
                chart
                    .configure_series_labels()
                    .label_font((FAMILY, 15))
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .position(SeriesLabelPosition::UpperRight)
                    .draw()
                    .map_err(|e| err(&e))?;
            }
        }};
    }
    if fig.log_x && fig.log_y {
        draw!(builder
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(|e| err(&e))?);
    } else if fig.log_x {
        draw!(builder
            .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
            .map_err(|e| err(&e))?);
    } else if fig.log_y {
        draw!(builder
            .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
            .map_err(|e| err(&e))?);
    } else {
        draw!(builder
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| err(&e))?);
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Width and height of a PNG from its IHDR chunk.
    fn png_size(path: &Path) -> (u32, u32) {
        let b = std::fs::read(path).unwrap();
        let be = |o: usize| u32::from_be_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
        (be(16), be(20))
    }

    #[test]
    fn many_series_put_the_legend_beside_the_plot() {
        let dir = tempfile::tempdir().unwrap();
        let fig = Figure {
            title: "legend",
            x_label: "wall time [s]",
            y_label: "error",
            log_x: true,
            log_y: true,
        };
        let series = |n: usize| -> Vec<Series> {
            (0..n)
                .map(|i| Series::points(format!("variant {i} (cuda)"), vec![(0.1 + i as f64, 0.5)]))
                .collect()
        };
        let few = dir.path().join("few.png");
        plot(&few, &fig, &series(LEGEND_INSIDE_MAX)).unwrap();
        assert_eq!(png_size(&few), (900, 600));
        let many = dir.path().join("many.png");
        plot(&many, &fig, &series(LEGEND_INSIDE_MAX + 12)).unwrap();
        assert_eq!(png_size(&many), (900 + LEGEND_WIDTH, 600));
    }
}
