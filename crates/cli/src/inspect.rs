//! `vibroatlas inspect`: summary of an atlas file.

use crate::args::InspectArgs;
use crate::summary::print_summary;
use anyhow::Result;

/// Runs the command.
pub fn run(a: InspectArgs) -> Result<()> {
    let l = store::read(&a.file)?;
    println!("file      {}", a.file.display());
    println!("created   {} by: {}", l.created, l.info.command);
    if let Some(s) = l.info.shard {
        println!("shard     {s} (merge the parts with `vibroatlas merge`)");
    }
    println!("run time  {:.2} s", l.info.run_time_s);
    print_summary(&l.atlas, 0.0, 0);
    Ok(())
}
