//! Poincaré sections of a classified cell.
//!
//! σ_II, the period section, is the state at `t = kT` (stroboscopic): the
//! classifier keeps those points. σ_I^s, the impact section of stop s, is the
//! state just before each impact on s, with its forcing phase `t mod T`; it is
//! recorded by re-simulating the classified window with [`ImpactRecorder`], so
//! nothing is stored unless asked.

use crate::accuracy::Accuracy;
use crate::classify::CellResult;
use crate::flow::Method;
use crate::simulate::{Observer, Simulator};
use crate::system::System;
use nalgebra::DVector;

/// Records up to `cap` impacts per stop: `[phase, x…, v…]` just before impact.
#[derive(Debug, Clone)]
pub struct ImpactRecorder {
    period: f64,
    cap: usize,
    /// Per stop, the recorded rows.
    pub rows: Vec<Vec<Vec<f64>>>,
}

impl ImpactRecorder {
    /// A recorder for `stops` stops of a system with forcing period `period`.
    pub fn new(stops: usize, period: f64, cap: usize) -> Self {
        ImpactRecorder { period, cap, rows: vec![Vec::new(); stops] }
    }
}

impl Observer for ImpactRecorder {
    fn impact(&mut self, time: f64, stop: usize, before: &DVector<f64>, _after: &DVector<f64>) {
        if self.rows[stop].len() < self.cap {
            let mut row = Vec::with_capacity(before.len() + 1);
            row.push(time.rem_euclid(self.period));
            row.extend(before.iter());
            self.rows[stop].push(row);
        }
    }
}

/// Impact sections of the classified window of `cell` (n periods when periodic,
/// the recorded window otherwise), at most `cap` points per stop. A cell that
/// cannot be re-simulated (unresolved) has empty sections.
pub fn impact_sections(
    sys: &System,
    acc: &Accuracy,
    method: Method,
    cell: &CellResult,
    cap: usize,
) -> Vec<Vec<Vec<f64>>> {
    let mut rec = ImpactRecorder::new(sys.stops.len(), sys.period, cap);
    if cell.section.is_empty() {
        return rec.rows;
    }
    if let Ok(mut sim) = Simulator::new(sys, *acc, method, &cell.window_start) {
        for _ in 0..cell.section.len() {
            if sim.run_period(&[], false, &mut rec).is_err() {
                break;
            }
        }
    }
    rec.rows
}
