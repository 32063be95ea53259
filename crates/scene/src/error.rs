//! Errors of scene parsing and evaluation: one line that names the field.

use thiserror::Error;

/// Everything that can be wrong with a scene file or with the parameters given to it.
///
/// Each variant prints as one line naming the offending field, e.g.
/// `stops[1].restitution: must be in [0, 1], got 1.2`.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SceneError {
    /// The text is not valid TOML, or does not match the schema (unknown or missing keys).
    #[error("scene file: {message}")]
    Syntax {
        /// What the TOML parser reported, with line and column.
        message: String,
    },
    /// A field holds a value or expression that is not allowed.
    #[error("{field}: {message}")]
    Field {
        /// Dotted path of the field, e.g. `masses[1].mass` or `parameters.delta1`.
        field: String,
        /// What is wrong with it.
        message: String,
    },
}

impl SceneError {
    /// Builds a [`SceneError::Field`].
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        SceneError::Field { field: field.into(), message: message.into() }
    }
}

/// At most `chars` characters of `text`, an ellipsis after a cut: a text
/// read from someone else's file, quoted in an error or a page.
pub fn excerpt(text: &str, chars: usize) -> String {
    match text.char_indices().nth(chars) {
        Some((at, _)) => format!("{}…", &text[..at]),
        None => text.to_string(),
    }
}
