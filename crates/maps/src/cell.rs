//! One cell of a plane as kept for storage: labels, flags as stop masks, the
//! final state and capped raw sections.

use solver::{Class, Label, Mask, Symmetry};

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
    /// Why the cell is unresolved (the solver's reason, as text), if it is.
    pub reason: Option<String>,
}

/// Largest `section_cap`: points kept per section per cell.
pub const MAX_SECTION_CAP: usize = 100_000;
