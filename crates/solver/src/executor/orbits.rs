//! Stable orbits sought near a record: Newton's method on the n-period map
//! from the record's near returns, the orbits it confirms, polishes and
//! settles on, and the tests of section points approaching one.

use super::decide::{EXPONENT_DOUBLINGS, UNDECIDED_DOUBLINGS};
use super::stability::NEUTRAL;
use super::{Departure, Executor};
use crate::accuracy::Accuracy;
use crate::circle::MOST_LOOPS;
use crate::floquet::multipliers;
use crate::newton::{fixed_point, MapKind, Pattern};
use crate::period::{detect, distance, remaining};
use crate::simulate::Ignore;
use nalgebra::DVector;

/// How much nearer a stable fixed point the last quarter of a record's
/// section points must be than the first quarter for
/// [`Executor::focus_of`] to take them as spiralling onto it.
pub(super) const SPIRAL: f64 = 0.9;

/// The least fall of the distance to a stable orbit, from the first quarter
/// of a record's section points to the last, that [`approaches`] takes
/// where it agrees with the orbit's multiplier: more than the points'
/// distances to it scatter by on a torus about it.
const SLOW_FALL: f64 = 0.98;

/// Largest distance, as a fraction of the extent of the section points,
/// between the last n points of a record without a period and the n before
/// them from which [`Executor::orbit_among`] tries Newton's method on the
/// n-period map: an orbit being reached comes back closer (1.1e-4 of the
/// extent at most, 1e-8 and less mostly, for the long and locked orbits of
/// the reference plane's edges), a torus's near returns are farther, and
/// each try costs up to 8n periods.
const ORBIT_RETURN: f64 = 1e-3;

/// Longest period of an orbit sought among the exponent's section points of a
/// record without a period (see [`Executor::orbit_among`]).
pub(super) const LONGEST_ORBIT: usize = 1000;

/// Periods tried by Newton's method per look for an orbit near a record
/// ([`Executor::stable_orbit_near`], [`Executor::orbit_among`]).
const CANDIDATES: usize = 3;

/// Largest distance between two section points of a record n periods apart,
/// as a fraction of the extent of the record's section points, from which
/// Newton's method on the n-period map is tried by
/// [`Executor::stable_orbit_near`].
const NEAR_RETURN: f64 = 0.1;

/// Largest distance (relative, max norm) between a record that contracts onto
/// an orbit longer than `n_max` and the fixed point Newton's method confirms it
/// with (see [`Executor::confirm`]).
const LONG_REACH: f64 = 1e-3;

/// The extent of section points: the distance (relative, max norm) across
/// their bounding box; 0 for none.
fn extent<'a>(mut points: impl Iterator<Item = &'a DVector<f64>>) -> f64 {
    let Some(first) = points.next() else { return 0.0 };
    let (lo, hi) =
        points.fold((first.clone(), first.clone()), |(lo, hi), p| (lo.zip_map(p, f64::min), hi.zip_map(p, f64::max)));
    distance(&hi, &lo)
}

/// How far section points (consecutive) stray from one orbit of period n:
/// the largest distance (relative, [`distance`]) of a point from the point
/// of its phase among the last n (a whole number of n periods after it);
/// NaN where a distance is. A step that adds up period after period
/// strays; rounding does not. `None` for no more than n points.
fn departure(points: &[DVector<f64>], n: usize) -> Option<f64> {
    let len = points.len();
    (len > n).then(|| {
        (0..len - n).map(|k| distance(&points[k], &points[k + (len - 1 - k) / n * n])).fold(0.0, |most, d| {
            if d > most || d.is_nan() {
                d
            } else {
                most
            }
        })
    })
}

/// Whether section points stay on one orbit of period n within `tol`
/// throughout ([`departure`]).
#[cfg(test)]
pub(super) fn periodic_throughout(points: &[DVector<f64>], n: usize, tol: f64) -> bool {
    departure(points, n).is_some_and(|d| d <= tol)
}

/// The lags n ≤ [`LONGEST_ORBIT`] (and half the points) at which the last
/// n section points all came back within [`ORBIT_RETURN`] of the points'
/// extent of the n before them, nearest first, at most [`CANDIDATES`] and
/// none a multiple of one taken ([`candidates`]).
fn return_lags(points: &[DVector<f64>]) -> Vec<usize> {
    let len = points.len();
    let within = ORBIT_RETURN * extent(points.iter());
    // How far the last n points are from the n before them, at most;
    // `None` as soon as one is not within reach (the lags are many).
    let away = |n: usize| {
        (len - n..len).try_fold(0.0, |most: f64, k| {
            let d = distance(&points[k], &points[k - n]);
            (d < within || d.is_nan()).then_some(most.max(d))
        })
    };
    let mut returns: Vec<(f64, usize)> =
        (1..=LONGEST_ORBIT.min(len / 2)).filter_map(|n| away(n).map(|a| (a, n))).collect();
    returns.sort_by(|a, b| a.0.total_cmp(&b.0));
    candidates(returns.into_iter().map(|(_, n)| (n, ()))).into_iter().map(|(n, ())| n).collect()
}

/// Whether section points (consecutive, the last nearest the motion's end)
/// approach `x`, a point of a stable orbit of period n whose n-period map's
/// largest multiplier modulus is `modulus` (|μ| < 1): the mean distance of
/// every n-th point, counted back from the last, to `x` fell by [`SPIRAL`]
/// from the first quarter of them to the last; or, for an orbit that
/// contracts too slowly for that over the record (the impact damper at
/// `fast` with μ = 0.17414, ω = 1.57692, up: a focus with |μ| = 0.99990,
/// its points 7 % nearer over 990 periods), by at least [`SLOW_FALL`] and
/// as |μ| says: the two quarters' centres lie `count − count/4` steps of
/// the map apart, over which the distance falls by |μ| to that power, and
/// the logarithm of the fall measured is within a factor of 2 of it. A
/// torus's or a chaotic motion's points keep their distance.
pub(super) fn approaches(points: &[DVector<f64>], x: &DVector<f64>, n: usize, modulus: f64) -> bool {
    let every: Vec<&DVector<f64>> = points.iter().rev().step_by(n).collect();
    let count = every.len();
    if count < 4 {
        return false;
    }
    let mean = |part: &[&DVector<f64>]| part.iter().map(|p| distance(p, x)).sum::<f64>() / part.len() as f64;
    // Newest first: the last quarter, then the first.
    let fall = mean(&every[..count / 4]) / mean(&every[count - count / 4..]);
    let expected = (count - count / 4) as f64 * modulus.ln();
    fall < SPIRAL || (fall < SLOW_FALL && (0.5..=2.0).contains(&(fall.ln() / expected)))
}

/// The periods Newton's method tries among `returns` (periods with what the
/// try needs, in the order of preference): the first [`CANDIDATES`], none a
/// multiple of one taken before it.
fn candidates<T>(returns: impl IntoIterator<Item = (usize, T)>) -> Vec<(usize, T)> {
    let mut taken: Vec<(usize, T)> = Vec::with_capacity(CANDIDATES);
    for (n, with) in returns {
        if taken.len() == CANDIDATES {
            break;
        }
        if !taken.iter().any(|(m, _)| n.is_multiple_of(*m)) {
            taken.push((n, with));
        }
    }
    taken
}

impl<'s> Executor<'s> {
    /// A found orbit of period n that repeats within `periodic_tol` but is
    /// still converging slowly (see [`converged`](crate::period::converged)): when brute force would need
    /// more than a Newton solve (about `3 (dim + 1) n` periods) to converge,
    /// Newton's method on the n-period map finishes it from the main state, on
    /// a probe: the stable fixed point with the record's impact pattern, within
    /// ten times the estimated distance still to go, to restart from. At most
    /// [`POLISHES`](super::POLISHES) tries a cell (in every preset: the orbit and its period are
    /// already found, only its convergence is finished).
    pub(super) fn polish(&mut self, n: usize) -> Option<DVector<f64>> {
        let (to_go, rho) = remaining(&self.hist, n)?;
        let dim = self.sim.state().len() as f64;
        let brute = (self.acc.periodic_tol / to_go).ln() / rho.ln() * n as f64;
        if self.polishes == 0 || brute <= 3.0 * (dim + 1.0) * n as f64 {
            return None;
        }
        self.polishes -= 1;
        let len = self.hist.len();
        let pattern: Pattern = self.hist.iter().skip(len - n).map(|r| r.impacts.clone()).collect();
        let y = self.sim.state().clone();
        let tol = 1e-3 * self.acc.periodic_tol;
        let mut probe = self.sim.probe();
        let sol = self.budget.spend(&mut self.sim, &mut probe, |p| fixed_point(p, &y, n, &pattern, tol))?;
        (distance(&y, &sol.x) <= 10.0 * to_go).then_some(sol.x)
    }

    /// How far the motion leaves the neutral orbit of period n that the
    /// record found, in a scene that dissipates nothing
    /// ([`System::lossless`](crate::system::System::lossless)): simulated on, on a probe, for as many
    /// periods as the exponent of an undecided record is measured over
    /// (standard: 6 400), the largest distance of a section point from the
    /// point of its phase among the last n ([`departure`]); `None` where the
    /// probe halted. It stays on the orbit where that is within
    /// `periodic_tol`. Where
    /// nothing contracts, a repeat within the tolerance may be a slow
    /// oscillation moving less than it per period (issue 42), which so long
    /// a record shows moving; a motion that stays put over it is the orbit,
    /// as far as the tolerance tells. Not asked of a scene that dissipates,
    /// whose neutral map is an orbit not yet reached.
    pub(super) fn left_orbit(&mut self, n: usize) -> Option<Departure> {
        let doublings = EXPONENT_DOUBLINGS + self.acc.extensions / 2 + UNDECIDED_DOUBLINGS;
        let periods = self.acc.lyapunov_periods.saturating_mul(1 << doublings).max(3 * n);
        let symmetric = self.sys.model.symmetric;
        let mut probe = self.sim.probe();
        let points = self.budget.spend(&mut self.sim, &mut probe, |p| {
            let mut points = vec![p.state().clone()];
            for _ in 0..periods {
                points.push(p.run_period(&[], symmetric, &mut Ignore).ok()?.end);
            }
            Some(points)
        });
        Some(Departure { periods, distance: departure(&points?, n)? })
    }

    /// Confirms an orbit of period `n` beyond `n_max` that the record
    /// contracts onto ([`Trail::long_period`](crate::period::Trail::long_period)): Newton's method on the
    /// n-period map from the main state converges, on a probe, to a stable
    /// fixed point within [`LONG_REACH`] of it, on which the record settles
    /// ([`Executor::settle_on`]: its period, n or a divisor). The cell is
    /// then periodic with that period, its window the last period of the
    /// record; `n_max` stays the limit of the search in the record (issue 28).
    pub(super) fn confirm(&mut self, n: usize) -> Option<usize> {
        let y = self.sim.state().clone();
        let (x, _) = self.stable_fixed_point(&y, n).filter(|(x, _)| distance(&y, x) <= LONG_REACH)?;
        self.settle_on(&x, n)
    }

    /// Restarts the record at `x`, a fixed point of the n-period map, and
    /// simulates 3n periods, which must repeat with a period m dividing n
    /// (the test of period detection with `n_max = n`): m, and the record is
    /// the orbit's. Otherwise the record is left as it was.
    fn settle_on(&mut self, x: &DVector<f64>, n: usize) -> Option<usize> {
        let before = (self.sim.state().clone(), self.hist.clone(), self.trail.clone());
        let settled = self.restart_on(x, n);
        if settled.is_none() {
            let (state, hist, trail) = before;
            self.sim.restart(state.as_slice()).ok()?;
            (self.hist, self.trail) = (hist, trail);
        }
        settled
    }

    /// [`Executor::settle_on`]'s restart and test.
    fn restart_on(&mut self, x: &DVector<f64>, n: usize) -> Option<usize> {
        self.sim.restart(x.as_slice()).ok()?;
        self.hist.clear();
        self.trail.clear();
        let wide = Accuracy { n_max: n, ..*self.acc };
        for _ in 0..3 * n {
            self.hist.push_back(self.sim.run_period(&[], self.sys.model.symmetric, &mut Ignore).ok()?);
        }
        detect(&self.hist, &wide).filter(|&m| n.is_multiple_of(m))
    }

    /// A stable fixed point of the n-period map found by Newton's method from
    /// `y`, on a probe: converged, with every multiplier inside the unit circle
    /// by more than [`NEUTRAL`] (a neutral family of orbits, such as an
    /// undamped oscillation, attracts nothing); with its largest multiplier
    /// modulus.
    fn stable_fixed_point(&mut self, y: &DVector<f64>, n: usize) -> Option<(DVector<f64>, f64)> {
        let tol = 1e-3 * self.acc.periodic_tol;
        let mut probe = self.sim.probe();
        self.budget.spend(&mut self.sim, &mut probe, |p| {
            let limits = crate::newton::Limits { tol, max_iter: 8, max_step: 0.1, stall: None };
            let sol = crate::newton::solve(p, y, MapKind::Periods(n), None, limits)?;
            let moduli: Vec<f64> = multipliers(&sol.jacobian).iter().map(|m| m.norm()).collect();
            let stable = !moduli.is_empty() && moduli.iter().all(|&m| m < 1.0 - NEUTRAL);
            stable.then(|| (sol.x, moduli.into_iter().fold(0.0, f64::max)))
        })
    }

    /// Whether the record passes near a stable periodic orbit, which a
    /// chaotic-looking transient may yet settle on: the shortest periods n ≤
    /// `n_max` at which the record came near to repeating (its nearest
    /// return within [`NEAR_RETURN`] of the extent of its section points; at
    /// most [`CANDIDATES`], none a multiple of one tried) are each tried once
    /// by Newton's method on the n-period map from the state of that return
    /// ([`Executor::stable_fixed_point`]).
    pub(super) fn stable_orbit_near(&mut self) -> bool {
        let (hist, len) = (&self.hist, self.hist.len());
        let extent = extent(hist.iter().map(|r| &r.end));
        let nearest = |n: usize| {
            (n..len).map(|k| (distance(&hist[k].end, &hist[k - n].end), n, k)).min_by(|a, b| a.0.total_cmp(&b.0))
        };
        let returns = (1..=self.acc.n_max.min(len.saturating_sub(1)))
            .filter_map(nearest)
            .filter(|r| r.0 < NEAR_RETURN * extent)
            .map(|(_, n, k)| (n, k));
        for (n, k) in candidates(returns) {
            let y = self.hist[k].end.clone();
            if self.stable_fixed_point(&y, n).is_some() {
                return true;
            }
        }
        false
    }

    /// A stable periodic orbit that the section points (consecutive, the
    /// last nearest the motion's end) contract onto, of a period n up to
    /// [`LONGEST_ORBIT`] (beyond `n_max`, or within it where the record's
    /// test missed it): the lags at which the last points came back within
    /// [`ORBIT_RETURN`] of the points' extent, nearest first (at most
    /// [`CANDIDATES`], none a multiple of one tried), each tried by Newton's
    /// method on the n-period map from the last point. One found within
    /// [`LONG_REACH`] of it is settled on and checked by period detection
    /// ([`Executor::settle_on`]); the cell is periodic with that period.
    pub(super) fn orbit_among(&mut self, points: &[DVector<f64>]) -> Option<usize> {
        let last = points.last()?;
        for n in return_lags(points) {
            let x = self.stable_fixed_point(last, n).filter(|(x, _)| distance(last, x) <= LONG_REACH);
            if let Some((x, _)) = x {
                return self.settle_on(&x, n);
            }
        }
        None
    }

    /// A stable orbit that a contracting record approaches from farther
    /// than [`LONG_REACH`]: Newton's method on the n-period map from the
    /// last point, for the lags at which the points came back near
    /// themselves ([`return_lags`]), a stable fixed point whose distance to
    /// every n-th point fell by [`SPIRAL`] from the first quarter of them to
    /// the last ([`approaches`]; a slow node's points creep along its
    /// weakest direction, each near the last), or a focus that every k-th
    /// point spirals onto ([`Executor::focus_of`], k ≤ 8). Settled on, its
    /// period ([`Executor::settle_on`]).
    pub(super) fn approached_orbit(&mut self, points: &[DVector<f64>]) -> Option<usize> {
        let last = points.last()?;
        for n in return_lags(points) {
            let x = self.stable_fixed_point(last, n).filter(|(x, modulus)| approaches(points, x, n, *modulus));
            if let Some(m) = x.and_then(|(x, _)| self.settle_on(&x, n)) {
                return Some(m);
            }
        }
        (1..=MOST_LOOPS).find_map(|k| self.focus_of(points, k))
    }

    /// A stable orbit that section points on a closed curve spiral onto: a
    /// focus whose multipliers are complex and near the unit circle, whose
    /// slow spiral turns like a torus's points (a converged rotation number,
    /// `arg μ / 2π`) but shrinks. Newton's method on the k-period map (k
    /// the curve's loops) from the centroid of
    /// every k-th point up to the last, a stable fixed point there whose
    /// distance to the points fell by [`SPIRAL`] from the first quarter of
    /// them to the last: settled on ([`Executor::settle_on`]), its period.
    /// `None` for a torus, whose points keep their distance.
    pub(super) fn focus_of(&mut self, points: &[DVector<f64>], k: usize) -> Option<usize> {
        let count = points.len().div_ceil(k);
        let centre = points.iter().rev().step_by(k).fold(DVector::zeros(points[0].len()), |a, p| a + p) / count as f64;
        let (x, modulus) = self.stable_fixed_point(&centre, k)?;
        approaches(points, &x, k, modulus).then(|| self.settle_on(&x, k)).flatten()
    }
}
