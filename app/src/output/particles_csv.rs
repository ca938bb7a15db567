//! Plain particle CSV, one row per particle, for comparisons with other codes
//! (`meshfree compare`): `id,kind,x,y,z,vx,vy,vz,density,pressure`, kind as its name.

use std::fmt::Write as _;
use std::io;
use std::path::Path;

use meshfree_core::particle::{Kind, Particle};

pub const HEADER: &str = "id,kind,x,y,z,vx,vy,vz,density,pressure";

/// Write the particles (callers pass them ordered by id).
pub fn write_particles_csv(path: &Path, particles: &[Particle]) -> io::Result<()> {
    let mut s = String::with_capacity(particles.len() * 96 + 64);
    s.push_str(HEADER);
    s.push('\n');
    for p in particles {
        let [x, y, z] = p.position;
        let [u, v, w] = p.velocity;
        let _ = writeln!(
            s,
            "{},{},{x},{y},{z},{u},{v},{w},{},{}",
            p.id,
            p.kind.name(),
            p.density,
            p.pressure
        );
    }
    std::fs::write(path, s)
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
