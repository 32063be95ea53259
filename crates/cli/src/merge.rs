//! `vibroatlas merge`: reassemble shard files into one atlas.

use crate::args::MergeArgs;
use crate::plan::command_line;
use anyhow::Result;
use store::RunInfo;

/// Runs the command.
pub fn run(a: MergeArgs) -> Result<()> {
    let (atlas, run_time_s) = store::merge(&a.parts)?;
    if !atlas.complete() {
        let missing: usize = atlas.maps.iter().map(|m| m.cells.iter().filter(|c| c.is_none()).count()).sum();
        eprintln!("note: {missing} cells are in none of the parts (a shard is missing)");
    }
    store::write(&a.output, &atlas, &RunInfo { command: command_line(), run_time_s, shard: None })?;
    println!("merged {} files into {}", a.parts.len(), a.output.display());
    Ok(())
}
