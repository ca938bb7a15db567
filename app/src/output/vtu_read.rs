//! Reading back the VTU files this program writes (`vtk::write_vtu`'s inverse), for
//! `meshfree render DIR` and `meshfree view DIR` (issue #51): the XML head's `DataArray`
//! tags (type, name, components, offset into the appended section), then each array from
//! the appended raw data, as its UInt64 byte count and bytes, or, with
//! `compressor="vtkZLibDataCompressor"` or `"vtkLZ4DataCompressor"`, as VTK's compressed
//! blocks. Not a general VTK reader:
//! a file of another layout (ASCII or base64 data, big endian, UInt32 headers, other array
//! types) is refused with what differs.

use std::path::Path;

use meshfree_core::solver::frame::FrameData;

use super::vtk::Compression;

/// One `<DataArray .../>` of the head.
struct Tag {
    name: String,
    ty: String,
    comps: usize,
    offset: usize,
}

/// The value of `attr="..."` in `tag`'s text.
fn attr<'a>(tag: &'a str, attr: &str) -> Option<&'a str> {
    let key = format!(" {attr}=\"");
    let start = tag.find(&key)? + key.len();
    let len = tag[start..].find('"')?;
    Some(&tag[start..start + len])
}

/// Read a `.vtu` written by `write_vtu` (raw, zlib or LZ4) into a frame: positions from the
/// Points, and each point-data array it holds (`id`, `kind`, `group`, `velocity`,
/// `density`, `pressure`, `stress`); a field the run did not write stays empty
/// (`FrameData::fields` says which it has). Time and step are not in the file (the series
/// `particles.pvd` has the time): zero. Errors name the file and what is wrong.
pub fn read_vtu(path: &Path) -> Result<FrameData, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse_vtu(&bytes).map_err(|e| format!("{}: {e}", path.display()))
}

fn parse_vtu(bytes: &[u8]) -> Result<FrameData, String> {
    const APPENDED: &[u8] = b"<AppendedData encoding=\"raw\">";
    let at = bytes
        .windows(APPENDED.len())
        .position(|w| w == APPENDED)
        .ok_or("no raw <AppendedData> section: not a VTU file written by meshfree")?;
    let head = std::str::from_utf8(&bytes[..at]).map_err(|_| "the XML head is not UTF-8")?;
    // The data start after the `_` that follows the tag.
    let underscore = bytes[at..]
        .iter()
        .position(|&b| b == b'_')
        .ok_or("no `_` opening the appended data")?;
    let data = &bytes[at + underscore + 1..];

    let vtk = head
        .find("<VTKFile")
        .map(|s| &head[s..s + head[s..].find('>').unwrap_or(0)])
        .ok_or("no <VTKFile> tag")?;
    if attr(vtk, "type") != Some("UnstructuredGrid") {
        return Err("not an UnstructuredGrid VTK file".into());
    }
    if attr(vtk, "byte_order") != Some("LittleEndian") {
        return Err("not little endian (meshfree writes LittleEndian)".into());
    }
    if attr(vtk, "header_type") != Some("UInt64") {
        return Err("the header type is not UInt64 (meshfree writes UInt64)".into());
    }
    let compression = Compression::from_vtk_name(attr(vtk, "compressor"))?;
    let piece = head
        .find("<Piece")
        .map(|s| &head[s..s + head[s..].find('>').unwrap_or(0)])
        .ok_or("no <Piece> tag")?;
    let n: usize = attr(piece, "NumberOfPoints")
        .and_then(|v| v.parse().ok())
        .ok_or("<Piece> has no NumberOfPoints")?;

    let mut tags = Vec::new();
    let mut rest = head;
    while let Some(s) = rest.find("<DataArray") {
        let end = rest[s..].find('>').ok_or("an unclosed <DataArray> tag")? + s;
        let t = &rest[s..end];
        let before = &head[..head.len() - rest.len() + s];
        // The Points' array has no name; the cells' arrays are skipped.
        let in_points = before.rfind("<Points>") > before.rfind("</Points>");
        let name = match attr(t, "Name") {
            Some(name) => name.to_string(),
            None if in_points => "Points".to_string(),
            None => return Err("a <DataArray> without a Name outside <Points>".into()),
        };
        if attr(t, "format") != Some("appended") {
            return Err(format!(
                "array `{name}`: format is not `appended` (meshfree writes appended raw data)"
            ));
        }
        let num = |key: &str| -> Result<usize, String> {
            attr(t, key)
                .and_then(|v| v.parse().ok())
                .ok_or_else(|| format!("array `{name}`: no {key}"))
        };
        tags.push(Tag {
            comps: num("NumberOfComponents")?,
            offset: num("offset")?,
            ty: attr(t, "type").unwrap_or("").to_string(),
            name,
        });
        rest = &rest[end..];
    }

    let mut frame = FrameData {
        len: n,
        ..Default::default()
    };
    for tag in &tags {
        let (ty, comps) = match tag.name.as_str() {
            "Points" | "velocity" => ("Float32", 3),
            "density" | "pressure" => ("Float32", 1),
            "stress" => ("Float32", 6),
            "id" => ("UInt32", 1),
            // The narrowest type that holds the scene's groups (`vtk::group_array`).
            "group" if ["UInt8", "UInt16"].contains(&tag.ty.as_str()) => (tag.ty.as_str(), 1),
            "group" => ("UInt32", 1),
            "kind" => ("UInt8", 1),
            _ => continue, // the cells, or an array this program does not draw
        };
        if tag.ty != ty || tag.comps != comps {
            return Err(format!(
                "array `{}` is {} x {}, expected {ty} x {comps}",
                tag.name, tag.ty, tag.comps
            ));
        }
        let size = match ty {
            "UInt8" => 1,
            "UInt16" => 2,
            _ => 4,
        };
        let raw = array_bytes(data, tag.offset, compression)
            .map_err(|e| format!("array `{}`: {e}", tag.name))?;
        if raw.len() != n * comps * size {
            return Err(format!(
                "array `{}` holds {} bytes, expected {} ({n} points x {comps} x {size})",
                tag.name,
                raw.len(),
                n * comps * size
            ));
        }
        let f32s = || -> Vec<f32> {
            raw.chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                .collect()
        };
        let u32s = || -> Vec<u32> {
            raw.chunks_exact(4)
                .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
                .collect()
        };
        let vec3 = |v: Vec<f32>| -> Vec<[f32; 3]> {
            v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
        };
        match tag.name.as_str() {
            "Points" => frame.position = vec3(f32s()),
            "velocity" => frame.velocity = vec3(f32s()),
            "density" => frame.density = f32s(),
            "pressure" => frame.pressure = f32s(),
            "stress" => {
                frame.stress = f32s()
                    .chunks_exact(6)
                    .map(|c| std::array::from_fn(|i| c[i]))
                    .collect()
            }
            "id" => frame.id = u32s(),
            "group" => {
                frame.group = match size {
                    1 => raw.iter().map(|&g| u32::from(g)).collect(),
                    2 => raw
                        .chunks_exact(2)
                        .map(|c| u32::from(u16::from_le_bytes([c[0], c[1]])))
                        .collect(),
                    _ => u32s(),
                }
            }
            "kind" => frame.kind = raw,
            _ => unreachable!(),
        }
    }
    if frame.position.len() != n {
        return Err("no Points array".into());
    }
    Ok(frame)
}

/// The little-endian UInt64 at `at` of `data`.
fn u64_at(data: &[u8], at: usize) -> Result<usize, String> {
    let b = data
        .get(at..at + 8)
        .ok_or("the appended data end early (a truncated file?)")?;
    usize::try_from(u64::from_le_bytes(b.try_into().unwrap())).map_err(|e| e.to_string())
}

/// One array's bytes at `offset` of the appended section: raw (a UInt64 count, then the
/// bytes) or VTK's compressed blocks (`vtk::Compression::head`).
fn array_bytes(data: &[u8], offset: usize, compression: Compression) -> Result<Vec<u8>, String> {
    let short = || "the appended data end early (a truncated file?)".to_string();
    if compression == Compression::Raw {
        let len = u64_at(data, offset)?;
        let start = offset + 8;
        return data
            .get(start..start.checked_add(len).ok_or_else(short)?)
            .map(<[u8]>::to_vec)
            .ok_or_else(short);
    }
    let blocks = u64_at(data, offset)?;
    let block = u64_at(data, offset + 8)?;
    let last = u64_at(data, offset + 16)?;
    if blocks > data.len() / 8 {
        return Err(format!(
            "{blocks} compressed blocks: more than the file holds"
        ));
    }
    let total = match (blocks, last) {
        (0, _) => 0,
        (b, 0) => b * block,
        (b, l) => (b - 1) * block + l,
    };
    let mut out = Vec::with_capacity(total.min(data.len() * 64));
    let mut at = offset + 24 + 8 * blocks;
    for k in 0..blocks {
        let size = u64_at(data, offset + 24 + 8 * k)?;
        let chunk = data
            .get(at..at.checked_add(size).ok_or_else(short)?)
            .ok_or_else(short)?;
        let len = if k + 1 == blocks && last != 0 {
            last
        } else {
            block
        };
        compression
            .unblock(chunk, len, &mut out)
            .map_err(|e| format!("compressed block {k}: {e}"))?;
        at += size;
    }
    Ok(out)
}
