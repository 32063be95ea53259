//! Drilling into one cell: its classified window sampled densely with every
//! event named ([`window`]), and its Poincaré
//! sections over many periods ([`sections`]).

use crate::error::{Error, Result};
use crate::error::{Opt, RequestError};
use crate::sim::Setup;
use solver::{CellResult, Simulator, System};

/// The sections of a cell over some periods from its final state: the first
/// labelled mass's `(x, v)` at `t = kT`, and per stop its impacts as
/// (forcing phase mod 2π, impact speed), empty where it has none.
#[derive(Debug, Clone)]
pub struct Sections {
    /// The mass of the period section (the first labelled one).
    pub mass: usize,
    /// Its `(x, v)` at each whole period.
    pub period: Vec<(f64, f64)>,
    /// Per stop, `(phase, speed)` of each impact.
    pub impacts: Vec<Vec<(f64, f64)>>,
}

/// Largest number of forcing periods of [`sections`].
pub const MAX_SECTION_PERIODS: usize = 1_000_000;
/// The periods of a cell's sections when the caller names none (`cell
/// --section-png`, Python's `va.cell(..., sections=True)`).
pub const DEFAULT_SECTION_PERIODS: usize = 1000;
/// Largest number of samples per forcing period of a trace ([`trace`]): a
/// trace of n periods holds about n × 100 000 rows.
pub const MAX_TRACE_SAMPLES: usize = 100_000;
/// Largest number of rows of a trace (about 1 GB of CSV for two masses).
pub const MAX_TRACE_ROWS: usize = 10_000_000;

/// The sections of cell `c` over `periods` periods (1 to
/// [`MAX_SECTION_PERIODS`]) from its final state.
pub fn sections(sys: &System, s: &Setup, c: &CellResult, periods: usize) -> Result<Sections> {
    if periods == 0 || periods > MAX_SECTION_PERIODS {
        let why = format!("expected 1 to {MAX_SECTION_PERIODS}, got {periods}");
        return Err(RequestError::option(Opt::SectionPeriods).text(why).into());
    }
    struct Points<'a>(&'a System, Vec<Vec<(f64, f64)>>);
    impl solver::EventObserver for Points<'_> {
        fn impact(&mut self, t: f64, stop: usize, before: &solver::DVector<f64>, _: &solver::DVector<f64>) {
            self.1[stop].push((self.0.phase_at(t), -self.0.gap_rate(stop, before)));
        }
    }
    let mass = sys.model.labels.first().map_or(0, |l| l.mass);
    let m = sys.dof();
    let mut sim = Simulator::new(sys, s.accuracy, s.method, &c.final_state)
        .map_err(|h| Error::Halted { what: "sections", why: halt_text(&h, s) })?;
    let mut obs = Points(sys, vec![Vec::new(); sys.stops.len()]);
    let mut period = Vec::with_capacity(periods);
    for _ in 0..periods {
        let rec = sim
            .run_period(&[], false, &mut obs)
            .map_err(|h| Error::Halted { what: "sections", why: halt_text(&h, s) })?;
        period.push((rec.end[mass], rec.end[m + mass]));
    }
    Ok(Sections { mass, period, impacts: obs.1 })
}

/// One row of the classified window: time, state, and the event it is (if any).
pub type Row = (f64, Vec<f64>, Option<String>);

/// Why a simulation halted, in the words of a cell's `reason`.
pub fn halt_text(h: &solver::Halt, s: &Setup) -> String {
    match h {
        solver::Halt::Budget => format!("event budget of {} events exhausted", s.accuracy.max_events()),
        solver::Halt::Stalled => "event location stalled at a degenerate contact".into(),
        solver::Halt::Error(e) => e.to_string(),
    }
}

/// The classified window, and what of it could not be traced (see [`window`]).
#[derive(Debug, Clone)]
pub struct Window {
    /// The rows: time, state, and the event a row is (if any).
    pub rows: Vec<Row>,
    /// Periods replayed at their events only, and why sampling them halted.
    pub events_only: Vec<(usize, String)>,
    /// Where the trace ends early: the periods traced, and why.
    pub ended: Option<(usize, String)>,
}

impl Window {
    /// One line saying what the trace lacks, if anything.
    pub fn note(&self, periods: usize) -> Option<String> {
        let mut parts = Vec::new();
        if let Some((k, why)) = self.events_only.first() {
            let count = self.events_only.len();
            let which =
                if count == 1 { format!("period {}", k + 1) } else { format!("{count} periods (first: {})", k + 1) };
            parts.push(format!("{which} traced at the events only (stopping at the samples halted it: {why})"));
        }
        if let Some((done, why)) = &self.ended {
            parts.push(format!("it ends after {done} of {periods} periods: {why}"));
        }
        (!parts.is_empty()).then(|| parts.join("; "))
    }
}

/// Dense samples (and every event, named: `impact A1`, `stick A12`, …) of
/// `periods` periods from the window start, each period's end included. It is
/// as robust as the cell itself: a period whose samples halt the simulation
/// (stopping at a sample time can meet a degenerate contact the cell's own run
/// stepped over) is replayed from its start at its events only, the cell's
/// trajectory; a halt that remains ends the window there (the samples up to
/// it kept), with its reason (the cell's `reason` when it is unresolved for it).
pub fn window(sys: &System, s: &Setup, c: &CellResult, periods: usize, samples: usize) -> Window {
    struct Rows<'a>(Vec<Row>, &'a System);
    impl solver::EventObserver for Rows<'_> {
        fn named_event(&mut self, t: f64, kind: solver::EventKind, y: &solver::DVector<f64>) {
            self.0.push((t, y.as_slice().to_vec(), Some(kind.describe(self.1))));
        }
        fn sample(&mut self, t: f64, y: &solver::DVector<f64>) {
            self.0.push((t, y.as_slice().to_vec(), None));
        }
    }
    let mut rows = Rows(vec![(0.0, c.window_start.clone(), None)], sys);
    let mut events_only = Vec::new();
    let mut sim = match Simulator::new(sys, s.accuracy, s.method, &c.window_start) {
        Ok(sim) => sim,
        Err(h) => return Window { rows: rows.0, events_only, ended: Some((0, halt_text(&h, s))) },
    };
    let times: Vec<f64> = (1..samples).map(|i| sys.period * i as f64 / samples as f64).collect();
    for k in 0..periods {
        // The period's end is a sample (the observer's, after the period).
        let (before, kept) = (sim.clone(), rows.0.len());
        let Err(h) = sim.run_period(&times, false, &mut rows) else { continue };
        let sampled = rows.0.split_off(kept);
        sim = before;
        if let Err(again) = sim.run_period(&[], false, &mut rows) {
            // A halt of the cell's own trajectory: the samples up to it.
            rows.0.truncate(kept);
            rows.0.extend(sampled);
            return Window { rows: rows.0, events_only, ended: Some((k, halt_text(&again, s))) };
        }
        events_only.push((k, halt_text(&h, s)));
    }
    Window { rows: rows.0, events_only, ended: None }
}

/// Refuses samples per forcing period of a trace out of 1 to [`MAX_TRACE_SAMPLES`].
pub fn check_trace_samples(samples: usize) -> Result<()> {
    if samples == 0 || samples > MAX_TRACE_SAMPLES {
        let why = format!("expected 1 to {MAX_TRACE_SAMPLES}, got {samples}");
        return Err(RequestError::option(Opt::TraceSamples).text(why).into());
    }
    Ok(())
}

/// Forcing periods of a cell's window: its period, or its section's periods.
pub fn window_periods(c: &CellResult) -> usize {
    c.n.unwrap_or(c.section.len().max(1))
}

/// The trace of cell `c`: its [`window`] over [`window_periods`], `samples`
/// per forcing period, refused when that is more than [`MAX_TRACE_ROWS`] rows.
pub fn trace(sys: &System, s: &Setup, c: &CellResult, samples: usize) -> Result<Window> {
    check_trace_samples(samples)?;
    let periods = window_periods(c);
    if periods.saturating_mul(samples) > MAX_TRACE_ROWS {
        let why =
            format!("{periods} periods x {samples} samples is more than {MAX_TRACE_ROWS} rows; take fewer samples");
        return Err(RequestError::option(Opt::TraceSamples).text(why).into());
    }
    Ok(window(sys, s, c, periods, samples))
}
