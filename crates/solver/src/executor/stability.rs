//! Phase 3: the Floquet multipliers of an accepted period's map, and
//! whether its orbit is stable, settled and a result ([`Executor::unsettled`]).

use super::{Executor, Unresolved};
use crate::accuracy::Accuracy;
use crate::floquet::{multipliers, spectral_radius};
use crate::lyapunov::Exponent;
use crate::newton::{evaluate, MapKind};
use crate::period::distance;
use num_complex::Complex64 as C64;

/// How far beyond `periodic_tol` the distance to a found orbit that its
/// multiplier gives may be before the orbit is not a result (see
/// [`Executor::unsettled`]): well clear of the tolerance's own estimate, so
/// that only orbits far from settled are refused.
const UNSETTLED: f64 = 100.0;

/// A found orbit whose largest multiplier modulus exceeds 1 by more than this
/// is unstable: the record only passed near it ([`Unresolved::Unstable`]).
/// Within it, an orbit at a bifurcation (a pitchfork's new orbits have a
/// multiplier that crosses 1 there, measured at a state not yet on them)
/// keeps its label.
pub(super) const UNSTABLE: f64 = 1e-2;

/// A map whose largest multiplier modulus is within this of 1 (from either
/// side) does not contract measurably: a conservative oscillation (see
/// [`Executor::unsettled`]).
pub(super) const NEUTRAL: f64 = 1e-9;

/// How far from 1 a family's multiplier may lie over a flow without events
/// (exactly 1 there: a rigid mode's, whose Jordan block's pair is split by
/// about the square root of the rounding, 1e-8; a stuck friction
/// contact's), see [`without_drift`].
const DRIFT: f64 = 1e-6;

/// Periods of simulation after which the motion is near enough to an orbit
/// of period n that [`Executor::unsettled`] found it still too far from
/// ([`Unresolved::Unsettled`], finite distance `d`, multiplier modulus `μ`
/// below 1 by more than [`NEUTRAL`]): the distance falls by μ every n
/// periods, so `d μ^j` is half the limit, [`UNSETTLED`] × `periodic_tol`,
/// after `j = ln(limit / 2d) / ln μ` of them. `None` for any other reason,
/// and where the map does not contract.
pub(super) fn periods_to_settle(why: &Unresolved, n: usize, acc: &Accuracy) -> Option<usize> {
    let Unresolved::Unsettled { multiplier, distance, .. } = *why else { return None };
    if !(multiplier < 1.0 - NEUTRAL && distance.is_finite() && distance > 0.0) {
        return None;
    }
    let goal = 0.5 * UNSETTLED * acc.periodic_tol;
    let steps = ((goal / distance).ln() / multiplier.ln()).ceil().max(1.0);
    // A contraction so slow that its periods overflow a count never fits a record.
    (steps * n as f64 <= 1e15).then(|| steps as usize * n)
}

/// `mu` without the (at most) `drift` multipliers nearest 1 that lie within
/// [`DRIFT`] of it, exactly 1 over a flow without events: a rigid mode's (a
/// Jordan block of position and velocity, which rounding splits by about
/// the square root of the rounding), a stuck friction contact's.
fn without_drift(mut mu: Vec<C64>, drift: usize) -> Vec<C64> {
    for _ in 0..drift {
        let nearest = (0..mu.len()).min_by(|&a, &b| (mu[a] - 1.0).norm().total_cmp(&(mu[b] - 1.0).norm()));
        match nearest {
            Some(k) if (mu[k] - 1.0).norm() <= DRIFT => {
                mu.swap_remove(k);
            }
            _ => break,
        }
    }
    mu
}

impl<'s> Executor<'s> {
    /// Why a period n found by the record is not a result. Where the ratio
    /// of its steps showed no contraction (`hidden`, see [`remaining`](crate::period::remaining)): the
    /// distance to its orbit that its largest multiplier modulus μ gives,
    /// `e / (1 − μ)` from the record's last n-period step `e` (infinite for
    /// μ within [`NEUTRAL`] of 1 and e > 0), is beyond [`UNSETTLED`] ×
    /// `periodic_tol`. Where it did: μ within [`NEUTRAL`] of 1 (a map that
    /// does not contract; not asked of a rigid mode's family of orbits). The record's own test
    /// ([`converged`](crate::period::converged)) estimates the contraction from the ratio of two
    /// steps, which rounding hides once the steps are near the rounding of
    /// the state: a map whose multiplier is 1 within 1e-9 (a conservative
    /// oscillation under fast forcing, a mass on a vanishing spring)
    /// repeats within the tolerance while still far from its orbit. The
    /// multiplier is the cell's own (kept in `measured`); it is measured
    /// here only where it is measured anyway (`multipliers`), or where the
    /// record had no event (one linear flow). Over n periods without an
    /// event, a rigid mode's multipliers (1: the free mass's drift, a family
    /// of orbits rather than a direction to contract along) and a stuck
    /// friction contact's (1: its masses' frozen offset) are left out of the
    /// test, not out of the multiplier the cell reports. `None` for a
    /// settled orbit.
    pub(super) fn unsettled(&mut self, n: usize, hidden: bool) -> Option<Unresolved> {
        if !self.acc.multipliers && self.hist.iter().any(|r| r.events > 0) {
            return None;
        }
        let (measured, multiplier) = self.multiplier(n)?;
        self.measured = Some(measured);
        if !hidden {
            // The record saw a contraction: only a neutral map belies it.
            let neutral = (multiplier - 1.0).abs() <= NEUTRAL;
            return neutral.then_some(Unresolved::Unsettled {
                periods: self.sim.periods() as usize,
                multiplier,
                distance: f64::INFINITY,
                left: None,
            });
        }
        let len = self.hist.len();
        let step = (len.saturating_sub(n)..len)
            .filter(|&i| i >= n)
            .map(|i| distance(&self.hist[i].end, &self.hist[i - n].end));
        let step = step.fold(0.0, f64::max);
        let distance = if step == 0.0 {
            0.0
        } else if multiplier > 1.0 + NEUTRAL {
            // Beyond 1 but not unstable (see UNSTABLE): an orbit at a
            // bifurcation, whose contraction no multiplier measured off it
            // can tell; the record's own test stands.
            0.0
        } else if multiplier >= 1.0 || self.sys.lossless() && multiplier >= 1.0 - NEUTRAL {
            // Where nothing dissipates no orbit contracts (the map preserves
            // volume): a modulus below 1 within NEUTRAL is 1 rounded, and
            // the orbit is the motion's where it stays on it.
            f64::INFINITY
        } else {
            step / (1.0 - multiplier)
        };
        (distance > UNSETTLED * self.acc.periodic_tol).then_some(Unresolved::Unsettled {
            periods: self.sim.periods() as usize,
            multiplier,
            distance,
            left: None,
        })
    }

    /// Phase 3: the largest Floquet multiplier modulus of the n-period map at
    /// the main simulator's state, on a probe tracking its tangent; and the
    /// same without the multipliers of a family of orbits over an event-free
    /// orbit ([`without_drift`]): a rigid mode's, and a friction contact's
    /// that stayed stuck.
    pub(super) fn multiplier(&mut self, n: usize) -> Option<(f64, f64)> {
        let mut tangent = self.sim.probe();
        tangent.track_tangent();
        let x = self.sim.state().clone();
        // Over n periods without an event, a rigid mode's drift is a family
        // of orbits, not a direction the orbit must contract along; so is
        // the offset of the masses of a friction contact stuck throughout
        // (frozen, whatever it is, while the friction holds: one multiplier
        // 1, its relative velocity's 0).
        let len = self.hist.len();
        let window = self.hist.range(len.saturating_sub(n)..);
        let drift = match window.clone().all(|r| r.events == 0) {
            true => 2 * self.sys.rigid_modes() + window.last().map_or(0, |r| r.end_key.stuck.count_ones() as usize),
            false => 0,
        };
        self.budget.spend(&mut self.sim, &mut tangent, |t| {
            let image = evaluate(t, &x, MapKind::Periods(n)).ok()?;
            let mu = multipliers(&image.jacobian);
            (!mu.is_empty()).then(|| (spectral_radius(&mu), spectral_radius(&without_drift(mu, drift))))
        })
    }

    /// The flights' exponent (per unit time) of an orbit of period n that
    /// sticks, where its flights are beyond the simulation's precision
    /// ([`crate::Flights::beyond_precision`]): measured on a probe over 2n
    /// periods from the main state, which hold at least one whole flight.
    pub(super) fn unresolved_flights(&mut self, n: usize) -> Option<f64> {
        let mut probe = self.sim.probe();
        let e = self.budget.spend(&mut self.sim, &mut probe, |p| Exponent::measure(p, 0, 2 * n).ok())?;
        e.flights().filter(|f| f.beyond_precision(self.acc.contact_tol)).map(|f| f.per_time())
    }
}
