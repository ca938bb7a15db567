//! VTK XML output for ParaView, the `vtk` Python module and meshio: one `.vtu`
//! (UnstructuredGrid) per output with the arrays as raw binary appended data (optionally
//! zlib-compressed) and one vertex cell per particle (so ParaView's Threshold and meshio
//! see every particle), and a `.pvd` collection of all of them.
//!
//! Layout (VTK file format version 1.0, little endian, UInt64 headers): each frame field is
//! a point-data array named as in the scene's `[output] fields` (velocity and stress with 3
//! and 6 components, stress as xx yy zz xy xz yz), the positions are the Points, and the
//! cells are n `VTK_VERTEX`es (connectivity i, offsets i + 1, Int32 below 2^31 points).
//! Arrays appear in the frame's storage order; `id` says which particle a row is.

use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use meshfree_core::solver::frame::{Field, Fields, FrameData};

/// VTK's cell type of a single point.
const VTK_VERTEX: u8 = 1;

/// Uncompressed bytes per zlib block (VTK's vtkZLibDataCompressor block layout).
const ZLIB_BLOCK: usize = 1 << 20;

/// One array of the appended section.
struct Array<'a> {
    name: &'static str,
    ty: &'static str,
    comps: usize,
    bytes: std::borrow::Cow<'a, [u8]>,
}

fn arr<'a, T: bytemuck::Pod>(
    name: &'static str,
    ty: &'static str,
    comps: usize,
    v: &'a [T],
) -> Array<'a> {
    Array {
        name,
        ty,
        comps,
        bytes: std::borrow::Cow::Borrowed(bytemuck::cast_slice(v)),
    }
}

/// Write `frame` to `path` (through a temporary file and a rename: a reader never sees
/// half a file): the `fields` it carries (position always). `zlib`: compress each array. Returns the bytes written.
pub fn write_vtu(path: &Path, frame: &FrameData, fields: Fields, zlib: bool) -> io::Result<u64> {
    let n = frame.len;
    let on = |f: Field, len: usize| fields.has(f) && len == n && n > 0;
    let mut point_data = Vec::new();
    if on(Field::Id, frame.id.len()) {
        point_data.push(arr("id", "UInt32", 1, &frame.id));
    }
    if on(Field::Kind, frame.kind.len()) {
        point_data.push(arr("kind", "UInt8", 1, &frame.kind));
    }
    if on(Field::Group, frame.group.len()) {
        point_data.push(arr("group", "UInt32", 1, &frame.group));
    }
    if on(Field::Velocity, frame.velocity.len()) {
        point_data.push(arr("velocity", "Float32", 3, &frame.velocity));
    }
    if on(Field::Density, frame.density.len()) {
        point_data.push(arr("density", "Float32", 1, &frame.density));
    }
    if on(Field::Pressure, frame.pressure.len()) {
        point_data.push(arr("pressure", "Float32", 1, &frame.pressure));
    }
    if on(Field::Stress, frame.stress.len()) {
        point_data.push(arr("stress", "Float32", 6, &frame.stress));
    }
    let zeros;
    let points = if frame.position.is_empty() {
        zeros = vec![[0.0f32; 3]; n];
        arr("Points", "Float32", 3, &zeros)
    } else {
        arr("Points", "Float32", 3, &frame.position)
    };
    let cells = cell_arrays(n);

    let mut xml = String::with_capacity(4096);
    xml.push_str("<?xml version=\"1.0\"?>\n");
    let _ = writeln!(
        xml,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"{}>",
        if zlib { " compressor=\"vtkZLibDataCompressor\"" } else { "" }
    );
    xml.push_str("  <UnstructuredGrid>\n");
    let _ = writeln!(
        xml,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{n}\">"
    );

    // Encode every array (compressed in parallel blocks where asked), then lay out offsets.
    // A raw array is its UInt64 byte count followed by its bytes, written from the frame.
    let mut offset = 0usize;
    let mut blobs: Vec<Vec<u8>> = Vec::new();
    let mut tag = |xml: &mut String, a: &Array, blobs: &mut Vec<Vec<u8>>| {
        let blob = if zlib {
            zlib_blocks(&a.bytes)
        } else {
            (a.bytes.len() as u64).to_le_bytes().to_vec()
        };
        let raw_len = if zlib { 0 } else { a.bytes.len() };
        let name = if a.name == "Points" {
            String::new()
        } else {
            format!(" Name=\"{}\"", a.name)
        };
        let _ = writeln!(
            xml,
            "        <DataArray type=\"{}\"{name} NumberOfComponents=\"{}\" format=\"appended\" offset=\"{offset}\"/>",
            a.ty, a.comps
        );
        offset += blob.len() + raw_len;
        blobs.push(blob);
    };
    let scalars = ["pressure", "density"]
        .into_iter()
        .find(|s| point_data.iter().any(|a| a.name == *s));
    let _ = writeln!(
        xml,
        "      <PointData{}{}>",
        scalars.map_or(String::new(), |s| format!(" Scalars=\"{s}\"")),
        if on(Field::Velocity, frame.velocity.len()) {
            " Vectors=\"velocity\""
        } else {
            ""
        }
    );
    for a in &point_data {
        tag(&mut xml, a, &mut blobs);
    }
    xml.push_str("      </PointData>\n      <Points>\n");
    tag(&mut xml, &points, &mut blobs);
    xml.push_str("      </Points>\n      <Cells>\n");
    for a in &cells {
        tag(&mut xml, a, &mut blobs);
    }
    xml.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
    xml.push_str("  <AppendedData encoding=\"raw\">\n   _");

    let (atomic, file) = super::files::Atomic::create(path)?;
    let written = (|| -> io::Result<u64> {
        let mut w = io::BufWriter::with_capacity(1 << 22, file);
        w.write_all(xml.as_bytes())?;
        let mut total = xml.len() as u64;
        let arrays = point_data.iter().chain([&points]).chain(cells.iter());
        for (head, a) in blobs.iter().zip(arrays) {
            w.write_all(head)?;
            total += head.len() as u64;
            if !zlib {
                w.write_all(&a.bytes)?;
                total += a.bytes.len() as u64;
            }
        }
        const TAIL: &[u8] = b"\n  </AppendedData>\n</VTKFile>\n";
        w.write_all(TAIL)?;
        w.flush()?;
        Ok(total + TAIL.len() as u64)
    })();
    let bytes = written?;
    atomic.commit()?;
    Ok(bytes)
}

/// connectivity, offsets and types of n vertex cells.
fn cell_arrays(n: usize) -> [Array<'static>; 3] {
    fn bytes<T: bytemuck::Pod>(v: Vec<T>) -> Vec<u8> {
        bytemuck::cast_slice(&v).to_vec()
    }
    let (connectivity, offsets, ty) = if n < i32::MAX as usize {
        let c: Vec<i32> = (0..n as i32).collect();
        let o: Vec<i32> = (1..=n as i32).collect();
        (bytes(c), bytes(o), "Int32")
    } else {
        let c: Vec<i64> = (0..n as i64).collect();
        let o: Vec<i64> = (1..=n as i64).collect();
        (bytes(c), bytes(o), "Int64")
    };
    let owned = |name, ty, bytes| Array {
        name,
        ty,
        comps: 1,
        bytes: std::borrow::Cow::Owned(bytes),
    };
    [
        owned("connectivity", ty, connectivity),
        owned("offsets", ty, offsets),
        owned("types", "UInt8", vec![VTK_VERTEX; n]),
    ]
}

/// VTK's zlib layout: a header of UInt64s [blocks, block size, size of the last block if
/// partial (else 0), compressed size of each block], then the compressed blocks. Blocks
/// are compressed in parallel.
fn zlib_blocks(data: &[u8]) -> Vec<u8> {
    let blocks: Vec<Vec<u8>> = data
        .par_chunks(ZLIB_BLOCK)
        .map(|chunk| {
            let mut e = flate2::write::ZlibEncoder::new(
                Vec::with_capacity(chunk.len() / 2),
                flate2::Compression::fast(),
            );
            e.write_all(chunk).expect("writing to a Vec");
            e.finish().expect("writing to a Vec")
        })
        .collect();
    let last = data.len() % ZLIB_BLOCK;
    let mut out =
        Vec::with_capacity(8 * (3 + blocks.len()) + blocks.iter().map(Vec::len).sum::<usize>());
    for h in [blocks.len(), ZLIB_BLOCK, last] {
        out.extend_from_slice(&(h as u64).to_le_bytes());
    }
    for b in &blocks {
        out.extend_from_slice(&(b.len() as u64).to_le_bytes());
    }
    for b in &blocks {
        out.extend_from_slice(b);
    }
    out
}

/// A `.pvd` collection, rewritten (atomically) after every `add` so a partial run is
/// readable.
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

    /// The series `path` listing `entries` (time, relative file name), as a run continued
    /// from a checkpoint has it; nothing written yet.
    pub fn with_entries(path: impl Into<PathBuf>, entries: Vec<(f64, String)>) -> PvdSeries {
        PvdSeries {
            path: path.into(),
            entries,
        }
    }

    /// Add a data file (relative name) at `time` and rewrite the collection.
    pub fn add(&mut self, time: f64, file: &str) -> io::Result<()> {
        self.entries.push((time, file.to_string()));
        self.write()
    }

    /// Write the collection (atomically).
    pub fn write(&self) -> io::Result<()> {
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
