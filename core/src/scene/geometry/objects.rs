//! The surfaces of a scene's objects: each read once when the scene is (`load_all`, before
//! the scene's checks), and checked against the domain and the spacing (`check`, one of
//! the scene's checks: `validate.rs`).

use super::base::Base;
use super::load::load;
use super::surface::Surface;
use crate::scene::ctx::{fmt, Ctx, R};
use crate::scene::format::{Outline, Side, SolidObject, Wall};
use crate::scene::scheme::SceneFile;
use crate::scene::SceneError;

/// An object's surface in a scene: the key that holds it, the object's group (`generate`'s
/// numbering: fluid blocks, solids, walls), for a wall the thickness of its rows outside
/// the surface's box (0 where they lie inside a closed surface, or are clipped to the
/// domain beside an open one), and whether it is open (`Side::open`: a wall's sheet or line).
pub struct Placed<'a> {
    pub field: String,
    pub group: u32,
    pub outline: &'a Outline,
    pub grow: f64,
    pub open: bool,
}

/// Every surface of `s`: the fluid blocks' `inside`, the solids' and the walls' `mesh` or
/// `polygon`, in that order.
pub fn surfaces(s: &SceneFile) -> Vec<Placed<'_>> {
    let dx = s.discretisation.spacing;
    let (n_fluid, n_solid) = (s.fluid_blocks.len() as u32, s.solids.len() as u32);
    let volume = |field: String, group: u32, outline| Placed {
        field,
        group,
        outline,
        grow: 0.0,
        open: false,
    };
    let mut out: Vec<Placed<'_>> = Vec::new();
    for (i, b) in s.fluid_blocks.iter().enumerate() {
        if let Some(o) = b.inside.as_ref() {
            out.push(volume(format!("fluid_blocks[{i}].inside"), i as u32, o));
        }
    }
    for (i, o) in s.solids.iter().enumerate() {
        let g = n_fluid + i as u32;
        match o {
            SolidObject::Mesh { mesh: o, .. } => {
                out.push(volume(format!("solids[{i}].mesh"), g, o))
            }
            SolidObject::Polygon { polygon: o, .. } => {
                out.push(volume(format!("solids[{i}].polygon"), g, o))
            }
            _ => {}
        }
    }
    for (i, w) in s.walls.iter().enumerate() {
        let (key, o, solid, layers) = match w {
            Wall::Mesh {
                mesh: o,
                solid,
                layers,
                ..
            } => ("mesh", o, *solid, *layers),
            Wall::Polygon {
                polygon: o,
                solid,
                layers,
                ..
            } => ("polygon", o, *solid, *layers),
            _ => continue,
        };
        out.push(Placed {
            field: format!("walls[{i}].{key}"),
            group: n_fluid + n_solid + i as u32,
            outline: o,
            grow: if solid == Side::Outside {
                layers as f64 * dx
            } else {
                0.0
            },
            open: solid.open(),
        });
    }
    out
}

/// Reads every surface of `s` from `base` (`geometry::load`): the first that cannot be read
/// or is no closed surface is the error. A scene whose dimension is neither 2 nor 3 is
/// left to the checks.
pub(in crate::scene) fn load_all(
    s: &SceneFile,
    origin: &str,
    base: &Base,
) -> Result<(), SceneError> {
    if s.dimension != 2 && s.dimension != 3 {
        return Ok(());
    }
    let c = Ctx::new(origin, s.dimension as usize);
    shapes_fit(&c, s)?;
    for p in surfaces(s) {
        if p.outline.loaded.get().is_none() {
            let surface: Surface = load(&c, &p.field, p.outline, p.open, base)?;
            p.outline.loaded.set(surface);
        }
    }
    Ok(())
}

/// A `mesh` is a 3D shape and a `polygon` a 2D one.
fn shapes_fit(c: &Ctx, s: &SceneFile) -> R {
    let wrong = |field: String, shape: &str| {
        let (other, dim) = if shape == "mesh" {
            ("polygon", 2)
        } else {
            ("mesh", 3)
        };
        Err(c.err(
            format!("{field}.shape"),
            format!(
                "a \"{shape}\" is a {}D shape; use \"{other}\" in a {dim}D scene",
                5 - dim
            ),
        ))
    };
    for (i, o) in s.solids.iter().enumerate() {
        match o {
            SolidObject::Mesh { .. } if c.dim == 2 => return wrong(format!("solids[{i}]"), "mesh"),
            SolidObject::Polygon { .. } if c.dim == 3 => {
                return wrong(format!("solids[{i}]"), "polygon")
            }
            _ => {}
        }
    }
    for (i, w) in s.walls.iter().enumerate() {
        match w {
            Wall::Mesh { .. } if c.dim == 2 => return wrong(format!("walls[{i}]"), "mesh"),
            Wall::Polygon { .. } if c.dim == 3 => return wrong(format!("walls[{i}]"), "polygon"),
            Wall::Mesh { solid, .. } | Wall::Polygon { solid, .. } => {
                let (why, fits) = if c.dim == 3 {
                    (
                        "a 3D mesh's sides are \"inside\" and \"outside\" (closed), or \"back\" and \"front\" of its faces (open)",
                        !matches!(solid, Side::Left | Side::Right),
                    )
                } else {
                    (
                        "a 2D polygon's sides are \"inside\" and \"outside\" (closed), or \"left\" and \"right\" of a line walked from its first point to its last (open)",
                        !matches!(solid, Side::Back | Side::Front),
                    )
                };
                if !fits {
                    return Err(c.err(format!("walls[{i}].solid"), why));
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Every surface of `s` is loaded, lies in the domain (a wall's with its rows outside it)
/// and is larger than one spacing; the likely unit slip (a file in mm read as m) is named.
pub(in crate::scene) fn check(c: &Ctx, s: &SceneFile) -> R {
    let dx = s.discretisation.spacing;
    let domain = &s.domain;
    for Placed {
        field,
        outline: o,
        grow,
        ..
    } in surfaces(s)
    {
        let Some(surface) = o.loaded.get() else {
            return Err(c.err(
                &field,
                "the surface was not read (a scene built in code must be read with Scene::from_toml_in)",
            ));
        };
        let info = &surface.info;
        let size = (0..c.dim)
            .map(|a| info.hi[a] - info.lo[a])
            .fold(0.0, f64::max);
        let span = (0..c.dim)
            .map(|a| domain.max[a] - domain.min[a])
            .fold(0.0, f64::max);
        let hint = unit_hint(size, span, o.scale);
        if size < dx {
            return Err(c.err(
                format!("{field}.scale"),
                format!(
                    "the surface is {} across, less than one spacing ({dx}): it makes no \
                     particle{hint}",
                    fmt(size)
                ),
            ));
        }
        let lo: Vec<f64> = info.lo[..c.dim].iter().map(|x| x - grow).collect();
        let hi: Vec<f64> = info.hi[..c.dim].iter().map(|x| x + grow).collect();
        let what = if grow > 0.0 {
            "the surface with its wall rows"
        } else {
            "the surface"
        };
        c.inside(&field, what, &lo, &hi, domain)
            .map_err(|e| match e {
                SceneError::Invalid {
                    origin,
                    field,
                    reason,
                } => SceneError::Invalid {
                    origin,
                    field,
                    reason: format!("{reason}{hint}"),
                },
                e => e,
            })?;
    }
    Ok(())
}

/// A hint where the surface's `size` is about 1000 times the domain's `span` or a
/// thousandth of it: a file in millimetres in a scene in metres, or the other way.
fn unit_hint(size: f64, span: f64, scale: f64) -> String {
    let ratio = size / span;
    if (100.0..100_000.0).contains(&ratio) {
        format!(
            " (it is {}x the domain: a file in millimetres? scale = {})",
            fmt(ratio),
            fmt(scale * 0.001)
        )
    } else if (1e-5..1e-2).contains(&ratio) {
        format!(
            " (it is {}x the domain: a file in metres for a scene in millimetres? scale = {})",
            fmt(ratio),
            fmt(scale * 1000.0)
        )
    } else {
        String::new()
    }
}

impl crate::scene::Scene {
    /// \[s\] the time its surfaces took to read (`Info::read_seconds`), part of a run's
    /// set-up.
    pub fn surfaces_seconds(&self) -> f64 {
        surfaces(&self.file)
            .iter()
            .filter_map(|p| p.outline.loaded.get())
            .map(|s| s.info.read_seconds)
            .sum()
    }
}
