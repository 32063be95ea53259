//! The executor of one cell: simulate, decide the steady motion, measure its
//! stability, label it, and record its sections.
//!
//! An [`Executor`] runs named phases on one main simulator and probes beside
//! it, all drawing on one [`Budget`]:
//!
//! 1. **record** ([`Executor::record`]): periods are simulated until the
//!    period section repeats (the period n, see [`crate::period`]) or the
//!    record's limit, with Newton acceleration of slowly contracting patterns;
//! 2. **exponent** ([`Executor::exponent`]): without a period, the largest
//!    Lyapunov exponent tells chaos from a torus and a contracting long
//!    transient from both, by its 95 % confidence interval
//!    ([`crate::Interval`]): chaos only when the whole interval is above 0,
//!    contraction only when it is below. A chaotic-looking record is chaotic
//!    only when no stable periodic orbit is found near it
//!    ([`Executor::stable_orbit_near`]); one that passes near such an orbit
//!    is a transient that may yet settle and goes on. With `chaos_check` the
//!    exponent is measured early (after `chaos_check` periods) and a chaotic
//!    record ends there; a record that still contracts, or a chaotic-looking
//!    one near a stable orbit, is extended by `max_periods`, at most
//!    `extensions` times ([`Executor::steady`] runs phases 1 and 2). An
//!    interval that contains 0 is measured twice as long, at most
//!    `2 + extensions / 2` times ([`Executor::decide`]): a record still
//!    about 0 then, or one found contracting, is searched for a stable orbit
//!    of period up to [`LONGEST_ORBIT`](orbits::LONGEST_ORBIT) that its section points contract
//!    onto (an orbit locked on a torus, or a long one not yet reached;
//!    [`Executor::orbit_among`]); without one, a torus when its section
//!    points lie on one closed curve with a converged rotation number
//!    ([`Rotation`](crate::circle::Rotation), the weighted Birkhoff average), or when that number
//!    alone has converged as only a torus's does (`turns_on_torus`: far
//!    faster than over the last quarter of the points, and not locked at a
//!    fraction), a transient (extended as above while extensions remain)
//!    when contracting. A free mass drifting towards a stop without an
//!    event is a transient too, and where it drifts through every extension
//!    it is followed to the stop without a record
//!    ([`Executor::follow_quiet`]), the motion recorded afresh from there.
//!    A record that still contracts but whose section has
//!    settled on an orbit longer than `n_max` (up to 128 periods) is not
//!    extended (no extension would find a period): Newton's method on that
//!    period's map confirms it and the cell is periodic with it
//!    ([`Executor::confirm`]), or it ends `unresolved`
//!    ([`Unresolved::LongPeriod`]);
//! 3. **multiplier** ([`Executor::multiplier`]): with a period, the largest
//!    Floquet multiplier modulus of the n-period map at the final state. An
//!    orbit whose multiplier exceeds 1.01 is unstable: the record only passed
//!    near it; in a scene that dissipates nothing the motion is measured on
//!    from there as a record without a period's (`C` or `Q` where that
//!    decides it), else the cell is `unresolved` ([`Unresolved::Unstable`]); so
//!    is one whose multiplier says that the state is still far from it where
//!    rounding hid the contraction from the record (unless the periods that
//!    close the distance are left in the record's whole budget,
//!    `max_periods x (1 + extensions)`, which it then goes on into:
//!    `periods_to_settle`), or that the map does not
//!    contract at all ([`Executor::unsettled`]:
//!    a conservative oscillation under fast forcing, a mass on a vanishing
//!    spring). An orbit that sticks, its multiplier 0, whose flights between
//!    the sticks grow the error of their impacts past where the next stick
//!    is decided, is `C` ([`crate::Flights::beyond_precision`]). Without a
//!    period, a motion that drifts away from every stop
//!    with no event is unbounded ([`Executor::unbounded`]), not chaos;
//!    numbers beyond what double precision answers for end a cell before it
//!    starts ([`System::check_range`]);
//! 4. **window** ([`Executor::window`]): impacts, sticking and chattering over
//!    the classified window (n periods, or the last `n_max` without a period),
//!    hence the labels;
//! 5. **sections** ([`Executor::window_pass`]): the window simulated again, to
//!    record the state before each impact.
//!
//! A cell that exhausts its budget, stalls, or whose exponent cannot tell is
//! `unresolved`, with an [`Unresolved`] reason.
//!
//! This module holds the executor, the record (phase 1), the window and its
//! sections (phases 4 and 5); the other phases are its submodules: `decide`
//! (phase 2: the exponent, and the torus tests), `orbits` (stable orbits
//! sought near a record, confirmed and settled on), `stability` (phase 3),
//! `quiet` (motions without events), and `unresolved` (the reasons).

use crate::acceleration::Newton;
use crate::accuracy::Accuracy;
use crate::budget::Budget;
use crate::flow::Method;
use crate::label::{label_masses, Class, Label, Mask, MassLabel, Symmetry};
use crate::period::{converged, detect, history_len, remaining, symmetry_of, History, Trail};
use crate::section::record_window;
use crate::simulate::{Halt, Ignore, Moment, PeriodRecord, Simulator, EVENT_WORK};
use crate::system::System;
use std::collections::VecDeque;

mod decide;
mod orbits;
mod quiet;
mod stability;
#[cfg(test)]
mod tests;
mod unresolved;

use quiet::Follow;
use stability::{periods_to_settle, UNSTABLE};
pub use unresolved::{Departure, Unresolved};

/// A cell without a period whose `λT` is below minus this on average still
/// contracts, whatever its uncertainty: a slow transient, whose record is
/// extended (see `Accuracy::extensions`).
const CONTRACTING_EXPONENT: f64 = 2e-3;

/// Smallest `λT` at which the early look of `Accuracy::chaos_check` may end a
/// record as chaotic (with its interval above 0 and no stable orbit near), so
/// that a weakly chaotic or slowly settling motion gets the whole record.
const CHAOTIC_EXPONENT: f64 = 0.05;

/// Newton polishes of a found, slowly converging orbit per cell (see
/// [`Executor::polish`]).
const POLISHES: usize = 2;

/// Everything known about a cell's steady motion.
#[derive(Debug, Clone, PartialEq)]
pub struct CellResult {
    /// Kind of motion.
    pub class: Class,
    /// Period in forcing periods, when periodic.
    pub n: Option<usize>,
    /// Label per labelled mass.
    pub labels: Vec<MassLabel>,
    /// Impacts per stop over the n periods (over the last `n_max` periods when not periodic).
    pub impacts: Vec<u32>,
    /// Stops that chattered: at least `chatter_impacts` impacts within one
    /// forcing period of the window.
    pub chatter: Mask,
    /// Stops that held their mass during the window.
    pub sticking: Mask,
    /// Friction contacts that stuck during the window.
    pub friction_stick: Mask,
    /// Symmetry of a periodic orbit of a symmetric scene.
    pub symmetry: Option<Symmetry>,
    /// Largest Lyapunov exponent (per unit time) of a cell without a period,
    /// when measured.
    pub lyapunov: Option<f64>,
    /// Largest Floquet multiplier modulus of a periodic cell (the Jacobian of
    /// the n-period map at the final state), when measured.
    pub multiplier: Option<f64>,
    /// Full state `[x; v]` at the end of the simulation (at `t = kT`).
    pub final_state: Vec<f64>,
    /// State at the start of the classified window (for traces and sections).
    pub window_start: Vec<f64>,
    /// Period-section points of the window (n points when periodic).
    pub section: Vec<Vec<f64>>,
    /// Forcing periods simulated, by every phase.
    pub periods: u64,
    /// Events handled, by every phase.
    pub events: usize,
    /// Why the cell is unresolved.
    pub reason: Option<Unresolved>,
}

/// Impact sections per stop: `[phase, x…, v…]` before each impact.
pub type ImpactSections = Vec<crate::section::Points>;

/// Simulates a cell from full state `y0` and classifies its steady motion.
pub fn run_cell(sys: &System, acc: &Accuracy, method: Method, y0: &[f64]) -> CellResult {
    run_cell_with_sections(sys, acc, method, y0, 0).0
}

/// [`run_cell`] and the impact sections of its classified window, at most
/// `section_cap` points per stop. The window is simulated again with the modes
/// the classification built; that work counts in the cell's periods and events.
pub fn run_cell_with_sections(
    sys: &System,
    acc: &Accuracy,
    method: Method,
    y0: &[f64],
    section_cap: usize,
) -> (CellResult, ImpactSections) {
    let (result, sections, _) = run_cell_measured(sys, acc, method, y0, section_cap, false);
    (result, sections)
}

/// [`run_cell_with_sections`] that, with `measure`, also measures the
/// quantities of the steady motion ([`crate::quantity`]) over the cell's
/// window (its orbit's n periods, else the last `n_max` periods of its
/// record), re-simulated from the window's start with the modes the record
/// built; the work counters are those of the cell without them. `None` where
/// the cell has no window (its record halted) or the window's motion cannot
/// be followed.
pub fn run_cell_measured(
    sys: &System,
    acc: &Accuracy,
    method: Method,
    y0: &[f64],
    section_cap: usize,
    measure: bool,
) -> (CellResult, ImpactSections, Option<crate::quantity::Quantities>) {
    let no_sections = || vec![crate::section::Points::default(); sys.stops.len()];
    if let Err(e) = sys.check_range(y0) {
        return (unresolved(sys, Unresolved::Failed(e), 0, 0, y0.to_vec()), no_sections(), None);
    }
    let mut cell = match Executor::start(sys, acc, method, y0) {
        Ok(cell) => cell,
        Err(why) => return (unresolved(sys, why, 0, 0, y0.to_vec()), no_sections(), None),
    };
    let steady = match cell.steady() {
        Ok(steady) => steady,
        Err(why) => {
            let (periods, events) = (cell.budget.periods(&cell.sim), cell.budget.events(&cell.sim));
            return (unresolved(sys, why, periods, events, cell.sim.state().as_slice().to_vec()), no_sections(), None);
        }
    };
    let (class, n, lyapunov, reason) = match steady {
        Steady::Periodic(n) => match cell.unsettled.take() {
            // A neutral orbit of an undamped linear flow: its n-period map
            // does not contract, so a step within `periodic_tol` that
            // rounding does not explain (a slow free oscillation under fast
            // forcing, a frequency nearly commensurate) would add up period
            // after period. Where the flow closes after n periods exactly,
            // the motion is this orbit, and its repeat shows that no event
            // ends it.
            Some(_) if cell.undamped_linear(n) && cell.sim.closes_after(n as f64 * sys.period) => {
                (Class::Periodic, Some(n), None, None)
            }
            // A neutral orbit in a scene that dissipates nothing, where no
            // orbit contracts: the orbit where the motion stays on it, and
            // otherwise said how far it left it.
            Some(Unresolved::Unsettled { periods, multiplier, distance, .. })
                if distance.is_infinite() && sys.lossless() =>
            {
                match cell.left_orbit(n) {
                    Some(left) if left.distance <= acc.periodic_tol => (Class::Periodic, Some(n), None, None),
                    left => (
                        Class::Unresolved,
                        None,
                        None,
                        Some(Unresolved::Unsettled { periods, multiplier, distance, left }),
                    ),
                }
            }
            Some(why) => (Class::Unresolved, None, None, Some(why)),
            None => (Class::Periodic, Some(n), None, None),
        },
        Steady::LongPeriod(n, l) => {
            (Class::Unresolved, None, Some(l), Some(Unresolved::LongPeriod { n, n_max: acc.n_max }))
        }
        Steady::Unmeasured => (Class::Chaotic, None, None, None),
        Steady::Failed(halt) => (
            Class::Unresolved,
            None,
            None,
            Some(Unresolved::NoExponent { halt: Box::new(Unresolved::of(halt, acc)), measured: None }),
        ),
        Steady::Aperiodic(class, l, reason) => match cell.unbounded() {
            Some(why) => (Class::Unresolved, None, Some(l), Some(why)),
            // One linear flow is never chaotic (a positive exponent is the
            // transient growth of a record shorter than its slowest motion).
            // A record whose last periods were quiet but whose exponent's
            // measurement met a stop is no one linear flow: its measurement
            // decides.
            None if (matches!(class, Class::Chaotic | Class::Quasiperiodic)
                || matches!(reason, Some(Unresolved::Undecided { .. } | Unresolved::Polynomial { .. })))
                && cell.quiet_history()
                && cell.exponent_events.is_none_or(|n| n == 0) =>
            {
                // Undamped, and never ended by an event, it is the motion for
                // all time: a torus of its free oscillations beside the
                // forcing (one that closes within `n_max` periods was found
                // by the record; beyond, a motion that does not contract keeps
                // its `Q`, as any torus does). Damped, or where an event may
                // yet end it, its torus attracts nothing, or not for long:
                // said so, rather than undecided.
                if cell.undamped_linear(cell.hist.len())
                    && (cell.sim.guard_margin().is_some_and(|m| m > 0.0) || cell.closes_late)
                {
                    (Class::Quasiperiodic, None, Some(l), None)
                } else {
                    let (closing, meets) = cell.drifting().unzip();
                    let overlap = cell.quiet_overlap();
                    let followed = match cell.follow {
                        Follow::Reached(periods) if overlap.is_some() => Some(periods),
                        _ => None,
                    };
                    let why = Unresolved::Linear { periods: cell.hist.len(), closing, meets, overlap, followed };
                    (Class::Unresolved, None, Some(l), Some(why))
                }
            }
            None => (class, None, Some(l), reason),
        },
    };
    let multiplier = match n {
        Some(n) if acc.multipliers => cell.measured.or_else(|| cell.multiplier(n).map(|(all, _)| all)),
        _ => None,
    };
    // The periods of the classified window, where not n's or the last `n_max`.
    let mut span = None;
    // An unstable orbit is not where the motion stays: the record only
    // passed near it. Where nothing dissipates the motion is measured on
    // as a record without a period's; `U` naming the orbit where that does
    // not decide it, and wherever something dissipates.
    let (class, n, lyapunov, reason, multiplier) = match multiplier {
        Some(mu) if mu > 1.0 + UNSTABLE => {
            let periods = cell.sim.periods() as usize;
            match cell.beyond_unstable() {
                Some((class, l)) => (class, None, Some(l), None, None),
                None => (Class::Unresolved, None, None, Some(Unresolved::Unstable { periods, multiplier: mu }), None),
            }
        }
        // An orbit that sticks, each stick erasing every perturbation (its
        // multiplier 0): where its flight from the release expands the error
        // of its impacts past where its next stick is decided, its repeat is
        // one computed flight's replay from the same release, not an orbit
        // the motion keeps (the single stop at ω = 2.8718, ζ = 0.04828:
        // `71-S-0` at `standard`, its flight's tangent growing by e^50, a
        // start 1e-16 away sticking in another period): chaos, its flights'
        // exponent. An orbit of one period sticks in every period: it has
        // no flight to measure. The test rides on the multiplier: with
        // `multipliers` off, or where its probe halts or the budget ends,
        // the orbit keeps its label. Its window stays the n periods of the
        // repeat found, which hold its sticks, rather than the last `n_max`.
        Some(0.0) => match n.filter(|&n| n > 1).and_then(|n| cell.unresolved_flights(n)) {
            Some(l) => {
                span = n;
                (Class::Chaotic, None, Some(l), None, None)
            }
            None => (class, n, lyapunov, reason, multiplier),
        },
        _ => (class, n, lyapunov, reason, multiplier),
    };
    // A torus reached within the measurement: the record goes on to where it ended.
    if class == Class::Quasiperiodic && n.is_none() && span.is_none() {
        span = cell.go_on_to_torus();
    }
    let mut result = cell.window(class, n, span, y0);
    let (sections, quantities) = cell.window_pass(&result, section_cap, measure);
    let sections = sections.unwrap_or_else(no_sections);
    result.lyapunov = lyapunov;
    result.multiplier = multiplier;
    result.reason = reason;
    result.periods = cell.budget.periods(&cell.sim);
    result.events = cell.budget.events(&cell.sim);
    (result, sections, quantities)
}

/// How a record ended.
#[derive(Debug)]
enum Steady {
    /// The section repeats with period n.
    Periodic(usize),
    /// The record contracts, and its section repeats with a period n beyond
    /// `n_max` (see [`Trail`]); the largest Lyapunov exponent (per unit time).
    LongPeriod(usize, f64),
    /// No period: chaotic, quasi-periodic, or unresolved with its reason; the
    /// largest Lyapunov exponent (per unit time).
    Aperiodic(Class, f64, Option<Unresolved>),
    /// No period, and the exponent is not measured (`lyapunov_periods = 0`):
    /// `C`, as the knob documents.
    Unmeasured,
    /// No period, and the run measuring the exponent halted.
    Failed(Halt),
}

/// One cell in execution: the main simulator, its recent periods, Newton's
/// state and the budget every phase draws on.
struct Executor<'s> {
    sys: &'s System,
    acc: &'s Accuracy,
    sim: Simulator<'s>,
    hist: History,
    /// The record's section points, for orbits longer than `n_max`.
    trail: Trail,
    newton: Newton<'s>,
    /// Newton polishes of a found but slowly converging orbit left to this cell.
    polishes: usize,
    budget: Budget,
    /// The largest multiplier modulus of the accepted period's map, where
    /// [`Executor::unsettled`] measured it (the cell's own).
    measured: Option<f64>,
    /// Why the accepted period is not a result, where it is not.
    unsettled: Option<Unresolved>,
    /// Whether a motion bound for a stop was followed to it, once a cell
    /// ([`Executor::follow_quiet`]).
    follow: Follow,
    /// An exponent's probe whose measurement ended quiet, in a scene
    /// without damping, on one linear flow that [`Executor::decide`] found
    /// to be the motion for all time (its torus clear of every stop, or its
    /// flow closing) while the record had events: the record goes on from
    /// where it ended ([`Executor::go_on_quiet`]).
    quiet_end: Option<Simulator<'s>>,
    /// Whether the record went on from such a probe's end: once a cell.
    quieted: bool,
    /// Whether [`Executor::decide`] found a quiet linear flow that closes
    /// after more than `n_max` periods (its torus a `Q` that may reach past
    /// a stop's bound, its phases never aligning there).
    closes_late: bool,
    /// The events of the periods over which [`Executor::decide`] last
    /// measured the exponent (its probe's, after the record), where it did.
    exponent_events: Option<u64>,
    /// The periods the exponent's probe simulated from the main state, for
    /// the record going on from there to take instead of simulating them
    /// again ([`Executor::next_period`]).
    ahead: Option<Ahead<'s>>,
    /// Where the measurement ended that found the motion reaching its
    /// torus within it, for the record to go on to
    /// ([`Executor::go_on_to_torus`]).
    torus_reached: Option<Reached<'s>>,
}

/// The periods a probe of the main simulation simulated on from its state
/// (the exponent's measurement, its warm-up included), which the record
/// takes one by one as its own ([`Executor::next_period`]) until it must
/// act on the main simulation itself ([`Executor::catch_up`]).
struct Ahead<'s> {
    /// The probe, where it stopped (the modes it built).
    sim: Simulator<'s>,
    /// Its periods' records not taken yet, in order, each with where the
    /// probe was at its end.
    recs: VecDeque<(PeriodRecord, Moment)>,
    /// Where the probe was at the end of the last period taken.
    last: Option<Moment>,
}

/// Where the measurement ended that found a record's motion reaching its
/// torus within it ([`Executor::decide`]): its probe, and the records of its
/// last periods, a window's and the one before it, which the record goes
/// on to ([`Executor::go_on_to_torus`]).
struct Reached<'s> {
    probe: Simulator<'s>,
    last: VecDeque<PeriodRecord>,
}

/// The result of a cell that ended without a classification.
fn unresolved(sys: &System, why: Unresolved, periods: u64, events: usize, y: Vec<f64>) -> CellResult {
    let stops = sys.stops.len();
    CellResult {
        class: Class::Unresolved,
        n: None,
        labels: sys
            .model
            .labels
            .iter()
            .map(|l| MassLabel { mass: sys.model.masses[l.mass].name.clone(), label: Label::Unresolved })
            .collect(),
        impacts: vec![0; stops],
        chatter: Mask::EMPTY,
        sticking: Mask::EMPTY,
        friction_stick: Mask::EMPTY,
        symmetry: None,
        lyapunov: None,
        multiplier: None,
        window_start: y.clone(),
        final_state: y,
        section: Vec::new(),
        periods,
        events,
        reason: Some(why),
    }
}

impl<'s> Executor<'s> {
    /// Starts the main simulation at `y0`.
    fn start(sys: &'s System, acc: &'s Accuracy, method: Method, y0: &[f64]) -> Result<Self, Unresolved> {
        let sim = Simulator::new(sys, *acc, method, y0).map_err(|h| Unresolved::of(h, acc))?;
        Ok(Executor {
            sys,
            acc,
            hist: History::with_capacity(history_len(acc) + 1),
            trail: Trail::new(sim.state().len()),
            sim,
            newton: Newton::default(),
            polishes: POLISHES,
            budget: Budget::new(acc.max_events),
            measured: None,
            unsettled: None,
            follow: Follow::Not,
            quiet_end: None,
            quieted: false,
            closes_late: false,
            exponent_events: None,
            ahead: None,
            torus_reached: None,
        })
    }

    /// Phase 1: simulates periods until the section repeats (the period n,
    /// returned) or `limit` periods in all are simulated (`None`), with Newton
    /// acceleration of slowly contracting patterns on the way. An orbit found
    /// still too far, whose contraction closes the distance within the
    /// record's whole budget (`max_periods x (1 + extensions)` periods, the
    /// budget extensions of a transient draw on), is followed there even
    /// beyond `limit`.
    fn record(&mut self, limit: usize) -> Result<Option<usize>, Halt> {
        let acc = self.acc;
        let budget = limit.max(acc.max_periods.saturating_mul(1 + acc.extensions));
        // Periods simulated before the record is tested again, while it
        // closes in on an orbit found still too far (see `periods_to_settle`).
        let mut wait_until = 0;
        while (self.sim.periods() as usize) < limit.max(wait_until) {
            let rec = self.next_period()?;
            if self.hist.len() == history_len(acc) {
                if let Some(old) = self.hist.pop_front() {
                    self.sim.recycle(old);
                }
            }
            self.trail.push(&rec.end);
            self.hist.push_back(rec);
            if (self.sim.periods() as usize) < acc.min_transient.max(wait_until) {
                continue;
            }
            if let Some(n) = detect(&self.hist, acc) {
                self.catch_up();
                // Accepted once converged, so that its symmetry and final state are the orbit's.
                if converged(&self.hist, n, acc) {
                    // Where rounding hid the contraction, the orbit's multiplier tells;
                    // so it does where it barely contracts (not a rigid mode's family).
                    let hidden = remaining(&self.hist, n).is_none();
                    let asked = hidden || (self.acc.multipliers && !self.sys.has_rigid_mode());
                    let why = if asked { self.unsettled(n, hidden) } else { None };
                    // Still too far from an orbit it contracts onto, with the
                    // periods to reach it left in the budget: the record goes
                    // on, and the multiplier is measured again at its next test.
                    let periods = self.sim.periods() as usize;
                    let more =
                        why.as_ref().and_then(|w| periods_to_settle(w, n, acc)).filter(|&m| periods + m <= budget);
                    if let Some(more) = more {
                        self.measured = None;
                        wait_until = periods + more;
                        continue;
                    }
                    self.unsettled = why;
                    return Ok(Some(n));
                }
                if let Some(x) = self.polish(n) {
                    if self.sim.restart(x.as_slice()).is_ok() {
                        self.hist.clear();
                        self.trail.clear();
                    }
                }
                continue;
            }
            if acc.newton
                && self.newton.due(&self.sim)
                && (self.ahead.is_none() || Newton::has_pattern(&self.hist, acc))
            {
                self.catch_up();
                if let Some(x) = self.newton.step(&mut self.sim, &self.hist, acc, &mut self.budget) {
                    if self.sim.restart(x.as_slice()).is_ok() {
                        self.hist.clear();
                        self.trail.clear();
                    }
                }
            }
        }
        self.catch_up();
        Ok(None)
    }

    /// The record's next period: the next one [`Ahead`] holds, counted as
    /// the main simulation's own, where the budget would not have halted
    /// the main simulation on it; else the main simulation's, once it has
    /// caught up ([`Executor::catch_up`]).
    fn next_period(&mut self) -> Result<PeriodRecord, Halt> {
        let fits = self.ahead.as_ref().map(|a| a.recs.front().is_some_and(|(rec, _)| self.sim.fits(rec.events)));
        match (fits, self.ahead.as_mut()) {
            (Some(true), Some(ahead)) => {
                let (rec, moment) = ahead.recs.pop_front().expect("a period ahead");
                ahead.last = Some(moment);
                self.sim.count_period(&rec);
                Ok(rec)
            }
            _ => {
                self.catch_up();
                self.sim.run_period(&[], self.sys.model.symmetric, &mut Ignore)
            }
        }
    }

    /// Brings the main simulation to the end of the periods the record took
    /// from [`Ahead`], and lets the rest go.
    fn catch_up(&mut self) {
        if let Some(mut ahead) = self.ahead.take() {
            if let Some(moment) = ahead.last.take() {
                self.sim.resume(moment, &mut ahead.sim);
            }
        }
    }

    /// Hands the periods the exponent's probe simulated from the main state
    /// on to the record that goes on from there ([`Ahead`]), where the main
    /// simulation is still `at` the probe's start (its periods, events and
    /// [`Moment`]): a search for a long orbit between them
    /// ([`Executor::confirm`]) may have moved it.
    fn look_ahead(&mut self, probe: Simulator<'s>, recs: Vec<(PeriodRecord, Moment)>, at: &(u64, usize, Moment)) {
        let here = (self.sim.periods(), self.sim.events(), self.sim.moment());
        if !recs.is_empty() && here == *at {
            self.ahead = Some(Ahead { sim: probe, recs: recs.into(), last: None });
        }
    }

    /// Goes on to where the measurement ended that found the motion
    /// reaching its torus within it ([`Reached`]), the records of its last
    /// periods the record's history: the window is then the torus that the
    /// class `Q` names, and the final state is on it. The record's periods
    /// before the measurement were still the transient (the impact damper
    /// with μ = 0.5, ζ = 0.05, R = 0.6 at ω = 1.846154, δ = 0.344828, down:
    /// its tangent growing by 28 over the first 800 of 1 600 periods and by
    /// −0.4 over the last 800, its points then on 13 loops; from the state
    /// the record had reached, two starts 1e-8 apart were 1e-2 apart 200
    /// periods on). The periods of the window; `None` where there is no
    /// such end (the main simulation went on past it).
    fn go_on_to_torus(&mut self) -> Option<usize> {
        let Reached { probe, last } = self.torus_reached.take()?;
        let window = last.len().checked_sub(1).filter(|&w| w > 0)?;
        if !self.take_over(probe) {
            return None;
        }
        self.hist.clear();
        self.hist.extend(last);
        Some(window)
    }

    /// The main simulation resumes where `probe`, a probe of it in time,
    /// stopped: its periods and events handed over from the probe's count
    /// to the main simulation's (counted once), and the periods taken ahead
    /// let go. `false`, and nothing done, where the main simulation ran on
    /// past the probe (a failed settling on an orbit simulates periods that
    /// it then takes back in state, not in count): it does not go on from
    /// there.
    pub(super) fn take_over(&mut self, mut probe: Simulator<'s>) -> bool {
        let Some(periods) = probe.periods().checked_sub(self.sim.periods()) else { return false };
        self.ahead = None;
        let events = probe.events();
        let moment = probe.moment();
        self.sim.resume(moment, &mut probe);
        self.sim.count_periods(periods, events);
        self.budget.hand_over(periods, events);
        true
    }

    /// Whether the last `periods` periods of the record are one undamped
    /// linear flow: no event over them and no damping in the scene, so that
    /// each free oscillation keeps its amplitude and the torus it lies on
    /// neither attracts nor repels. Where the section repeated after n
    /// periods, none of them had an event and the flow closes after them
    /// exactly ([`Simulator::closes_after`]), the motion is that periodic
    /// orbit for all time, whatever impacts came before it (a last impact
    /// that left the mass below its stop, issue 62); where the whole record
    /// had no event and no guard of its mode can ever reach zero
    /// ([`Simulator::guard_margin`] positive), it is that flow for all time.
    /// Either is regular whatever a finite record's exponent says.
    fn undamped_linear(&self, periods: usize) -> bool {
        self.hist.iter().rev().take(periods).all(|r| r.events == 0) && self.sys.undamped()
    }

    /// Whether the record's history holds no event at all.
    fn quiet_history(&self) -> bool {
        self.hist.iter().all(|r| r.events == 0)
    }

    /// The work (thousandths of an event) of simulating again the window
    /// of a record without a period, its last `n_max` periods, for their
    /// impact sections (phase 5): the events those periods handled, and the
    /// one by which a run that meets its limit crosses it.
    fn window_work(&self) -> u64 {
        let events: usize = self.hist.iter().rev().take(self.acc.n_max).map(|r| r.events).sum();
        (events as u64 + 1).saturating_mul(EVENT_WORK)
    }

    /// Phases 1 and 2: records until a period is found or the exponent ends
    /// the record (early look, extensions of contracting records and of
    /// chaotic-looking ones near a stable orbit, and a contracting record
    /// whose section repeats beyond `n_max`).
    fn steady(&mut self) -> Result<Steady, Unresolved> {
        let acc = self.acc;
        let mut early_look = acc.chaos_check > 0 && acc.chaos_check < acc.max_periods && acc.lyapunov_periods > 0;
        let mut limit = if early_look { acc.chaos_check } else { acc.max_periods };
        let mut extensions = 0;
        loop {
            if let Some(n) = self.record(limit).map_err(|h| Unresolved::of(h, acc))? {
                return Ok(Steady::Periodic(n));
            }
            if acc.lyapunov_periods == 0 {
                return Ok(Steady::Unmeasured);
            }
            // Where the exponent's probe starts: the record takes its periods
            // only if it goes on from there.
            let at = (self.sim.periods(), self.sim.events(), self.sim.moment());
            let mut exponent = self.exponent(true);
            let kept = exponent.as_mut().map(|(_, e)| e.take_kept()).unwrap_or_default();
            let growth = exponent.as_ref().ok().map(|(_, e)| e.interval());
            // Still contracting: below 0 beyond its uncertainty, or on average (a slow transient).
            let contracting = growth.is_some_and(|g| g.high() < 0.0 || g.mean < -CONTRACTING_EXPONENT);
            // Above 0 beyond its uncertainty (at the early look, clearly so).
            let above = growth.is_some_and(|g| g.low() > 0.0 && (!early_look || g.mean > CHAOTIC_EXPONENT));
            // Chaotic-looking, and no stable orbit near that it may yet settle on.
            let chaotic = above && !self.stable_orbit_near();
            if early_look {
                early_look = false;
                limit = acc.max_periods;
                match (chaotic, exponent) {
                    (true, Ok((tangent, e))) => {
                        let decided = self.decide(tangent, e, true);
                        if self.go_on_quiet() || self.follow_once(Some(&decided))? {
                            self.torus_reached = None;
                            limit = self.sim.periods() as usize + acc.max_periods;
                            continue;
                        }
                        return Ok(decided);
                    }
                    (false, Ok((tangent, _))) => self.look_ahead(tangent, kept, &at),
                    (_, Err(_)) => {}
                }
                continue;
            }
            // A contracting record settled on an orbit longer than n_max: no
            // extension finds a period. Unconfirmed, it is the cell's result
            // where the contraction is shown: the exponent's interval below
            // 0, in a scene that dissipates. One below 0 on average only, or
            // in a scene that dissipates nothing (where nothing contracts:
            // a motion turning by nearly p/n on a torus, its map neutral,
            // which Newton's stable fixed point refuses), is measured on
            // like any record without a period.
            if let (true, Ok((_, e))) = (contracting, &exponent) {
                if let Some(n) = self.trail.long_period(acc) {
                    if let Some(m) = self.confirm(n) {
                        return Ok(Steady::Periodic(m));
                    }
                    if e.interval().high() < 0.0 && !self.sys.lossless() {
                        return Ok(Steady::LongPeriod(n, e.per_time()));
                    }
                }
            }
            // A free mass drifting towards a stop without an event: follow it there.
            let transient = contracting || above && !chaotic || self.drifting().is_some();
            if transient && extensions < acc.extensions {
                extensions += 1;
                self.newton.renew();
                limit += acc.max_periods;
                if let Ok((tangent, _)) = exponent {
                    self.look_ahead(tangent, kept, &at);
                }
                continue;
            }
            // Still drifting when the budget ends: followed to the wall, once.
            if self.follow_once(None)? {
                (extensions, limit) = (0, self.sim.periods() as usize + acc.max_periods);
                continue;
            }
            let (tangent, e) = match exponent {
                Ok(measured) => measured,
                Err(halt) => return Ok(Steady::Failed(halt)),
            };
            let decided = self.decide(tangent, e, extensions >= acc.extensions);
            if self.go_on_quiet() || self.follow_once(Some(&decided))? {
                self.torus_reached = None;
                (extensions, limit) = (0, self.sim.periods() as usize + acc.max_periods);
                continue;
            }
            // Contracting once its measurement was doubled: a transient
            // like any other, extended while extensions remain (within the
            // same budget of max_periods x (1 + extensions) periods, which
            // the doublings' periods count in).
            if matches!(decided, Steady::Aperiodic(_, _, Some(Unresolved::Contracting { .. })))
                && extensions < acc.extensions
            {
                extensions += 1;
                self.newton.renew();
                limit += acc.max_periods;
                continue;
            }
            return Ok(decided);
        }
    }

    /// Phase 4: the cell's labels and flags over its classified window (n
    /// periods; `span` periods for a motion whose repeat was no orbit, its
    /// flights beyond the precision; or the last `n_max` recorded without a
    /// period); stability, reason and work are filled in by the caller.
    fn window(&self, class: Class, n: Option<usize>, span: Option<usize>, y0: &[f64]) -> CellResult {
        let (sys, acc, hist) = (self.sys, self.acc, &self.hist);
        let stops = sys.stops.len();
        let len = hist.len();
        let window = n.or(span).map_or(acc.n_max.min(len), |w| w.min(len));
        let recs: Vec<&PeriodRecord> = hist.iter().skip(len - window).collect();
        let mut impacts = vec![0u32; stops];
        let (mut held, mut stuck) = (0u32, 0u32);
        for r in &recs {
            for (a, b) in impacts.iter_mut().zip(&r.impacts) {
                *a += b;
            }
            held |= r.held;
            stuck |= r.stuck;
        }
        let sticking = Mask::from_bits(held);
        let chatter = Mask::of(stops, |k| recs.iter().any(|r| r.impacts[k] as usize >= acc.chatter_impacts));
        let symmetry = match (sys.model.symmetric, n) {
            (true, Some(n)) => Some(symmetry_of(hist, n, acc)),
            _ => None,
        };
        CellResult {
            class,
            n,
            labels: label_masses(sys, n, class, &impacts, sticking),
            impacts,
            chatter,
            sticking,
            friction_stick: Mask::from_bits(stuck),
            symmetry,
            lyapunov: None,
            multiplier: None,
            final_state: self.sim.state().as_slice().to_vec(),
            window_start: if len > window { hist[len - window - 1].end.as_slice().to_vec() } else { y0.to_vec() },
            section: recs.iter().map(|r| r.end.as_slice().to_vec()).collect(),
            periods: 0,
            events: 0,
            reason: None,
        }
    }

    /// Phase 5: the impact sections of the classified window of `cell`, at most
    /// `cap` points per stop, simulated again on a probe.
    /// The window simulated again from its start: its impact sections (at
    /// most `cap` points per stop; none without a cap) as work of the cell, and
    /// with `measure` the quantities of the steady motion over the whole
    /// window (see [`run_cell_measured`]) on the same simulation, its periods
    /// past the sections counting no work. The quantities take the exact
    /// flow: a cell integrated by RK4 is measured on a simulation of its own.
    fn window_pass(
        &mut self,
        cell: &CellResult,
        cap: usize,
        measure: bool,
    ) -> (Option<ImpactSections>, Option<crate::quantity::Quantities>) {
        let periods = cell.section.len();
        // A window without a period is measured over its first periods only.
        let measured = if cell.n.is_some() { periods } else { periods.min(crate::quantity::APERIODIC_WINDOW) };
        let exact = self.sim.method() == Method::Exact;
        let mut meter = (measure && exact && periods > 0).then(|| crate::quantity::Meter::new(self.sys, measured));
        let mut probe = self.sim.probe();
        let (sections, ran) = match cap {
            0 => (None, Some(0)),
            _ => {
                let (start, impacts) = (&cell.window_start, &cell.impacts);
                let mut ignore = crate::simulate::Ignore;
                let also: &mut dyn crate::simulate::EventObserver = match meter.as_mut() {
                    Some(meter) => meter,
                    None => &mut ignore,
                };
                let (rows, ran) = self
                    .budget
                    .spend(&mut self.sim, &mut probe, |p| record_window(p, start, periods, impacts, cap, also));
                (Some(rows), ran)
            }
        };
        if !measure || periods == 0 {
            return (sections, None);
        }
        let Some(mut meter) = meter else {
            return (sections, crate::quantity::measure(self.sys, self.acc, &cell.window_start, measured).ok());
        };
        // The rest of the measured window, uncounted.
        let quantities = ran.and_then(|ran| {
            probe.set_budget(u64::MAX);
            if ran == 0 && probe.restart(&cell.window_start).is_err() {
                return None;
            }
            (ran..measured)
                .try_for_each(|_| probe.run_period(&[], false, &mut meter).map(|r| probe.recycle(r)))
                .ok()?;
            Some(meter.finish(measured))
        });
        (sections, quantities)
    }
}
