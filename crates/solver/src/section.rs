//! Poincaré sections of a classified cell.
//!
//! σ_II, the period section, is the state at `t = kT` (stroboscopic): the
//! classifier keeps those points. σ_I^s, the impact section of stop s, is the
//! state just before each impact on s, with its forcing phase `t mod T`; it is
//! recorded by re-simulating the classified window with [`ImpactRecorder`]
//! ([`record_window`], called by [`crate::run_cell_with_sections`]),
//! so nothing is stored unless asked.

use crate::simulate::{Both, EventObserver, Simulator};
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

impl EventObserver for ImpactRecorder {
    fn impact(&mut self, time: f64, stop: usize, before: &DVector<f64>, _after: &DVector<f64>) {
        if self.rows[stop].len() < self.cap {
            let mut row = Vec::with_capacity(before.len() + 1);
            row.push(time.rem_euclid(self.period));
            row.extend(before.iter());
            self.rows[stop].push(row);
        }
    }
}

/// Impact sections of a window of `periods` forcing periods from full state
/// `start` (a classified window with `impacts` impacts per stop), simulated
/// again by `sim`, at most `cap` points per stop; empty when there is no window
/// or it cannot be simulated. The simulation stops once every stop has all the
/// points it will get.
/// The simulation is observed by `also` too; with the sections, the periods
/// it ran (`None` where the window could not be simulated to that point).
pub(crate) fn record_window(
    sim: &mut Simulator<'_>,
    start: &[f64],
    periods: usize,
    impacts: &[u32],
    cap: usize,
    also: &mut dyn EventObserver,
) -> (Vec<Vec<Vec<f64>>>, Option<usize>) {
    let sys = sim.system();
    let mut rec = ImpactRecorder::new(sys.stops.len(), sys.period, cap);
    if periods == 0 || sim.restart(start).is_err() {
        return (rec.rows, None);
    }
    let complete = |rec: &ImpactRecorder| rec.rows.iter().zip(impacts).all(|(r, &n)| r.len() >= cap.min(n as usize));
    let mut ran = 0;
    while ran < periods && !complete(&rec) {
        if sim.run_period(&[], false, &mut Both(&mut rec, also)).is_err() {
            return (rec.rows, None);
        }
        ran += 1;
    }
    (rec.rows, Some(ran))
}
