//! Plain particle CSV, one row per particle ordered by id, for comparisons with other codes
//! (`meshfree compare`) and pandas: `id,kind,x,y,z,vx,vy,vz,density,pressure` (kind as its
//! code: 0 fluid, 1 solid, 2 boundary, as in the VTU files; a reader takes the name too), then `group` and the stress `sxx,syy,szz,sxy,sxz,syz`; a field the scene's
//! `[output] fields` leaves out leaves out its columns.

use std::fmt::Write as _;
use std::io;
use std::path::Path;

use meshfree_core::physics::particle::{Kind, Particle};
use meshfree_core::solver::frame::{Field, Fields, FrameData};

pub const HEADER: &str = "id,kind,x,y,z,vx,vy,vz,density,pressure";

/// Write the `fields` of the frame's particles, ordered by id where it has ids (through a temporary file
/// and a rename). Returns the bytes written.
pub fn write_particles_csv(path: &Path, f: &FrameData, fields: Fields) -> io::Result<u64> {
    let mut order: Vec<usize> = (0..f.len).collect();
    if !f.id.is_empty() {
        order.sort_unstable_by_key(|&i| f.id[i]);
    }
    let on = |field: Field, len: usize| fields.has(field) && len == f.len && f.len > 0;
    let mut cols: Vec<&str> = Vec::new();
    if on(Field::Id, f.id.len()) {
        cols.push("id");
    }
    if on(Field::Kind, f.kind.len()) {
        cols.push("kind");
    }
    cols.extend(["x", "y", "z"]);
    if on(Field::Velocity, f.velocity.len()) {
        cols.extend(["vx", "vy", "vz"]);
    }
    if on(Field::Density, f.density.len()) {
        cols.push("density");
    }
    if on(Field::Pressure, f.pressure.len()) {
        cols.push("pressure");
    }
    if on(Field::Group, f.group.len()) {
        cols.push("group");
    }
    if on(Field::Stress, f.stress.len()) {
        cols.extend(["sxx", "syy", "szz", "sxy", "sxz", "syz"]);
    }
    let mut s = String::with_capacity(f.len * 96 + 128);
    s.push_str(&cols.join(","));
    s.push('\n');
    for i in order {
        let mut row = Vec::<String>::with_capacity(cols.len());
        if on(Field::Id, f.id.len()) {
            row.push(f.id[i].to_string());
        }
        if on(Field::Kind, f.kind.len()) {
            // The code, 0 fluid, 1 solid, 2 boundary, as in the VTU files (issue #51); the
            // readers take the name as well.
            row.push(f.kind[i].to_string());
        }
        let x = f.position.get(i).copied().unwrap_or_default();
        row.extend(x.iter().map(f32::to_string));
        if on(Field::Velocity, f.velocity.len()) {
            row.extend(f.velocity[i].iter().map(f32::to_string));
        }
        if on(Field::Density, f.density.len()) {
            row.push(f.density[i].to_string());
        }
        if on(Field::Pressure, f.pressure.len()) {
            row.push(f.pressure[i].to_string());
        }
        if on(Field::Group, f.group.len()) {
            row.push(f.group[i].to_string());
        }
        if on(Field::Stress, f.stress.len()) {
            row.extend(f.stress[i].iter().map(f32::to_string));
        }
        let _ = writeln!(s, "{}", row.join(","));
    }
    super::write_atomic(path, s.as_bytes())?;
    Ok(s.len() as u64)
}

/// Read a particle CSV written by `write_particles_csv` (or by another code in the same
/// columns; extra columns after `pressure` are ignored). Errors name the file, the line and
/// the field.
pub fn read_particles_csv(path: &Path) -> Result<Vec<Particle>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines().enumerate();
    let Some((_, header)) = lines.next() else {
        return Err(format!("{}: empty file", path.display()));
    };
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let want: Vec<&str> = HEADER.split(',').collect();
    if names.len() < want.len() || names[..want.len()] != want[..] {
        return Err(format!(
            "{}: line 1: header must start with `{HEADER}`",
            path.display()
        ));
    }
    let mut out = Vec::new();
    for (k, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let at = |i: usize| -> Result<&str, String> {
            f.get(i).copied().ok_or_else(|| {
                format!(
                    "{}: line {}: no `{}` column",
                    path.display(),
                    k + 1,
                    want[i]
                )
            })
        };
        let num = |i: usize| -> Result<f32, String> {
            at(i)?
                .parse::<f32>()
                .map_err(|e| format!("{}: line {}: `{}`: {e}", path.display(), k + 1, want[i]))
        };
        let kind_text = at(1)?;
        let kind = Kind::ALL
            .into_iter()
            .find(|c| c.name() == kind_text || c.code().to_string() == kind_text)
            .ok_or_else(|| {
                format!(
                    "{}: line {}: `kind`: unknown kind `{kind_text}`",
                    path.display(),
                    k + 1
                )
            })?;
        out.push(Particle {
            id: at(0)?
                .parse()
                .map_err(|e| format!("{}: line {}: `id`: {e}", path.display(), k + 1))?,
            kind,
            position: [num(2)?, num(3)?, num(4)?],
            velocity: [num(5)?, num(6)?, num(7)?],
            density: num(8)?,
            pressure: num(9)?,
            ..Default::default()
        });
    }
    Ok(out)
}
