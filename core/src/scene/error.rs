//! `SceneError`: every way a scene can be refused. Each names the scene's origin (a file
//! path or `builtin:<name>`), the field as a dotted path (`fluid_blocks[1].max`) and why.

/// Why a scene was refused. Displayed as `<origin>: <field>: <reason>`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{origin}: {reason}")]
    Io { origin: String, reason: String },
    /// TOML syntax, an unknown key, a wrong type or a missing key.
    #[error("{origin}: {field}: {reason} (line {line}, column {column})")]
    Parse {
        origin: String,
        /// Dotted path of the offending value; `(document)` for syntax errors.
        field: String,
        reason: String,
        /// 1-based; 0 where toml gave no position.
        line: usize,
        column: usize,
    },
    /// The file parsed but a value is not acceptable.
    #[error("{origin}: {field}: {reason}")]
    Invalid {
        origin: String,
        field: String,
        reason: String,
    },
    /// `Scene::builtin` with a name that is not built in.
    #[error("builtin:{name}: no built-in scene of that name (known: {known})")]
    UnknownBuiltin { name: String, known: String },
}

impl SceneError {
    /// The dotted field path, where the error has one.
    pub fn field(&self) -> Option<&str> {
        match self {
            SceneError::Parse { field, .. } | SceneError::Invalid { field, .. } => Some(field),
            _ => None,
        }
    }

    /// The scene's origin (file path or `builtin:<name>`).
    pub fn origin(&self) -> String {
        match self {
            SceneError::Io { origin, .. }
            | SceneError::Parse { origin, .. }
            | SceneError::Invalid { origin, .. } => origin.clone(),
            SceneError::UnknownBuiltin { name, .. } => format!("builtin:{name}"),
        }
    }

    /// Build a `Parse` error from toml's error and the path serde_path_to_error found.
    pub(crate) fn from_toml(
        origin: &str,
        text: &str,
        err: serde_path_to_error::Error<toml::de::Error>,
    ) -> SceneError {
        let path = err.path().to_string();
        let inner = err.into_inner();
        let (line, column) = match inner.span() {
            Some(span) => line_column(text, span.start),
            None => (0, 0),
        };
        let at = inner.span().map(|s| s.start);
        let field = if path.is_empty() || path == "." {
            at.and_then(|at| key_at(text, at))
                .unwrap_or_else(|| "(document)".to_string())
        } else {
            path
        };
        // toml's message may span several lines (it quotes the source); keep the first that
        // says something.
        let mut reason = inner
            .message()
            .lines()
            .map(str::trim)
            .find(|l| !l.is_empty())
            .unwrap_or("")
            .to_string();
        let bare_cr = text
            .as_bytes()
            .windows(2)
            .any(|w| w[0] == b'\r' && w[1] != b'\n')
            || text.ends_with('\r');
        if bare_cr {
            reason = "the file has bare carriage returns (CR-only line endings, as on classic Mac \
                      OS): TOML needs LF or CR LF line endings"
                .to_string();
        } else if let Some(word) = at.map(|at| word_at(text, at)).filter(|w| !w.is_empty()) {
            let lower = word.to_ascii_lowercase();
            if [
                "nan",
                "+nan",
                "-nan",
                "infinity",
                "+infinity",
                "-infinity",
                "inf",
                "+inf",
                "-inf",
            ]
            .contains(&lower.as_str())
            {
                reason = format!(
                    "`{word}` is not a TOML number (TOML spells nan and inf), and a scene takes \
                     finite numbers only"
                );
            } else if reason == "invalid string" || reason.is_empty() {
                reason = format!(
                    "`{word}` is not a value: text goes in quotes (\"{word}\"), numbers in digits"
                );
            }
        } else if reason.is_empty() {
            reason = "not valid TOML here".to_string();
        }
        // A type error inside a tagged object (a wall, a solid) names the object: find the key.
        let field = super::tagged_field::narrow(text, &field, &reason).unwrap_or(field);
        SceneError::Parse {
            origin: origin.to_string(),
            field,
            reason,
            line,
            column,
        }
    }
}

/// The dotted key of the `key = value` line holding byte `at` (its table from the last
/// `[table]` or `[[array]]` header above it), where that line has one.
fn key_at(text: &str, at: usize) -> Option<String> {
    let at = at.min(text.len());
    let start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let line = text[start..].lines().next().unwrap_or("");
    let key = line.split_once('=')?.0.trim();
    let plain = |k: &str| {
        !k.is_empty()
            && k.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
    };
    if !plain(key) {
        return None;
    }
    let table = text[..start].lines().rev().find_map(|l| {
        let l = l.trim();
        let name = l.strip_prefix("[[").and_then(|r| r.split("]]").next());
        let name = name.or_else(|| l.strip_prefix('[').and_then(|r| r.split(']').next()));
        name.map(|n| n.trim().to_string())
    });
    Some(match table {
        Some(t) if plain(&t) => format!("{t}.{key}"),
        _ => key.to_string(),
    })
}

/// The bare word that starts at byte `at` (letters, digits, signs, dots).
fn word_at(text: &str, at: usize) -> &str {
    let rest = text.get(at.min(text.len())..).unwrap_or("");
    let end = rest
        .find(|c: char| !(c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.' | '_')))
        .unwrap_or(rest.len());
    &rest[..end]
}

/// 1-based line and column (in characters) of byte offset `at` in `text`.
pub(crate) fn line_column(text: &str, at: usize) -> (usize, usize) {
    let at = at.min(text.len());
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map(|i| i + 1).unwrap_or(0);
    (line, before[start..].chars().count() + 1)
}
