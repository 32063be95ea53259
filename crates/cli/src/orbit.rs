//! `vibroatlas orbit`: one periodic orbit by Newton's method, with its impacts
//! and Floquet multipliers.

use crate::args::OrbitArgs;
use crate::common::{sim_from, start};
use crate::out::{outln, outp};
use anyhow::Result;
use solver::{Orbit, System};
use std::fmt::Write as _;

/// Runs the command.
pub fn run(a: OrbitArgs) -> Result<()> {
    let mut r = engine::OrbitRequest::new(sim_from(&a.sim, &a.start)?);
    (r.start, r.n) = (start(&a.start)?, a.n);
    let found = engine::orbit(&r, &engine::Quiet)?;
    crate::common::tell(found.warning.as_ref(), found.note.as_ref());
    if a.json {
        outln!("{}", serde_json::to_string(&found.to_json())?);
    } else {
        outp!("{}", to_text(&found.system, &found.orbit));
    }
    Ok(())
}

fn to_text(sys: &System, o: &Orbit) -> String {
    let mut out = String::new();
    let params: Vec<String> = sys.model.parameters.iter().map(|(k, v)| format!("{k}={}", scene::number(*v))).collect();
    let _ = writeln!(out, "scene        {} ({})", sys.model.name, params.join(" "));
    for l in &o.labels {
        let _ = writeln!(out, "label        {:<6} {}", l.mass, l);
    }
    let sym = o.symmetry.map_or(String::new(), |x| format!(", symmetry {}", x.name()));
    let _ = writeln!(out, "orbit        n = {}, period {:.12}{sym}", o.n, sys.period * o.n as f64);
    if o.least_period < o.n {
        let (d, n) = (o.least_period, o.n);
        let periods = if d == 1 { "period" } else { "periods" };
        let _ = writeln!(
            out,
            "note         the orbit closes after {d} forcing {periods}: --n {n} goes round it {} times, and the labels count {n} periods (--n {d} gives its own)",
            n / d
        );
    }
    let _ = writeln!(out, "fixed point  {:?}", o.solution.x.as_slice());
    let _ = writeln!(out, "newton       {} steps, residual {:.1e}", o.solution.iterations, o.solution.residual);
    let _ = writeln!(out, "impacts      stop      time            phase     v before      v after");
    for i in &o.impacts {
        let _ = writeln!(
            out,
            "             {:<8}  {:<14.10}  {:<8.6}  {:<12.8}  {:.8}",
            sys.model.stops[i.stop].name, i.time, i.phase, i.velocity.0, i.velocity.1
        );
    }
    let _ = writeln!(out, "multipliers  (|μ|, arg)");
    for m in &o.multipliers {
        let _ = writeln!(out, "             {:<22} |μ| = {:.10}  arg = {:+.6}", format!("{:.8}", m), m.norm(), m.arg());
    }
    let _ = writeln!(out, "stable       {}", o.stable);
    out
}
