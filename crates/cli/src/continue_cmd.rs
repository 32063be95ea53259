//! `vibroatlas continue`: follow one periodic orbit along a parameter and
//! locate its bifurcations (PD, SN, PF, NS, grazing).

use crate::args::ContinueArgs;
use crate::common::{sim_from, start};
use crate::out::{outln, outp};
use anyhow::Result;
use grid::Axis;
use scene::Named;
use solver::continuation::Branch;
use std::fmt::Write as _;
use store::write_atomically;

/// Runs the command.
pub fn run(a: ContinueArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let axis = Axis::parse(&a.axis, "--axis")?;
    let (sim, from) = (sim_from(&a.sim, &a.start)?, start(&a.start)?);
    crate::figure::check("--png", a.png.as_ref(), &sim.inputs(&from), &page)?;
    let mut r = engine::ContinuationRequest::new(sim, axis.clone());
    (r.start, r.n, r.arclength) = (from, a.n, a.arclength);
    let c = engine::continuation(&r, &engine::Quiet)?;
    crate::common::tell(c.warning.as_ref(), c.note.as_ref());
    let (sys, branch) = (&c.system, &c.branch);
    if let Some(path) = &a.png {
        let title = format!("{}: orbit continued in {}", sys.model.name, c.symbol);
        let first = &sys.model.masses[0].name;
        write_atomically(path, |tmp| render::branch(&c.points(), &c.marks(), &title, &c.symbol, first, &page, tmp))?;
    }
    if a.json {
        outln!("{}", serde_json::to_string(&c.to_json())?);
    } else {
        outp!("{}", to_text(&axis.name, branch));
    }
    Ok(())
}

fn to_text(name: &str, b: &Branch) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "{:<14} {:<10} {:<7} {:<14} label", name, "stable", "sym", "max |μ|");
    for p in &b.points {
        let labels: Vec<String> = p.orbit.labels.iter().map(|l| format!("{} {}", l.mass, l)).collect();
        let _ = writeln!(
            o,
            "{:<14.9} {:<10} {:<7} {:<14.10} {}",
            p.value,
            p.orbit.stable,
            p.orbit.symmetry.map_or("-", |x| x.name()),
            solver::floquet::spectral_radius(&p.orbit.multipliers),
            labels.join(", ")
        );
    }
    for x in &b.bifurcations {
        let _ = writeln!(
            o,
            "bifurcation {:<8} at {name} = {:.10}  critical multiplier |μ| = {:.8}, arg = {:+.6} rad",
            x.kind.name(),
            x.value,
            x.critical.norm(),
            x.critical.arg()
        );
    }
    if let Some(e) = &b.ended {
        let _ = writeln!(o, "ended: {e}");
    }
    o
}
