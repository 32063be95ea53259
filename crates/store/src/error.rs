//! Errors of the store: one line naming the file and what failed.

use thiserror::Error;

/// What went wrong reading or writing atlas files.
#[derive(Debug, Error)]
pub enum StoreError {
    /// HDF5 library error.
    #[error("{path}: {message}")]
    Hdf5 {
        /// File.
        path: String,
        /// The library's message.
        message: String,
    },
    /// Operating-system I/O error.
    #[error("{path}: {cause}")]
    Io {
        /// File.
        path: String,
        /// Cause (printed in the message, so not chained as a source).
        cause: std::io::Error,
    },
    /// The file is not an atlas of this layout, or does not fit with others.
    #[error("{path}: {message}")]
    Format {
        /// File.
        path: String,
        /// What does not fit.
        message: String,
    },
}

impl StoreError {
    /// Wraps an HDF5 error with the file's path.
    pub fn hdf5(path: &std::path::Path, e: hdf5::Error) -> Self {
        // The library's messages span lines: one line, as every error.
        let message = e.to_string().split_whitespace().collect::<Vec<_>>().join(" ");
        StoreError::Hdf5 { path: path.display().to_string(), message }
    }

    /// Wraps an I/O error with the file's path.
    pub fn io(path: &std::path::Path, cause: std::io::Error) -> Self {
        StoreError::Io { path: path.display().to_string(), cause }
    }

    /// A format error for `path`.
    pub fn format(path: &std::path::Path, message: impl Into<String>) -> Self {
        StoreError::Format { path: path.display().to_string(), message: message.into() }
    }
}
