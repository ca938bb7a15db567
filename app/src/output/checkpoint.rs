//! `checkpoint.bin`: a run's whole state at one step boundary, from which `meshfree run
//! --resume` continues (`crate::resume`). Binary, little-endian, versioned and checksummed,
//! written through a temporary file, flushed to the disk and renamed over the last one, so
//! that a run killed at any moment leaves the previous checkpoint or the new one, whole.
//!
//! Layout (version 1):
//! - 16 bytes: `MESHFREE-CHKPNT` and a NUL;
//! - u32: the format version;
//! - u64: the length of the header, then the header: JSON, UTF-8, with the run's own state
//!   (`run`: whatever the caller gives), the solver's scalars (`dim`, `time`, `steps`, `dt`)
//!   and the list of arrays that follow (`arrays`: name, element type, count);
//! - the arrays, each the raw little-endian elements of `SolverCheckpoint`'s field of that
//!   name (vectors as 3 floats, symmetric tensors as 6);
//! - u32: the CRC-32 (IEEE) of everything before it.
//!
//! A decomposed run (`Solver::save_pieces`) writes one such file per rank, its *piece*
//! (`checkpoint-step<S>-rank<k>of<N>.bin`: the rank's particles, and `{rank, ranks}` as
//! its run state), and then `checkpoint.bin` as their *index*: the run's state and the
//! clock, no particles, and the header's `pieces` (`PieceList`: the slabs' axis and cuts,
//! each piece's file and particle count). The pieces are named by the step, so the index's
//! rename is what moves a run from one checkpoint to the next; the previous pieces go after
//! it (`remove_stale_pieces`). A kill at any moment leaves an index whose pieces are all
//! there, whole.
//!
//! Python reads it with `struct`, `json`, `zlib` and `numpy.frombuffer`
//! (`docs/reference/checkpoint.md`, whose reader `tests/python_readers.rs` runs).

use std::io::{self, Write};
use std::path::Path;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use meshfree_core::solver::checkpoint::{BodyState, SolverCheckpoint};

mod pieces;
pub use pieces::{
    is_piece_name, load, piece_name, remove_stale_pieces, PieceFile, PieceList, Saved,
};

/// The file name in a run's output directory.
pub use meshfree_core::run_files::CHECKPOINT as FILE;
/// The first 16 bytes.
pub const MAGIC: &[u8; 16] = b"MESHFREE-CHKPNT\0";
/// The layout this build writes and reads.
pub const VERSION: u32 = 1;

#[derive(Serialize, Deserialize)]
struct Header<R> {
    run: R,
    dim: u32,
    time: f64,
    steps: u64,
    dt: f32,
    arrays: Vec<ArrayEntry>,
    /// The floating bodies' states (exact: JSON's numbers read back to the same f64).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    bodies: Vec<BodyState>,
    /// The open boundaries' next id and tallies (exact, as the bodies'); absent without.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    open: Option<meshfree_core::physics::open::OpenState>,
    /// Only in the index of a checkpoint in pieces.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pieces: Option<PieceList>,
}

#[derive(Serialize, Deserialize, PartialEq, Debug)]
struct ArrayEntry {
    name: String,
    /// "u8", "u32" or "f32".
    #[serde(rename = "type")]
    ty: String,
    /// Elements (a vector counts its 3 floats, a tensor its 6).
    count: u64,
}

/// The arrays, in file order, with their element types.
const ARRAYS: [(&str, &str); 11] = [
    ("id", "u32"),
    ("kind", "u8"),
    ("group", "u32"),
    ("mass", "f32"),
    ("pos", "f32"),
    ("vel", "f32"),
    ("rho", "f32"),
    ("p", "f32"),
    ("stress", "f32"),
    ("rho_dev", "f32"),
    ("tl_disp", "f32"),
];

fn le_u32(v: &[u32]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}
fn le_f32<'a>(v: impl IntoIterator<Item = &'a f32>) -> Vec<u8> {
    v.into_iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// The little-endian bytes of array `name` of `c` (one at a time: a checkpoint of many
/// millions of particles is not copied whole).
fn encode(c: &SolverCheckpoint, name: &str) -> Vec<u8> {
    match name {
        "id" => le_u32(&c.id),
        "kind" => c.kind.clone(),
        "group" => le_u32(&c.group),
        "mass" => le_f32(&c.mass),
        "pos" => le_f32(c.pos.iter().flatten()),
        "vel" => le_f32(c.vel.iter().flatten()),
        "rho" => le_f32(&c.rho),
        "p" => le_f32(&c.p),
        "stress" => le_f32(c.stress.iter().flatten()),
        "rho_dev" => le_f32(&c.rho_dev),
        "tl_disp" => le_f32(c.tl_disp.iter().flatten()),
        _ => unreachable!("an array of ARRAYS"),
    }
}

/// Elements of array `name` of `c`.
fn count(c: &SolverCheckpoint, name: &str) -> usize {
    match name {
        "id" | "kind" | "group" | "mass" | "rho" | "p" => c.len(),
        "pos" => 3 * c.pos.len(),
        "vel" => 3 * c.vel.len(),
        "stress" => 6 * c.stress.len(),
        "rho_dev" => c.rho_dev.len(),
        "tl_disp" => 3 * c.tl_disp.len(),
        _ => unreachable!("an array of ARRAYS"),
    }
}

/// A writer that keeps the CRC-32 of what went through it.
struct Crc<W: Write> {
    inner: W,
    crc: crc32fast::Hasher,
}

impl<W: Write> Write for Crc<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.crc.update(&buf[..n]);
        Ok(n)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

/// Write `solver` and the run's state `run` to `path`, atomically (temporary file, fsync,
/// rename, fsync of the directory). Returns the bytes written.
pub fn write<R: Serialize>(path: &Path, solver: &SolverCheckpoint, run: &R) -> io::Result<u64> {
    write_file(path, solver, run, None)
}

fn write_file<R: Serialize>(
    path: &Path,
    solver: &SolverCheckpoint,
    run: &R,
    pieces: Option<PieceList>,
) -> io::Result<u64> {
    let header = Header {
        pieces,
        run,
        dim: solver.dim,
        time: solver.time,
        steps: solver.steps,
        dt: solver.dt,
        bodies: solver.bodies.clone(),
        open: solver.open.clone(),
        arrays: ARRAYS
            .iter()
            .map(|&(name, ty)| ArrayEntry {
                name: name.to_string(),
                ty: ty.to_string(),
                count: count(solver, name) as u64,
            })
            .collect(),
    };
    let json = serde_json::to_vec(&header).map_err(io::Error::other)?;
    let (atomic, file) = super::files::Atomic::create(path)?;
    let mut w = Crc {
        inner: io::BufWriter::with_capacity(1 << 20, file),
        crc: crc32fast::Hasher::new(),
    };
    w.write_all(MAGIC)?;
    w.write_all(&VERSION.to_le_bytes())?;
    w.write_all(&(json.len() as u64).to_le_bytes())?;
    w.write_all(&json)?;
    for (name, _) in ARRAYS {
        w.write_all(&encode(solver, name))?;
    }
    let crc = w.crc.clone().finalize();
    let mut inner = w.inner;
    inner.write_all(&crc.to_le_bytes())?;
    let file = inner.into_inner().map_err(|e| e.into_error())?;
    file.sync_all()?;
    let bytes = file.metadata()?.len();
    drop(file);
    atomic.commit()?;
    if let Some(dir) = path.parent() {
        // The rename itself made durable (where the platform lets a directory be opened).
        if let Ok(d) = std::fs::File::open(if dir.as_os_str().is_empty() {
            Path::new(".")
        } else {
            dir
        }) {
            let _ = d.sync_all();
        }
    }
    Ok(bytes)
}

/// Read a whole checkpoint: the solver's state and the run's. Err: why it cannot be used
/// (not a checkpoint, another version, a wrong checksum, a truncated or inconsistent file,
/// the index of one in pieces: `load` reads those).
pub fn read<R: DeserializeOwned>(path: &Path) -> Result<(SolverCheckpoint, R), String> {
    match read_file(path)? {
        (c, run, None) => Ok((c, run)),
        (_, _, Some(_)) => Err(
            "it is the index of a checkpoint in pieces, one file per rank (a decomposed run's)"
                .into(),
        ),
    }
}

type Contents<R> = (SolverCheckpoint, R, Option<PieceList>);

fn read_file<R: DeserializeOwned>(path: &Path) -> Result<Contents<R>, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read it: {e}"))?;
    let fixed = MAGIC.len() + 4 + 8;
    if bytes.len() < fixed + 4 || &bytes[..MAGIC.len()] != MAGIC {
        return Err("not a meshfree checkpoint (no MESHFREE-CHKPNT header)".into());
    }
    let version = u32::from_le_bytes(bytes[16..20].try_into().unwrap());
    if version != VERSION {
        return Err(format!(
            "checkpoint format version {version}; this build reads version {VERSION} (resume \
             with the build that wrote it)"
        ));
    }
    let (body, tail) = bytes.split_at(bytes.len() - 4);
    let stored = u32::from_le_bytes(tail.try_into().unwrap());
    let computed = crc32fast::hash(body);
    if stored != computed {
        return Err(format!(
            "damaged: its checksum is {stored:#010x} and its contents give {computed:#010x} \
             (a truncated or altered file)"
        ));
    }
    let json_len = u64::from_le_bytes(bytes[20..28].try_into().unwrap()) as usize;
    let json = body
        .get(fixed..fixed.saturating_add(json_len))
        .ok_or("damaged: the header runs past the end of the file")?;
    let header: Header<R> =
        serde_json::from_slice(json).map_err(|e| format!("damaged header: {e}"))?;
    let mut data = &body[fixed + json_len..];
    let mut c = SolverCheckpoint {
        dim: header.dim,
        time: header.time,
        steps: header.steps,
        dt: header.dt,
        bodies: header.bodies,
        open: header.open,
        ..SolverCheckpoint::default()
    };
    let expected: Vec<(&str, &str)> = ARRAYS.to_vec();
    let listed: Vec<(&str, &str)> = header
        .arrays
        .iter()
        .map(|a| (a.name.as_str(), a.ty.as_str()))
        .collect();
    if listed != expected {
        return Err(format!(
            "damaged header: its arrays are {listed:?}; version {VERSION} has {expected:?}"
        ));
    }
    for a in &header.arrays {
        let width = if a.ty == "u8" { 1 } else { 4 };
        let len = (a.count as usize)
            .checked_mul(width)
            .filter(|&l| l <= data.len())
            .ok_or_else(|| format!("damaged: array `{}` runs past the end", a.name))?;
        let (raw, rest) = data.split_at(len);
        data = rest;
        let u32s = || -> Vec<u32> {
            raw.chunks_exact(4)
                .map(|b| u32::from_le_bytes(b.try_into().unwrap()))
                .collect()
        };
        let f32s = || -> Vec<f32> {
            raw.chunks_exact(4)
                .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
                .collect()
        };
        fn group<const N: usize>(v: Vec<f32>, name: &str) -> Result<Vec<[f32; N]>, String> {
            if !v.len().is_multiple_of(N) {
                return Err(format!(
                    "array `{name}` holds {} floats, not a multiple of {N}",
                    v.len()
                ));
            }
            Ok(v.chunks_exact(N).map(|c| c.try_into().unwrap()).collect())
        }
        match a.name.as_str() {
            "id" => c.id = u32s(),
            "kind" => c.kind = raw.to_vec(),
            "group" => c.group = u32s(),
            "mass" => c.mass = f32s(),
            "pos" => c.pos = group(f32s(), "pos")?,
            "vel" => c.vel = group(f32s(), "vel")?,
            "rho" => c.rho = f32s(),
            "p" => c.p = f32s(),
            "stress" => c.stress = group(f32s(), "stress")?,
            "rho_dev" => c.rho_dev = f32s(),
            "tl_disp" => c.tl_disp = group(f32s(), "tl_disp")?,
            _ => unreachable!("names checked against ARRAYS"),
        }
    }
    if !data.is_empty() {
        return Err(format!(
            "damaged: {} bytes after the last array",
            data.len()
        ));
    }
    Ok((c, header.run, header.pieces))
}
