//! `vibroatlas continue`: follow one periodic orbit along a parameter and
//! locate its bifurcations (PD, SN, PF, NS, grazing).

use crate::args::ContinueArgs;
use crate::common::setup_from;
use crate::orbit::multipliers_json;
use crate::out::{outln, outp};
use anyhow::{anyhow, bail, Result};
use engine::{check_period, labels_json};
use grid::Axis;
use serde_json::{json, Value};
use solver::arclength::follow_arclength;
use solver::continuation::{follow, Branch};
use solver::{orbit_of_cell, System};
use std::fmt::Write as _;
use store::write_atomically;

/// Runs the command.
pub fn run(a: ContinueArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let (s, origin) = setup_from(&a.sim, &a.start)?;
    let axis = Axis::parse(&a.axis, "--axis")?;
    s.scene.check_parameter(&axis.name, "--axis")?;
    if axis.count < 2 {
        bail!("--axis: COUNT must be at least 2, got {}", axis.count);
    }
    check_period(a.n)?;
    let values = axis.values();
    let family = |v: f64| -> Option<System> { s.system_with(&[(&axis.name, v)]).ok() };
    let sys = s.system_with(&[(&axis.name, values[0])])?;
    let y0 = origin.map_or_else(|| sys.model.initial_state(), |o| o.state);
    let start =
        orbit_of_cell(&sys, &s.accuracy, &y0, a.n).map_err(|e| anyhow!("at {} = {}: {e}", axis.name, values[0]))?;
    let branch = if a.arclength {
        follow_arclength(&family, &s.accuracy, &values, start)
    } else {
        follow(&family, &s.accuracy, &values, start)
    };
    if let Some(path) = &a.png {
        let pts: Vec<(f64, f64, f64, bool)> = branch
            .points
            .iter()
            .map(|p| {
                (p.value, p.orbit.solution.x[0], solver::floquet::spectral_radius(&p.orbit.multipliers), p.orbit.stable)
            })
            .collect();
        let marks: Vec<(f64, String)> =
            branch.bifurcations.iter().map(|b| (b.value, b.kind.name().to_string())).collect();
        let symbol = s.scene.symbol(&axis.name);
        let title = format!("{}: orbit continued in {symbol}", sys.model.name);
        let first = sys.model.masses[0].name.clone();
        write_atomically(path, |tmp| render::branch(&pts, &marks, &title, &symbol, &first, &page, tmp))?;
    }
    if a.json {
        outln!("{}", serde_json::to_string(&to_json(&branch))?);
    } else {
        outp!("{}", to_text(&axis.name, &branch));
    }
    Ok(())
}

fn to_json(b: &Branch) -> Value {
    let branch: Vec<Value> = b
        .points
        .iter()
        .map(|p| {
            json!({
                "value": p.value,
                "stable": p.orbit.stable,
                "multipliers": multipliers_json(&p.orbit.multipliers),
                "labels": labels_json(&p.orbit.labels),
                "symmetry": p.orbit.symmetry.map(|x| x.name()),
                "fixed_point": p.orbit.solution.x.as_slice(),
            })
        })
        .collect();
    let bifurcations: Vec<Value> = b
        .bifurcations
        .iter()
        .map(|x| {
            json!({
                "kind": x.kind.name(),
                "value": x.value,
                "multipliers": multipliers_json(&x.multipliers),
                "critical": {"re": x.critical.re, "im": x.critical.im, "abs": x.critical.norm(), "arg": x.critical.arg()},
            })
        })
        .collect();
    json!({"branch": branch, "bifurcations": bifurcations, "ended": b.ended})
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
