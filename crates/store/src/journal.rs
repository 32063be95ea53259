//! The resume journal: an append-only file of finished lines, one JSON object
//! per line, flushed and synced as each line finishes. An interrupted run
//! leaves at most one torn last line, which is ignored on resume; the first
//! line is a fingerprint of the run's settings so that a journal is never
//! resumed into a different atlas. Every other line carries a checksum of its
//! content and of that fingerprint, and is checked against the atlas's shape
//! (sweep, line index, cells per line, masses, state dimension, stops): an
//! edited, truncated or foreign line is refused with its line number, never
//! taken into the output and never a panic.
//!
//! The journal is a regular file of the run's own: a named pipe, device,
//! socket or symbolic link at its path is refused with one line, never opened
//! for reading (see [`crate::lock::check_own_file`]).

use crate::error::{JournalProblem, StoreError};
use maps::{CellData, Line, Meta, SweepKind};
use scene::Named;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;
use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

#[derive(Serialize, Deserialize)]
struct Header {
    fingerprint: String,
}

/// A finished line as the journal holds it: its cells in their one serde
/// form ([`maps::code`]), borrowed when written.
#[derive(Serialize, Deserialize)]
struct JLine<'a> {
    sweep: Cow<'a, str>,
    index: usize,
    cells: Cow<'a, [CellData]>,
}

/// A journal line as written: the line and the checksum of its JSON text with
/// the run's fingerprint.
#[derive(Serialize, Deserialize)]
struct Sealed {
    checksum: String,
    line: Box<serde_json::value::RawValue>,
}

/// A journal line ready to append: its JSON text with its checksum, and the
/// newline.
#[derive(Debug, Clone)]
pub struct SealedLine(Vec<u8>);

/// Encodes and seals lines for one journal (the costly part of an append,
/// done by the worker that computed the line).
#[derive(Debug)]
pub struct Sealer {
    path: PathBuf,
    fingerprint: String,
    /// The longest sealed line so far, in bytes: the next one's buffer is
    /// that long from the start, so a line is written once, into memory
    /// touched once (a buffer grown by doubling as serde writes into it, then
    /// copied beside its checksum, touched three to four times as many fresh
    /// pages, and zeroing them cost 1.6 % of the main job's samples).
    longest: AtomicUsize,
}

impl Sealer {
    /// The sealed text of `line`.
    pub fn seal(&self, line: &Line) -> Result<SealedLine, StoreError> {
        let text = sealed_text(&self.fingerprint, self.longest.load(Ordering::Relaxed), |out| {
            serde_json::to_writer(out, &encode(line))
        })
        .map_err(|e: serde_json::Error| StoreError::format(&self.path, e.to_string()))?;
        self.longest.fetch_max(text.len(), Ordering::Relaxed);
        Ok(SealedLine(text))
    }
}

/// An open journal.
#[derive(Debug)]
pub struct Journal {
    file: File,
    path: PathBuf,
    fingerprint: String,
}

/// The text of [`Sealed`] `{ checksum, line }` as serde_json writes it, and
/// the newline, in one buffer of at least `capacity` bytes: `write` puts the
/// line's JSON text in place, and its checksum within the run `fingerprint_`
/// is filled in before it. Written directly, not through
/// [`serde_json::value::RawValue`], which would parse the line's text again.
fn sealed_text<E>(
    fingerprint_: &str,
    capacity: usize,
    write: impl FnOnce(&mut Vec<u8>) -> Result<(), E>,
) -> Result<Vec<u8>, E> {
    const HEAD: &[u8] = b"{\"checksum\":\"";
    const DIGITS: usize = 16;
    let mut out = Vec::with_capacity(capacity);
    out.extend_from_slice(HEAD);
    out.extend_from_slice(&[b'0'; DIGITS]);
    out.extend_from_slice(b"\",\"line\":");
    let start = out.len();
    write(&mut out)?;
    let checksum = seal(fingerprint_, &out[start..]);
    debug_assert_eq!(checksum.len(), DIGITS, "a checksum's hex digits");
    out[HEAD.len()..HEAD.len() + DIGITS].copy_from_slice(checksum.as_bytes());
    out.extend_from_slice(b"}\n");
    Ok(out)
}

/// The 64-bit FNV-1a hash `h` continued with `bytes`.
fn fnv1a(h: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(h, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x100000001b3))
}

/// The 64-bit FNV-1a hash's starting value.
const FNV_OFFSET: u64 = 0xcbf29ce484222325;

/// 64-bit FNV-1a hash of a text, as hex.
pub fn fingerprint(text: &str) -> String {
    format!("{:016x}", fnv1a(FNV_OFFSET, text.as_bytes()))
}

fn encode(line: &Line) -> JLine<'_> {
    JLine { sweep: Cow::Borrowed(line.sweep.name()), index: line.index, cells: Cow::Borrowed(&line.cells) }
}

/// Checks a decoded line against the shape of the atlas it belongs to.
fn decode(j: JLine, meta: &Meta) -> Result<Line, String> {
    let sweep = SweepKind::parse(&j.sweep)
        .filter(|s| meta.sweeps.contains(s))
        .ok_or_else(|| format!("sweep '{}' is not one of this run's", j.sweep))?;
    let p = &meta.plane;
    if j.index >= p.lines() {
        return Err(format!("line index {} is outside the grid's {} lines", j.index, p.lines()));
    }
    if j.cells.len() != p.line_len() {
        return Err(format!("{} cells, the grid's lines have {}", j.cells.len(), p.line_len()));
    }
    for (i, c) in j.cells.iter().enumerate() {
        let bad = |what: &str| Err(format!("cell {i}: {what}"));
        if c.labels.len() != meta.masses.len() {
            return bad("wrong number of labels");
        }
        if c.final_state.len() != meta.dim || c.period_section.iter().any(|r| r.len() != meta.dim) {
            return bad("state of the wrong dimension");
        }
        if c.impact_sections.len() != meta.stops.len()
            || c.impact_sections.iter().flatten().any(|r| r.len() != meta.dim + 1)
        {
            return bad("impact sections of the wrong shape");
        }
        if c.quantities.len() != meta.quantities.len() {
            return bad("wrong number of quantities");
        }
    }
    Ok(Line { sweep, index: j.index, cells: j.cells.into_owned() })
}

/// Checksum of a line's JSON text within the run `fingerprint`.
fn seal(fingerprint_: &str, text: &[u8]) -> String {
    let h = [fingerprint_.as_bytes(), b"\n", text].into_iter().fold(FNV_OFFSET, fnv1a);
    format!("{h:016x}")
}

impl Journal {
    /// Starts a new journal (replacing any old one) for a run with `fingerprint`.
    pub fn create(path: &Path, fingerprint: &str) -> Result<Journal, StoreError> {
        let io = |e| StoreError::io(path, e);
        let mut options = OpenOptions::new();
        options.write(true).create(true).truncate(true);
        let mut file = crate::lock::open_own_file(path, "journal", &mut options)?;
        let fingerprint_ = fingerprint.to_string();
        let header = serde_json::to_string(&Header { fingerprint: fingerprint.to_string() })
            .map_err(|e| StoreError::format(path, e.to_string()))?;
        writeln!(file, "{header}").map_err(io)?;
        file.sync_data().map_err(io)?;
        Ok(Journal { file, path: path.to_path_buf(), fingerprint: fingerprint_ })
    }

    /// Reopens a journal for a run with `fingerprint` over the atlas `meta`
    /// and returns its finished lines; a missing journal starts a new one. A
    /// torn last line (an interrupted append) is dropped; any other line that
    /// does not parse, fails its checksum or does not fit the atlas is an error.
    pub fn resume(path: &Path, fingerprint: &str, meta: &Meta) -> Result<(Journal, Vec<Line>), StoreError> {
        match std::fs::symlink_metadata(path) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Ok((Journal::create(path, fingerprint)?, Vec::new()))
            }
            _ => {}
        }
        let io = |e| StoreError::io(path, e);
        let mut file = crate::lock::open_own_file(path, "journal", OpenOptions::new().read(true).write(true))?;
        let mut bytes = Vec::new();
        file.read_to_end(&mut bytes).map_err(io)?;
        let mut lines = Vec::new();
        let mut good_bytes = 0u64;
        let mut rows: Vec<&[u8]> = bytes.split(|&b| b == b'\n').collect();
        // The text after the last newline is a torn append (or nothing).
        let torn = rows.pop().unwrap_or_default();
        let refuse = |line: usize, why: String| StoreError::Journal {
            path: path.display().to_string(),
            problem: JournalProblem::Damaged { line, why },
        };
        for (i, text) in rows.iter().enumerate() {
            if i == 0 {
                let h: Header =
                    serde_json::from_slice(text).map_err(|_| StoreError::format(path, "not a vibroatlas journal"))?;
                if h.fingerprint != fingerprint {
                    return Err(StoreError::Journal {
                        path: path.display().to_string(),
                        problem: JournalProblem::OtherRun,
                    });
                }
            } else {
                let sealed: Sealed =
                    serde_json::from_slice(text).map_err(|e| refuse(i + 1, format!("not a journal line ({e})")))?;
                if seal(fingerprint, sealed.line.get().as_bytes()) != sealed.checksum {
                    return Err(refuse(i + 1, "checksum mismatch (edited or corrupt)".into()));
                }
                let j: JLine =
                    serde_json::from_str(sealed.line.get()).map_err(|e| refuse(i + 1, format!("malformed ({e})")))?;
                lines.push(decode(j, meta).map_err(|why| refuse(i + 1, why))?);
            }
            good_bytes += text.len() as u64 + 1;
        }
        if rows.is_empty() && !torn.is_empty() {
            return Err(StoreError::format(path, "not a vibroatlas journal"));
        }
        file.set_len(good_bytes).map_err(io)?;
        let mut j = Journal { file, path: path.to_path_buf(), fingerprint: fingerprint.to_string() };
        use std::io::Seek;
        j.file.seek(std::io::SeekFrom::End(0)).map_err(io)?;
        Ok((j, lines))
    }

    /// What seals lines for this journal, on any thread.
    pub fn sealer(&self) -> Sealer {
        Sealer { path: self.path.clone(), fingerprint: self.fingerprint.clone(), longest: AtomicUsize::new(0) }
    }

    /// Appends lines sealed by [`Journal::sealer`] (in any thread), all of
    /// them durably with one sync: a writer that falls behind its workers
    /// syncs once per batch instead of once per line.
    pub fn append_sealed<'a>(&mut self, lines: impl IntoIterator<Item = &'a SealedLine>) -> Result<(), StoreError> {
        let io = |e| StoreError::io(&self.path, e);
        for l in lines {
            self.file.write_all(&l.0).map_err(io)?;
        }
        self.file.sync_data().map_err(io)
    }

    /// Deletes the journal (after the atlas file is complete). Returns
    /// `false` when the journal was no longer there: removed (or replaced by
    /// another file, then left as it is) by someone else during the run, whose
    /// lines were then never durable; the output is complete all the same.
    pub fn remove(self) -> Result<bool, StoreError> {
        let ours = match (self.file.metadata(), std::fs::symlink_metadata(&self.path)) {
            (Ok(a), Ok(b)) => crate::lock::same_file(&a, &b),
            (_, Err(e)) if e.kind() == std::io::ErrorKind::NotFound => false,
            (_, Err(e)) => return Err(StoreError::io(&self.path, e)),
            (Err(e), _) => return Err(StoreError::io(&self.path, e)),
        };
        if !ours {
            return Ok(false);
        }
        std::fs::remove_file(&self.path).map_err(|e| StoreError::io(&self.path, e))?;
        Ok(true)
    }

    /// The journal's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A line sealed directly is the text serde_json writes for [`Sealed`],
    /// and its checksum is the FNV-1a hash of the fingerprint, a newline and
    /// the line's text, as journals have always held it.
    #[test]
    fn a_sealed_line_is_what_serde_writes_with_the_same_checksum() {
        let line = r#"{"sweep":"up","index":3,"cells":[{"class":0,"final_state":[0.5,-1e-300]}]}"#;
        let checksum = seal("0123456789abcdef", line.as_bytes());
        assert_eq!(checksum, fingerprint(&format!("0123456789abcdef\n{line}")));
        let sealed = Sealed {
            checksum: checksum.clone(),
            line: serde_json::value::RawValue::from_string(line.to_string()).unwrap(),
        };
        let mut want = serde_json::to_vec(&sealed).unwrap();
        want.push(b'\n');
        for capacity in [0, 10, 4096] {
            let text = sealed_text("0123456789abcdef", capacity, |out| {
                out.extend_from_slice(line.as_bytes());
                Ok::<(), ()>(())
            });
            assert_eq!(String::from_utf8(text.unwrap()).unwrap(), String::from_utf8(want.clone()).unwrap());
        }
        // FNV-1a's published value of "a".
        assert_eq!(fingerprint("a"), "af63dc4c8601ec8c");
    }
}
