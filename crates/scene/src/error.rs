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

/// `v` as a message or a header shows it: its shortest text that reads back
/// as the same number, plainly from 1e-4 to 1e16 and at 0 (`0.25`, `300`),
/// else with an exponent (`1e-15`, `1e300`, not hundreds of digits).
pub fn number(v: f64) -> String {
    if v == 0.0 || (1e-4..1e16).contains(&v.abs()) || !v.is_finite() {
        v.to_string()
    } else {
        format!("{v:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::number;

    /// Every number shown reads back as itself; extreme ones are short.
    #[test]
    fn a_number_is_shown_short_and_reads_back() {
        for (v, shown) in [
            (0.25, "0.25"),
            (300.0, "300"),
            (1e-4, "0.0001"),
            (1e300, "1e300"),
            (-2.5e-9, "-2.5e-9"),
            (0.0, "0"),
            (1e-15, "1e-15"),
            (2e20, "2e20"),
        ] {
            assert_eq!(number(v), shown);
        }
        for v in [f64::MAX, f64::MIN_POSITIVE, 1e16, 9.99e15, 0.1 + 0.2, -2.5e-300, 5e-324, -0.0, -8.402545495426143] {
            let text = number(v);
            assert!(text.len() <= 24, "{text}");
            assert_eq!(text.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{text}");
        }
    }
}
