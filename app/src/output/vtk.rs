//! VTK XML output for ParaView, the `vtk` Python module and meshio: one `.vtu`
//! (UnstructuredGrid) per output with the arrays as binary appended data, raw or compressed
//! in 1 MiB blocks by VTK's zlib or LZ4 compressor, and one vertex cell per particle (so
//! ParaView's Threshold and meshio see every particle), and a `.pvd` collection of all of
//! them.
//!
//! Layout (VTK file format version 1.0, little endian, UInt64 headers): each frame field is
//! a point-data array named as in the scene's `[output] fields` (velocity and stress with 3
//! and 6 components, stress as xx yy zz xy xz yz; `group` in the narrowest unsigned type that
//! holds the scene's largest group: UInt8, UInt16 or UInt32), the positions are the Points,
//! and the cells are n `VTK_VERTEX`es (connectivity i, offsets i + 1, Int32 below 2^31
//! points). Arrays appear in the frame's storage order; `id` says which particle a row is.
//!
//! A run's writer keeps one `VtuWriter`: the cells' arrays depend only on the particle count,
//! so they are built and compressed once and written again from memory at every frame.

use std::borrow::Cow;
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;

use meshfree_core::scene::format::OutputFormat;
use meshfree_core::solver::frame::{Field, Fields, FrameData};

/// VTK's cell type of a single point.
const VTK_VERTEX: u8 = 1;

/// Uncompressed bytes per compressed block (the block layout of VTK's compressors).
const BLOCK: usize = 1 << 20;

/// How the arrays of a VTU are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compression {
    /// Each array's bytes as they are, after their UInt64 count.
    Raw,
    /// `vtkZLibDataCompressor` (zlib at its fastest level): about 2-4x smaller, slow.
    Zlib,
    /// `vtkLZ4DataCompressor` (the LZ4 block format): less small than zlib, many times faster
    /// to write and read.
    Lz4,
}

impl Compression {
    /// The compression of a VTU format; None for the formats that are not VTU.
    pub fn of(format: OutputFormat) -> Option<Compression> {
        match format {
            OutputFormat::Vtu => Some(Compression::Raw),
            OutputFormat::VtuZlib => Some(Compression::Zlib),
            OutputFormat::VtuLz4 => Some(Compression::Lz4),
            OutputFormat::Csv | OutputFormat::None => None,
        }
    }

    /// The `compressor` attribute of the `VTKFile` tag (none for raw data).
    pub fn vtk_name(self) -> Option<&'static str> {
        match self {
            Compression::Raw => None,
            Compression::Zlib => Some("vtkZLibDataCompressor"),
            Compression::Lz4 => Some("vtkLZ4DataCompressor"),
        }
    }

    /// The compression a `compressor` attribute names (none: raw).
    pub fn from_vtk_name(name: Option<&str>) -> Result<Compression, String> {
        [Compression::Raw, Compression::Zlib, Compression::Lz4]
            .into_iter()
            .find(|c| c.vtk_name() == name)
            .ok_or_else(|| {
                format!(
                    "compressor `{}`: only zlib and LZ4 are read",
                    name.unwrap_or_default()
                )
            })
    }

    /// One block compressed.
    fn block(self, chunk: &[u8]) -> Vec<u8> {
        match self {
            Compression::Raw => chunk.to_vec(),
            Compression::Zlib => {
                let mut e = flate2::write::ZlibEncoder::new(
                    Vec::with_capacity(chunk.len() / 2),
                    flate2::Compression::fast(),
                );
                e.write_all(chunk).expect("writing to a Vec");
                e.finish().expect("writing to a Vec")
            }
            Compression::Lz4 => lz4_flex::block::compress(chunk),
        }
    }

    /// One block decompressed into `out` (`len`: its uncompressed size, from the header).
    pub fn unblock(self, chunk: &[u8], len: usize, out: &mut Vec<u8>) -> Result<(), String> {
        use std::io::Read as _;
        let start = out.len();
        match self {
            Compression::Raw => out.extend_from_slice(chunk),
            Compression::Zlib => {
                flate2::read::ZlibDecoder::new(chunk)
                    .read_to_end(out)
                    .map_err(|e| e.to_string())?;
            }
            Compression::Lz4 => {
                // LZ4 expands at most 255 times: a larger size is a damaged header, not an
                // allocation to make.
                if len > chunk.len().saturating_mul(255).saturating_add(16) {
                    return Err(format!(
                        "{} compressed bytes cannot hold the {len} of its header",
                        chunk.len()
                    ));
                }
                out.resize(start + len, 0);
                let got = lz4_flex::block::decompress_into(chunk, &mut out[start..])
                    .map_err(|e| e.to_string())?;
                out.truncate(start + got);
            }
        }
        match out.len() - start {
            got if got == len => Ok(()),
            got => Err(format!("holds {got} bytes, its header says {len}")),
        }
    }

    /// One array in VTK's layout: raw, its UInt64 byte count (the bytes follow, written from
    /// the frame); compressed, a header of UInt64s [blocks, block size, size of the last block
    /// if partial (else 0), compressed size of each block], then the blocks, compressed in
    /// parallel.
    fn head(self, data: &[u8]) -> Vec<u8> {
        if self == Compression::Raw {
            return (data.len() as u64).to_le_bytes().to_vec();
        }
        let blocks: Vec<Vec<u8>> = data.par_chunks(BLOCK).map(|c| self.block(c)).collect();
        let last = data.len() % BLOCK;
        let mut out =
            Vec::with_capacity(8 * (3 + blocks.len()) + blocks.iter().map(Vec::len).sum::<usize>());
        for h in [blocks.len(), BLOCK, last] {
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
}

/// One array of the appended section.
struct Array<'a> {
    name: &'static str,
    ty: &'static str,
    comps: usize,
    bytes: Cow<'a, [u8]>,
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
        bytes: Cow::Borrowed(bytemuck::cast_slice(v)),
    }
}

/// The groups in the narrowest unsigned type that holds the largest.
fn group_array(group: &[u32]) -> Array<'_> {
    let max = group.par_iter().copied().max().unwrap_or(0);
    if max <= u32::from(u8::MAX) {
        let v: Vec<u8> = group.par_iter().map(|&g| g as u8).collect();
        Array {
            name: "group",
            ty: "UInt8",
            comps: 1,
            bytes: Cow::Owned(v),
        }
    } else if max <= u32::from(u16::MAX) {
        let v: Vec<u16> = group.par_iter().map(|&g| g as u16).collect();
        Array {
            name: "group",
            ty: "UInt16",
            comps: 1,
            bytes: Cow::Owned(bytemuck::cast_slice(&v).to_vec()),
        }
    } else {
        arr("group", "UInt32", 1, group)
    }
}

/// The seconds a frame's file took: building and compressing its arrays, and writing.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VtuTimes {
    pub encode_seconds: f64,
    pub write_seconds: f64,
}

/// The cells' arrays of one particle count, each in its file layout (head and bytes).
struct Cells {
    n: usize,
    ty: &'static str,
    blobs: [Vec<u8>; 3],
}

/// A run's VTU writer: the compression, and the cells' arrays kept from frame to frame.
pub struct VtuWriter {
    compression: Compression,
    cells: Option<Cells>,
}

/// Write `frame` to `path` with a writer of its own (`VtuWriter::write`). Returns the bytes
/// written.
pub fn write_vtu(
    path: &Path,
    frame: &FrameData,
    fields: Fields,
    compression: Compression,
) -> io::Result<u64> {
    VtuWriter::new(compression)
        .write(path, frame, fields)
        .map(|(bytes, _)| bytes)
}

impl VtuWriter {
    pub fn new(compression: Compression) -> VtuWriter {
        VtuWriter {
            compression,
            cells: None,
        }
    }

    /// The cells of `n` vertices, built and compressed at the first frame of that count.
    fn cells(&mut self, n: usize) -> &Cells {
        if self.cells.as_ref().is_none_or(|c| c.n != n) {
            fn bytes<T: bytemuck::Pod + Send + Sync>(v: Vec<T>) -> Vec<u8> {
                bytemuck::cast_slice(&v).to_vec()
            }
            let (connectivity, offsets, ty) = if n < i32::MAX as usize {
                let c: Vec<i32> = (0..n as i32).into_par_iter().collect();
                let o: Vec<i32> = (1..=n as i32).into_par_iter().collect();
                (bytes(c), bytes(o), "Int32")
            } else {
                let c: Vec<i64> = (0..n as i64).into_par_iter().collect();
                let o: Vec<i64> = (1..=n as i64).into_par_iter().collect();
                (bytes(c), bytes(o), "Int64")
            };
            let c = self.compression;
            let blob = |data: Vec<u8>| {
                let mut b = c.head(&data);
                if c == Compression::Raw {
                    b.extend_from_slice(&data);
                }
                b
            };
            self.cells = Some(Cells {
                n,
                ty,
                blobs: [blob(connectivity), blob(offsets), blob(vec![VTK_VERTEX; n])],
            });
        }
        self.cells.as_ref().expect("just built")
    }

    /// Write `frame` to `path` (through a temporary file and a rename: a reader never sees
    /// half a file): the `fields` it carries (position always). Returns the bytes written
    /// and the time spent encoding and writing.
    pub fn write(
        &mut self,
        path: &Path,
        frame: &FrameData,
        fields: Fields,
    ) -> io::Result<(u64, VtuTimes)> {
        let started = Instant::now();
        let n = frame.len;
        let compression = self.compression;
        let on = |f: Field, len: usize| fields.has(f) && len == n && n > 0;
        let mut point_data = Vec::new();
        if on(Field::Id, frame.id.len()) {
            point_data.push(arr("id", "UInt32", 1, &frame.id));
        }
        if on(Field::Kind, frame.kind.len()) {
            point_data.push(arr("kind", "UInt8", 1, &frame.kind));
        }
        if on(Field::Group, frame.group.len()) {
            point_data.push(group_array(&frame.group));
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
        // Each array's head (compressed: the whole array) and, raw, its bytes after it.
        let heads: Vec<Vec<u8>> = point_data
            .iter()
            .chain([&points])
            .map(|a| compression.head(&a.bytes))
            .collect();
        let cells = self.cells(n);

        let mut xml = String::with_capacity(4096);
        xml.push_str("<?xml version=\"1.0\"?>\n");
        let _ = writeln!(
            xml,
            "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"{}>",
            compression
                .vtk_name()
                .map_or(String::new(), |c| format!(" compressor=\"{c}\""))
        );
        xml.push_str("  <UnstructuredGrid>\n");
        let _ = writeln!(
            xml,
            "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{n}\">"
        );
        let mut offset = 0usize;
        let mut tag = |xml: &mut String, name: &str, ty: &str, comps: usize, size: usize| {
            let name = if name == "Points" {
                String::new()
            } else {
                format!(" Name=\"{name}\"")
            };
            let _ = writeln!(
                xml,
                "        <DataArray type=\"{ty}\"{name} NumberOfComponents=\"{comps}\" format=\"appended\" offset=\"{offset}\"/>",
            );
            offset += size;
        };
        let raw = |a: &Array| {
            if compression == Compression::Raw {
                a.bytes.len()
            } else {
                0
            }
        };
        let scalars = ["pressure", "density"]
            .into_iter()
            .find(|s| point_data.iter().any(|a| a.name == *s));
        let _ = writeln!(
            xml,
            "      <PointData{}{}>",
            scalars.map_or(String::new(), |s| format!(" Scalars=\"{s}\"")),
            if point_data.iter().any(|a| a.name == "velocity") {
                " Vectors=\"velocity\""
            } else {
                ""
            }
        );
        for (a, head) in point_data.iter().zip(&heads) {
            tag(&mut xml, a.name, a.ty, a.comps, head.len() + raw(a));
        }
        xml.push_str("      </PointData>\n      <Points>\n");
        tag(
            &mut xml,
            "Points",
            "Float32",
            3,
            heads[point_data.len()].len() + raw(&points),
        );
        xml.push_str("      </Points>\n      <Cells>\n");
        let cell_names = [
            ("connectivity", cells.ty),
            ("offsets", cells.ty),
            ("types", "UInt8"),
        ];
        for ((name, ty), blob) in cell_names.into_iter().zip(&cells.blobs) {
            tag(&mut xml, name, ty, 1, blob.len());
        }
        xml.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n");
        xml.push_str("  <AppendedData encoding=\"raw\">\n   _");
        let encoded = Instant::now();

        // The file, in order: the head, each point array's head and (raw) bytes, the cells.
        const TAIL: &[u8] = b"\n  </AppendedData>\n</VTKFile>\n";
        let mut parts: Vec<&[u8]> = vec![xml.as_bytes()];
        for (a, head) in point_data.iter().chain([&points]).zip(&heads) {
            parts.push(head);
            if compression == Compression::Raw {
                parts.push(&a.bytes);
            }
        }
        parts.extend(cells.blobs.iter().map(Vec::as_slice));
        parts.push(TAIL);
        let (atomic, file) = super::files::Atomic::create(path)?;
        let mut w = io::BufWriter::with_capacity(1 << 22, file);
        let mut total = 0u64;
        for p in parts {
            w.write_all(p)?;
            total += p.len() as u64;
        }
        w.into_inner().map_err(io::IntoInnerError::into_error)?;
        atomic.commit()?;
        let times = VtuTimes {
            encode_seconds: (encoded - started).as_secs_f64(),
            write_seconds: encoded.elapsed().as_secs_f64(),
        };
        Ok((total, times))
    }
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
