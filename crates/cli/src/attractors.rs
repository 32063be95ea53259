//! `vibroatlas attractors`: the coexisting attractors of one parameter point,
//! each with its label, a state on it, its stability and its basin fraction
//! (see `grid::attractors` for the sampling and the grouping).

use crate::args::AttractorsArgs;
use crate::common::{sim_from, start};
use crate::out::outln;
use anyhow::{anyhow, Result};
use engine::AttractorsRequest;
use grid::attractors::Sampling;
use store::write_atomically;

/// Runs the command.
pub fn run(a: AttractorsArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let (x, v) = a
        .sample_box
        .split_once(',')
        .and_then(|(x, v)| Some((x.trim().parse::<f64>().ok()?, v.trim().parse::<f64>().ok()?)))
        .ok_or_else(|| anyhow!("--box: expected X,V (two numbers >= 0), got '{}'", a.sample_box))?;
    let (sim, from) = (sim_from(&a.sim, &a.start)?, start(&a.start)?);
    crate::figure::check("--png", a.png.as_ref(), &sim.inputs(&from), &page)?;
    let r = AttractorsRequest {
        sim,
        point: from,
        sampling: Sampling { samples: a.samples, seed: a.seed, x, v },
        threads: engine::threads(a.threads)?,
    };
    let res = engine::attractors(&r, &engine::Quiet)?;
    crate::common::tell(res.warning.as_ref(), res.note.as_ref());
    let found = &res.found;
    let label = |a: &grid::attractors::Attractor| res.labels(a);
    if let Some(png) = &a.png {
        write_atomically(png, |tmp| engine::draw_basins(&res, &page, tmp))?;
    }
    if a.json {
        outln!("{}", serde_json::to_string(&res.to_json())?);
    } else {
        outln!("{} samples (seed {}, box |x| <= {x}, |v| <= {v}): {} attractors", a.samples, a.seed, found.len());
        for at in found {
            let c = &at.cell;
            // Its stability, else why it is unresolved, else nothing.
            let stability = match (c.multiplier, c.lyapunov, &c.reason) {
                (Some(mu), _, _) => format!("  (max |multiplier| {mu:.6})"),
                (_, Some(l), _) => format!("  (lyapunov {l:.6})"),
                (_, _, Some(why)) => format!("  ({why})"),
                _ => String::new(),
            };
            let sym = c.symmetry.map_or(String::new(), |x| format!(" {}", x.name()));
            outln!(
                "{:>6.1} %  {}{sym}  {}{stability}",
                100.0 * at.count as f64 / a.samples as f64,
                label(at).join(" "),
                c.class.name(),
            );
        }
    }
    Ok(())
}
