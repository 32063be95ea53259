//! The one error of an atlas's data: a field with a bad value.

use scene::Named;
use thiserror::Error;

/// An option or field with a bad value (an axis, a sweep, a shard): one line
/// naming the field, which each front end spells its own way.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{field}: {message}")]
pub struct FieldError {
    /// The field (`x`, `shard`, a study file's key); the CLI names its flag.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

impl FieldError {
    /// A [`FieldError`] of `field`.
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        FieldError { field: field.into(), message: message.into() }
    }
}

/// The value of `T` named `text`, or an error naming `field`, the names and
/// the one meant where one is close.
pub fn read<T: Named>(text: &str, field: &str) -> Result<T, FieldError> {
    T::parse(text).ok_or_else(|| FieldError::field(field, T::expected(text)))
}
