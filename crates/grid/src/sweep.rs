//! Continuation sweeps: a chain of cells along one parameter in which every
//! cell starts from the final state of the one before, so that a motion is
//! followed for as long as it exists; run up and down, the two chains disagree
//! where motions coexist (hysteresis).

use crate::cell::CellSetup;
use crate::error::GridError;
use crate::observer::Observer;
use maps::CellData;

/// Runs cells in the given order, each from the previous cell's final state
/// (the first from the scene's initial state).
pub fn chain(
    setup: &CellSetup,
    points: &[Vec<(String, f64)>],
    progress: &dyn Observer,
) -> Result<Vec<CellData>, GridError> {
    chain_from(setup, points, None, progress)
}

/// [`chain`] whose first cell starts from `first` (a stored or given state;
/// the scene's initial state when `None` or not admissible).
pub fn chain_from(
    setup: &CellSetup,
    points: &[Vec<(String, f64)>],
    first: Option<&[f64]>,
    progress: &dyn Observer,
) -> Result<Vec<CellData>, GridError> {
    let mut out: Vec<CellData> = Vec::with_capacity(points.len());
    for p in points {
        if progress.cancelled() {
            return Err(GridError::Cancelled);
        }
        let start = out.last().map_or(first, |c| Some(c.final_state.as_slice()));
        let cell = setup.run(p, start)?;
        out.push(cell);
        progress.advance(1);
    }
    Ok(out)
}
