//! Surface files: triangles from STL (binary and ASCII, `stl_io`), OBJ (`tobj`, polygons
//! triangulated) and PLY (ASCII and binary, `ply-rs-bw`), and a 2D polygon's corners from a
//! text file of points. Each reader gives vertices [L, the file's unit] and triangles (three
//! vertex indices); what they mean (a closed surface, its side) is `super`'s.

use std::io::{BufReader, Cursor, Read};

/// The largest surface file read \[bytes\]: a binary STL of 10 M triangles is 500 MB.
pub const MAX_BYTES: u64 = 1 << 30;

/// Vertices and triangles of a surface, as read.
#[derive(Clone, Debug, Default)]
pub struct Raw {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
}

/// The formats, from the file name's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Stl,
    Obj,
    Ply,
    /// 2D: a polygon's corners, one `x y` (or `x,y`) per line; `#` starts a comment.
    Points,
}

impl Format {
    /// The format of a file named `name`, None where its extension is none of them.
    pub fn of(name: &str) -> Option<Format> {
        let ext = name.rsplit_once('.')?.1.to_ascii_lowercase();
        Some(match ext.as_str() {
            "stl" => Format::Stl,
            "obj" => Format::Obj,
            "ply" => Format::Ply,
            "csv" | "txt" | "dat" | "xy" => Format::Points,
            _ => return None,
        })
    }
}

/// The surface in `bytes`, read as `format`; Err with the reason.
pub fn parse(bytes: &[u8], format: Format) -> Result<Raw, String> {
    match format {
        Format::Stl => stl(bytes),
        Format::Obj => obj(bytes),
        Format::Ply => ply(bytes),
        Format::Points => points(bytes).map(|corners| Raw {
            vertices: corners.into_iter().map(|[x, y]| [x, y, 0.0]).collect(),
            triangles: Vec::new(),
        }),
    }
}

/// The bytes of `path`, at most `MAX_BYTES`.
pub fn bytes_of(path: &std::path::Path) -> Result<Vec<u8>, String> {
    bytes_at_most(path, MAX_BYTES, "a surface")
}

/// The bytes of `path`, refused where it is not a regular file or holds more than `max`
/// bytes (`what` names the kind of file in the reason: "a surface").
pub fn bytes_at_most(path: &std::path::Path, max: u64, what: &str) -> Result<Vec<u8>, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read the file: {e}"))?;
    if !meta.is_file() {
        return Err("is not a regular file".into());
    }
    if meta.len() > max {
        return Err(format!(
            "the file is {} MiB, larger than the {} MiB {what} may be",
            meta.len() >> 20,
            max >> 20
        ));
    }
    let mut out = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(max + 1).read_to_end(&mut out))
        .map_err(|e| format!("cannot read the file: {e}"))?;
    Ok(out)
}

fn stl(bytes: &[u8]) -> Result<Raw, String> {
    let mesh = stl_io::read_stl(&mut Cursor::new(bytes))
        .map_err(|e| format!("not a readable STL file (binary or ASCII): {e}"))?;
    let vertices = mesh.vertices.iter().map(|v| v.0.map(f64::from)).collect();
    let triangles = mesh
        .faces
        .iter()
        .map(|f| f.vertices.map(|i| i as u32))
        .collect();
    Ok(Raw {
        vertices,
        triangles,
    })
}

fn obj(bytes: &[u8]) -> Result<Raw, String> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials do not shape the surface: a missing .mtl file is no error.
    let (models, _) = tobj::load_obj_buf(&mut BufReader::new(bytes), &options, |_| {
        Ok(Default::default())
    })
    .map_err(|e| format!("not a readable OBJ file: {e}"))?;
    let mut raw = Raw::default();
    for m in &models {
        let base = raw.vertices.len() as u32;
        raw.vertices.extend(
            m.mesh
                .positions
                .chunks_exact(3)
                .map(|p| [p[0], p[1], p[2]].map(f64::from)),
        );
        raw.triangles.extend(
            m.mesh
                .indices
                .chunks_exact(3)
                .map(|t| [base + t[0], base + t[1], base + t[2]]),
        );
    }
    Ok(raw)
}

fn ply(bytes: &[u8]) -> Result<Raw, String> {
    use ply_rs_bw::ply::Property as P;
    let parser = ply_rs_bw::parser::Parser::<ply_rs_bw::ply::DefaultElement>::new();
    let ply = parser
        .read_ply(&mut BufReader::new(bytes))
        .map_err(|e| format!("not a readable PLY file: {e}"))?;
    let scalar = |p: &P| -> Option<f64> {
        Some(match p {
            P::Char(x) => *x as f64,
            P::UChar(x) => *x as f64,
            P::Short(x) => *x as f64,
            P::UShort(x) => *x as f64,
            P::Int(x) => *x as f64,
            P::UInt(x) => *x as f64,
            P::Float(x) => *x as f64,
            P::Double(x) => *x,
            _ => return None,
        })
    };
    let list = |p: &P| -> Option<Vec<i64>> {
        Some(match p {
            P::ListChar(v) => v.iter().map(|&x| x as i64).collect(),
            P::ListUChar(v) => v.iter().map(|&x| x as i64).collect(),
            P::ListShort(v) => v.iter().map(|&x| x as i64).collect(),
            P::ListUShort(v) => v.iter().map(|&x| x as i64).collect(),
            P::ListInt(v) => v.iter().map(|&x| x as i64).collect(),
            P::ListUInt(v) => v.iter().map(|&x| x as i64).collect(),
            _ => return None,
        })
    };
    let mut raw = Raw::default();
    let empty = Vec::new();
    for v in ply.payload.get("vertex").unwrap_or(&empty) {
        let mut p = [0.0; 3];
        for (k, name) in ["x", "y", "z"].iter().enumerate() {
            p[k] = v.get(*name).and_then(scalar).ok_or_else(|| {
                format!("a vertex has no number {name} (the PLY's vertex element needs x, y, z)")
            })?;
        }
        raw.vertices.push(p);
    }
    let n = raw.vertices.len() as i64;
    for f in ply.payload.get("face").unwrap_or(&empty) {
        let idx = (f.get("vertex_indices").or_else(|| f.get("vertex_index")))
            .and_then(list)
            .ok_or("a face has no list vertex_indices")?;
        if let Some(bad) = idx.iter().find(|&&i| i < 0 || i >= n) {
            return Err(format!(
                "a face names vertex {bad}, but the file has {n} vertices"
            ));
        }
        // A polygon as a fan of triangles.
        for k in 1..idx.len().saturating_sub(1) {
            raw.triangles
                .push([idx[0] as u32, idx[k] as u32, idx[k + 1] as u32]);
        }
    }
    Ok(raw)
}

/// A polygon's corners from text: per line two numbers, separated by spaces, tabs or a
/// comma; blank lines, `#` comments and one header line of words are skipped.
fn points(bytes: &[u8]) -> Result<Vec<[f64; 2]>, String> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        format!(
            "not a text file of points (not UTF-8 at byte {})",
            e.valid_up_to()
        )
    })?;
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let words: Vec<&str> = line
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|w| !w.is_empty())
            .collect();
        let nums: Result<Vec<f64>, _> = words.iter().map(|w| w.parse::<f64>()).collect();
        match nums {
            Ok(v) if v.len() == 2 && v.iter().all(|x| x.is_finite()) => out.push([v[0], v[1]]),
            Err(_) if out.is_empty() && n == 0 => continue, // a header such as "x,y"
            _ => {
                return Err(format!(
                    "line {}: expected two finite numbers (x y), found {line:?}",
                    n + 1
                ))
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_from_the_extension() {
        assert_eq!(Format::of("a/b.STL"), Some(Format::Stl));
        assert_eq!(Format::of("x.obj"), Some(Format::Obj));
        assert_eq!(Format::of("x.ply"), Some(Format::Ply));
        assert_eq!(Format::of("profile.csv"), Some(Format::Points));
        assert_eq!(Format::of("x.step"), None);
        assert_eq!(Format::of("noext"), None);
    }

    #[test]
    fn points_skip_a_header_and_comments_and_name_a_bad_line() {
        let p = points(b"x,y\n0,0 # origin\n\n1 0\n1\t1\n").unwrap();
        assert_eq!(p, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]);
        let e = points(b"0 0\n1 2 3\n").unwrap_err();
        assert!(e.contains("line 2"), "{e}");
    }

    #[test]
    fn an_obj_quad_is_two_triangles_and_a_ply_quad_too() {
        let obj = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
        let r = parse(obj, Format::Obj).unwrap();
        assert_eq!((r.vertices.len(), r.triangles.len()), (4, 2));
        let ply = b"ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
        let r = parse(ply, Format::Ply).unwrap();
        assert_eq!((r.vertices.len(), r.triangles.len()), (4, 2));
        assert!(parse(b"solid x\nthis is not stl", Format::Stl).is_err());
    }
}
