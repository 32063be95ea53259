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

use crate::simulate::Simulator;

/// The event limit of a cell and the work its probes have done so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Budget {
    limit: usize,
    /// Forcing periods the probes simulated.
    periods: u64,
    /// Events the probes handled.
    events: usize,
}

impl Budget {
    /// A budget of `limit` events, nothing spent.
    pub(crate) fn new(limit: usize) -> Budget {
        Budget { limit, periods: 0, events: 0 }
    }

    /// Events left once `main`'s and the probes' are taken.
    fn left(&self, main: &Simulator<'_>) -> usize {
        self.limit.saturating_sub(main.events() + self.events)
    }

    /// Runs `phase` on `probe`, lent the events the cell has left, and charges
    /// what it spent; `main` is then held to what is left for it.
    pub(crate) fn spend<'s, T>(
        &mut self,
        main: &mut Simulator<'s>,
        probe: &mut Simulator<'s>,
        phase: impl FnOnce(&mut Simulator<'s>) -> T,
    ) -> T {
        let (periods, events) = (probe.periods(), probe.events());
        probe.set_budget(events + self.left(main));
        let out = phase(probe);
        self.periods += probe.periods() - periods;
        self.events += probe.events() - events;
        main.set_budget(self.limit.saturating_sub(self.events));
        out
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
