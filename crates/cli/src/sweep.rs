//! `vibroatlas sweep`: continuation along one parameter. Computed as a plane of
//! one row (the other axis is a plain parameter held at its value), so the file,
//! the renderer and the hysteresis logic are those of the atlas.

use crate::args::SweepArgs;
use crate::common::{command_line, sim_from, start};
use crate::out::outln;
use crate::progress::Shown;
use anyhow::Result;
use engine::{Legs, SweepRequest};
use grid::{Atlas, Axis, SweepKind};
use scene::Named;
use std::path::Path;
use store::write_atomically;

/// Runs the command.
pub fn run(a: SweepArgs) -> Result<()> {
    let axis = Axis::parse(&a.axis, "--axis")?;
    let page = crate::figure::page(&a.figure)?;
    if let Some(points) = a.points.filter(|&p| p > grid::MAX_SECTION_CAP) {
        anyhow::bail!("--points: at most {}, got {points}", grid::MAX_SECTION_CAP);
    }
    let (sim, from) = (sim_from(&a.sim, &a.start)?, start(&a.start)?);
    // Not the inputs, nor the sweep's file.
    let taken: Vec<&Path> = sim.inputs(&from).into_iter().chain(a.output.as_deref()).collect();
    crate::figure::check("--png", a.png.as_ref(), &taken, &page)?;
    let r = SweepRequest {
        sim,
        start: from,
        axis,
        direction: a.direction,
        section_cap: a.points.unwrap_or(a.run.section_cap),
        threads: engine::threads(a.run.threads)?,
        output: a.output.clone(),
        command: command_line(),
        variable: a.variable.clone(),
    };
    let swept = engine::sweep(&r, &Shown::new("sweep", a.run.quiet || a.json))?;
    crate::common::tell(
        swept.origin.as_ref().and_then(|o| o.warning.as_ref()),
        swept.origin.as_ref().and_then(|o| o.note.as_ref()),
    );
    let atlas = &swept.atlas;
    if let Some(png) = &a.png {
        let mut d = crate::render_cmd::diagram(atlas, 0, a.variable.as_deref(), a.impact)?;
        if let Legs::Loop(first) = swept.legs {
            d.first = Some(first);
        }
        write_atomically(png, |tmp| render::bifurcation(atlas, &d, &page, tmp))?;
    }
    if a.json {
        outln!("{}", serde_json::to_string(&swept.to_json())?);
    } else {
        print_text(atlas, &atlas.meta.sweeps)?;
        if let Some(png) = &a.png {
            crate::render_cmd::wrote(png, &page)?;
        }
    }
    Ok(())
}

/// The table of the sweep: a row per value of the swept parameter, a column
/// per sweep with each labelled mass's label (the header names them); with
/// up and down, rows where they differ are marked `*` (hysteresis).
fn print_text(atlas: &Atlas, sweeps: &[SweepKind]) -> Result<()> {
    let p = &atlas.meta.plane;
    let masses = atlas.meta.masses.join(" ");
    let header: Vec<String> = sweeps.iter().map(|s| format!("{:<24}", format!("{} ({masses})", s.name()))).collect();
    outln!("{}", format!("{:<12} {}", p.x.name, header.join("")).trim_end());
    let both = sweeps.contains(&SweepKind::Up) && sweeps.contains(&SweepKind::Down);
    let labels = |s: SweepKind, ix: usize| atlas.map(s).and_then(|m| m.cells[ix].as_ref()).map(|c| c.labels.clone());
    let mut differ = 0;
    for ix in 0..p.x.count {
        let cols: Vec<String> = sweeps
            .iter()
            .map(|&s| {
                let c = atlas.map(s).and_then(|m| m.cells[ix].as_ref());
                let text = c.map_or(String::new(), |c| {
                    (0..atlas.meta.masses.len()).map(|i| c.labels[i].to_string()).collect::<Vec<_>>().join(" ")
                });
                format!("{text:<24}")
            })
            .collect();
        let mark = both && labels(SweepKind::Up, ix) != labels(SweepKind::Down, ix);
        differ += usize::from(mark);
        let row = format!("{:<12.6} {}{}", p.x.value(ix), cols.join(""), if mark { "*" } else { "" });
        outln!("{}", row.trim_end());
    }
    if differ > 0 {
        outln!("* up and down differ ({differ} of {} values: hysteresis)", p.x.count);
    }
    Ok(())
}
