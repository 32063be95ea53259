//! One cell: its classification from a start ([`cell`]) and the JSON object
//! of `cell --json` ([`Cell::to_json`]).

use crate::sim::{labels_json, parameters_json, Origin, Setup, Sim, Start};
use anyhow::Result;
use serde_json::{json, Map, Value};
use solver::{run_cell_with_sections, CellResult, Mask, System};

/// A classified cell with what it was computed from.
#[derive(Debug, Clone)]
pub struct Cell {
    /// The validated set-up.
    pub setup: Setup,
    /// The system at the cell's parameters.
    pub system: System,
    /// Where it started, when not from the scene's initial state.
    pub origin: Option<Origin>,
    /// The classification.
    pub result: CellResult,
}

/// Simulates and classifies one cell. From a stored cell, it starts from the
/// state that cell started from and with the stored run's section cap, so
/// that the same simulation runs again (its result equals the stored one bit
/// for bit).
pub fn cell(sim: &Sim, start: &Start) -> Result<Cell> {
    let (setup, origin) = sim.setup_from(start)?;
    let system = setup.system()?;
    let y0 = match &origin {
        Some(o) if o.is_stored_cell() => grid::start_state(&system, o.cell_start.as_deref()),
        Some(o) => o.state.clone(),
        None => system.model.initial_state(),
    };
    let cap = origin.as_ref().and_then(|o| o.section_cap).unwrap_or(0);
    let result = run_cell_with_sections(&system, &setup.accuracy, setup.method, &y0, cap).0;
    Ok(Cell { setup, system, origin, result })
}

impl Cell {
    /// The JSON object of the cell (the contract of `cell --json`).
    pub fn to_json(&self) -> Value {
        let (sys, s, c) = (&self.system, &self.setup, &self.result);
        let mut out = json!({
            "scene": sys.model.name,
            "parameters": parameters_json(sys),
            "preset": s.preset.name(),
            "integrator": s.method.name(),
            "class": c.class.name(),
            "n": c.n,
            "labels": labels_json(&c.labels),
            "impacts": per_stop(sys, &c.impacts),
            "chatter": members(sys, c.chatter),
            "sticking": members(sys, c.sticking),
            "symmetry": c.symmetry.map(|x| x.name()),
            "lyapunov": c.lyapunov,
            "max_multiplier": c.multiplier,
            "final_state": c.final_state,
            "period_section": c.section,
            "periods_simulated": c.periods,
            "events": c.events,
            "reason": c.reason.as_ref().map(ToString::to_string),
        });
        if !sys.model.friction.is_empty() {
            let stuck: Map<String, Value> = friction_names(sys)
                .into_iter()
                .enumerate()
                .map(|(i, n)| (n, Value::from(c.friction_stick.contains(i))))
                .collect();
            out["friction_stick"] = Value::Object(stuck);
        }
        if let Some(origin) = &self.origin {
            out["from"] = origin.about.clone();
        }
        out
    }
}

/// Per stop (by name), its value.
fn per_stop<T: Copy>(sys: &System, values: &[T]) -> Map<String, Value>
where
    Value: From<T>,
{
    sys.model.stops.iter().zip(values).map(|(s, &v)| (s.name.clone(), Value::from(v))).collect()
}

/// Per stop, whether it is in `mask`.
fn members(sys: &System, mask: Mask) -> Map<String, Value> {
    sys.model.stops.iter().enumerate().map(|(k, s)| (s.name.clone(), Value::from(mask.contains(k)))).collect()
}

/// Names of the friction contacts, `M1-M2` from their masses.
pub fn friction_names(sys: &System) -> Vec<String> {
    let m = &sys.model.masses;
    sys.model.friction.iter().map(|f| format!("{}-{}", m[f.a].name, m[f.b].name)).collect()
}
