//! One cell of a plane as kept for storage: labels, flags as stop masks, the
//! final state and capped raw sections.

use solver::{Class, Label, Mask, Symmetry, Unresolved};
use std::collections::HashMap;

/// What is kept of a classified cell.
#[derive(Debug, Clone, PartialEq)]
pub struct CellData {
    /// Kind of motion.
    pub class: Class,
    /// Label per labelled mass.
    pub labels: Vec<Label>,
    /// Stops that chattered.
    pub chatter: Mask,
    /// Stops that held their mass.
    pub sticking: Mask,
    /// Symmetry of periodic orbits of symmetric scenes.
    pub symmetry: Option<Symmetry>,
    /// Largest Lyapunov exponent (per unit time) of a cell without a period.
    pub lyapunov: Option<f64>,
    /// Largest Floquet multiplier modulus of a periodic cell.
    pub multiplier: Option<f64>,
    /// Final state `[x…, v…]`.
    pub final_state: Vec<f64>,
    /// Periods simulated.
    pub periods: u64,
    /// Events handled.
    pub events: u64,
    /// Period-section points (states at `t = kT`).
    pub period_section: Vec<Vec<f64>>,
    /// Per stop: `[phase, x…, v…]` before each impact of the window.
    pub impact_sections: Vec<Vec<Vec<f64>>>,
    /// Why the cell is unresolved (the solver's reason, with its numbers),
    /// if it is.
    pub reason: Option<Unresolved>,
}

/// Largest `section_cap`: points kept per section per cell.
pub const MAX_SECTION_CAP: usize = 100_000;

/// Points kept per section per cell when the caller names no `section_cap`.
pub const DEFAULT_SECTION_CAP: usize = 16;

/// The labels of mass `mass` over `cells` with their cell counts, most
/// frequent first (ties in the order of the labels' text): the order of
/// every legend and label table.
pub fn label_counts<'a>(cells: impl IntoIterator<Item = &'a CellData>, mass: usize) -> Vec<(Label, u64)> {
    let mut counts: HashMap<Label, u64> = HashMap::new();
    for c in cells {
        *counts.entry(c.labels[mass]).or_default() += 1;
    }
    by_frequency(counts, Label::to_string)
}

/// Counts most frequent first, ties in the order of `key` (the text a
/// legend writes): the same order whatever order the counts came in.
pub fn by_frequency<K, S: Ord>(counts: impl IntoIterator<Item = (K, u64)>, key: impl Fn(&K) -> S) -> Vec<(K, u64)> {
    let mut v: Vec<(K, u64)> = counts.into_iter().collect();
    v.sort_by_cached_key(|(k, n)| (std::cmp::Reverse(*n), key(k)));
    v
}
