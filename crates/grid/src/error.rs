//! Errors of grid set-up: one line naming the option or field.

use thiserror::Error;

/// What is wrong with a plane, a sweep, a shard or a study.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum GridError {
    /// An option or field has a bad value.
    #[error(transparent)]
    Field(#[from] maps::FieldError),
    /// A cell's parameters do not make a valid scene.
    #[error("{}{cause}", cell_at(params))]
    Cell {
        /// The cell's parameter values.
        params: String,
        /// The scene's complaint (printed in the message, not chained).
        cause: scene::SceneError,
    },
    /// The solver refuses the scene.
    #[error(transparent)]
    Solver(#[from] solver::SolverError),
    /// The caller asked the work to stop ([`crate::Observer::cancelled`]).
    #[error("cancelled")]
    Cancelled,
}

impl GridError {
    /// Builds a [`GridError::Field`].
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        GridError::Field(maps::FieldError::field(field, message))
    }
}

/// `cell omega=1 delta=0.5: ` before a cell's complaint; nothing where no
/// parameter varies (a basin map's starts share one scene).
fn cell_at(params: &str) -> String {
    match params.is_empty() {
        true => String::new(),
        false => format!("cell {params}: "),
    }
}
