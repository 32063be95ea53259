//! Newton acceleration of slowly contracting transients.
//!
//! Once a cell's impact pattern repeats with some period n while its section
//! points still contract too slowly to reach `periodic_tol` soon, the stable
//! fixed point of the n-period map that the trajectory is heading to is solved
//! by Newton's method on a probe simulator, and the record restarts from it.
//! The fixed point is taken only when it is provably this trajectory's
//! destination (see [`Newton::step`]); otherwise brute force goes on.

use crate::accuracy::Accuracy;
use crate::budget::Budget;
use crate::contact::Contact;
use crate::newton::{fixed_point, Pattern, Solution};
use crate::period::{distance, History};
use crate::simulate::{EventObserver, Simulator};
use crate::system::System;
use nalgebra::DVector;

/// Largest distance (relative, max norm) from which a Newton solution is taken
/// as the trajectory's destination: farther out a slowly attracting orbit may
/// lose the trajectory to another attractor (a long transient passes near it).
const NEWTON_REACH: f64 = 5e-3;

/// Newton tries per record (reset when a record is extended).
const TRIES: usize = 3;

/// Newton acceleration of one cell: tries spent, the period from which the
/// next may start, and the probe simulator that evaluates the period map (kept
/// between tries; its work is charged to the cell's [`Budget`]).
#[derive(Default)]
pub(crate) struct Newton<'s> {
    tries: usize,
    next: u64,
    probe: Option<Simulator<'s>>,
}

/// What a try found.
enum Try {
    /// No fixed point, or not this trajectory's destination.
    Refused,
    /// A fixed point too far ahead: wait this many periods before the next try.
    Wait(u64),
    /// The destination: restart the record from it.
    Restart(DVector<f64>),
}

impl<'s> Newton<'s> {
    /// Whether a try is due at the main simulator's current period.
    pub(crate) fn due(&self, sim: &Simulator<'_>) -> bool {
        self.tries < TRIES && sim.periods() >= self.next
    }

    /// Whether a try due now would have a contracting pattern of `hist` to
    /// work on: without one, [`Newton::step`] returns at once and touches
    /// nothing.
    pub(crate) fn has_pattern(hist: &History, acc: &Accuracy) -> bool {
        contracting_pattern(hist, acc).is_some()
    }

    /// A new record (an extension) gets its tries again.
    pub(crate) fn renew(&mut self) {
        self.tries = 0;
    }

    /// One attempt on a contracting pattern of the records `hist` of `sim`: the
    /// state to restart from when the trajectory is heading to a stable orbit.
    /// Farther than [`NEWTON_REACH`] it waits as many periods as the observed
    /// contraction needs, without spending a try.
    pub(crate) fn step(
        &mut self,
        sim: &mut Simulator<'s>,
        hist: &History,
        acc: &Accuracy,
        budget: &mut Budget,
    ) -> Option<DVector<f64>> {
        let (n, pattern, to_go, rho) = contracting_pattern(hist, acc)?;
        self.tries += 1;
        self.next = sim.periods() + 3 * n as u64;
        let y = sim.state().clone();
        let probe = self.probe.get_or_insert_with(|| sim.probe());
        let found = budget.spend(sim, probe, |p| {
            let Some(sol) = fixed_point(p, &y, n, &pattern, 1e-3 * acc.periodic_tol) else { return Try::Refused };
            let d = distance(&y, &sol.x);
            if d > NEWTON_REACH && d <= 10.0 * to_go {
                return Try::Wait(((NEWTON_REACH / d).ln() / rho.ln()).ceil().max(1.0) as u64 * n as u64);
            }
            // The fixed point must be where this trajectory is heading: a stable
            // orbit much farther away than the remaining contraction reaches belongs
            // to another attractor, and so does one whose linearisation does not
            // carry the trajectory's last n periods (it is outside the orbit's linear
            // neighbourhood, e.g. across a grazing): brute force goes on.
            if heading_to(hist, n, &y, &sol, to_go) && within_margin(p, &sol, n, &y).unwrap_or(false) {
                Try::Restart(sol.x)
            } else {
                Try::Refused
            }
        });
        match found {
            Try::Refused => None,
            Try::Wait(periods) => {
                self.next = sim.periods() + periods;
                self.tries -= 1;
                None
            }
            Try::Restart(x) => Some(x),
        }
    }
}

/// Whether the trajectory, now at `y` after the records `h`, is heading to the
/// Newton solution `sol` of its n-period map: within ten times the distance it
/// still has to go (`to_go`) and within [`NEWTON_REACH`], closer than n periods ago, and its last n-period
/// step is the orbit's linearisation `y - x* ≈ DPⁿ (y_prev - x*)`, with an error
/// below half the contraction the linearisation predicts.
fn heading_to(h: &History, n: usize, y: &DVector<f64>, sol: &Solution, to_go: f64) -> bool {
    let len = h.len();
    if len <= n || distance(y, &sol.x) > (10.0 * to_go).min(NEWTON_REACH) {
        return false;
    }
    let (now, before) = (y - &sol.x, &h[len - 1 - n].end - &sol.x);
    let predicted = &sol.jacobian * &before;
    // The part of the step the linearisation misses must be smaller than the
    // contraction it predicts, or it may undo it (near |μ| = 1 it does).
    let contraction = before.norm() - predicted.norm();
    now.norm() < before.norm() && (&now - predicted).norm() <= 0.5 * contraction
}

/// Whether `y` lies well inside the orbit's smooth neighbourhood: its position
/// deviation from the fixed point is below a quarter of the smallest gap that
/// a stop the orbit never hits keeps along the orbit (64 samples per period,
/// evaluated inside the flow's segments: the check costs about one plain
/// simulation of the orbit). Closer to such a stop the trajectory may graze
/// it and leave for another attractor although the orbit is stable. `None` when the orbit cannot be
/// simulated.
fn within_margin(probe: &mut Simulator<'_>, sol: &Solution, n: usize, y: &DVector<f64>) -> Option<bool> {
    struct Gaps<'a>(&'a System, Vec<f64>);
    impl EventObserver for Gaps<'_> {
        fn sample(&mut self, _t: f64, y: &DVector<f64>) {
            // A soft stop pressed all along keeps its distance from the clearance.
            for (k, g) in self.1.iter_mut().enumerate() {
                let gap = self.0.gap(k, y);
                *g = g.min(if self.0.stops[k].law.yields() { gap.abs() } else { gap });
            }
        }
    }
    let sys = probe.system();
    let mut gaps = Gaps(sys, vec![f64::INFINITY; sys.stops.len()]);
    // Only states are needed here; Newton's next solve tracks the tangent again.
    probe.untrack_tangent();
    let times: Vec<f64> = (1..64).map(|i| sys.period * i as f64 / 64.0).collect();
    probe.restart(sol.x.as_slice()).ok()?;
    for _ in 0..n {
        probe.run_period_sampled(&times, &mut gaps).ok()?;
    }
    let hit = |k: usize| sol.pattern.iter().any(|p| p[k] > 0);
    let margin = (0..sys.stops.len()).filter(|&k| !hit(k)).map(|k| gaps.1[k]).fold(f64::INFINITY, f64::min);
    let m = sys.dof();
    let deviation = (0..m).map(|i| (y[i] - sol.x[i]).abs()).fold(0.0, f64::max);
    Some(deviation <= 0.25 * margin)
}

/// The smallest n whose impact pattern repeated over the last 3n periods while
/// the section points still move and contract too slowly: at the observed rate
/// `ρ = |s_k - s_{k-n}| / |s_{k-n} - s_{k-2n}|`, reaching `periodic_tol` would
/// take longer than a Newton solve (about `3 (dim + 1) n` periods). Returns n,
/// the pattern, the distance the trajectory still has to go at that rate,
/// `|s_k - s_{k-n}| / (1 - ρ)`, and ρ.
fn contracting_pattern(h: &History, acc: &Accuracy) -> Option<(usize, Pattern, f64, f64)> {
    let len = h.len();
    let dim = h.back()?.end.len() as f64;
    let (n, e1, rho) = (1..=acc.n_max).find_map(|n| {
        if len <= 3 * n
            || !(len - 2 * n..len).all(|i| h[i].impacts == h[i - n].impacts && h[i].end_key == h[i - n].end_key)
        {
            return None;
        }
        let e1 = distance(&h[len - 1].end, &h[len - 1 - n].end);
        let rho = e1 / distance(&h[len - 1 - n].end, &h[len - 1 - 2 * n].end);
        let remaining = (acc.periodic_tol / e1).ln() / rho.ln() * n as f64;
        (e1 > acc.periodic_tol && rho < 1.0 && remaining > 3.0 * (dim + 1.0) * n as f64).then_some((n, e1, rho))
    })?;
    Some((n, h.iter().skip(len - n).map(|r| r.impacts.clone()).collect(), e1 / (1.0 - rho), rho))
}
