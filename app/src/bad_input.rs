//! `BadInput`: a refusal of what the user gave a command, other than a scene (a file that
//! cannot be read or parsed, such as `compare`'s particle CSV files). `cli::exit_code` maps
//! it to exit status 2 (bad input), as it maps a `SceneError`.

/// A refusal naming the input and why; displayed as its message.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct BadInput(pub String);
