//! A parameter plane: two axes, cells `(iy, ix)` stored row-major, and lines
//! (rows along x, or columns with `along y`) as the units of parallel work,
//! sharding and resuming: a fresh line's cells are independent, an up or down
//! line is a continuation chain.

use crate::axis::Axis;
use crate::cell::CellData;
use crate::error::FieldError;
use crate::sweep::SweepKind;
use std::collections::BTreeMap;

scene::named_enum! {
    /// Which axis the continuation chains follow.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Along {
        /// Chains are rows: x varies.
        X = "x",
        /// Chains are columns: y varies.
        Y = "y",
    }
}

/// Two axes and the direction of continuation.
#[derive(Debug, Clone, PartialEq)]
pub struct Plane {
    /// Horizontal axis (columns).
    pub x: Axis,
    /// Vertical axis (rows).
    pub y: Axis,
    /// Direction of continuation chains.
    pub along: Along,
}

/// The states continuation chains enter a plane with, per `(sweep, line)`:
/// a zoom's lines start from the state its parent's chain had at the box's
/// edge. A chain without an entry starts from the scene's initial state.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Entries(pub BTreeMap<(SweepKind, usize), Vec<f64>>);

impl Entries {
    /// The state line `line` of `sweep` starts from, if given.
    pub fn get(&self, sweep: SweepKind, line: usize) -> Option<&[f64]> {
        self.0.get(&(sweep, line)).map(Vec::as_slice)
    }
}

/// The cells of one line, in increasing position along it.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Which sweep.
    pub sweep: SweepKind,
    /// Line index (row for `along x`, column for `along y`).
    pub index: usize,
    /// Cells in increasing position.
    pub cells: Vec<CellData>,
}

impl Plane {
    /// Builds a plane; axes must be ascending and name different parameters.
    pub fn new(x: Axis, y: Axis, along: Along) -> Result<Plane, FieldError> {
        let x = x.checked("x")?.ascending("x")?;
        let y = y.checked("y")?.ascending("y")?;
        if x.name == y.name {
            return Err(FieldError::field("y", format!("both axes sweep '{}'", x.name)));
        }
        Ok(Plane { x, y, along })
    }

    /// Number of cells.
    pub fn cells(&self) -> usize {
        self.x.count * self.y.count
    }

    /// Number of lines.
    pub fn lines(&self) -> usize {
        match self.along {
            Along::X => self.y.count,
            Along::Y => self.x.count,
        }
    }

    /// Cells per line.
    pub fn line_len(&self) -> usize {
        match self.along {
            Along::X => self.x.count,
            Along::Y => self.y.count,
        }
    }

    /// `(iy, ix)` of position `pos` on line `line`.
    pub fn cell(&self, line: usize, pos: usize) -> (usize, usize) {
        match self.along {
            Along::X => (line, pos),
            Along::Y => (pos, line),
        }
    }

    /// `(line, position on it)` of cell `(iy, ix)`: the inverse of [`Plane::cell`].
    pub fn position(&self, iy: usize, ix: usize) -> (usize, usize) {
        match self.along {
            Along::X => (iy, ix),
            Along::Y => (ix, iy),
        }
    }

    /// Parameter values of cell `(iy, ix)`.
    pub fn params(&self, iy: usize, ix: usize) -> Vec<(String, f64)> {
        vec![(self.x.name.clone(), self.x.value(ix)), (self.y.name.clone(), self.y.value(iy))]
    }
}
