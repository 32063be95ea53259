//! The sweeps of a map: fresh (every cell from the scene's initial state) or
//! a continuation chain along one parameter in which every cell starts from
//! the final state of the one before, so that a motion is followed for as
//! long as it exists; run up and down, the two chains disagree where motions
//! coexist (hysteresis).

use crate::error::FieldError;

/// Direction of a sweep, or a fresh (independent cells) map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum SweepKind {
    /// Every cell from the scene's initial state.
    Fresh,
    /// Continuation in increasing parameter order.
    Up,
    /// Continuation in decreasing parameter order.
    Down,
}

impl SweepKind {
    /// `fresh`, `up` or `down`.
    pub fn name(self) -> &'static str {
        match self {
            SweepKind::Fresh => "fresh",
            SweepKind::Up => "up",
            SweepKind::Down => "down",
        }
    }

    /// Parses a name.
    pub fn parse(name: &str) -> Option<SweepKind> {
        match name {
            "fresh" => Some(SweepKind::Fresh),
            "up" => Some(SweepKind::Up),
            "down" => Some(SweepKind::Down),
            _ => None,
        }
    }

    /// The sweeps of a `--sweep` value: `fresh`, `up`, `down` or `both` (up and down).
    pub fn parse_set(text: &str, flag: &str) -> Result<Vec<SweepKind>, FieldError> {
        match text {
            "both" => Ok(vec![SweepKind::Up, SweepKind::Down]),
            other => SweepKind::parse(other)
                .map(|k| vec![k])
                .ok_or_else(|| FieldError::field(flag, format!("expected fresh, up, down or both, got '{text}'"))),
        }
    }
}
