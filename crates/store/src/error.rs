//! Errors of the store: one line naming the file and what failed. A cause
//! of another library (HDF5, a picture's writer) is kept as the error's
//! [`source`](std::error::Error::source), so that `{:#}` (anyhow) prints
//! `file: cause` on one line.

use thiserror::Error;

/// What went wrong reading or writing atlas files.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum StoreError {
    /// HDF5 library error.
    #[error("{path}")]
    Hdf5 {
        /// File.
        path: String,
        /// The library's error (the source).
        #[source]
        cause: Hdf5Error,
    },
    /// A resume journal that cannot be resumed from: the run must start over
    /// (the journal removed) or run without resuming.
    #[error("{path}: {problem}")]
    Journal {
        /// The journal.
        path: String,
        /// What is wrong with it.
        problem: JournalProblem,
    },
    /// A vibroatlas file of another kind than the one asked for.
    #[error("{path}: {found}")]
    Kind {
        /// The file.
        path: String,
        /// What it is instead.
        found: OtherKind,
    },
    /// Two parts of a merge that are not parts of the same run.
    #[error("{path}: is not a part of the same run as {first}: different {setting}")]
    OtherRun {
        /// The part refused.
        path: String,
        /// The first part.
        first: String,
        /// The first of their settings that differs.
        setting: Setting,
    },
    /// The writer of a file written atomically ([`crate::write_atomically`])
    /// failed: nothing was put in place.
    #[error("{path}")]
    Write {
        /// The file that was to be written.
        path: String,
        /// The writer's error (the source): a picture's, the HDF5 library's, the system's.
        #[source]
        cause: Box<dyn std::error::Error + Send + Sync>,
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
    /// A dataset of a file read is not what the layout and the file's other
    /// datasets say it must be (its length, an offset, a code), or larger
    /// than a reader takes: the file is refused before any of it is used.
    #[error("{path}: {dataset}: {message}")]
    Dataset {
        /// File.
        path: String,
        /// The dataset, as a path in the file (`up/flags`).
        dataset: String,
        /// What is wrong with it (`59 rows, the grid has 60`).
        message: String,
    },
    /// A file just written does not read back as it was written (a chunk that
    /// fails its checksum or does not inflate, a file cut short under the
    /// writer, values that differ): it was not renamed into place.
    #[error("{path}: the file written does not read back as written ({dataset}: {message}); it was not put in place")]
    Unverified {
        /// The file that was to be written.
        path: String,
        /// The first dataset that failed (`up/class`; `/` for the file).
        dataset: String,
        /// How it failed.
        message: String,
    },
}

/// Why a journal cannot be resumed from.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum JournalProblem {
    /// A line that this run did not write as it is (edited, truncated, foreign).
    #[error("line {line}: {why}; the journal cannot be trusted")]
    Damaged {
        /// The line's number (from 1, the header's).
        line: usize,
        /// What is wrong with it.
        why: String,
    },
    /// The journal of a run with other settings.
    #[error("the journal belongs to a run with other settings")]
    OtherRun,
}

/// What a file read is instead of the kind asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum OtherKind {
    /// A curve file where an atlas was asked for.
    #[error("not an atlas (a curve file)")]
    CurvesNotAtlas,
    /// Neither a curve file nor an atlas with curves, where curves were asked for.
    #[error("not a vibroatlas curve file nor an atlas with curves")]
    NoCurves,
}

/// The setting in which two parts of a merge differ (the first that does,
/// in this order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum Setting {
    /// The scene.
    #[error("scene")]
    Scene,
    /// The parameter values that override the scene's.
    #[error("parameter overrides")]
    Overrides,
    /// The grid: its axes, or the axis its chains follow.
    #[error("grid")]
    Grid,
    /// The sweeps.
    #[error("sweeps")]
    Sweeps,
    /// The preset, the accuracy knobs or the integrator.
    #[error("accuracy settings")]
    Accuracy,
    /// Any other setting.
    #[error("settings")]
    Other,
}

impl StoreError {
    /// Wraps an HDF5 error with the file's path.
    pub fn hdf5(path: &std::path::Path, e: hdf5::Error) -> Self {
        StoreError::Hdf5 { path: path.display().to_string(), cause: Hdf5Error(e) }
    }

    /// Wraps an I/O error with the file's path.
    pub fn io(path: &std::path::Path, cause: std::io::Error) -> Self {
        StoreError::Io { path: path.display().to_string(), cause }
    }

    /// A [`StoreError::Dataset`] error: `dataset` of `path` is not as it must be.
    pub fn dataset(path: &std::path::Path, dataset: &str, message: impl Into<String>) -> Self {
        StoreError::Dataset {
            path: path.display().to_string(),
            dataset: dataset.trim_start_matches('/').to_string(),
            message: message.into(),
        }
    }

    /// A format error for `path`.
    pub fn format(path: &std::path::Path, message: impl Into<String>) -> Self {
        StoreError::Format { path: path.display().to_string(), message: message.into() }
    }
}

/// An error of the HDF5 library, shown on one line (the library's messages
/// span lines); [`Hdf5Error::library`] is the library's own error.
#[derive(Debug)]
pub struct Hdf5Error(hdf5::Error);

impl Hdf5Error {
    /// The library's error.
    pub fn library(&self) -> &hdf5::Error {
        &self.0
    }
}

impl From<hdf5::Error> for Hdf5Error {
    fn from(e: hdf5::Error) -> Self {
        Hdf5Error(e)
    }
}

impl std::fmt::Display for Hdf5Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0.to_string().split_whitespace().collect::<Vec<_>>().join(" "))
    }
}

impl std::error::Error for Hdf5Error {}
