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
    if let Some(name) = &a.quantity {
        return quantity(&l.atlas, name, a.sweep.as_deref(), a.json);
    }
    if a.sweep.is_some() {
        anyhow::bail!("--sweep: only with --quantity");
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

/// `inspect --quantity NAME`: where the quantity is smallest and largest.
fn quantity(atlas: &grid::Atlas, name: &str, sweep: Option<&str>, json: bool) -> Result<()> {
    let sweep = match sweep {
        None => None,
        Some(s) => Some(
            grid::SweepKind::parse(s)
                .ok_or_else(|| anyhow::anyhow!("--sweep: expected fresh, up or down, got '{s}'"))?,
        ),
    };
    let r = engine::QuantityReport::of(atlas, name, sweep)?;
    if json {
        outln!("{}", serde_json::to_string(&r.to_json())?);
        return Ok(());
    }
    outln!("quantity  {} ({}; units {})", r.name, r.long_name, r.units);
    let (x, y) = (&atlas.meta.plane.x.name, &atlas.meta.plane.y.name);
    let at = |e: &engine::Extreme| format!("{x}={}, {y}={}", e.at[x], e.at[y]);
    for (s, e) in &r.sweeps {
        match (&e.min, &e.max) {
            (Some(lo), Some(hi)) => {
                outln!("{s:<9} min {} at {}; max {} at {} ({} cells)", lo.value, at(lo), hi.value, at(hi), e.cells)
            }
            _ => outln!("{s:<9} not measured in any cell"),
        }
    }
    Ok(())
}
