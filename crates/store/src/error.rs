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
    #[error("{path}: is not a part of the same run as {first}: different {}", differing(.setting, .differences))]
    OtherRun {
        /// The part refused.
        path: String,
        /// The first part.
        first: String,
        /// The first of their settings that differs.
        setting: Setting,
        /// Each setting that differs with its values, the first part's then
        /// this part's (`section_cap 100 and 4`).
        differences: Vec<String>,
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
    #[error("{path}: the file written does not read back as written ({}); it was not put in place", at(.dataset, .message))]
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
    /// A basin file where an atlas was asked for.
    #[error("not an atlas (a basin file of vibroatlas basins: render draws it, xarray opens it)")]
    BasinsNotAtlas,
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
        let plain = plain_of(&e, Some(path));
        StoreError::Hdf5 { path: path.display().to_string(), cause: Hdf5Error(e, plain) }
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

/// The settings that differ (`section_cap 100 and 4, preset standard and
/// fast`), or the first's words where none is listed.
fn differing(setting: &Setting, differences: &[String]) -> String {
    if differences.is_empty() {
        setting.to_string()
    } else {
        differences.join(", ")
    }
}

/// `dataset: message`, or the message alone for the file as a whole.
fn at(dataset: &str, message: &str) -> String {
    if dataset.is_empty() {
        message.to_string()
    } else {
        format!("{dataset}: {message}")
    }
}

/// An error of the HDF5 library, shown on one line (the library's messages
/// span lines); an error of the system under it (the library's text carries
/// `errno = N`) in the system's words with the file's name (`No space left
/// on device`). [`Hdf5Error::library`] is the library's own error, its whole
/// text.
#[derive(Debug)]
pub struct Hdf5Error(hdf5::Error, Option<String>);

impl Hdf5Error {
    /// The library's error.
    pub fn library(&self) -> &hdf5::Error {
        &self.0
    }
}

impl From<hdf5::Error> for Hdf5Error {
    fn from(e: hdf5::Error) -> Self {
        let plain = plain_of(&e, None);
        Hdf5Error(e, plain)
    }
}

impl std::fmt::Display for Hdf5Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.1 {
            Some(plain) => f.write_str(plain),
            None => f.write_str(&one_line(&self.0.to_string())),
        }
    }
}

/// The library's messages span lines: one line.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// An HDF5 error in one line: where the library failed on a system call
/// (`errno = N` in its text), the system's words for `N` after the name of
/// the file (`name = '…'` in the text), left out when it is `path`'s;
/// otherwise the library's text on one line.
pub(crate) fn plain(e: &hdf5::Error) -> String {
    plain_of(e, None).unwrap_or_else(|| one_line(&e.to_string()))
}

/// The system's words for the error `errno = N` of an HDF5 error's text,
/// after the file's name unless it is `path`'s; `None` without an errno.
fn plain_of(e: &hdf5::Error, path: Option<&std::path::Path>) -> Option<String> {
    let text = e.to_string();
    let at = text.find("errno = ")? + "errno = ".len();
    let digits: String = text[at..].chars().take_while(char::is_ascii_digit).collect();
    let errno: i32 = digits.parse().ok().filter(|&n| n > 0)?;
    let words = std::io::Error::from_raw_os_error(errno).to_string();
    // `No such file or directory (os error 2)`: the words alone.
    let words = words.split(" (os error").next().unwrap_or(&words).to_string();
    let name = text.find("name = '").and_then(|i| {
        let rest = &text[i + "name = '".len()..];
        rest.find('\'').map(|j| rest[..j].to_string())
    });
    let same = |n: &str| path.is_some_and(|p| std::path::Path::new(n) == p || p.ends_with(n));
    Some(match name {
        Some(n) if !n.is_empty() && !same(&n) => format!("{n}: {words}"),
        _ => words,
    })
}

impl std::error::Error for Hdf5Error {}

#[cfg(test)]
mod tests {
    use super::*;

    /// The library's text of a failed system call reads as the system's
    /// words with the file's name, on one line; other texts as they are.
    #[test]
    fn a_system_error_under_hdf5_is_said_in_the_systems_words() {
        let open = hdf5::Error::from(
            "H5Fopen(): unable to open file: unable to open file: name = '/tmp/d/.o.partial.h5', errno = 2, error message = 'No such file or directory', flags = 0, o_flags = 0",
        );
        assert_eq!(plain(&open), "/tmp/d/.o.partial.h5: No such file or directory");
        let full = hdf5::Error::from(
            "H5Fflush(): unable to flush file's cached information: file write failed: time = Thu Nov 27 17:10:20 2026\n, filename = '/tmp/d/.m.partial.h5', file descriptor = 4, errno = 28, error message = 'No space left on device', buf = 0x5, total write size = 2048, bytes this sub-write = 2048, bytes actually written = 18446744073709551615, offset = 0",
        );
        assert_eq!(plain(&full), "/tmp/d/.m.partial.h5: No space left on device");
        let e = StoreError::hdf5(std::path::Path::new("/tmp/d/.m.partial.h5"), full);
        let StoreError::Hdf5 { cause, .. } = &e else { panic!() };
        assert_eq!(cause.to_string(), "No space left on device", "the file's name once");
        assert!(cause.library().to_string().contains("errno = 28"), "the library's text kept");
        assert_eq!(plain(&hdf5::Error::from("no conversion\n path")), "no conversion path");
        let unverified = StoreError::Unverified { path: "o.h5".into(), dataset: String::new(), message: "gone".into() };
        assert_eq!(
            unverified.to_string(),
            "o.h5: the file written does not read back as written (gone); it was not put in place"
        );
    }
}
