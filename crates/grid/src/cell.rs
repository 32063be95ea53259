//! One cell of a plane: its parameters, its run, and the compact record kept
//! for storage (labels as `(n, p, q)` numbers, flags as bit masks, the final
//! state and capped raw sections).

use crate::error::GridError;
use scene::Scene;
use solver::{run_cell_with_sections, Accuracy, Class, Count, Method, Symmetry, System};

/// Code of a `S` (sticking) count in stored labels.
pub const STUCK: u16 = u16::MAX;

/// What is kept of a classified cell.
#[derive(Debug, Clone, PartialEq)]
pub struct CellData {
    /// Kind of motion.
    pub class: Class,
    /// `(n, p, q)` per labelled mass; `n = 0` when not periodic; [`STUCK`] for `S`.
    pub labels: Vec<[u16; 3]>,
    /// Bit k: stop k chatters.
    pub chatter: u32,
    /// Bit k: stop k held its mass.
    pub sticking: u32,
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
}

impl CellData {
    /// The label of mass `m` as text: `1-4-4`, `1-S-S`, `C`, `U`.
    pub fn label_text(&self, m: usize) -> String {
        label_text(self.class, self.labels[m])
    }
}

/// Text of a stored label.
pub fn label_text(class: Class, npq: [u16; 3]) -> String {
    let c = |v: u16| if v == STUCK { "S".to_string() } else { v.to_string() };
    match class {
        Class::Periodic => format!("{}-{}-{}", npq[0], c(npq[1]), c(npq[2])),
        Class::Unresolved => "U".into(),
        Class::Quasiperiodic => "Q".into(),
        Class::Chaotic => "C".into(),
    }
}

/// The state a cell starts from: `start` (a previous cell's final state, or a
/// stored one) when it is admissible for this system's stops, else the
/// scene's initial state.
pub fn start_state(sys: &System, start: Option<&[f64]>) -> Vec<f64> {
    let init = sys.model.initial_state();
    let m = sys.dof();
    match start {
        Some(s) if s.len() == init.len() && (0..sys.stops.len()).all(|k| sys.model.gap(k, &s[..m]) >= -1e-9) => {
            s.to_vec()
        }
        _ => init,
    }
}

/// Everything needed to run cells of one scene.
#[derive(Debug, Clone)]
pub struct CellSetup {
    /// The scene.
    pub scene: Scene,
    /// Parameter overrides common to every cell (`--set`).
    pub base: Vec<(String, f64)>,
    /// Accuracy knobs.
    pub accuracy: Accuracy,
    /// Integrator.
    pub method: Method,
    /// Largest number of points kept per section per cell.
    pub section_cap: usize,
}

fn describe(params: &[(String, f64)]) -> String {
    params.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(" ")
}

impl CellSetup {
    /// The system of a cell with `params` on top of the base overrides.
    pub fn system(&self, params: &[(String, f64)]) -> Result<System, GridError> {
        let mut all = self.base.clone();
        all.extend_from_slice(params);
        let model = self.scene.evaluate(&all).map_err(|cause| GridError::Cell { params: describe(params), cause })?;
        Ok(System::new(model)?)
    }

    /// Runs one cell from `start` (a previous cell's final state) when it is
    /// admissible for this cell's stops, else from the scene's initial state.
    pub fn run(&self, params: &[(String, f64)], start: Option<&[f64]>) -> Result<CellData, GridError> {
        let sys = self.system(params)?;
        let y0 = start_state(&sys, start);
        let (cell, impact) = run_cell_with_sections(&sys, &self.accuracy, self.method, &y0, self.section_cap);
        let code = |c: Count| match c {
            Count::Impacts(v) => v.min(STUCK as u32 - 1) as u16,
            Count::Stuck => STUCK,
        };
        let mask = |v: &[bool]| v.iter().enumerate().filter(|(_, &b)| b).fold(0u32, |m, (k, _)| m | (1 << k));
        Ok(CellData {
            class: cell.class,
            labels: cell
                .labels
                .iter()
                .map(|l| match l.npq {
                    Some((n, p, q)) => [n as u16, code(p), code(q)],
                    None => [0, 0, 0],
                })
                .collect(),
            chatter: mask(&cell.chatter),
            sticking: mask(&cell.sticking),
            symmetry: cell.symmetry,
            lyapunov: cell.lyapunov,
            multiplier: cell.multiplier,
            final_state: cell.final_state,
            periods: cell.periods,
            events: cell.events as u64,
            period_section: cell.section.into_iter().take(self.section_cap).collect(),
            impact_sections: impact,
        })
    }
}
