//! Motions without events: a free mass drifting towards a stop, followed to
//! it ([`Executor::follow_quiet`]), a flow that escapes, and the record
//! going on from a quiet linear flow.

use super::{Executor, Steady, Unresolved};
use crate::period::history_len;
use crate::simulate::{Halt, Ignore, PeriodRecord, Simulator};
use crate::system::System;

/// How far a free mass drifting without an event is followed beyond the
/// record's budget, in units of `max_periods` (see
/// [`Executor::follow_quiet`]).
pub(super) const DRIFT_REACH: usize = 100;

/// Fewest periods without an event over which growing gaps show a motion
/// that escapes (see [`Executor::unbounded`]).
const ESCAPE_PERIODS: usize = 20;

/// Whether a motion without events bound for a stop was followed towards it
/// ([`Executor::follow_quiet`]): at most once a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Follow {
    /// Not followed.
    Not,
    /// Followed to an event, and recorded afresh from there.
    Met,
    /// Followed for these periods, to the reach, without an event.
    Reached(u64),
}

/// Where `sim`'s current flow carries a free mass towards a stop by drift
/// (the masses have a rigid mode, and a stop's gap closes by the secular
/// part of the flow, [`Simulator::gap_drifts`]): the gap's decrease per
/// forcing period (the fastest to close) and the periods it needs to close
/// at that rate from the current gap. `None` otherwise.
pub(super) fn closing_drift(sys: &System, sim: &mut Simulator<'_>) -> Option<(f64, f64)> {
    if !sys.has_rigid_mode() {
        return None;
    }
    let drifts = sim.gap_drifts()?;
    let y = sim.state();
    drifts
        .into_iter()
        .filter_map(|(k, rate)| {
            let closing = -rate * sys.period;
            (closing > 0.0).then(|| (closing, sys.gap(k, y).max(0.0) / closing))
        })
        .min_by(|x, y| x.1.total_cmp(&y.1))
}

impl<'s> Executor<'s> {
    /// Why a record without a period is not chaos or a torus: the motion
    /// escapes. The masses have a rigid mode, the last half of the record
    /// (at least [`ESCAPE_PERIODS`] periods) had no event, and every stop's
    /// gap grew at every one of its periods: nothing is left that would stop
    /// the drift. `None` otherwise.
    pub(super) fn unbounded(&self) -> Option<Unresolved> {
        let (sys, hist) = (self.sys, &self.hist);
        let half = hist.len() / 2;
        if half < ESCAPE_PERIODS || hist.iter().skip(half).any(|r| r.events > 0) || !sys.has_rigid_mode() {
            return None;
        }
        let recs: Vec<&PeriodRecord> = hist.iter().skip(half).collect();
        let grows = |k: usize| recs.windows(2).all(|w| sys.gap(k, &w[1].end) > sys.gap(k, &w[0].end));
        if !(0..sys.stops.len()).all(grows) {
            return None;
        }
        let m = sys.dof();
        let (a, b) = (&recs[recs.len() - 2].end, &recs[recs.len() - 1].end);
        let drift = (0..m).map(|i| (b[i] - a[i]).abs()).fold(0.0, f64::max);
        Some(Unresolved::Unbounded { periods: recs.len(), drift })
    }

    /// A motion without an event that will meet a stop, followed there:
    /// period after period of the same exact flow, without a record (an
    /// event-free period costs a few steps of the flow and nothing else),
    /// until the first period with an event. A free mass drifting towards a
    /// stop through the record's whole budget ([`Executor::drifting`]) is
    /// followed for at most twice the periods that its closing rate gives;
    /// an undamped oscillation beside the forcing whose torus reaches past a
    /// stop ([`Executor::quiet_overlap`]: it meets the stop where the phases
    /// of its free oscillation and of the forcing next come near alignment,
    /// which no closing rate foretells) until the reach. Either for at most
    /// [`DRIFT_REACH`] × `max_periods`. `true` when an event came: the motion
    /// from there is recorded afresh (its history, trail and Newton
    /// acceleration start again); `false` where no motion is bound for a
    /// stop, or when the reach ended first (the history then holds the last
    /// periods followed, and [`Executor::follow`] how many there were).
    pub(super) fn follow_quiet(&mut self) -> Result<bool, Halt> {
        let reach = (DRIFT_REACH * self.acc.max_periods) as u64;
        let span = match self.drifting() {
            Some((_, meets)) if meets <= reach as f64 => (2.0 * meets).ceil().min(reach as f64) as u64 + 1,
            Some(_) => return Ok(false),
            None if self.quiet_overlap().is_some() => reach,
            None => return Ok(false),
        };
        let until = self.sim.periods() + span;
        self.trail.clear();
        while self.sim.periods() < until {
            let rec = self.sim.run_period(&[], self.sys.model.symmetric, &mut Ignore)?;
            if rec.events > 0 {
                self.record_afresh();
                self.follow = Follow::Met;
                return Ok(true);
            }
            // The last periods stay in the history: a motion followed to the
            // reach is said to be where it is then.
            if self.hist.len() == history_len(self.acc) {
                self.hist.pop_front();
            }
            self.hist.push_back(rec);
        }
        self.follow = Follow::Reached(span);
        Ok(false)
    }

    /// Follows a motion without events that is bound for a stop to its next
    /// event ([`Executor::follow_quiet`]), once a cell: a drift or an
    /// undamped torus reaching a stop where nothing is `decided` yet; an
    /// undamped torus alone ([`Executor::quiet_overlap`]) where the exponent
    /// decided a record without a period, which went quiet while it was
    /// measured. `true` when an event came.
    pub(super) fn follow_once(&mut self, decided: Option<&Steady>) -> Result<bool, Unresolved> {
        let bound = self.follow == Follow::Not
            && decided.is_none_or(|d| matches!(d, Steady::Aperiodic(..)) && self.quiet_overlap().is_some());
        match bound {
            true => self.follow_quiet().map_err(|h| Unresolved::of(h, self.acc)),
            false => Ok(false),
        }
    }

    /// Goes on from where an exponent's measurement ended quiet
    /// (`quiet_end`, [`Executor::decide`]): in a scene without damping, on
    /// one linear flow that is the motion for all time, or with a free mass
    /// drifting towards a stop. The main simulation resumes where that probe
    /// stopped, its periods and events handed over from the probe's count to
    /// the main simulation's (counted once), and the record starts again
    /// from there, its history, trail and Newton acceleration anew: a
    /// period within `n_max` is found there, and the cell's window is the
    /// flow's; or the drift is followed to the wall. The probe simulated
    /// whole periods: in a symmetric scene, whose record stops at each half
    /// period too, its state is the motion's to rounding rather than bit
    /// for bit the record's own (the same for the same cell, every run).
    /// Once a cell; `true` when it did.
    pub(super) fn go_on_quiet(&mut self) -> bool {
        let Some(probe) = self.quiet_end.take() else { return false };
        if !self.take_over(probe) {
            return false;
        }
        self.quieted = true;
        self.exponent_events = None;
        self.record_afresh();
        true
    }

    /// Starts the record again from where the main simulation is: its
    /// history, trail and Newton acceleration anew.
    fn record_afresh(&mut self) {
        self.hist.clear();
        self.trail.clear();
        self.newton.renew();
    }

    /// How far the torus of an undamped oscillation beside the forcing,
    /// without an event over the record's history, reaches past a stop: the
    /// bound of its flow's terms (the forcing's response and each free
    /// oscillation's amplitude added, as where their phases align,
    /// [`Simulator::guard_margin`]) beyond the gap, in the stop's units.
    /// `Some` where it reaches the stop (within the event tolerance): the
    /// motion meets it again once their phases come near that alignment.
    /// `None` where the history had an event, a damper acts, a term grows,
    /// or the torus clears every stop (it is then the motion for all time).
    pub(super) fn quiet_overlap(&mut self) -> Option<f64> {
        if self.hist.is_empty() || !self.undamped_linear(self.hist.len()) {
            return None;
        }
        self.sim.guard_margin().filter(|&m| m <= 0.0).map(|m| -m)
    }

    /// A free mass drifting towards a stop: the record has had no event, the
    /// masses have a rigid mode, and a stop's gap closes by drift (the
    /// secular part of the flow, [`Simulator::gap_drifts`]: a free mass's
    /// velocity, not the oscillation of the mass it rattles in, which once
    /// read as a drift where the free mass rested). Its rate (the gap's
    /// decrease per forcing period, the fastest time to close) and the
    /// periods it needs to close at that rate from the current gap. `None`
    /// otherwise.
    pub(super) fn drifting(&mut self) -> Option<(f64, f64)> {
        if self.hist.len() < 2 || self.hist.iter().any(|r| r.events > 0) {
            return None;
        }
        closing_drift(self.sys, &mut self.sim)
    }
}
