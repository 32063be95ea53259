//! `vibroatlas inspect`: summary of an atlas file.

use crate::args::InspectArgs;
use crate::out::outln;
use crate::summary::print_summary;
use anyhow::Result;
use scene::Named;

/// Runs the command.
pub fn run(a: InspectArgs) -> Result<()> {
    let l = match store::read(&a.file) {
        // A basin or curve file has no atlas to summarise; --verify checks
        // every value of it against its checksums.
        Err(store::StoreError::Kind { found, .. })
            if a.verify
                && a.quantity.is_none()
                && matches!(found, store::OtherKind::BasinsNotAtlas | store::OtherKind::CurvesNotAtlas) =>
        {
            return verify_other(&a, found);
        }
        read => read?,
    };
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
    match l.info.shard {
        Some(s) if s.is_whole() => outln!("shard     {s} (the whole plane)"),
        Some(s) => outln!("shard     {s} (merge the parts with `vibroatlas merge`)"),
        None => {}
    }
    if let Some(p) = &l.info.parent {
        outln!("zoom of   {} (labels crc32 {:08x}), box {}", p.path, p.labels_crc32, p.region);
    }
    outln!("run time  {:.2} s", l.info.run_time_s);
    print_summary(&l.atlas, 0.0, 0)?;
    Ok(())
}

/// `inspect --verify` of a basin or curve file: every value read back under
/// its checksums (`basins_crc32`, `curves_crc32`), and what it holds.
fn verify_other(a: &InspectArgs, found: store::OtherKind) -> Result<()> {
    if a.sweep.is_some() {
        anyhow::bail!("--sweep: only with --quantity");
    }
    let (content, holds) = match found {
        store::OtherKind::BasinsNotAtlas => {
            let map = store::read_basins(&a.file)?;
            let starts = format!("{} × {} starts", map.x.count, map.y.count);
            ("basins", format!("{starts} of {}, {}", map.scene, counted(map.attractors.len(), "attractor")))
        }
        _ => {
            let curves = store::read_curves(&a.file)?;
            let points: usize = curves.iter().map(|c| c.points.len()).sum();
            ("curves", format!("{}, {}", counted(curves.len(), "bifurcation curve"), counted(points, "point")))
        }
    };
    if a.json {
        let report = serde_json::json!({"file": a.file, "content": content, "verified": true, "holds": holds});
        outln!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    outln!("file      {}", a.file.display());
    outln!("verified  every value reads back under the file's checksums");
    outln!("holds     {holds}");
    Ok(())
}

/// `n` and `what`, plural unless one.
fn counted(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
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
                let (lo_v, hi_v) = (scene::number(lo.value), scene::number(hi.value));
                outln!("{s:<9} min {lo_v} at {}; max {hi_v} at {} ({} cells)", at(lo), at(hi), e.cells)
            }
            _ => outln!("{s:<9} not measured in any cell"),
        }
    }
    Ok(())
}
