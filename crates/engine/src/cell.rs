//! One cell: its classification from a start ([`cell`]) and its report, the
//! JSON object of `cell --json` ([`CellReport`]).

use crate::error::Result;
use crate::record::CellRecord;
use crate::sim::{parameters_of, Origin, Setup, Sim, Source, Start};
use grid::{CellData, Quantity};
use scene::Named;
use serde::Serialize;
use serde_json::Value;
use solver::{run_cell_measured, CellResult, Mask, System};
use std::collections::BTreeMap;

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
    /// The quantities of its steady motion ([`solver::quantity`]), when its
    /// motion could be followed over their window.
    pub quantities: Option<solver::quantity::Quantities>,
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
    let (result, _, quantities) = run_cell_measured(&system, &setup.accuracy, setup.method, &y0, cap, true);
    Ok(Cell { setup, system, origin, result, quantities })
}

/// The JSON of a cell (the contract of `cell --json`): what was run and
/// how it was classified, per stop and per mass by name.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CellReport {
    /// The scene's name.
    pub scene: String,
    /// Every parameter of the cell's model.
    pub parameters: BTreeMap<String, f64>,
    /// The accuracy preset.
    pub preset: &'static str,
    /// The integrator.
    pub integrator: &'static str,
    /// Its classification, labels, stability, reason, final state,
    /// section points and quantities ([`CellRecord`]).
    #[serde(flatten)]
    pub record: CellRecord,
    /// The period in forcing periods, when periodic.
    pub n: Option<usize>,
    /// Per stop, its impacts per period.
    pub impacts: BTreeMap<String, u32>,
    /// Per stop, whether it chattered.
    pub chatter: BTreeMap<String, bool>,
    /// Per stop, whether it held its mass.
    pub sticking: BTreeMap<String, bool>,
    /// Forcing periods simulated.
    pub periods_simulated: u64,
    /// Events handled.
    pub events: usize,
    /// Per friction contact (`M1-M2`), whether it ended stuck; only for a
    /// scene with friction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_stick: Option<BTreeMap<String, bool>>,
    /// Where the simulation started, when not from the scene's initial state.
    #[serde(rename = "from", skip_serializing_if = "Option::is_none")]
    pub origin: Option<Source>,
}

impl Cell {
    /// The cell as its report ([`CellReport`]).
    pub fn report(&self) -> CellReport {
        let (sys, s, c) = (&self.system, &self.setup, &self.result);
        let by_stop =
            |mask: Mask| sys.model.stops.iter().enumerate().map(move |(k, s)| (s.name.clone(), mask.contains(k)));
        let friction = friction_names(sys).into_iter().enumerate().map(|(i, n)| (n, c.friction_stick.contains(i)));
        let names = Quantity::of(sys);
        let quantities = self.quantities.clone().unwrap_or_else(|| vec![f64::NAN; names.len()]);
        let kept = CellData::from_result(c.clone(), Vec::new(), quantities, usize::MAX);
        CellReport {
            record: CellRecord::of(&sys.model.labelled_masses(), &names, &kept),
            scene: sys.model.name.clone(),
            parameters: parameters_of(sys),
            preset: s.preset.name(),
            integrator: s.method.name(),
            n: c.n,
            impacts: sys.model.stops.iter().zip(&c.impacts).map(|(s, &v)| (s.name.clone(), v)).collect(),
            chatter: by_stop(c.chatter).collect(),
            sticking: by_stop(c.sticking).collect(),
            periods_simulated: c.periods,
            events: c.events,
            friction_stick: (!sys.model.friction.is_empty()).then(|| friction.collect()),
            origin: self.origin.as_ref().map(|o| o.source.clone()),
        }
    }

    /// The JSON object of the cell (the contract of `cell --json`).
    pub fn to_json(&self) -> Value {
        crate::report::to_value(&self.report())
    }
}

/// Names of the friction contacts, `M1-M2` from their masses.
pub fn friction_names(sys: &System) -> Vec<String> {
    (0..sys.model.friction.len()).map(|i| sys.friction_name(i)).collect()
}
