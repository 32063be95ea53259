//! The one JSON record of a classified cell ([`CellRecord`]): what
//! `cell --json` prints of its classification, each point of `sweep --json`,
//! each attractor of `attractors --json` and the explorer's cell. Each of
//! those reports flattens it and adds only what is its own (the parameters
//! of a cell, the swept value of a point, the basin share of an attractor).

use grid::{CellData, Meta, Quantity};
use serde::Serialize;
use std::collections::BTreeMap;

/// A classified cell as JSON: its kind of motion, labels, stability
/// numbers, reason, final state, section points and the quantities of its
/// steady motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CellRecord {
    /// The kind of motion ([`solver::Class::name`]).
    pub class: &'static str,
    /// Per labelled mass, its label (`1-4-4`).
    pub labels: BTreeMap<String, String>,
    /// The symmetry of a periodic orbit of a symmetric scene.
    pub symmetry: Option<&'static str>,
    /// The largest Lyapunov exponent (per unit time) of a cell without a period.
    pub lyapunov: Option<f64>,
    /// The largest Floquet multiplier modulus of a periodic cell.
    pub max_multiplier: Option<f64>,
    /// Why the cell is unresolved, when it is.
    pub reason: Option<String>,
    /// The same reason with its numbers (the solver's
    /// [`solver::Unresolved`]: `kind` and the variant's fields), when it is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason_detail: Option<solver::Unresolved>,
    /// The final state `[x…, v…]`.
    pub final_state: Vec<f64>,
    /// The period-section points kept.
    pub period_section: Vec<Vec<f64>>,
    /// The quantities of the steady motion by name ([`solver::quantity::TABLE`]
    /// and the scene's own: `max_abs_x_M1`, `impact_speed_max_A1`, `power_in`,
    /// …), null when none is measured or the motion could not be followed;
    /// a single quantity without a finite value (a defined one's `sqrt` of a
    /// negative number) is null.
    pub quantities: Option<BTreeMap<String, f64>>,
}

impl CellRecord {
    /// The record of `c`, a cell of a run whose labelled masses are named
    /// `masses` and which measures `quantities` (in the order of
    /// [`CellData::quantities`]).
    pub fn of(masses: &[String], quantities: &[Quantity], c: &CellData) -> CellRecord {
        let measured = c.quantities.iter().any(|v| !v.is_nan());
        CellRecord {
            class: c.class.name(),
            labels: labels(masses, c),
            symmetry: c.symmetry.map(|s| s.name()),
            lyapunov: c.lyapunov,
            max_multiplier: c.multiplier,
            reason: c.reason.as_ref().map(ToString::to_string),
            reason_detail: c.reason.as_deref().cloned(),
            final_state: c.final_state.clone(),
            period_section: c.period_section.to_rows(),
            quantities: measured.then(|| quantities.iter().map(|q| q.name.clone()).zip(c.quantities.clone()).collect()),
        }
    }

    /// The record of a cell of the atlas of `m`.
    pub fn in_atlas(m: &Meta, c: &CellData) -> CellRecord {
        CellRecord::of(&m.masses, &m.quantities, c)
    }
}

/// The labels of `c` by mass, its labelled masses named `masses`.
pub(crate) fn labels(masses: &[String], c: &CellData) -> BTreeMap<String, String> {
    masses.iter().cloned().zip(c.labels.iter().map(ToString::to_string)).collect()
}
