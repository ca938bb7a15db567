//! A stability map as a PNG: one coloured cell per run (green stable, amber inaccurate,
//! red failed), annotated with the error or the blow-up time. Drawn in pixel coordinates on
//! plotters' bitmap backend with the embedded font of `crate::plot`.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{Class, MapResult};
use crate::plot::{register_font, Typeset, FAMILY};

const W: i32 = 900;
const H: i32 = 640;
const LEFT: i32 = 130;
const RIGHT: i32 = 30;
const TOP: i32 = 60;
const BOTTOM: i32 = 110;

fn colour(c: Class) -> RGBColor {
    match c {
        Class::Stable => RGBColor(120, 200, 120),
        Class::Inaccurate => RGBColor(240, 190, 80),
        Class::Failed => RGBColor(220, 80, 70),
    }
}

fn annotation(c: &super::Cell) -> (String, String) {
    match c.class {
        Class::Stable => (
            "stable".into(),
            format!("err {:.3}", c.error.unwrap_or(f64::NAN)),
        ),
        Class::Inaccurate => (
            "inaccurate".into(),
            format!("err {:.3}", c.error.unwrap_or(f64::NAN)),
        ),
        Class::Failed => (
            "FAILED".into(),
            format!("t = {:.4}", c.blow_up_time.unwrap_or(f64::NAN)),
        ),
    }
}

/// Draw `map` to `path`.
pub fn draw(path: &Path, map: &MapResult) -> anyhow::Result<()> {
    register_font();
    let err = |e: &dyn std::fmt::Display| anyhow::anyhow!("heat map {}: {e}", path.display());
    let root = Typeset(BitMapBackend::new(path, (W as u32, H as u32))).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let (nx, ny) = (map.def.x.values.len() as i32, map.def.y.values.len() as i32);
    let cw = (W - LEFT - RIGHT) / nx.max(1);
    let ch = (H - TOP - BOTTOM) / ny.max(1);
    let centre = Pos::new(HPos::Center, VPos::Center);
    let text = |size: u32| TextStyle::from((FAMILY, size).into_font()).pos(centre);
    root.draw(&Text::new(map.def.title.clone(), (W / 2, 25), text(20)))
        .map_err(|e| err(&e))?;
    for (k, c) in map.cells.iter().enumerate() {
        let (col, row) = (k as i32 % nx, k as i32 / nx);
        // Row 0 (the first y value) at the bottom.
        let x0 = LEFT + col * cw;
        let y0 = TOP + (ny - 1 - row) * ch;
        root.draw(&Rectangle::new(
            [(x0, y0), (x0 + cw, y0 + ch)],
            colour(c.class).filled(),
        ))
        .map_err(|e| err(&e))?;
        root.draw(&Rectangle::new(
            [(x0, y0), (x0 + cw, y0 + ch)],
            WHITE.stroke_width(2),
        ))
        .map_err(|e| err(&e))?;
        let (a, b) = annotation(c);
        let size = if nx > 3 { 14 } else { 17 };
        root.draw(&Text::new(a, (x0 + cw / 2, y0 + ch / 2 - 10), text(size)))
            .map_err(|e| err(&e))?;
        root.draw(&Text::new(b, (x0 + cw / 2, y0 + ch / 2 + 10), text(size)))
            .map_err(|e| err(&e))?;
    }
    for (col, x) in map.def.x.values.iter().enumerate() {
        let px = LEFT + col as i32 * cw + cw / 2;
        root.draw(&Text::new(
            format!("{x}"),
            (px, TOP + ny * ch + 15),
            text(15),
        ))
        .map_err(|e| err(&e))?;
    }
    for (row, y) in map.def.y.values.iter().enumerate() {
        let py = TOP + (ny - 1 - row as i32) * ch + ch / 2;
        root.draw(&Text::new(format!("{y}"), (LEFT - 30, py), text(15)))
            .map_err(|e| err(&e))?;
    }
    root.draw(&Text::new(
        map.def.x.param.label(),
        (LEFT + nx * cw / 2, TOP + ny * ch + 40),
        text(17),
    ))
    .map_err(|e| err(&e))?;
    root.draw(&Text::new(
        map.def.y.param.label(),
        (10, TOP - 15),
        TextStyle::from((FAMILY, 15).into_font()).pos(Pos::new(HPos::Left, VPos::Center)),
    ))
    .map_err(|e| err(&e))?;
    let tol = map.cells.first().map(|c| c.tolerance).unwrap_or(f64::NAN);
    root.draw(&Text::new(
        format!(
            "dx = {}; error: {} (tolerance {tol})",
            map.spacing, map.error_measure
        ),
        (W / 2, H - 35),
        text(13),
    ))
    .map_err(|e| err(&e))?;
    root.draw(&Text::new(
        "green: stable   amber: inaccurate (error > tolerance)   red: failed (blow-up, simulated time)",
        (W / 2, H - 15),
        text(13),
    ))
    .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
