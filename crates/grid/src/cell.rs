//! One cell of a plane: its parameters and its run into the record kept for
//! storage ([`CellData`]).

use crate::error::GridError;
use maps::CellData;
use scene::Scene;
use solver::{run_cell_measured, Accuracy, Method, System};

/// The state a cell starts from: `start` (a previous cell's final state, or a
/// stored one) when it is admissible for this system's stops, else the
/// scene's initial state.
pub fn start_state(sys: &System, start: Option<&[f64]>) -> Vec<f64> {
    match start {
        Some(s) if sys.admits(s) => s.to_vec(),
        _ => sys.model.initial_state(),
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
    /// Largest number of points kept per section per cell (at most
    /// [`maps::MAX_SECTION_CAP`]).
    pub section_cap: usize,
    /// The quantities of its steady motion each cell measures and keeps:
    /// indices into [`solver::quantity::all_names`] of the cell's system, in
    /// order (empty: none).
    pub quantities: Vec<usize>,
}

fn describe(params: &[(String, f64)]) -> String {
    params.iter().map(|(k, v)| format!("{k}={}", scene::number(*v))).collect::<Vec<_>>().join(" ")
}

impl CellSetup {
    /// The system of a cell with `params` on top of the base overrides.
    pub fn system(&self, params: &[(String, f64)]) -> Result<System, GridError> {
        let mut all = self.base.clone();
        all.extend_from_slice(params);
        let model = self.scene.evaluate(&all).map_err(|cause| GridError::Cell { params: describe(params), cause })?;
        Ok(System::new(model)?)
    }

    /// The set-up of cells whose attractors are compared with each other
    /// (`attractors`, `basins`): every period-section point kept (up to
    /// the longest period searched), no quantities measured.
    pub(crate) fn comparing(&self) -> CellSetup {
        CellSetup { section_cap: self.section_cap.max(self.accuracy.n_max()), quantities: Vec::new(), ..self.clone() }
    }

    /// Runs one cell from `start` (a previous cell's final state) when it is
    /// admissible for this cell's stops, else from the scene's initial state.
    pub fn run(&self, params: &[(String, f64)], start: Option<&[f64]>) -> Result<CellData, GridError> {
        let sys = self.system(params)?;
        Ok(self.run_system(&sys, &start_state(&sys, start)))
    }

    /// Runs the cell of system `sys` (built by [`CellSetup::system`], perhaps
    /// changed since) from the admissible state `y0`.
    pub fn run_system(&self, sys: &System, y0: &[f64]) -> CellData {
        let measure = !self.quantities.is_empty();
        let (cell, impact, all) = run_cell_measured(sys, &self.accuracy, self.method, y0, self.section_cap, measure);
        let quantities = match all {
            Some(all) => self.quantities.iter().map(|&k| all[k]).collect(),
            None => vec![f64::NAN; self.quantities.len()],
        };
        CellData::from_result(cell, impact, quantities, self.section_cap)
    }
}
