//! `vibroatlas inspect`: summary of an atlas file.

use crate::args::InspectArgs;
use crate::out::outln;
use crate::summary::print_summary;
use anyhow::Result;

/// Runs the command.
pub fn run(a: InspectArgs) -> Result<()> {
    let l = store::read(&a.file)?;
    if a.verify {
        store::check_finished(&a.file, &l)?;
    }
    if a.json {
        let mut report = engine::InspectReport::of(&a.file, &l);
        report.verified = a.verify.then_some(true);
        outln!("{}", serde_json::to_string(&report.to_json())?);
        return Ok(());
    }
    outln!("file      {}", a.file.display());
    if a.verify {
        outln!("verified  every group, dataset and attribute reads as vibroatlas writes this content");
    }
    outln!("created   {} by: {}", l.created, l.info.command);
    if let Some(s) = l.info.shard {
        outln!("shard     {s} (merge the parts with `vibroatlas merge`)");
    }
    if let Some(p) = &l.info.parent {
        outln!("zoom of   {} (labels crc32 {:08x}), box {}", p.path, p.labels_crc32, p.region);
    }
    outln!("run time  {:.2} s", l.info.run_time_s);
    print_summary(&l.atlas, 0.0, 0)?;
    Ok(())
}
