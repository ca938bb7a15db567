//! What a scene file may cost to read, checked before the TOML parser sees it: the TOML
//! parser holds a document of about 1 KB per table and 200 B per value, so 4.3 MB of
//! dotted keys (`a1.b.c.d.e.f.g.h = 1` is eight tables) took 1.15 GB (issue #52). A file is
//! read up to `MAX_BYTES` (and one byte more, to tell that it is larger: `/dev/zero` or a
//! huge file is refused without filling memory), then its tables and values are counted
//! by a scan that skips strings and comments, and held against `MAX_TABLES` and
//! `MAX_VALUES`. A scene of 100,000 blocks fits within all three.

use std::io::Read;
use std::path::Path;

use super::SceneError;

/// \[bytes\] the largest scene file (a 100,000-block scene is about 6 to 13 MB).
pub const MAX_BYTES: usize = 16 << 20;
/// The most tables (`[header]`, `[[array]]` entries, inline `{}` tables, and each part of a
/// dotted key) a scene may hold: about 1 KB each to parse.
pub const MAX_TABLES: usize = 250_000;
/// The most values (key-value pairs, arrays and array entries) a scene may hold: about
/// 200 B each to parse.
pub const MAX_VALUES: usize = 2_000_000;

/// The text of the scene file `path`, refused where it is larger than `MAX_BYTES` or not
/// UTF-8; reads at most `MAX_BYTES` + 1 bytes.
pub(super) fn read(path: &Path, origin: &str) -> Result<String, SceneError> {
    let io = |reason: String| SceneError::Io {
        origin: origin.to_string(),
        reason,
    };
    let file = std::fs::File::open(path).map_err(|e| io(format!("cannot read the file: {e}")))?;
    let mut bytes = Vec::new();
    file.take(MAX_BYTES as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| io(format!("cannot read the file: {e}")))?;
    if bytes.len() > MAX_BYTES {
        return Err(io(too_large()));
    }
    String::from_utf8(bytes).map_err(|e| {
        io(format!(
            "cannot read the file: it is not UTF-8 text (byte {})",
            e.utf8_error().valid_up_to()
        ))
    })
}

fn too_large() -> String {
    format!(
        "the file is larger than {} MiB: not a scene (a scene of 100,000 objects is about 10 MB)",
        MAX_BYTES >> 20
    )
}

/// Refuse `text` where it is larger than `MAX_BYTES` or holds more tables or values than
/// `MAX_TABLES` / `MAX_VALUES` (`count`).
pub(super) fn check(text: &str, origin: &str) -> Result<(), SceneError> {
    let refuse = |reason: String| SceneError::Invalid {
        origin: origin.to_string(),
        field: "(document)".into(),
        reason,
    };
    if text.len() > MAX_BYTES {
        return Err(refuse(too_large()));
    }
    let c = count(text);
    if c.tables > MAX_TABLES {
        return Err(refuse(format!(
            "the file holds {} tables (headers, [[array]] entries, inline tables and each part \
             of a dotted key), more than the {MAX_TABLES} a scene may hold",
            c.tables
        )));
    }
    if c.values > MAX_VALUES {
        return Err(refuse(format!(
            "the file holds {} values (keys, arrays and their entries), more than the \
             {MAX_VALUES} a scene may hold",
            c.values
        )));
    }
    Ok(())
}

/// Tables and values of a TOML text, counted from its punctuation outside strings and
/// comments (an upper bound on well-formed TOML; any count for text that is not).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Count {
    pub tables: usize,
    pub values: usize,
}

pub fn count(text: &str) -> Count {
    let b = text.as_bytes();
    let mut c = Count::default();
    // Open arrays and inline tables, innermost last.
    let mut open: Vec<u8> = Vec::new();
    // Whether a key may come next (line start, after `{` or a `,` in an inline table).
    let mut key = true;
    let mut line_start = true;
    let mut i = 0;
    while i < b.len() {
        let ch = b[i];
        match ch {
            b'#' => {
                i = memchr(b, i, b'\n');
                continue;
            }
            b'"' | b'\'' => {
                i = skip_string(b, i);
                line_start = false;
                continue;
            }
            b'\n' if open.is_empty() => {
                key = true;
                line_start = true;
            }
            b' ' | b'\t' | b'\r' | b'\n' => {}
            b'[' if open.is_empty() && line_start => {
                // A `[table]` or `[[array]]` header: one table and one per dot.
                c.tables += 1;
                i += 1;
                while i < b.len() && b[i] != b'\n' && b[i] != b'#' {
                    match b[i] {
                        b'"' | b'\'' => {
                            i = skip_string(b, i);
                            continue;
                        }
                        b'.' => c.tables += 1,
                        _ => {}
                    }
                    i += 1;
                }
                line_start = false;
                continue;
            }
            b'[' => {
                open.push(b'[');
                c.values += 1;
                key = false;
            }
            b'{' => {
                open.push(b'{');
                c.tables += 1;
                key = true;
            }
            b']' | b'}' => {
                open.pop();
                key = false;
            }
            b'=' => {
                c.values += 1;
                key = false;
            }
            b',' => {
                c.values += 1;
                key = open.last() == Some(&b'{');
            }
            b'.' if key => c.tables += 1,
            _ => {}
        }
        if !matches!(ch, b' ' | b'\t' | b'\r' | b'\n') {
            line_start = false;
        }
        i += 1;
    }
    c
}

/// The index of the first `x` in `b` from `i` on, or `b.len()`.
fn memchr(b: &[u8], i: usize, x: u8) -> usize {
    b[i..]
        .iter()
        .position(|&c| c == x)
        .map_or(b.len(), |k| i + k)
}

/// The index just past the string that starts at `b[i]` (a quote): basic `"..."` with
/// backslash escapes, literal `'...'`, and their multi-line `"""` / `'''` forms; the end
/// of the text where it is not closed.
fn skip_string(b: &[u8], i: usize) -> usize {
    let q = b[i];
    let triple = b.len() >= i + 3 && b[i + 1] == q && b[i + 2] == q;
    let mut k = if triple { i + 3 } else { i + 1 };
    while k < b.len() {
        if q == b'"' && b[k] == b'\\' {
            k += 2;
            continue;
        }
        if b[k] == q {
            if !triple {
                return k + 1;
            }
            if b.len() >= k + 3 && b[k + 1] == q && b[k + 2] == q {
                return k + 3;
            }
        } else if b[k] == b'\n' && !triple {
            // An unclosed one-line string ends at its line (the parser will say why).
            return k;
        }
        k += 1;
    }
    b.len()
}
