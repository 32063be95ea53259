//! Basins of attraction over a grid of initial states: every start of the
//! grid simulated as a cell of its own (on all the pool's threads), and the
//! starts grouped by the attractor they reach, by the rule of
//! [`crate::attractors`] (same class, labels and symmetry, and for periodic
//! motions the same period-section points).
//!
//! Starts are grouped in row order, whatever the number of threads: the ids,
//! the attractors and their order are the same on one thread or many. Only
//! one cell per attractor is held (its first start's), so a grid of any size
//! needs the memory of one batch of cells.

use crate::attractors::{same, Attractor};
use crate::cell::CellSetup;
use crate::error::GridError;
use crate::sweep::Progress;
use maps::basins::INADMISSIBLE;
use maps::Axis;
use rayon::prelude::*;

/// The grid of starts: two components of the state over two axes, every
/// other component at its value in `start`, at the forcing phase `phase`.
#[derive(Debug, Clone, PartialEq)]
pub struct StateGrid {
    /// The horizontal axis (its name is the component's, `x_M2`).
    pub x: Axis,
    /// The vertical axis.
    pub y: Axis,
    /// The index in the state `[x…, v…]` of the horizontal axis's component.
    pub x_index: usize,
    /// The index of the vertical axis's component.
    pub y_index: usize,
    /// The state outside the two axes.
    pub start: Vec<f64>,
    /// The forcing phase `ω t + τ` at the start (radians).
    pub phase: f64,
}

impl StateGrid {
    /// The state of start `i` (row-major, x fastest).
    pub fn state(&self, i: usize) -> Vec<f64> {
        let mut s = self.start.clone();
        s[self.x_index] = self.x.value(i % self.x.count);
        s[self.y_index] = self.y.value(i / self.x.count);
        s
    }

    /// The number of starts.
    pub fn starts(&self) -> usize {
        self.x.count * self.y.count
    }
}

/// Which attractor every start reached.
#[derive(Debug, Clone, PartialEq)]
pub struct Reached {
    /// Per start (row-major), the index of its attractor in `attractors`, or
    /// [`INADMISSIBLE`] for a start that penetrates a stop.
    pub ids: Vec<i32>,
    /// Per start, the forcing periods it was simulated for (0 when inadmissible).
    pub periods: Vec<u64>,
    /// The attractors, the largest basin first (ties: the first reached);
    /// `members` is left empty (the ids say it).
    pub attractors: Vec<Attractor>,
}

/// Starts simulated before they are grouped.
const BATCH: usize = 4096;

/// Simulates every start of `grid` at the parameters `params` and groups
/// them by attractor; `progress` hears of every start done and may stop the
/// run ([`GridError::Cancelled`]).
pub fn basins(
    setup: &CellSetup,
    params: &[(String, f64)],
    grid: &StateGrid,
    threads: usize,
    progress: &dyn Progress,
) -> Result<Reached, GridError> {
    let mut sys = setup.system(params)?;
    // The same system with its time origin moved so that the forcing's
    // phase at t = 0 is `phase` (every harmonic moves with it).
    sys.tau = grid.phase;
    let dims = 2 * sys.dof();
    for (name, index) in [("x", grid.x_index), ("y", grid.y_index)] {
        if index >= dims || grid.start.len() != dims {
            return Err(GridError::field(name, format!("a state of {dims} components has no component {index}")));
        }
    }
    let setup = CellSetup {
        section_cap: setup.section_cap.max(setup.accuracy.n_max()),
        quantities: Vec::new(),
        ..setup.clone()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| GridError::field("threads", e.to_string()))?;
    let n = grid.starts();
    let (mut ids, mut periods) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut found: Vec<Attractor> = Vec::new();
    for first in (0..n).step_by(BATCH) {
        let cells = pool.install(|| {
            (first..(first + BATCH).min(n))
                .into_par_iter()
                .map(|i| {
                    if progress.cancelled() {
                        return Err(GridError::Cancelled);
                    }
                    let y0 = grid.state(i);
                    let cell = sys.admits(&y0).then(|| setup.run_system(&sys, &y0));
                    progress.advance(1);
                    Ok((i, y0, cell))
                })
                .collect::<Result<Vec<_>, _>>()
        })?;
        for (i, y0, cell) in cells {
            let Some(cell) = cell else {
                ids.push(INADMISSIBLE);
                periods.push(0);
                continue;
            };
            periods.push(cell.periods);
            match found.iter().position(|a| same(&a.cell, &cell)) {
                Some(k) => {
                    found[k].count += 1;
                    ids.push(k as i32);
                }
                None => {
                    ids.push(found.len() as i32);
                    found.push(Attractor { cell, start: y0, count: 1, members: vec![i] });
                }
            }
        }
    }
    // Largest basin first; `members[0]` is each attractor's first start.
    let mut order: Vec<usize> = (0..found.len()).collect();
    order.sort_by(|&a, &b| found[b].count.cmp(&found[a].count).then(found[a].members[0].cmp(&found[b].members[0])));
    let mut rank = vec![0i32; found.len()];
    for (r, &k) in order.iter().enumerate() {
        rank[k] = r as i32;
    }
    for id in ids.iter_mut().filter(|id| **id != INADMISSIBLE) {
        *id = rank[*id as usize];
    }
    let mut slots: Vec<Option<Attractor>> = found.into_iter().map(Some).collect();
    let attractors =
        order.iter().filter_map(|&k| slots[k].take()).map(|a| Attractor { members: Vec::new(), ..a }).collect();
    Ok(Reached { ids, periods, attractors })
}
