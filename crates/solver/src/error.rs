//! Errors of the solver. Running out of the event budget is not an error but an
//! outcome (`unresolved`); these are conditions under which no answer exists.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Why a system cannot be simulated. Serialised (serde) as one object whose
/// `error` names the variant in snake case, with the variant's fields.
#[derive(Debug, Clone, PartialEq, Error, Serialize, Deserialize)]
#[serde(tag = "error", rename_all = "snake_case")]
pub enum SolverError {
    /// A linear mode could not be decomposed accurately.
    #[error("ill-conditioned linear mode: {message}")]
    IllConditioned {
        /// Details.
        message: String,
    },
    /// The scene uses something this solver does not model.
    #[error("{field}: {message}")]
    Unsupported {
        /// Scene field.
        field: String,
        /// What is not supported.
        message: String,
    },
    /// A number of the system or its state lies where double precision holds
    /// no answer: beyond [`crate::LARGEST_MAGNITUDE`] (products of two such
    /// numbers overflow), below its reciprocal but not zero, or not finite.
    #[error("out of range: {message}")]
    OutOfRange {
        /// Which number, and its value.
        message: String,
    },
    /// An accuracy setting is out of range.
    #[error("accuracy.{field}: {message}")]
    Accuracy {
        /// Name of the knob.
        field: String,
        /// What is wrong with it.
        message: String,
    },
}
