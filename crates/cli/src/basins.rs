//! `vibroatlas basins`: the basins of attraction of one parameter point over
//! a grid of initial states (see `grid::basins`), written to a basin file,
//! summarised on standard output, drawn with `--png`.

use crate::args::BasinsArgs;
use crate::common::{command_line, sim_from, start};
use crate::out::outln;
use crate::progress::Shown;
use anyhow::Result;
use engine::BasinsRequest;
use grid::Axis;
use std::path::Path;
use store::write_atomically;

/// Runs the command.
pub fn run(a: BasinsArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let (sim, from) = (sim_from(&a.sim, &a.start)?, start(&a.start)?);
    // The figure's path checked before the work, as the file's (which it
    // must not replace either).
    let inputs: Vec<&Path> = sim.inputs(&from).into_iter().chain([a.output.as_path()]).collect();
    crate::figure::check("--png", a.png.as_ref(), &inputs, &page)?;
    let r = BasinsRequest {
        sim,
        start: from,
        x: Axis::parse(&a.x, "--x")?,
        y: Axis::parse(&a.y, "--y")?,
        phase: a.phase,
        early: a.early_stop,
        threads: engine::threads(a.threads)?,
        output: Some(a.output.clone()),
        command: command_line(),
    };
    let (map, origin) = engine::basins(&r, &Shown::new("basins", a.quiet))?;
    crate::common::tell(
        origin.as_ref().and_then(|o| o.warning.as_ref()),
        origin.as_ref().and_then(|o| o.note.as_ref()),
    );
    if let Some(png) = &a.png {
        write_atomically(png, |tmp| render::basin_map(&map, &page, tmp))?;
    }
    let report = engine::basins_report(&map);
    if a.json {
        outln!("{}", serde_json::to_string(&report.to_json())?);
        return Ok(());
    }
    let (x, y) = (&report.x, &report.y);
    outln!(
        "{} starts ({} {}..{} x {} {}..{}, phase {:.4}): {} attractors, {} starts penetrate a stop",
        report.starts,
        x.name,
        x.start,
        x.stop,
        y.name,
        y.start,
        y.stop,
        report.phase,
        report.attractors.len(),
        report.starts as u64 - report.admissible
    );
    for at in &report.attractors {
        let labels: Vec<String> = at.labels.iter().map(|(m, l)| format!("{m} {l}")).collect();
        let sym = at.symmetry.as_deref().map_or(String::new(), |s| format!(" {s}"));
        let stability = match (at.max_multiplier, at.lyapunov, &at.reason) {
            (Some(mu), _, _) => format!("max |multiplier| {mu:.6}"),
            (_, Some(l), _) => format!("lyapunov {l:.6}"),
            (_, _, Some(why)) => why.clone(),
            _ => String::new(),
        };
        outln!("{:>3} {:>6.2} %  {}{sym}  {}  ({stability})", at.id, 100.0 * at.fraction, labels.join(", "), at.class);
    }
    let b = &report.boundary;
    let alpha = b.uncertainty_exponent.map_or("none".to_string(), |u| format!("{u:.3}"));
    let boxes = format!("{} x {}", b.entropy_box, b.entropy_box);
    let entropy = if report.admissible == 0 {
        "none: no start is admissible".to_string()
    } else if !b.basin_entropy.is_finite() {
        format!("none: the grid is smaller than one box of {boxes}")
    } else {
        let fractal = if b.fractal { "yes" } else { "no" };
        format!(
            "{:.4}, boundary basin entropy {:.4} (boxes of {boxes}; fractal by ln 2: {fractal}); uncertainty exponent {alpha}",
            b.basin_entropy, b.boundary_basin_entropy
        )
    };
    outln!("basin entropy {entropy}");
    outln!("mean periods per start {:.1}", report.mean_periods);
    outln!("wrote {}", a.output.display());
    if let Some(png) = &a.png {
        crate::render_cmd::wrote(png, &page)?;
    }
    Ok(())
}
