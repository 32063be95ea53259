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
//!    transient from both. With `chaos_check` it is measured early (after
//!    `chaos_check` periods) and a clearly chaotic record (`λT > 0.05`) ends
//!    there; a record that still contracts (`λT < -0.002`) is extended by
//!    `max_periods`, at most `extensions` times ([`Executor::steady`] runs
//!    phases 1 and 2). A record that still contracts but whose section has
//!    settled on an orbit longer than `n_max` (up to 128 periods) is not
//!    extended (no extension would find a period): Newton's method on that
//!    period's map confirms it and the cell is periodic with it
//!    ([`Executor::confirm`]), or it ends `unresolved`
//!    ([`Unresolved::LongPeriod`]);
//! 3. **multiplier** ([`Executor::multiplier`]): with a period, the largest
//!    Floquet multiplier modulus of the n-period map at the final state;
//! 4. **window** ([`Executor::window`]): impacts, sticking and chattering over
//!    the classified window (n periods, or the last `n_max` without a period),
//!    hence the labels;
//! 5. **sections** ([`Executor::sections`]): the window simulated again, to
//!    record the state before each impact.
//!
//! A cell that exhausts its budget, stalls, or whose exponent cannot tell is
//! `unresolved`, with an [`Unresolved`] reason.

use crate::acceleration::Newton;
use crate::accuracy::Accuracy;
use crate::budget::Budget;
use crate::error::SolverError;
use crate::floquet::{multipliers, spectral_radius};
use crate::flow::Method;
use crate::label::{label_masses, Class, Label, Mask, MassLabel, Symmetry};
use crate::lyapunov::{fills_closed_curve, largest_exponent};
use crate::newton::{evaluate, fixed_point, MapKind, Pattern};
use crate::period::{converged, detect, distance, history_len, remaining, symmetry_of, History, Trail};
use crate::section::record_window;
use crate::simulate::{Halt, Ignore, PeriodRecord, Simulator};
use crate::system::System;
use nalgebra::DVector;

/// Periods of tangent alignment before the Lyapunov exponent is averaged.
const LYAPUNOV_WARMUP: usize = 10;

/// A cell without a period whose `λ T` is below minus this still contracts: a
/// long transient, whose record is extended (see `Accuracy::extensions`).
const CONTRACTING_EXPONENT: f64 = 2e-3;

/// Smallest `λ T` at which the early look of `Accuracy::chaos_check` ends a
/// record as chaotic: five times the quasi-periodic band, so that a torus or a
/// weakly chaotic motion gets the whole record.
const CHAOTIC_EXPONENT: f64 = 0.05;

/// Largest `|λ T|` (growth per forcing period) of a quasi-periodic motion: a
/// torus has `λ = 0`, and a finite average over 100 periods stays within this.
const QUASIPERIODIC_EXPONENT: f64 = 0.01;

/// Largest distance (relative, max norm) between a record that contracts onto
/// an orbit longer than `n_max` and the fixed point Newton's method confirms it
/// with (see [`Executor::confirm`]).
const LONG_REACH: f64 = 1e-3;

/// Newton polishes of a found, slowly converging orbit per cell (see
/// [`Executor::polish`]).
const POLISHES: usize = 2;

/// Why a cell is `unresolved`.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Unresolved {
    /// The event budget (`max_events`) ran out.
    Budget {
        /// The budget, in events.
        max_events: usize,
    },
    /// An event search made no progress (a degenerate contact).
    Stalled,
    /// The system cannot be simulated.
    Failed(SolverError),
    /// No period within the record, and the motion still contracts after every
    /// extension: a transient longer than the record.
    Contracting {
        /// The largest Lyapunov exponent per forcing period, `λT`.
        growth: f64,
    },
    /// No period; the exponent is in the quasi-periodic band but the period
    /// section is not one closed curve.
    Undecided {
        /// The largest Lyapunov exponent per forcing period, `λT`.
        growth: f64,
    },
    /// No period, and the run that measures the exponent halted (why inside).
    NoExponent(Box<Unresolved>),
    /// No period up to `n_max`, and the motion contracts onto an orbit of a
    /// longer period (see `n_max`), which no extension of the record would
    /// find and Newton's method did not confirm (a confirmed one is a label).
    LongPeriod {
        /// The orbit's period, in forcing periods.
        n: usize,
        /// The longest period tested (`Accuracy::n_max`).
        n_max: usize,
    },
}

impl Unresolved {
    fn of(halt: Halt, acc: &Accuracy) -> Unresolved {
        match halt {
            Halt::Budget => Unresolved::Budget { max_events: acc.max_events },
            Halt::Stalled => Unresolved::Stalled,
            Halt::Error(e) => Unresolved::Failed(e),
        }
    }
}

impl std::fmt::Display for Unresolved {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unresolved::Budget { max_events } => write!(f, "event budget of {max_events} events exhausted"),
            Unresolved::Stalled => write!(f, "event location stalled at a degenerate contact"),
            Unresolved::Failed(e) => write!(f, "{e}"),
            Unresolved::Contracting { growth } => write!(
                f,
                "no period within the record, and the motion still contracts (λT = {growth:.3e}): a transient longer than max_periods x (1 + extensions)"
            ),
            Unresolved::Undecided { growth } => write!(
                f,
                "no period within the record; the largest Lyapunov exponent is in the quasi-periodic band (λT = {growth:.3e}) but the period section is not one closed curve"
            ),
            Unresolved::LongPeriod { n, n_max } => write!(
                f,
                "no period up to n_max = {n_max}: the motion contracts onto an orbit of period {n}, which Newton's method on the {n}-period map did not confirm (raise n_max to search for it in the record)"
            ),
            Unresolved::NoExponent(why) => {
                write!(f, "no period within the record, and its largest Lyapunov exponent could not be measured: {why}")
            }
        }
    }
}

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
pub type ImpactSections = Vec<Vec<Vec<f64>>>;

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
    let no_sections = || vec![Vec::new(); sys.stops.len()];
    let mut cell = match Executor::start(sys, acc, method, y0) {
        Ok(cell) => cell,
        Err(why) => return (unresolved(sys, why, 0, 0, y0.to_vec()), no_sections()),
    };
    let steady = match cell.steady() {
        Ok(steady) => steady,
        Err(why) => {
            let (periods, events) = (cell.budget.periods(&cell.sim), cell.budget.events(&cell.sim));
            return (unresolved(sys, why, periods, events, cell.sim.state().as_slice().to_vec()), no_sections());
        }
    };
    let (class, n, lyapunov, reason) = match steady {
        Steady::Periodic(n) => (Class::Periodic, Some(n), None, None),
        Steady::LongPeriod(n, l) => {
            (Class::Unresolved, None, Some(l), Some(Unresolved::LongPeriod { n, n_max: acc.n_max }))
        }
        Steady::Unmeasured => (Class::Chaotic, None, None, None),
        Steady::Failed(halt) => {
            (Class::Unresolved, None, None, Some(Unresolved::NoExponent(Box::new(Unresolved::of(halt, acc)))))
        }
        Steady::Exponent(l, points) => {
            let (class, reason) = without_period(l * sys.period, || fills_closed_curve(&points));
            (class, None, Some(l), reason)
        }
    };
    let multiplier = match n {
        Some(n) if acc.multipliers => cell.multiplier(n),
        _ => None,
    };
    let mut result = cell.window(class, n, y0);
    let sections = if section_cap == 0 { no_sections() } else { cell.sections(&result, section_cap) };
    result.lyapunov = lyapunov;
    result.multiplier = multiplier;
    result.reason = reason;
    result.periods = cell.budget.periods(&cell.sim);
    result.events = cell.budget.events(&cell.sim);
    (result, sections)
}

/// How a record ended.
#[derive(Debug)]
enum Steady {
    /// The section repeats with period n.
    Periodic(usize),
    /// The record contracts, and its section repeats with a period n beyond
    /// `n_max` (see [`Trail`]); the largest Lyapunov exponent (per unit time).
    LongPeriod(usize, f64),
    /// No period; the largest Lyapunov exponent (per unit time) and the
    /// period-section points it visited.
    Exponent(f64, Vec<DVector<f64>>),
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
        })
    }

    /// Phase 1: simulates periods until the section repeats (the period n,
    /// returned) or `limit` periods in all are simulated (`None`), with Newton
    /// acceleration of slowly contracting patterns on the way.
    fn record(&mut self, limit: usize) -> Result<Option<usize>, Halt> {
        let acc = self.acc;
        while (self.sim.periods() as usize) < limit {
            let rec = self.sim.run_period(&[], self.sys.model.symmetric, &mut Ignore)?;
            if self.hist.len() == history_len(acc) {
                self.hist.pop_front();
            }
            self.trail.push(&rec.end);
            self.hist.push_back(rec);
            if (self.sim.periods() as usize) < acc.min_transient {
                continue;
            }
            if let Some(n) = detect(&self.hist, acc) {
                // Accepted once converged, so that its symmetry and final state are the orbit's.
                if converged(&self.hist, n, acc) {
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
            if acc.newton && self.newton.due(&self.sim) {
                if let Some(x) = self.newton.step(&mut self.sim, &self.hist, acc, &mut self.budget) {
                    if self.sim.restart(x.as_slice()).is_ok() {
                        self.hist.clear();
                        self.trail.clear();
                    }
                }
            }
        }
        Ok(None)
    }

    /// A found orbit of period n that repeats within `periodic_tol` but is
    /// still converging slowly (see [`converged`]): when brute force would need
    /// more than a Newton solve (about `3 (dim + 1) n` periods) to converge,
    /// Newton's method on the n-period map finishes it from the main state, on
    /// a probe: the stable fixed point with the record's impact pattern, within
    /// ten times the estimated distance still to go, to restart from. At most
    /// [`POLISHES`] tries a cell (in every preset: the orbit and its period are
    /// already found, only its convergence is finished).
    fn polish(&mut self, n: usize) -> Option<DVector<f64>> {
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

    /// Confirms an orbit of period `n` beyond `n_max` that the record
    /// contracts onto ([`Trail::long_period`]): Newton's method on the
    /// n-period map from the main state converges, on a probe, to a stable
    /// fixed point within [`LONG_REACH`] of it; the record restarts there and
    /// is simulated 3n periods, which must repeat with period n (the test of
    /// period detection with `n_max = n`). The cell is then periodic with that
    /// period, its window the last n of them; `n_max` stays the limit of the
    /// search in the record (issue 28).
    fn confirm(&mut self, n: usize) -> bool {
        let acc = self.acc;
        let y = self.sim.state().clone();
        let tol = 1e-3 * acc.periodic_tol;
        let mut probe = self.sim.probe();
        let found = self.budget.spend(&mut self.sim, &mut probe, |p| {
            let sol = crate::newton::solve(p, &y, MapKind::Periods(n), None, tol, 8, 0.1)?;
            let mu = crate::floquet::multipliers(&sol.jacobian);
            (!mu.is_empty() && mu.iter().all(|m| m.norm() < 1.0)).then_some(sol.x)
        });
        let Some(x) = found.filter(|x| distance(&y, x) <= LONG_REACH) else { return false };
        if self.sim.restart(x.as_slice()).is_err() {
            return false;
        }
        self.hist.clear();
        self.trail.clear();
        let wide = Accuracy { n_max: n, ..*acc };
        for _ in 0..3 * n {
            match self.sim.run_period(&[], self.sys.model.symmetric, &mut Ignore) {
                Ok(rec) => self.hist.push_back(rec),
                Err(_) => return false,
            }
        }
        detect(&self.hist, &wide) == Some(n)
    }

    /// Phase 2: the largest Lyapunov exponent (per unit time) of the motion
    /// from the main simulator's state, on a probe, with the section points it
    /// visited; why not when its run halts.
    fn exponent(&mut self) -> Result<(f64, Vec<DVector<f64>>), Halt> {
        let mut tangent = self.sim.probe();
        let periods = self.acc.lyapunov_periods;
        self.budget.spend(&mut self.sim, &mut tangent, |t| largest_exponent(t, LYAPUNOV_WARMUP, periods))
    }

    /// Phases 1 and 2: records until a period is found or the exponent ends
    /// the record (early look, extensions of contracting records, and a
    /// contracting record whose section repeats beyond `n_max`).
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
            let exponent = self.exponent();
            // Growth per forcing period decides: the record ends, or goes on to a new limit.
            let growth = exponent.as_ref().ok().map(|(l, _)| l * self.sys.period);
            let contracting = growth.is_some_and(|g| g < -CONTRACTING_EXPONENT);
            // A contracting record settled on an orbit longer than n_max: no extension finds a period.
            if let (false, true, Ok((l, _))) = (early_look, contracting, &exponent) {
                if let Some(n) = self.trail.long_period(acc) {
                    if self.confirm(n) {
                        return Ok(Steady::Periodic(n));
                    }
                    return Ok(Steady::LongPeriod(n, *l));
                }
            }
            let ended = || match exponent {
                Ok((l, points)) => Steady::Exponent(l, points),
                Err(halt) => Steady::Failed(halt),
            };
            limit = if early_look {
                early_look = false;
                if growth.is_some_and(|g| g > CHAOTIC_EXPONENT) {
                    return Ok(ended());
                }
                acc.max_periods
            } else if contracting && extensions < acc.extensions {
                extensions += 1;
                self.newton.renew();
                limit + acc.max_periods
            } else {
                return Ok(ended());
            };
        }
    }

    /// Phase 3: the largest Floquet multiplier modulus of the n-period map at
    /// the main simulator's state, on a probe tracking its tangent.
    fn multiplier(&mut self, n: usize) -> Option<f64> {
        let mut tangent = self.sim.probe();
        tangent.track_tangent();
        let x = self.sim.state().clone();
        self.budget.spend(&mut self.sim, &mut tangent, |t| {
            let image = evaluate(t, &x, MapKind::Periods(n)).ok()?;
            let mu = multipliers(&image.jacobian);
            (!mu.is_empty()).then(|| spectral_radius(&mu))
        })
    }

    /// Phase 4: the cell's labels and flags over its classified window (n
    /// periods, or the last `n_max` recorded without a period); stability,
    /// reason and work are filled in by the caller.
    fn window(&self, class: Class, n: Option<usize>, y0: &[f64]) -> CellResult {
        let (sys, acc, hist) = (self.sys, self.acc, &self.hist);
        let stops = sys.stops.len();
        let len = hist.len();
        let window = n.unwrap_or(acc.n_max.min(len));
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
    fn sections(&mut self, cell: &CellResult, cap: usize) -> ImpactSections {
        let mut probe = self.sim.probe();
        self.budget.spend(&mut self.sim, &mut probe, |p| {
            record_window(p, &cell.window_start, cell.section.len(), &cell.impacts, cap)
        })
    }
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

/// The class of a cell without a period from its largest Lyapunov exponent
/// `growth = λT` per forcing period, and the reason when it is undecided:
/// chaotic only when the exponent is positive beyond the quasi-periodic band;
/// quasi-periodic inside the band when the period-section points lie on one
/// closed curve; otherwise (inside the band without a closed curve, or still
/// contracting after every extension: a transient longer than the record)
/// unresolved, never chaotic.
fn without_period(growth: f64, closed_curve: impl FnOnce() -> bool) -> (Class, Option<Unresolved>) {
    if growth > QUASIPERIODIC_EXPONENT {
        (Class::Chaotic, None)
    } else if growth < -QUASIPERIODIC_EXPONENT {
        (Class::Unresolved, Some(Unresolved::Contracting { growth }))
    } else if closed_curve() {
        (Class::Quasiperiodic, None)
    } else {
        (Class::Unresolved, Some(Unresolved::Undecided { growth }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::system;

    fn multi_stop(omega: f64, delta: f64) -> System {
        system("multi-stop.toml", &[("omega", omega), ("delta", delta)])
    }

    fn executor<'s>(sys: &'s System, acc: &'s Accuracy) -> Executor<'s> {
        Executor::start(sys, acc, Method::Exact, &sys.model.initial_state()).unwrap()
    }

    /// Phase 1 with and without Newton acceleration: the same period and
    /// final state (to the period tolerance), Newton in fewer periods, its
    /// probe's work in the budget.
    #[test]
    fn newton_shortens_the_record_and_its_work_is_counted() {
        // A slowly contracting 1-2-1 orbit: over 500 periods of plain simulation.
        let sys = multi_stop(1.5, 0.1);
        let (with, without) = (Accuracy::default(), Accuracy::default().with(crate::Knob::Newton, 0.0).unwrap());
        let (mut a, mut b) = (executor(&sys, &with), executor(&sys, &without));
        let limit = 3000;
        assert_eq!((a.record(limit).unwrap(), b.record(limit).unwrap()), (Some(1), Some(1)));
        let d = crate::period::distance(a.sim.state(), b.sim.state());
        assert!(d <= 10.0 * with.periodic_tol, "final states {d:e} apart");
        assert!(a.sim.periods() < b.sim.periods(), "{} against {} periods", a.sim.periods(), b.sim.periods());
        assert!(a.budget.periods(&a.sim) > a.sim.periods(), "the probe's periods are counted");
        assert_eq!(b.budget.periods(&b.sim), b.sim.periods(), "no probe without Newton");
    }

    /// Phases 2 and 3 agree on a periodic orbit: the largest Lyapunov exponent
    /// per forcing period is the log of the largest Floquet multiplier.
    #[test]
    fn the_exponent_of_an_orbit_is_the_log_of_its_multiplier() {
        let sys = multi_stop(0.33, 0.6);
        let acc = Accuracy::default();
        let mut cell = executor(&sys, &acc);
        assert_eq!(cell.record(600).unwrap(), Some(1));
        let mu = cell.multiplier(1).unwrap();
        let (lambda, points) = cell.exponent().unwrap();
        assert_eq!(points.len(), acc.lyapunov_periods);
        assert!(
            (lambda * sys.period - mu.ln()).abs() < 0.02 * mu.ln().abs(),
            "λT {} against ln μ {}",
            lambda * sys.period,
            mu.ln()
        );
    }

    /// Phase 3 against finite differences: the spectral radius of the
    /// period map's Jacobian by central differences of simulated periods.
    #[test]
    fn the_multiplier_is_that_of_the_period_maps_derivative() {
        let sys = multi_stop(2.0, 1.2);
        let acc = Accuracy::default();
        let mut cell = executor(&sys, &acc);
        assert_eq!(cell.record(600).unwrap(), Some(1));
        let x = cell.sim.state().clone();
        let map = |y: &DVector<f64>| {
            let mut sim = Simulator::new(&sys, acc, Method::Exact, y.as_slice()).unwrap();
            sim.run_period(&[], false, &mut Ignore).unwrap();
            sim.state().clone()
        };
        let h = 1e-6;
        let jac = nalgebra::DMatrix::from_fn(4, 4, |i, j| {
            let e = DVector::from_fn(4, |k, _| if k == j { h } else { 0.0 });
            (map(&(&x + &e))[i] - map(&(&x - &e))[i]) / (2.0 * h)
        });
        let fd = spectral_radius(&multipliers(&jac));
        let mu = cell.multiplier(1).unwrap();
        assert!((mu - fd).abs() < 1e-6, "{mu} against finite differences {fd}");
    }

    /// A record that contracts onto an orbit longer than `n_max` ends at the
    /// first look after that orbit has repeated twice, before the whole
    /// extended record (`max_periods (1 + extensions)` = 3 000 periods), and
    /// Newton's method on the 60-period map confirms it: the cell is periodic
    /// with period 60 and the labels of the same cell searched with `n_max`
    /// above that period (period detection as the oracle; issue 28: it was
    /// `unresolved`, naming the period). A neutral torus that closes after
    /// more than `n_max` periods (the undamped oscillator away from its stop
    /// at ω = 33/13: period 33) does not contract and stays quasi-periodic.
    #[test]
    fn an_orbit_longer_than_n_max_is_confirmed_and_labelled() {
        let sys = multi_stop(1.1042553191489362, 2.0);
        let acc = Accuracy::default();
        let cell = run_cell(&sys, &acc, Method::Exact, &sys.model.initial_state());
        assert_eq!((cell.class, cell.n), (Class::Periodic, Some(60)), "{:?}", cell.reason);
        assert!(cell.periods < 3000, "{} periods", cell.periods);
        assert_eq!(cell.section.len(), 60);
        let wide = acc.with(crate::Knob::NMax, 64.0).unwrap();
        let oracle = run_cell(&sys, &wide, Method::Exact, &sys.model.initial_state());
        assert_eq!((oracle.class, oracle.n), (Class::Periodic, Some(60)));
        assert_eq!(cell.labels, oracle.labels);
        assert_eq!(cell.impacts, oracle.impacts);
        let torus = system("single-stop.toml", &[("sigma", 0.3), ("omega", 33.0 / 13.0)]);
        let cell = run_cell(&torus, &acc, Method::Exact, &torus.model.initial_state());
        assert_eq!(cell.class, Class::Quasiperiodic, "{:?}", cell.reason);
    }

    /// Phases 1 and 4 on complete chattering (ω = 0.2, δ = 0.6): M1 sticks to
    /// both of its stops (A12 and A1, label 1-S-S), A1 chatters first.
    #[test]
    fn the_window_labels_sticking_and_chattering() {
        let sys = multi_stop(0.2, 0.6);
        let acc = Accuracy::default();
        let mut cell = executor(&sys, &acc);
        let Steady::Periodic(n) = cell.steady().unwrap() else { panic!("not periodic") };
        let result = cell.window(Class::Periodic, Some(n), &sys.model.initial_state());
        assert_eq!(result.labels[0].to_string(), "1-S-S");
        assert!(result.sticking.contains(0) && result.sticking.contains(2), "{:?}", result.sticking);
        assert!(result.chatter.contains(0), "{:?}", result.chatter);
        assert_eq!(result.section.len(), n);
    }

    /// Phase 5: every stop gets min(cap, its impacts) points, each on its
    /// stop, and the re-simulation counts in the cell's work.
    #[test]
    fn sections_lie_on_their_stops_and_count_as_work() {
        let sys = multi_stop(0.33, 0.6);
        let acc = Accuracy::default();
        let mut cell = executor(&sys, &acc);
        assert_eq!(cell.record(600).unwrap(), Some(1));
        let result = cell.window(Class::Periodic, Some(1), &sys.model.initial_state());
        let before = cell.budget.periods(&cell.sim);
        let sections = cell.sections(&result, 3);
        assert_eq!(cell.budget.periods(&cell.sim), before + 1, "one period simulated again");
        for (k, rows) in sections.iter().enumerate() {
            assert_eq!(rows.len(), (result.impacts[k] as usize).min(3), "stop {k}");
            for row in rows {
                let gap = sys.gap(k, &DVector::from_column_slice(&row[1..]));
                assert!(gap.abs() <= 10.0 * acc.contact_tol, "stop {k}: gap {gap:e}");
            }
        }
    }

    /// One budget: whatever the phase that exhausts it, a cell handles at
    /// most `max_events` events plus the one that crossed the limit in each
    /// of the two simulators that saw it, and says why it stopped.
    #[test]
    fn every_phase_draws_on_one_budget() {
        for (omega, delta) in [(1.05, 0.05), (0.33, 0.6), (0.98, 0.34)] {
            let sys = multi_stop(omega, delta);
            for max in [30.0, 300.0, 3000.0] {
                let acc = Accuracy::default().with(crate::Knob::MaxEvents, max).unwrap();
                let (cell, _) = run_cell_with_sections(&sys, &acc, Method::Exact, &sys.model.initial_state(), 16);
                assert!(cell.events <= max as usize + 2, "ω {omega}: {} events of {max}", cell.events);
                if cell.class == Class::Unresolved {
                    // The record ran out, or the exponent's run did.
                    let budget = Unresolved::Budget { max_events: max as usize };
                    let exponent = Unresolved::NoExponent(Box::new(budget.clone()));
                    assert!(cell.reason == Some(budget) || cell.reason == Some(exponent), "{:?}", cell.reason);
                }
                // Without a period, never chaotic without an exponent.
                assert!(cell.class != Class::Chaotic || cell.lyapunov.is_some(), "ω {omega}, {max}: {cell:?}");
            }
        }
    }

    #[test]
    fn reasons_read_as_documented() {
        assert_eq!(Unresolved::Budget { max_events: 5 }.to_string(), "event budget of 5 events exhausted");
        assert_eq!(Unresolved::Stalled.to_string(), "event location stalled at a degenerate contact");
        let (class, why) = without_period(-0.5, || true);
        assert_eq!(class, Class::Unresolved);
        assert!(why
            .unwrap()
            .to_string()
            .starts_with("no period within the record, and the motion still contracts (λT = -5.000e-1)"));
        assert_eq!(without_period(0.2, || false), (Class::Chaotic, None));
        assert_eq!(without_period(0.001, || true), (Class::Quasiperiodic, None));
        assert_eq!(without_period(0.001, || false).0, Class::Unresolved);
    }
}
