//! `vibroatlas inspect`: summary of an atlas file.

use crate::args::InspectArgs;
use crate::out::outln;
use crate::summary::print_summary;
use anyhow::Result;
use engine::summary_json;

/// Runs the command.
pub fn run(a: InspectArgs) -> Result<()> {
    let l = store::read(&a.file)?;
    if a.json {
        let mut o = summary_json(&l.atlas);
        o["file"] = a.file.display().to_string().into();
        o["created"] = l.created.clone().into();
        o["command"] = l.info.command.clone().into();
        o["history"] = l.info.history.clone().into();
        o["run_time_s"] = l.info.run_time_s.into();
        o["shard"] = l.info.shard.map(|s| s.to_string()).into();
        outln!("{}", serde_json::to_string(&o)?);
        return Ok(());
    }
    outln!("file      {}", a.file.display());
    outln!("created   {} by: {}", l.created, l.info.command);
    if let Some(s) = l.info.shard {
        outln!("shard     {s} (merge the parts with `vibroatlas merge`)");
    }
    outln!("run time  {:.2} s", l.info.run_time_s);
    print_summary(&l.atlas, 0.0, 0)?;
    Ok(())
}
