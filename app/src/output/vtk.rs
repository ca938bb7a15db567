//! VTK XML output for ParaView: one `.vtu` (UnstructuredGrid, ASCII) per output time with
//! the particles as one poly-vertex cell, and a `.pvd` collection of all of them.

use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

use meshfree_core::particle::Particle;

/// Write the particles (in the order given: callers pass them ordered by id) to `path`.
/// Point data: id, kind, group, velocity (3), speed, density, pressure, and stress
/// (6 components xx yy zz xy xz yz) when `with_stress`.
pub fn write_vtu(path: &Path, particles: &[Particle], with_stress: bool) -> io::Result<()> {
    let n = particles.len();
    let mut s = String::with_capacity(n * 160 + 2048);
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
    s.push_str("  <UnstructuredGrid>\n");
    let cells = if n > 0 { 1 } else { 0 };
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{cells}\">"
    );

    s.push_str("      <PointData Scalars=\"speed\" Vectors=\"velocity\">\n");
    array(
        &mut s,
        "id",
        "UInt32",
        1,
        particles.iter().map(|p| p.id.to_string()),
    );
    array(
        &mut s,
        "kind",
        "UInt8",
        1,
        particles.iter().map(|p| p.kind.code().to_string()),
    );
    array(
        &mut s,
        "group",
        "UInt32",
        1,
        particles.iter().map(|p| p.group.to_string()),
    );
    array(
        &mut s,
        "velocity",
        "Float32",
        3,
        particles
            .iter()
            .map(|p| format!("{} {} {}", p.velocity[0], p.velocity[1], p.velocity[2])),
    );
    array(
        &mut s,
        "speed",
        "Float32",
        1,
        particles.iter().map(|p| p.speed().to_string()),
    );
    array(
        &mut s,
        "density",
        "Float32",
        1,
        particles.iter().map(|p| p.density.to_string()),
    );
    array(
        &mut s,
        "pressure",
        "Float32",
        1,
        particles.iter().map(|p| p.pressure.to_string()),
    );
    if with_stress {
        array(
            &mut s,
            "stress",
            "Float32",
            6,
            particles.iter().map(|p| {
                p.stress
                    .iter()
                    .map(|x| x.to_string())
                    .collect::<Vec<_>>()
                    .join(" ")
            }),
        );
    }
    s.push_str("      </PointData>\n");

    s.push_str("      <Points>\n");
    array(
        &mut s,
        "Points",
        "Float32",
        3,
        particles
            .iter()
            .map(|p| format!("{} {} {}", p.position[0], p.position[1], p.position[2])),
    );
    s.push_str("      </Points>\n");

    // One VTK_POLY_VERTEX (type 2) cell holding every point, so ParaView draws them.
    s.push_str("      <Cells>\n");
    array(
        &mut s,
        "connectivity",
        "Int64",
        1,
        (0..n).map(|i| i.to_string()),
    );
    array(
        &mut s,
        "offsets",
        "Int64",
        1,
        (0..cells).map(|_| n.to_string()),
    );
    array(
        &mut s,
        "types",
        "UInt8",
        1,
        (0..cells).map(|_| "2".to_string()),
    );
    s.push_str("      </Cells>\n");
    s.push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    super::write_atomic(path, s.as_bytes())
}

/// An ASCII DataArray, 8 tuples a line.
fn array(s: &mut String, name: &str, ty: &str, comps: usize, values: impl Iterator<Item = String>) {
    let _ = writeln!(
        s,
        "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{comps}\" format=\"ascii\">"
    );
    let per_line = if comps == 1 { 16 } else { 4 };
    for (i, v) in values.enumerate() {
        if i % per_line == 0 {
            if i > 0 {
                s.push('\n');
            }
            s.push_str("          ");
        } else {
            s.push(' ');
        }
        s.push_str(&v);
    }
    s.push_str("\n        </DataArray>\n");
}

/// A `.pvd` collection, rewritten after every `add` so a partial run is readable.
#[derive(Clone, Debug)]
pub struct PvdSeries {
    path: PathBuf,
    entries: Vec<(f64, String)>,
}

impl PvdSeries {
    /// The series file `path`; the data files are named relative to its directory.
    pub fn new(path: impl Into<PathBuf>) -> PvdSeries {
        PvdSeries {
            path: path.into(),
            entries: Vec::new(),
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    /// Add a data file (relative name) at `time` and rewrite the collection.
    pub fn add(&mut self, time: f64, file: &str) -> io::Result<()> {
        self.entries.push((time, file.to_string()));
        let mut s = String::new();
        s.push_str("<?xml version=\"1.0\"?>\n");
        s.push_str("<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n");
        s.push_str("  <Collection>\n");
        for (t, f) in &self.entries {
            let _ = writeln!(
                s,
                "    <DataSet timestep=\"{t}\" group=\"\" part=\"0\" file=\"{f}\"/>"
            );
        }
        s.push_str("  </Collection>\n</VTKFile>\n");
        super::write_atomic(&self.path, s.as_bytes())
    }
}
