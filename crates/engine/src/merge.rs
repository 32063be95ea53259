//! Shard files merged into one atlas ([`merge`]): the output checked and
//! locked, the parts read and checked to be of one run ([`store::merge`]),
//! the cells that no part holds refused or, when allowed, stored as not
//! computed, and the atlas written.

use crate::error::Result;
use crate::error::{Opt, RequestError};
use grid::Observer;
use std::path::PathBuf;
use store::RunInfo;

/// Parts to merge.
#[derive(Debug, Clone)]
pub struct MergeRequest {
    /// The shard files (or any parts of one run).
    pub parts: Vec<PathBuf>,
    /// The atlas to write. A symbolic link's target is written.
    pub output: PathBuf,
    /// Write the atlas even when cells are in none of the parts (a shard
    /// missing): they are stored as not computed.
    pub allow_missing: bool,
    /// What made the merge (the file's `command` attribute).
    pub command: String,
}

/// Merges the parts and writes the atlas; cells in none of the parts are an
/// error (naming the missing shards), or with `allow_missing` a warning to
/// `observer`. Returns the merged parts.
pub fn merge(r: &MergeRequest, observer: &dyn Observer) -> Result<store::Merged> {
    let inputs: Vec<&std::path::Path> = r.parts.iter().map(|p| p.as_path()).collect();
    store::check_output(&r.output, &inputs)?;
    // A symbolic link's target is written (the link stays), locked by that name.
    let output = store::canonical_output(&r.output)?;
    let _lock = store::OutputLock::acquire(&output)?;
    let merged = store::merge(&r.parts)?;
    let atlas = &merged.atlas;
    if !atlas.complete() {
        let cells: usize = atlas.maps.iter().map(|m| m.cells.iter().filter(|c| c.is_none()).count()).sum();
        let shards = if merged.missing.is_empty() {
            String::new()
        } else {
            let list: Vec<String> = merged.missing.iter().map(|k| k.to_string()).collect();
            format!(" (shards {} missing)", list.join(", "))
        };
        let missing = format!("{cells} cells are in none of the parts{shards}");
        if !r.allow_missing {
            let refusal = RequestError::message().text(format!("merge: {missing}; add the missing parts, or pass "));
            return Err(refusal.opt(Opt::AllowMissing).text(" to write them as not computed").into());
        }
        observer.warn(&format!("{missing}; they are stored as not computed"));
    }
    let info = RunInfo {
        command: r.command.clone(),
        run_time_s: merged.run_time_s,
        shard: None,
        history: merged.history.clone(),
        parent: None,
    };
    store::write(&output, atlas, &info, crate::threads(None)?)?;
    Ok(merged)
}
