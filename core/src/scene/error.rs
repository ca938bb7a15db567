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
        let field = if path.is_empty() || path == "." {
            "(document)".to_string()
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
        } else if reason.is_empty() {
            reason = "not valid TOML here".to_string();
        }
        SceneError::Parse {
            origin: origin.to_string(),
            field,
            reason,
            line,
            column,
        }
    }
}

/// 1-based line and column (in characters) of byte offset `at` in `text`.
pub(crate) fn line_column(text: &str, at: usize) -> (usize, usize) {
    let at = at.min(text.len());
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map(|i| i + 1).unwrap_or(0);
    (line, before[start..].chars().count() + 1)
}
