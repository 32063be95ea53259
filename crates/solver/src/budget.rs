//! The work budget of one cell.
//!
//! A cell runs one main simulation (the record) and several probes beside it,
//! copies of the main simulator that share its built modes: Newton's period
//! map, the tangents of the Lyapunov exponent and of the Floquet multiplier,
//! and the re-simulation of the classified window for the impact sections.
//! Every one draws on one event limit (`max_events`): a probe is lent what the
//! cell has left, and what it spent is charged, so that the main simulation
//! and all probes together never handle more than the limit, and the cell's
//! `periods` and `events` count all of their work.
//!
//! The integrator's steps draw on the same limit (issue 30): RK4's steps cost
//! a fraction of an event each (`flow::rk4`, [`crate::flow::rk4::FULL_STEP_WORK`]
//! and [`crate::flow::rk4::REFINED_STEP_WORK`]), so that `max_events` bounds
//! the work of a cell under either integrator. Work is counted in thousandths
//! of an event ([`EVENT_WORK`]); the exact integrator's steps are free, and its
//! budget is exactly `max_events` events, as before.

use crate::simulate::{Simulator, EVENT_WORK};

/// The event limit of a cell and the work its probes have done so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Budget {
    /// The limit, in thousandths of an event.
    limit: u64,
    /// Forcing periods the probes simulated.
    periods: u64,
    /// Events the probes handled.
    events: usize,
    /// Work the probes did (their events and steps), in thousandths of an event.
    work: u64,
}

impl Budget {
    /// A budget of `limit` events, nothing spent.
    pub(crate) fn new(limit: usize) -> Budget {
        Budget { limit: (limit as u64).saturating_mul(EVENT_WORK), periods: 0, events: 0, work: 0 }
    }

    /// Work left once `main`'s and the probes' are taken, in thousandths of an event.
    fn left(&self, main: &Simulator<'_>) -> u64 {
        self.limit.saturating_sub(main.work().saturating_add(self.work))
    }

    /// Runs `phase` on `probe`, lent the work the cell has left, and charges
    /// what it spent; `main` is then held to what is left for it.
    pub(crate) fn spend<'s, T>(
        &mut self,
        main: &mut Simulator<'s>,
        probe: &mut Simulator<'s>,
        phase: impl FnOnce(&mut Simulator<'s>) -> T,
    ) -> T {
        self.spend_keeping(main, probe, 0, phase)
    }

    /// As [`Budget::spend`], but lent the work the cell has left less
    /// `keep` (thousandths of an event), which stays for a later phase.
    pub(crate) fn spend_keeping<'s, T>(
        &mut self,
        main: &mut Simulator<'s>,
        probe: &mut Simulator<'s>,
        keep: u64,
        phase: impl FnOnce(&mut Simulator<'s>) -> T,
    ) -> T {
        let (periods, events, work) = (probe.periods(), probe.events(), probe.work());
        probe.set_budget(work.saturating_add(self.left(main).saturating_sub(keep)));
        let out = phase(probe);
        self.periods += probe.periods() - periods;
        self.events += probe.events() - events;
        self.work = self.work.saturating_add(probe.work() - work);
        main.set_budget(self.limit.saturating_sub(self.work));
        out
    }

    /// Hands `periods` periods with `events` events that a probe simulated
    /// over to the main simulation, which went on from the probe's end and
    /// counts them as its own ([`Simulator::count_periods`]): counted once,
    /// and their events' work charged to the main simulation alone.
    pub(crate) fn hand_over(&mut self, periods: u64, events: usize) {
        self.periods = self.periods.saturating_sub(periods);
        self.events = self.events.saturating_sub(events);
        self.work = self.work.saturating_sub((events as u64).saturating_mul(EVENT_WORK));
    }

    /// Forcing periods of the cell: `main`'s and the probes'.
    pub(crate) fn periods(&self, main: &Simulator<'_>) -> u64 {
        main.periods() + self.periods
    }

    /// Events of the cell: `main`'s and the probes'.
    pub(crate) fn events(&self, main: &Simulator<'_>) -> usize {
        main.events() + self.events
    }
}
