//! The sweeps of a map: fresh (every cell from the scene's initial state) or
//! a continuation chain along one parameter in which every cell starts from
//! the final state of the one before, so that a motion is followed for as
//! long as it exists; run up and down, the two chains disagree where motions
//! coexist (hysteresis).

use crate::error::FieldError;

scene::named_enum! {
    /// Direction of a sweep, or a fresh (independent cells) map.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
    pub enum SweepKind {
        /// Every cell from the scene's initial state.
        Fresh = "fresh",
        /// Continuation in increasing parameter order.
        Up = "up",
        /// Continuation in decreasing parameter order.
        Down = "down",
    }
}

scene::named_enum! {
    /// The sweeps a map computes (an atlas's `--sweep`).
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Sweeps {
        /// Every cell from the scene's initial state.
        Fresh = "fresh",
        /// Continuation chains upwards.
        Up = "up",
        /// Continuation chains downwards.
        Down = "down",
        /// Up and down.
        Both = "both",
    }
}

impl Sweeps {
    /// The sweeps, in the order they are computed.
    pub fn kinds(self) -> Vec<SweepKind> {
        match self {
            Sweeps::Fresh => vec![SweepKind::Fresh],
            Sweeps::Up => vec![SweepKind::Up],
            Sweeps::Down => vec![SweepKind::Down],
            Sweeps::Both => vec![SweepKind::Up, SweepKind::Down],
        }
    }
}

impl SweepKind {
    /// The sweeps of a `--sweep` value: `fresh`, `up`, `down` or `both` (up and down).
    pub fn parse_set(text: &str, flag: &str) -> Result<Vec<SweepKind>, FieldError> {
        Ok(crate::read::<Sweeps>(text, flag)?.kinds())
    }
}
