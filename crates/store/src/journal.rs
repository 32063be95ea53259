//! The resume journal: an append-only file of finished lines, one JSON object
//! per line, flushed and synced as each line finishes. An interrupted run
//! leaves at most one torn last line, which is ignored on resume; the first
//! line is a fingerprint of the run's settings so that a journal is never
//! resumed into a different atlas.

use crate::error::StoreError;
use grid::{CellData, Line, SweepKind};
use serde::{Deserialize, Serialize};
use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};

#[derive(Serialize, Deserialize)]
struct Header {
    fingerprint: String,
}

#[derive(Serialize, Deserialize)]
struct JCell {
    class: u8,
    labels: Vec<[u16; 3]>,
    chatter: u32,
    sticking: u32,
    symmetry: u8,
    #[serde(default)]
    lyapunov: Option<f64>,
    #[serde(default)]
    multiplier: Option<f64>,
    final_state: Vec<f64>,
    periods: u64,
    events: u64,
    period_section: Vec<Vec<f64>>,
    impact_sections: Vec<Vec<Vec<f64>>>,
}

#[derive(Serialize, Deserialize)]
struct JLine {
    sweep: String,
    index: usize,
    cells: Vec<JCell>,
}

/// An open journal.
#[derive(Debug)]
pub struct Journal {
    file: File,
    path: PathBuf,
}

/// The journal path of an output file: `.<name>.journal` beside it.
pub fn journal_path(output: &Path) -> PathBuf {
    let name = output.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    output.with_file_name(format!(".{name}.journal"))
}

/// 64-bit FNV-1a hash of a text, as hex.
pub fn fingerprint(text: &str) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in text.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    format!("{h:016x}")
}

fn encode(line: &Line) -> JLine {
    JLine {
        sweep: line.sweep.name().to_string(),
        index: line.index,
        cells: line
            .cells
            .iter()
            .map(|c| JCell {
                class: crate::layout::class_code(c.class),
                labels: c.labels.clone(),
                chatter: c.chatter,
                sticking: c.sticking,
                symmetry: crate::layout::symmetry_code(c.symmetry),
                lyapunov: c.lyapunov,
                multiplier: c.multiplier,
                final_state: c.final_state.clone(),
                periods: c.periods,
                events: c.events,
                period_section: c.period_section.clone(),
                impact_sections: c.impact_sections.clone(),
            })
            .collect(),
    }
}

fn decode(j: JLine) -> Option<Line> {
    Some(Line {
        sweep: SweepKind::parse(&j.sweep)?,
        index: j.index,
        cells: j
            .cells
            .into_iter()
            .map(|c| {
                Some(CellData {
                    class: crate::layout::class_of(c.class)?,
                    labels: c.labels,
                    chatter: c.chatter,
                    sticking: c.sticking,
                    symmetry: crate::layout::symmetry_of(c.symmetry),
                    lyapunov: c.lyapunov,
                    multiplier: c.multiplier,
                    final_state: c.final_state,
                    periods: c.periods,
                    events: c.events,
                    period_section: c.period_section,
                    impact_sections: c.impact_sections,
                })
            })
            .collect::<Option<Vec<_>>>()?,
    })
}

impl Journal {
    /// Starts a new journal (replacing any old one) for a run with `fingerprint`.
    pub fn create(path: &Path, fingerprint: &str) -> Result<Journal, StoreError> {
        let io = |e| StoreError::io(path, e);
        let mut file = File::create(path).map_err(io)?;
        let header = serde_json::to_string(&Header { fingerprint: fingerprint.to_string() })
            .map_err(|e| StoreError::format(path, e.to_string()))?;
        writeln!(file, "{header}").map_err(io)?;
        file.sync_data().map_err(io)?;
        Ok(Journal { file, path: path.to_path_buf() })
    }

    /// Reopens a journal for a run with `fingerprint` and returns its finished
    /// lines; a missing journal starts a new one.
    pub fn resume(path: &Path, fingerprint: &str) -> Result<(Journal, Vec<Line>), StoreError> {
        if !path.exists() {
            return Ok((Journal::create(path, fingerprint)?, Vec::new()));
        }
        let io = |e| StoreError::io(path, e);
        let reader = BufReader::new(File::open(path).map_err(io)?);
        let mut lines = Vec::new();
        let mut good_bytes = 0u64;
        for (i, text) in reader.split(b'\n').enumerate() {
            let Ok(text) = text else { break };
            if i == 0 {
                let h: Header =
                    serde_json::from_slice(&text).map_err(|_| StoreError::format(path, "not a vibroatlas journal"))?;
                if h.fingerprint != fingerprint {
                    return Err(StoreError::format(
                        path,
                        "the journal belongs to a run with other settings; remove it or run without --resume",
                    ));
                }
            } else {
                match serde_json::from_slice::<JLine>(&text).ok().and_then(decode) {
                    Some(l) => lines.push(l),
                    None => break,
                }
            }
            good_bytes += text.len() as u64 + 1;
        }
        let file = OpenOptions::new().write(true).open(path).map_err(io)?;
        file.set_len(good_bytes).map_err(io)?;
        let mut j = Journal { file, path: path.to_path_buf() };
        use std::io::Seek;
        j.file.seek(std::io::SeekFrom::End(0)).map_err(io)?;
        Ok((j, lines))
    }

    /// Appends a finished line durably.
    pub fn append(&mut self, line: &Line) -> Result<(), StoreError> {
        let io = |e| StoreError::io(&self.path, e);
        let mut text = serde_json::to_vec(&encode(line)).map_err(|e| StoreError::format(&self.path, e.to_string()))?;
        text.push(b'\n');
        self.file.write_all(&text).map_err(io)?;
        self.file.sync_data().map_err(io)
    }

    /// Deletes the journal (after the atlas file is complete).
    pub fn remove(self) -> Result<(), StoreError> {
        std::fs::remove_file(&self.path).map_err(|e| StoreError::io(&self.path, e))
    }
}
