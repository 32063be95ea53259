//! `vibroatlas orbit`: one periodic orbit by Newton's method, with its impacts
//! and Floquet multipliers.

use crate::args::OrbitArgs;
use crate::common::setup_from;
use crate::out::{outln, outp};
use anyhow::{anyhow, Result};
use engine::{check_period, labels_json};
use serde_json::{json, Value};
use solver::{orbit_of_cell, Complex64, Orbit, System};
use std::fmt::Write as _;

/// Runs the command.
pub fn run(a: OrbitArgs) -> Result<()> {
    let (s, origin) = setup_from(&a.sim, &a.start)?;
    check_period(a.n)?;
    let model = s.scene.evaluate(&s.overrides)?;
    let y0 = origin.map_or_else(|| model.initial_state(), |o| o.state);
    let sys = System::new(model)?;
    let orbit = orbit_of_cell(&sys, &s.accuracy, &y0, a.n).map_err(|e| anyhow!("{e}"))?;
    if a.json {
        outln!("{}", serde_json::to_string(&to_json(&sys, &orbit))?);
    } else {
        outp!("{}", to_text(&sys, &orbit));
    }
    Ok(())
}

/// Multipliers as `[{"re", "im", "abs"}, ...]` (the JSON contract).
pub fn multipliers_json(mu: &[Complex64]) -> Value {
    mu.iter().map(|m| json!({"re": m.re, "im": m.im, "abs": m.norm()})).collect()
}

/// The JSON object of an orbit (the contract of `orbit --json`).
pub fn to_json(sys: &System, o: &Orbit) -> Value {
    let impacts: Vec<Value> = o
        .impacts
        .iter()
        .map(|i| {
            json!({
                "stop": sys.model.stops[i.stop].name,
                "time": i.time,
                "phase": i.phase,
                "velocity_before": i.velocity.0,
                "velocity_after": i.velocity.1,
            })
        })
        .collect();
    json!({
        "scene": sys.model.name,
        "labels": labels_json(&o.labels),
        "n": o.n,
        "period": sys.period * o.n as f64,
        "fixed_point": o.solution.x.as_slice(),
        "residual": o.solution.residual,
        "newton_iterations": o.solution.iterations,
        "multipliers": multipliers_json(&o.multipliers),
        "half_map_multipliers": (o.map == solver::MapKind::Half).then(|| multipliers_json(&o.map_multipliers)),
        "stable": o.stable,
        "symmetry": o.symmetry.map(|x| x.name()),
        "impacts": impacts,
    })
}

fn to_text(sys: &System, o: &Orbit) -> String {
    let mut out = String::new();
    let params: Vec<String> = sys.model.parameters.iter().map(|(k, v)| format!("{k}={v}")).collect();
    let _ = writeln!(out, "scene        {} ({})", sys.model.name, params.join(" "));
    for l in &o.labels {
        let _ = writeln!(out, "label        {:<6} {}", l.mass, l);
    }
    let sym = o.symmetry.map_or(String::new(), |x| format!(", symmetry {}", x.name()));
    let _ = writeln!(out, "orbit        n = {}, period {:.12}{sym}", o.n, sys.period * o.n as f64);
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
