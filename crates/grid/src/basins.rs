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
use crate::observer::Observer;
use maps::basins::INADMISSIBLE;
use maps::Axis;
use rayon::prelude::*;
use solver::proximity::Proximity;

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
    /// Stop a start once it reaches a stable periodic attractor already
    /// known ([`solver::proximity`]), rather than running its full record.
    pub early: bool,
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

/// Starts simulated before they are grouped with the early stop, which
/// reaches only the attractors of the batches before.
const EARLY_BATCH: usize = 256;

/// How one start was run.
enum Run {
    /// It penetrates a stop.
    Inadmissible,
    /// Stopped early on the known orbit of that index, after those periods.
    Reached(usize, u64),
    /// Its full record.
    Whole(Box<maps::CellData>),
}

/// The early stop of one batch: the stable periodic attractors known, their
/// section points, the distance within which a start has reached one, and
/// the periods it is followed for at most.
struct Early {
    /// Per orbit, the index of its attractor among those found.
    attractor: Vec<usize>,
    /// Per orbit, its period-section points.
    orbits: Vec<solver::Points>,
    /// Relative distance of [`solver::proximity::reaches`].
    tol: f64,
    /// Periods followed before the start runs its full record instead.
    budget: u64,
}

/// The proximity of [`Early`]: 1e-6 (relative), or a tenth of the distance
/// between the nearest points of two known orbits where that is smaller.
const PROXIMITY: f64 = 1e-6;

impl Early {
    /// The early stop toward the stable periodic attractors of `found`
    /// (largest multiplier below 1), followed for at most twice `mean`
    /// periods (the mean of the starts run whole so far; within the
    /// transient and the record's limits); `None` when there are none.
    fn of(found: &[Attractor], setup: &CellSetup, mean: u64) -> Option<Early> {
        let stable =
            |a: &&Attractor| a.cell.class == solver::Class::Periodic && a.cell.multiplier.is_some_and(|m| m < 1.0);
        let (attractor, orbits): (Vec<usize>, Vec<solver::Points>) = found
            .iter()
            .enumerate()
            .filter(|(_, a)| stable(a))
            .map(|(k, a)| (k, a.cell.period_section.clone()))
            .unzip();
        if orbits.is_empty() {
            return None;
        }
        let d =
            |p: &[f64], q: &[f64]| p.iter().zip(q).map(|(a, b)| (a - b).abs() / (1.0 + b.abs())).fold(0.0, f64::max);
        let mut nearest = f64::INFINITY;
        for (j, a) in orbits.iter().enumerate() {
            for b in &orbits[j + 1..] {
                for p in a {
                    nearest = b.iter().map(|q| d(p, q)).fold(nearest, f64::min);
                }
            }
        }
        let acc = &setup.accuracy;
        let budget = (2 * mean).clamp(acc.min_transient() as u64 + 16, acc.max_periods() as u64);
        Some(Early { attractor, orbits, tol: PROXIMITY.min(0.1 * nearest), budget })
    }

    /// Follows the start `y0` toward the known orbits.
    fn reaches(&self, sys: &solver::System, setup: &CellSetup, y0: &[f64]) -> Proximity {
        solver::proximity::reaches(sys, &setup.accuracy, setup.method, y0, &self.orbits, self.tol, self.budget)
    }
}

/// Simulates every start of `grid` at the parameters `params` and groups
/// them by attractor; `progress` hears of every start done and may stop the
/// run ([`GridError::Cancelled`]).
pub fn basins(
    setup: &CellSetup,
    params: &[(String, f64)],
    grid: &StateGrid,
    threads: usize,
    progress: &dyn Observer,
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
    let setup = setup.comparing();
    let pool = crate::pool(threads)?;
    let n = grid.starts();
    let (mut ids, mut periods) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut found: Vec<Attractor> = Vec::new();
    // Periods of the starts run whole, for the early stop's budget.
    let (mut whole_runs, mut whole_periods) = (0u64, 0u64);
    // With the early stop, smaller batches: what is known grows sooner.
    let batch = if grid.early { EARLY_BATCH } else { BATCH };
    for first in (0..n).step_by(batch) {
        // What the early stop may reach: the stable periodic attractors
        // known when the batch begins (the same on any number of threads).
        let early = match grid.early {
            true => Early::of(&found, &setup, whole_periods / whole_runs.max(1)),
            false => None,
        };
        let cells = pool.install(|| {
            (first..(first + batch).min(n))
                .into_par_iter()
                .map(|i| {
                    if progress.cancelled() {
                        return Err(GridError::Cancelled);
                    }
                    let y0 = grid.state(i);
                    let run = match sys.admits(&y0) {
                        false => Run::Inadmissible,
                        true => match early.as_ref().map(|e| e.reaches(&sys, &setup, &y0)) {
                            Some(Proximity::Reached { orbit, periods }) => Run::Reached(orbit, periods),
                            _ => Run::Whole(Box::new(setup.run_system(&sys, &y0))),
                        },
                    };
                    progress.advance(1);
                    Ok((i, y0, run))
                })
                .collect::<Result<Vec<_>, _>>()
        })?;
        for (i, y0, run) in cells {
            let cell = match run {
                Run::Inadmissible => {
                    ids.push(INADMISSIBLE);
                    periods.push(0);
                    continue;
                }
                Run::Reached(orbit, p) => {
                    let k = early.as_ref().map_or(0, |e| e.attractor[orbit]);
                    found[k].count += 1;
                    ids.push(k as i32);
                    periods.push(p);
                    continue;
                }
                Run::Whole(cell) => *cell,
            };
            periods.push(cell.periods);
            (whole_runs, whole_periods) = (whole_runs + 1, whole_periods + cell.periods);
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
