//! A parameter plane: two axes, cells `(iy, ix)` stored row-major, and lines
//! (rows along x, or columns with `--along y`) as the units of parallel work,
//! sharding and resuming. Fresh lines tile their cells across cores; up and
//! down lines are continuation chains, run in parallel with each other. Every
//! line's result depends only on its inputs, so the plane is identical whatever
//! the number of threads or the order in which lines finish.

use crate::axis::Axis;
use crate::cell::{CellData, CellSetup};
use crate::error::GridError;
use crate::sweep::{chain_from, Progress, SweepKind};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// Which axis the continuation chains follow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Along {
    /// Chains are rows: x varies.
    X,
    /// Chains are columns: y varies.
    Y,
}

impl Along {
    /// `x` or `y`.
    pub fn name(self) -> &'static str {
        match self {
            Along::X => "x",
            Along::Y => "y",
        }
    }

    /// Parses `x` or `y`.
    pub fn parse(text: &str) -> Result<Along, GridError> {
        match text {
            "x" => Ok(Along::X),
            "y" => Ok(Along::Y),
            _ => Err(GridError::field("along", format!("expected x or y, got '{text}'"))),
        }
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
    pub fn new(x: Axis, y: Axis, along: Along) -> Result<Plane, GridError> {
        let x = x.checked("x")?.ascending("x")?;
        let y = y.checked("y")?.ascending("y")?;
        if x.name == y.name {
            return Err(GridError::field("y", format!("both axes sweep '{}'", x.name)));
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

    /// Checks that every cell's parameters make a valid scene, before any work
    /// (cells in parallel on `threads` threads; the first failing cell in row
    /// order is reported).
    pub fn validate(&self, setup: &CellSetup, threads: usize) -> Result<(), GridError> {
        for (field, axis) in [("x", &self.x), ("y", &self.y)] {
            setup.scene.check_parameter(&axis.name, field).map_err(|e| match e {
                scene::SceneError::Field { message, .. } => GridError::field(field, message),
                other => GridError::field(field, other.to_string()),
            })?;
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| GridError::field("threads", e.to_string()))?;
        // The first failing cell in row order, whatever the thread count.
        let failed = pool.install(|| {
            (0..self.y.count)
                .into_par_iter()
                .find_map_first(|iy| (0..self.x.count).find_map(|ix| setup.system(&self.params(iy, ix)).err()))
        });
        failed.map_or(Ok(()), Err)
    }

    /// Computes one line of one sweep; a chain starts from `entry` (the
    /// scene's initial state when `None`).
    pub fn line(
        &self,
        setup: &CellSetup,
        sweep: SweepKind,
        index: usize,
        entry: Option<&[f64]>,
        progress: &dyn Progress,
    ) -> Result<Line, GridError> {
        let len = self.line_len();
        let point = |pos: usize| {
            let (iy, ix) = self.cell(index, pos);
            self.params(iy, ix)
        };
        let cells = match sweep {
            SweepKind::Fresh => (0..len)
                .into_par_iter()
                .map(|pos| {
                    if progress.cancelled() {
                        return Err(GridError::Cancelled);
                    }
                    let c = setup.run(&point(pos), None);
                    progress.advance(1);
                    c
                })
                .collect::<Result<Vec<_>, _>>()?,
            SweepKind::Up => chain_from(setup, &(0..len).map(point).collect::<Vec<_>>(), entry, progress)?,
            SweepKind::Down => {
                let mut c = chain_from(setup, &(0..len).rev().map(point).collect::<Vec<_>>(), entry, progress)?;
                c.reverse();
                c
            }
        };
        Ok(Line { sweep, index, cells })
    }

    /// Computes the given `(sweep, line)` jobs on `threads` threads (chains
    /// from their `entries`), handing each finished line to `sink` (from the
    /// worker thread that computed it). Workers take jobs first come, first
    /// served in the order given, so that a caller listing expensive lines
    /// first keeps both cores busy to the end.
    pub fn run(
        &self,
        setup: &CellSetup,
        jobs: &[(SweepKind, usize)],
        entries: &Entries,
        threads: usize,
        progress: &dyn Progress,
        sink: &(dyn Fn(Line) + Sync),
    ) -> Result<(), GridError> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| GridError::field("threads", e.to_string()))?;
        let next = AtomicUsize::new(0);
        let failed: Mutex<Option<GridError>> = Mutex::new(None);
        pool.broadcast(|_| loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let Some(&(sweep, index)) = jobs.get(i) else { break };
            match self.line(setup, sweep, index, entries.get(sweep, index), progress) {
                Ok(line) => sink(line),
                Err(e) => {
                    failed.lock().unwrap_or_else(|p| p.into_inner()).get_or_insert(e);
                    next.store(jobs.len(), Ordering::Relaxed);
                }
            }
        });
        match failed.into_inner().unwrap_or_else(|p| p.into_inner()) {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}
