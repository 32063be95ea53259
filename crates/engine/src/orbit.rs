//! Periodic orbits: one by Newton's method ([`orbit`], `orbit --json`), and
//! one followed along a parameter with its bifurcations located
//! ([`continuation`], `continue --json`).

use crate::error::{Opt, RequestError};
use crate::sim::{check_period, labels_json, unknown, Sim, Start};
use anyhow::{anyhow, bail, Result};
use grid::Axis;
use serde_json::{json, Value};
use solver::continuation::Branch;
use solver::{orbit_of_cell, Complex64, Orbit, OrbitError, System};

/// The orbit a cell settles on: simulated from its start, then solved by
/// Newton's method on the `n`-period map (the cell's own period when `None`).
#[derive(Debug, Clone)]
pub struct Found {
    /// The system.
    pub system: System,
    /// The orbit.
    pub orbit: Orbit,
    /// A warning about the start (the scene differs from a stored one).
    pub warning: Option<String>,
}

/// Finds the periodic orbit of a cell.
pub fn orbit(sim: &Sim, start: &Start, n: Option<usize>) -> Result<Found> {
    let (s, origin) = sim.setup_from(start)?;
    check_period(n)?;
    let model = s.scene.evaluate(&s.overrides)?;
    let warning = origin.as_ref().and_then(|o| o.warning.clone());
    let y0 = origin.map_or_else(|| model.initial_state(), |o| o.state);
    let system = System::new(model)?;
    let orbit = orbit_of_cell(&system, &s.accuracy, &y0, n).map_err(|e| no_orbit(String::new(), e))?;
    Ok(Found { system, orbit, warning })
}

/// No orbit found (`at`: where, or empty): a motion that is not periodic
/// needs its period given ([`Opt::N`]).
fn no_orbit(at: String, e: OrbitError) -> anyhow::Error {
    match e {
        OrbitError::NoPeriod(_) => {
            RequestError::message().text(format!("{at}{e}; give its period with ")).opt(Opt::N).into()
        }
        e => anyhow!("{at}{e}"),
    }
}

/// Multipliers as `[{"re", "im", "abs"}, ...]` (the JSON contract).
fn multipliers_json(mu: &[Complex64]) -> Value {
    mu.iter().map(|m| json!({"re": m.re, "im": m.im, "abs": m.norm()})).collect()
}

impl Found {
    /// The JSON object of the orbit (the contract of `orbit --json`).
    pub fn to_json(&self) -> Value {
        let (sys, o) = (&self.system, &self.orbit);
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
}

/// An orbit followed along one parameter.
#[derive(Debug, Clone)]
pub struct Continued {
    /// The system at the first value.
    pub system: System,
    /// The parameter.
    pub axis: Axis,
    /// The parameter's symbol in the scene (`ω`), for figures.
    pub symbol: String,
    /// The branch and its bifurcations.
    pub branch: Branch,
    /// A warning about the start (the scene differs from a stored one).
    pub warning: Option<String>,
}

/// Follows the orbit of a cell along `axis` (natural continuation, or
/// pseudo-arclength with `arclength`), locating its bifurcations.
pub fn continuation(sim: &Sim, start: &Start, axis: &Axis, n: Option<usize>, arclength: bool) -> Result<Continued> {
    let (s, origin) = sim.setup_from(start)?;
    s.scene.check_parameter(&axis.name, "").map_err(|e| unknown(RequestError::option(Opt::Axis), e))?;
    if axis.count < 2 {
        bail!(RequestError::option(Opt::Axis).text(format!("COUNT must be at least 2, got {}", axis.count)));
    }
    check_period(n)?;
    let values = axis.values();
    let family = |v: f64| -> Option<System> { s.system_with(&[(&axis.name, v)]).ok() };
    let system = s.system_with(&[(&axis.name, values[0])])?;
    let warning = origin.as_ref().and_then(|o| o.warning.clone());
    let y0 = origin.map_or_else(|| system.model.initial_state(), |o| o.state);
    let start = orbit_of_cell(&system, &s.accuracy, &y0, n)
        .map_err(|e| no_orbit(format!("at {} = {}: ", axis.name, values[0]), e))?;
    let branch = if arclength {
        solver::arclength::follow_arclength(&family, &s.accuracy, &values, start)
    } else {
        solver::continuation::follow(&family, &s.accuracy, &values, start)
    };
    Ok(Continued { system, axis: axis.clone(), symbol: s.scene.symbol(&axis.name), branch, warning })
}

impl Continued {
    /// Each point of the branch as a figure draws it: the parameter, the
    /// first coordinate of the fixed point, the largest |Floquet multiplier|,
    /// and whether the orbit is stable.
    pub fn points(&self) -> Vec<(f64, f64, f64, bool)> {
        let radius = |o: &Orbit| solver::floquet::spectral_radius(&o.multipliers);
        self.branch.points.iter().map(|p| (p.value, p.orbit.solution.x[0], radius(&p.orbit), p.orbit.stable)).collect()
    }

    /// Each bifurcation: the parameter and the kind's name (`PD`).
    pub fn marks(&self) -> Vec<(f64, String)> {
        self.branch.bifurcations.iter().map(|b| (b.value, b.kind.name().to_string())).collect()
    }

    /// The JSON object of the branch (the contract of `continue --json`).
    pub fn to_json(&self) -> Value {
        let b = &self.branch;
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
}
