//! The key behind a type error inside a tagged object (issue #51).
//!
//! An object chosen by its `shape` (a wall, a solid) is read by serde as a whole before its
//! variant is known, so a wrong type in one of its keys comes back blamed on the object,
//! `walls[0]: invalid type: map, expected a sequence`. This finds the key from the text:
//! the object's keys whose value is (or holds) the value the message quotes; where exactly
//! one does, the error names it, `walls[0].motion`. Likewise for an unknown key inside a
//! table of the object (`motion = { spin = 2 }`): the one key whose table holds it.

/// `path` + `.key` where the reason's offending value sits in exactly one key of the object
/// at `path` in `text`; None where the path is no object of the text or the key is not
/// certain.
pub(super) fn narrow(text: &str, path: &str, reason: &str) -> Option<String> {
    let unknown = reason
        .strip_prefix("unknown field `")
        .and_then(|r| r.split('`').next());
    let found = match unknown {
        Some(_) => "",
        None => reason
            .strip_prefix("invalid type: ")?
            .split(", expected")
            .next()?,
    };
    let root: toml::Value = toml::from_str(text).ok()?;
    let mut at = &root;
    for part in path.split('.') {
        let (key, index) = match part.split_once('[') {
            Some((k, i)) => (k, Some(i.strip_suffix(']')?.parse::<usize>().ok()?)),
            None => (part, None),
        };
        at = at.get(key)?;
        if let Some(i) = index {
            at = at.get(i)?;
        }
    }
    let keys: Vec<&String> = (at.as_table()?.iter())
        .filter(|(_, v)| match unknown {
            Some(key) => has_key(v, key),
            None => holds(v, found),
        })
        .map(|(k, _)| k)
        .collect();
    match keys.as_slice() {
        [key] => Some(format!("{path}.{key}")),
        _ => None,
    }
}

/// Whether `v` is a table that has `key`, or holds one that does.
fn has_key(v: &toml::Value, key: &str) -> bool {
    match v {
        toml::Value::Table(t) => t.contains_key(key) || t.values().any(|x| has_key(x, key)),
        toml::Value::Array(a) => a.iter().any(|x| has_key(x, key)),
        _ => false,
    }
}

/// Whether `v` is, or holds in an array or a table, a value serde describes as `found` (`map`,
/// `sequence`, `string "x"`, `integer `3``, `floating point `1.5``, `boolean `true``).
fn holds(v: &toml::Value, found: &str) -> bool {
    let quoted = |prefix: &str| found.strip_prefix(prefix).map(|s| s.trim_matches('`'));
    let is = match v {
        toml::Value::Table(_) => found == "map",
        toml::Value::Array(a) => found == "sequence" || a.iter().any(|x| holds(x, found)),
        toml::Value::String(s) => found.strip_prefix("string ") == Some(&format!("{s:?}")),
        toml::Value::Integer(i) => quoted("integer ") == Some(&i.to_string()),
        toml::Value::Float(f) => quoted("floating point ") == Some(&f.to_string()),
        toml::Value::Boolean(b) => quoted("boolean ") == Some(&b.to_string()),
        toml::Value::Datetime(_) => found.starts_with("datetime") || found == "map",
    };
    is || match v {
        toml::Value::Array(a) => a.iter().any(|x| holds(x, found)),
        toml::Value::Table(t) => t.values().any(|x| holds(x, found)),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::narrow;

    const TEXT: &str =
        "[[walls]]\nshape = \"box\"\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\nmotion = {a = 1}\n\
                        [[walls]]\nshape = \"box\"\nmotion = [1.0, \"x\"]\nlayers = 3\n";

    #[test]
    fn names_the_key_that_holds_the_value() {
        let r = "invalid type: map, expected a sequence";
        assert_eq!(
            narrow(TEXT, "walls[0]", r).as_deref(),
            Some("walls[0].motion")
        );
        let r = "invalid type: string \"x\", expected f64";
        assert_eq!(
            narrow(TEXT, "walls[1]", r).as_deref(),
            Some("walls[1].motion")
        );
        let r = "invalid type: integer `3`, expected a boolean";
        assert_eq!(
            narrow(TEXT, "walls[1]", r).as_deref(),
            Some("walls[1].layers")
        );
        // Inside a table of the object: its key.
        let r = "invalid type: integer `1`, expected f64";
        assert_eq!(
            narrow(TEXT, "walls[0]", r).as_deref(),
            Some("walls[0].motion")
        );
        let r = "unknown field `a`, expected one of `velocity`, `ramp`";
        assert_eq!(
            narrow(TEXT, "walls[0]", r).as_deref(),
            Some("walls[0].motion")
        );
        assert_eq!(narrow(TEXT, "walls[1]", r), None);
        // Not certain (two arrays), or no such object: the error stays as it was.
        assert_eq!(
            narrow(TEXT, "walls[0]", "invalid type: sequence, expected f64"),
            None
        );
        assert_eq!(
            narrow(TEXT, "walls[7]", "invalid type: map, expected f64"),
            None
        );
    }
}
