//! `vibroatlas merge`: reassemble shard files into one atlas.

use crate::args::MergeArgs;
use crate::common::command_line;
use anyhow::{bail, Result};
use store::RunInfo;

/// Runs the command.
pub fn run(a: MergeArgs) -> Result<()> {
    let inputs: Vec<&std::path::Path> = a.parts.iter().map(|p| p.as_path()).collect();
    store::check_output(&a.output, &inputs, a.force)?;
    // A symbolic link's target is written (the link stays), locked by that name.
    let output = store::canonical_output(&a.output)?;
    let _lock = store::OutputLock::acquire(&output)?;
    let merged = store::merge(&a.parts)?;
    let atlas = &merged.atlas;
    if !atlas.complete() {
        let cells: usize = atlas.maps.iter().map(|m| m.cells.iter().filter(|c| c.is_none()).count()).sum();
        let shards = if merged.missing.is_empty() {
            String::new()
        } else {
            let list: Vec<String> = merged.missing.iter().map(|k| k.to_string()).collect();
            format!(" (shards {} missing)", list.join(", "))
        };
        if !a.allow_missing {
            bail!("merge: {cells} cells are in none of the parts{shards}; add the missing parts, or pass --allow-missing to write them as not computed");
        }
        crate::out::errln!("warning: {cells} cells are in none of the parts{shards}; they are stored as not computed");
    }
    let info = RunInfo { command: command_line(), run_time_s: merged.run_time_s, shard: None, history: merged.history };
    store::write(&output, atlas, &info, engine::threads(None)?)?;
    crate::out::line(&format!("merged {} files into {}", a.parts.len(), a.output.display()))?;
    Ok(())
}
