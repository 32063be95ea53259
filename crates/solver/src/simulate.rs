//! The event loop: one forcing period at a time, from event to event.
//!
//! Time is kept as (period index, time within the period) so that the forcing
//! phase `ω t + τ` never loses precision over long runs. Each period ends exactly
//! at `t = kT`, where the stroboscopic (period) section is sampled. Events are
//! contacts (impact law, then sticking decision), chatter accumulation (pass to
//! sticking), releases (a held stop's reaction reaching zero), and the friction
//! events: a slip ending (relative velocity zero: stick or reverse) and a
//! breakaway (the stuck friction force reaching the static limit). After every
//! event [`settle`] chooses the next mode.

use crate::accuracy::Accuracy;
use crate::chatter::ChatterTracker;
use crate::contact::Contact;
use crate::error::SolverError;
use crate::flow::exact::Workspace;
use crate::flow::{Advance, Method};
use crate::impact;
use crate::mode::{GuardKind, Key, Mode};
use crate::soft;
use crate::stick::{candidates, settle, touching, ModeCache, RECURRING};
use crate::system::System;
use nalgebra::{DMatrix, DVector, RowDVector};
use num_complex::Complex64 as C64;

/// One event of a cell's work budget ([`crate::budget`]), in the units work
/// is counted in (thousandths of an event).
pub(crate) const EVENT_WORK: u64 = 1000;

/// Receives what happens during a simulation; section recorders and traces are
/// observers, so nothing is stored unless asked.
pub trait EventObserver {
    /// An impact at `stop` at absolute time `time`, states before and after.
    fn impact(&mut self, _time: f64, _stop: usize, _before: &DVector<f64>, _after: &DVector<f64>) {}
    /// Any event (impact, stick, release) after it was handled.
    fn event(&mut self, _time: f64, _y: &DVector<f64>) {}
    /// A geometric chatter sequence at `stop` whose impacts would accumulate
    /// at `until` was cut at `time` (its tail replaced by the hold that
    /// follows it, see the `chatter` module): the mass rests on the stop from then,
    /// but the true motion bounces on it until `until` (called before
    /// [`EventObserver::event`]).
    fn accumulates(&mut self, _stop: usize, _time: f64, _until: f64) {}
    /// The same event with what it was (after [`EventObserver::event`]).
    fn named_event(&mut self, _time: f64, _kind: EventKind, _y: &DVector<f64>) {}
    /// A requested sample time within a period was reached.
    fn sample(&mut self, _time: f64, _y: &DVector<f64>) {}
    /// Whether the observer takes every flow segment ([`EventObserver::segment`]).
    fn wants_segments(&self) -> bool {
        false
    }
    /// A flow segment of the exact flow, just flown and before the event
    /// that ends it is handled: its closed form evaluates the state anywhere
    /// within it. Only when [`EventObserver::wants_segments`]; RK4's steps have
    /// no closed form and give none.
    fn segment(&mut self, _segment: &mut Segment<'_>) {}
}

/// One segment of the exact flow between two events (or an event and a
/// period's end), in one mode: its start, its length and its closed form.
pub struct Segment<'a> {
    /// Completed forcing periods at its start.
    pub periods: u64,
    /// Time within the period at its start (the forcing phase there is
    /// `ω clock + τ`).
    pub clock: f64,
    /// Its length (time units of the scene).
    pub span: f64,
    /// Held stops (bit k: stop k holds its mass).
    pub held: u32,
    /// Stuck friction contacts (bit i).
    pub stuck: u32,
    /// Pressed soft stops (bit k: its force pushes).
    pub pressed: u32,
    /// Parting soft stops (bit k: its gap closed, its force none, as damping
    /// makes a contact end before its gap reopens).
    pub parting: u32,
    mode: &'a Mode,
    work: &'a mut Workspace,
    scratch: &'a mut DVector<f64>,
    full: usize,
}

impl Segment<'_> {
    /// The full state `[x; v]` at time `u` (0 to [`Segment::span`]) into its
    /// start, from the closed form of the flow.
    pub fn state(&mut self, u: f64, out: &mut DVector<f64>) {
        self.work.state_at(self.mode, u, self.scratch);
        if out.len() != self.full {
            *out = DVector::zeros(self.full);
        }
        self.mode.lift_into(self.scratch, out);
    }

    /// The largest rate of the flow's terms (the fastest mode's |eigenvalue|,
    /// forcing harmonics included), per unit time.
    pub fn fastest(&self) -> f64 {
        self.mode.spectral.fastest()
    }

    /// The reaction of stop `stop`, which holds its mass in this segment, at
    /// the time of the last [`Segment::state`]: the constraint force along
    /// the stop's normal by which it holds (force units of the scene, at
    /// least 0 while it holds; between two masses, the force each takes).
    /// `None` for a stop that does not hold.
    pub fn reaction(&self, stop: usize) -> Option<f64> {
        let guard = self
            .mode
            .guards
            .iter()
            .find(|g| g.kind == GuardKind::Reaction && g.target == crate::mode::Target::Stop(stop))?;
        Some(guard.entries.iter().map(|&(i, c)| c * self.scratch[i]).sum())
    }
}

/// What an event was. Stops and friction contacts are indices into the
/// system's stops and friction contacts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum EventKind {
    /// An impact at a stop (the first stop hit, when several are).
    Impact(usize),
    /// A mass came to rest on a stop without an impact and stays there.
    Stick(usize),
    /// A stop's reaction vanished: its mass leaves it.
    Release(usize),
    /// A gap closed with no impact and no sticking (a grazing contact).
    Grazing(usize),
    /// A slipping friction contact came to relative rest and sticks.
    FrictionStick(usize),
    /// A slipping friction contact reversed its direction of slip.
    SlipReversal(usize),
    /// A stuck friction contact reached its static limit and slips.
    Breakaway(usize),
    /// A soft stop's gap closed and its contact pushes.
    Contact(usize),
    /// A soft stop's contact force fell to zero: the contact ends.
    Separation(usize),
    /// The gap of a soft stop whose contact ended under damping reopened.
    Reopen(usize),
    /// A soft stop's contact pushes again before its gap reopened.
    Return(usize),
}

impl EventKind {
    /// The stop the event is at; `None` for an event of a friction contact.
    pub fn stop(self) -> Option<usize> {
        match self {
            EventKind::Impact(k)
            | EventKind::Stick(k)
            | EventKind::Release(k)
            | EventKind::Grazing(k)
            | EventKind::Contact(k)
            | EventKind::Separation(k)
            | EventKind::Reopen(k)
            | EventKind::Return(k) => Some(k),
            EventKind::FrictionStick(_) | EventKind::SlipReversal(_) | EventKind::Breakaway(_) => None,
        }
    }

    /// `kind stop-or-contact`, e.g. `impact A1`, `breakaway M1-M2`.
    pub fn describe(self, sys: &System) -> String {
        let stop = |k: usize| sys.model.stops.get(k).map_or(k.to_string(), |s| s.name.clone());
        let contact = |i: usize| if i < sys.model.friction.len() { sys.friction_name(i) } else { i.to_string() };
        match self {
            EventKind::Impact(k) => format!("impact {}", stop(k)),
            EventKind::Stick(k) => format!("stick {}", stop(k)),
            EventKind::Release(k) => format!("release {}", stop(k)),
            EventKind::Grazing(k) => format!("grazing {}", stop(k)),
            EventKind::FrictionStick(i) => format!("stick {}", contact(i)),
            EventKind::SlipReversal(i) => format!("slip-reversal {}", contact(i)),
            EventKind::Breakaway(i) => format!("breakaway {}", contact(i)),
            EventKind::Contact(k) => format!("contact {}", stop(k)),
            EventKind::Separation(k) => format!("separation {}", stop(k)),
            EventKind::Reopen(k) => format!("reopen {}", stop(k)),
            EventKind::Return(k) => format!("return {}", stop(k)),
        }
    }
}

/// An observer that keeps nothing.
#[derive(Debug, Default, Clone, Copy)]
pub struct Ignore;
impl EventObserver for Ignore {}

/// Two observers of one simulation, each told everything in turn.
pub(crate) struct Both<'a>(pub &'a mut dyn EventObserver, pub &'a mut dyn EventObserver);

impl EventObserver for Both<'_> {
    fn impact(&mut self, time: f64, stop: usize, before: &DVector<f64>, after: &DVector<f64>) {
        self.0.impact(time, stop, before, after);
        self.1.impact(time, stop, before, after);
    }

    fn event(&mut self, time: f64, y: &DVector<f64>) {
        self.0.event(time, y);
        self.1.event(time, y);
    }

    fn accumulates(&mut self, stop: usize, time: f64, until: f64) {
        self.0.accumulates(stop, time, until);
        self.1.accumulates(stop, time, until);
    }

    fn named_event(&mut self, time: f64, kind: EventKind, y: &DVector<f64>) {
        self.0.named_event(time, kind, y);
        self.1.named_event(time, kind, y);
    }

    fn sample(&mut self, time: f64, y: &DVector<f64>) {
        self.0.sample(time, y);
        self.1.sample(time, y);
    }

    fn wants_segments(&self) -> bool {
        self.0.wants_segments() || self.1.wants_segments()
    }

    fn segment(&mut self, segment: &mut Segment<'_>) {
        if self.0.wants_segments() {
            self.0.segment(segment);
        }
        if self.1.wants_segments() {
            self.1.segment(segment);
        }
    }
}

/// What happened during one forcing period.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodRecord {
    /// Impacts per stop (for a soft stop: contacts begun).
    pub impacts: Vec<u32>,
    /// Stops that held their mass at some time during the period, and soft
    /// stops whose gap stayed closed through the whole period (bit mask).
    pub(crate) held: u32,
    /// Friction contacts stuck at some time during the period (bit mask).
    pub(crate) stuck: u32,
    /// Full state at the end of the period (the period-section point).
    pub end: DVector<f64>,
    /// Mode (held stops, friction states) at the end of the period.
    pub(crate) end_key: Key,
    /// Events handled during the period (impacts, sticks, releases, friction
    /// events): none means the period was one linear flow.
    pub(crate) events: usize,
    /// State at the middle of the period, when asked for.
    pub half: Option<DVector<f64>>,
    /// Tangent map at the middle of the period, when asked for and tracked.
    pub(crate) half_tangent: Option<DMatrix<f64>>,
}

/// Where a simulation is at the end of a period: with its count of periods
/// (the absolute time a chattering stop's impacts are timed by), all that
/// its next periods depend on ([`Simulator::moment`], [`Simulator::resume`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Moment {
    /// Full state `[x; v]`.
    y: DVector<f64>,
    /// The mode: held stops and friction states.
    key: Key,
    /// Time within the current period.
    clock: f64,
    /// The last impacts at each stop, by which chatter is told.
    chatter: ChatterTracker,
    /// Events in a row without time passing.
    zero_steps: usize,
}

/// Why a simulation stopped before its end.
#[derive(Debug, Clone, PartialEq)]
pub enum Halt {
    /// The event budget ran out (runaway chatter, a too long run, or RK4's
    /// steps, which count against it: a creeping event refinement).
    Budget,
    /// An event search made no progress (a degenerate contact).
    Stalled,
    /// The system cannot be simulated.
    Error(SolverError),
}

impl std::fmt::Display for Halt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Halt::Budget => write!(f, "the event budget (max_events) ran out"),
            Halt::Stalled => write!(f, "event location stalled at a degenerate contact"),
            Halt::Error(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for Halt {}

impl From<SolverError> for Halt {
    fn from(e: SolverError) -> Self {
        Halt::Error(e)
    }
}

/// Buffers of the event loop, reused from event to event.
#[derive(Debug, Clone, Default)]
struct Buffers {
    /// Augmented state at the start of an advance.
    start: DVector<f64>,
    /// Augmented state where an advance stopped.
    end: DVector<f64>,
    /// Full state before an impact.
    before: DVector<f64>,
    /// Times within a period at which an advance stops.
    targets: Vec<f64>,
    /// Stops in contact at an impact.
    contacts: Vec<usize>,
    /// Impacts of one contact event.
    hits: Vec<impact::Hit>,
    /// Augmented and full state at a sample taken inside an advance.
    sample: (DVector<f64>, DVector<f64>),
    /// Augmented state of a segment's closed form ([`Segment::state`]).
    segment: DVector<f64>,
    /// The tangent's update: the flow's factors, its transition over a
    /// segment (lent to a [`Saltation`] across an event), and two products.
    factors: Vec<C64>,
    flow: DMatrix<f64>,
    product: DMatrix<f64>,
    next: DMatrix<f64>,
    /// The saltation matrix's parts, across events.
    salt: SaltBuffers,
}

/// What [`Saltation`] and [`Simulator::saltate`] compute an event's saltation
/// matrix in (no allocation per event once sized): the vector field before
/// and after, the guard's gradient, the jump, its products and the impulse
/// Jacobians of the scene's stops (each the same at every impact with the
/// same restitution).
#[derive(Debug, Clone, Default)]
struct SaltBuffers {
    projected: DVector<f64>,
    field: DVector<f64>,
    f_before: DVector<f64>,
    f_after: DVector<f64>,
    moved: DVector<f64>,
    grad: DVector<f64>,
    slope: RowDVector<f64>,
    jump: DMatrix<f64>,
    spare: DMatrix<f64>,
    impulses: Vec<(usize, u64, DMatrix<f64>)>,
}

/// `out = a b` in `out`'s storage (sized as needed: no allocation once
/// sized), bit for bit `a * b`: nalgebra's product is this same `gemm`
/// with `α = 1`, `β = 0`.
fn multiply(a: &DMatrix<f64>, b: &DMatrix<f64>, out: &mut DMatrix<f64>) {
    if out.shape() != (a.nrows(), b.ncols()) {
        *out = DMatrix::zeros(a.nrows(), b.ncols());
    }
    out.gemm(1.0, a, b, 0.0);
}

/// `out = v` in `out`'s storage where it has `v`'s length (nalgebra's
/// `clone_from` is a new clone).
fn assign(out: &mut DVector<f64>, v: &DVector<f64>) {
    if out.len() == v.len() {
        out.copy_from(v);
    } else {
        *out = v.clone();
    }
}

/// `out = a v` in `out`'s storage, bit for bit `a * v` (the same `gemm`).
pub(crate) fn apply(a: &DMatrix<f64>, v: &DVector<f64>, out: &mut DVector<f64>) {
    if out.len() != a.nrows() {
        *out = DVector::zeros(a.nrows());
    }
    out.gemm(1.0, a, v, 0.0);
}

/// What the saltation matrix of an event needs from before it, in full
/// coordinates: the flow transition to the event, the vector field `f⁻`, the
/// guard's gradient `∇h` and its rate `ḣ`.
struct Saltation {
    flow: DMatrix<f64>,
    f_before: DVector<f64>,
    grad: DVector<f64>,
    rate: f64,
}

impl Saltation {
    /// At the event of guard `g` of `mode`, reached at augmented state
    /// `state`, with the flow's transition to it in `flow` (the buffer lent).
    fn before(mode: &Mode, g: usize, state: &DVector<f64>, flow: DMatrix<f64>, b: &mut SaltBuffers) -> Saltation {
        apply(&mode.aug, state, &mut b.field);
        let (mut f_before, mut grad) = (std::mem::take(&mut b.f_before), std::mem::take(&mut b.grad));
        apply(mode.lift_matrix(), &b.field, &mut f_before);
        let gradient = mode.guard_gradient(g);
        if grad.len() != gradient.len() {
            grad = DVector::zeros(gradient.len());
        }
        grad.copy_from(gradient);
        Saltation { flow, f_before, grad, rate: mode.guards[g].row.dot(&b.field) }
    }
}

/// The transition of `mode`'s flow over a segment of duration `h` just
/// flown, into `flow`: from the factors its exact advance ended with, kept
/// in `work`, else computed into `f` (the same numbers, bit for bit).
fn transition(mode: &Mode, work: &Workspace, h: f64, f: &mut Vec<C64>, flow: &mut DMatrix<f64>) {
    match work.factors_at(h) {
        Some(kept) => mode.transition_of(kept, flow),
        None => mode.transition_into(h, f, flow),
    }
}

/// The budget of a new simulation, in thousandths of an event: `max_events`
/// events.
fn full_budget(acc: &Accuracy) -> u64 {
    (acc.max_events as u64).saturating_mul(EVENT_WORK)
}

/// How far from a whole number of turns, and from no growth, a term of a
/// flow may be over a span that [`Simulator::closes_after`] closes: rounding
/// of the phases (1e-16 relative) over the spans of a long orbit.
const CLOSURE: f64 = 1e-12;

/// The size of a flow's term coefficient ([`crate::spectral::Modal::magnitudes`])
/// up to which the state `start` does not excite the term: rounding of the
/// state's largest entry (a free mass at rest leaves its drift unexcited).
fn excited(start: &DVector<f64>) -> f64 {
    1e-12 * (1.0 + start.amax())
}

/// A running simulation of one cell.
#[derive(Debug, Clone)]
pub struct Simulator<'s> {
    sys: &'s System,
    acc: Accuracy,
    method: Method,
    cache: ModeCache,
    work: Workspace,
    chatter: ChatterTracker,
    /// Full state `[x; v]`.
    y: DVector<f64>,
    /// The current mode: held stops and friction states.
    key: Key,
    /// Time within the current period.
    clock: f64,
    /// Completed periods.
    periods: u64,
    /// Events handled so far.
    events: usize,
    /// What the integrator's steps cost of the budget so far (RK4's; the
    /// exact flow's are free), in thousandths of an event.
    step_work: u64,
    /// The budget: the simulation halts once its events (each
    /// [`EVENT_WORK`]) and its steps cost more than this, in thousandths of an
    /// event (`max_events` events unless set by [`Simulator::set_budget`]).
    budget: u64,
    zero_steps: usize,
    /// Impulses applied while handling the current event.
    applied: Vec<(usize, f64)>,
    /// Reused buffers of the event loop (no allocation per event once warm).
    buffers: Buffers,
    /// Tangent map `∂y(t)/∂y(0)` since the last restart, when tracked.
    tangent: Option<DMatrix<f64>>,
    /// A record its owner is done with ([`Simulator::recycle`]), whose
    /// buffers the next period's record reuses.
    spare: Option<PeriodRecord>,
}

impl<'s> Simulator<'s> {
    /// Starts at full state `y0` at `t = 0`; stops in contact at rest are held.
    pub fn new(sys: &'s System, acc: Accuracy, method: Method, y0: &[f64]) -> Result<Self, Halt> {
        let mut sim = Simulator {
            sys,
            acc,
            method,
            cache: ModeCache::default(),
            work: Workspace::default(),
            chatter: ChatterTracker::new(sys.stops.len()),
            y: DVector::zeros(y0.len()),
            key: Key::FREE,
            clock: 0.0,
            periods: 0,
            events: 0,
            step_work: 0,
            budget: full_budget(&acc),
            zero_steps: 0,
            applied: Vec::new(),
            buffers: Buffers::default(),
            tangent: None,
            spare: None,
        };
        sim.restart(y0)?;
        Ok(sim)
    }

    /// Starts again at `y0` as [`Simulator::new`] would, keeping the modes
    /// built so far: counters and budget as new, the tangent map not tracked.
    pub fn reset(&mut self, y0: &[f64]) -> Result<(), Halt> {
        (self.periods, self.events, self.step_work) = (0, 0, 0);
        self.budget = full_budget(&self.acc);
        self.applied.clear();
        self.tangent = None;
        self.restart(y0)
    }

    /// The integrator.
    pub fn method(&self) -> Method {
        self.method
    }

    /// A copy sharing nothing but the built modes, with zeroed counters (for
    /// Newton probes; their budget is set with [`Simulator::set_budget`]).
    /// Its scratch buffers start empty, as a new simulation's do: each is
    /// sized where it is used and holds nothing from one event to the next.
    pub(crate) fn probe(&self) -> Self {
        Simulator {
            sys: self.sys,
            acc: self.acc,
            method: self.method,
            cache: self.cache.clone(),
            work: Workspace::default(),
            chatter: self.chatter.clone(),
            y: self.y.clone(),
            key: self.key,
            clock: self.clock,
            periods: 0,
            events: 0,
            step_work: 0,
            budget: self.budget,
            zero_steps: self.zero_steps,
            applied: Vec::new(),
            buffers: Buffers::default(),
            tangent: self.tangent.clone(),
            spare: None,
        }
    }

    /// A [`Simulator::probe`] whose clock goes on from this simulation's
    /// periods rather than from 0: its absolute times, which time a
    /// chattering stop's impacts, are this simulation's, so that the periods
    /// it simulates are those this simulation would.
    pub(crate) fn probe_in_time(&self) -> Self {
        Simulator { periods: self.periods, ..self.probe() }
    }

    /// Takes back a period's record that its owner is done with: the next
    /// period's record reuses its buffers (no allocation per period).
    pub(crate) fn recycle(&mut self, rec: PeriodRecord) {
        self.spare = Some(rec);
    }

    /// Sets the budget, in thousandths of an event: the simulation halts once
    /// its [`Simulator::work`] is more than this.
    pub(crate) fn set_budget(&mut self, budget: u64) {
        self.budget = budget;
    }

    /// Whether a period that handles `events` more events stays within the
    /// budget: the simulation would not halt on it.
    pub(crate) fn fits(&self, events: usize) -> bool {
        self.work().saturating_add((events as u64).saturating_mul(EVENT_WORK)) <= self.budget
    }

    /// Counts as this simulation's own a period that a probe simulated from
    /// its state ([`Simulator::resume`]): one period, and its events.
    pub(crate) fn count_period(&mut self, rec: &PeriodRecord) {
        self.count_periods(1, rec.events);
    }

    /// Counts as this simulation's own `periods` periods with `events`
    /// events that a probe simulated from its state ([`Simulator::resume`]).
    pub(crate) fn count_periods(&mut self, periods: u64, events: usize) {
        self.periods += periods;
        self.events += events;
    }

    /// Where this simulation is: with its count of periods, all that its
    /// next periods depend on.
    pub(crate) fn moment(&self) -> Moment {
        Moment {
            y: self.y.clone(),
            key: self.key,
            clock: self.clock,
            chatter: self.chatter.clone(),
            zero_steps: self.zero_steps,
        }
    }

    /// Goes on from `moment`, where a probe of this simulation (exact flow,
    /// at this simulation's time: [`Simulator::probe_in_time`]) got to over
    /// the periods since counted here ([`Simulator::count_period`]), as
    /// simulating them here would have left it where this simulation runs
    /// whole periods as the probe did: the flow's steps depend on the state,
    /// the mode and the clock alone (a record that stops at half periods
    /// too, in a symmetric scene, would differ from it by rounding). The
    /// modes the probe built (`ahead`'s) are this simulation's too.
    pub(crate) fn resume(&mut self, moment: Moment, ahead: &mut Simulator<'s>) {
        let Moment { y, key, clock, chatter, zero_steps } = moment;
        (self.y, self.key, self.clock, self.chatter, self.zero_steps) = (y, key, clock, chatter, zero_steps);
        std::mem::swap(&mut self.cache, &mut ahead.cache);
    }

    /// What the simulation has cost of its budget, in thousandths of an event:
    /// its events and the integrator's steps (RK4's, `flow::rk4`).
    pub(crate) fn work(&self) -> u64 {
        (self.events as u64).saturating_mul(EVENT_WORK).saturating_add(self.step_work)
    }

    /// The full state `[x; v]`.
    pub fn state(&self) -> &DVector<f64> {
        &self.y
    }

    /// Completed forcing periods.
    pub fn periods(&self) -> u64 {
        self.periods
    }

    /// Events handled so far.
    pub fn events(&self) -> usize {
        self.events
    }

    /// Tracks the tangent map `∂y(t)/∂y(0)` from now on (from the identity at
    /// every restart): the state-transition matrix `L e^{Â h} P` of each flow
    /// segment and the saltation matrix of each event,
    /// `S = J + (f⁺ - J f⁻) ∇hᵀ / ḣ`, with `J` the Jacobian of the reset (impulses,
    /// projection onto new constraints), `f∓` the vector fields before and after
    /// and `h` the event's guard. Exact except at grazing (`ḣ = 0`, where the map
    /// is not differentiable; the jump is then taken alone) and at a chatter
    /// sequence's accumulation point.
    pub fn track_tangent(&mut self) {
        self.tangent = Some(DMatrix::identity(self.y.len(), self.y.len()));
    }

    /// Stops tracking the tangent map (a run that needs only states pays for
    /// none of its matrices).
    pub(crate) fn untrack_tangent(&mut self) {
        self.tangent = None;
    }

    /// Restarts the tracked tangent map from the identity at the current state.
    pub fn reset_tangent(&mut self) {
        if let Some(t) = self.tangent.as_mut() {
            t.fill_with_identity();
        }
    }

    /// The forcing period `T`.
    pub fn period(&self) -> f64 {
        self.sys.period
    }

    /// The system simulated.
    pub fn system(&self) -> &'s System {
        self.sys
    }

    /// The tangent map since the last restart, when tracked.
    pub fn tangent(&self) -> Option<&DMatrix<f64>> {
        self.tangent.as_ref()
    }

    /// Restarts from full state `y0` at `t = 0` (counters and built modes are kept).
    pub fn restart(&mut self, y0: &[f64]) -> Result<(), Halt> {
        if let Some(t) = self.tangent.as_mut() {
            t.fill_with_identity();
        }
        self.y = DVector::from_column_slice(y0);
        self.clock = 0.0;
        self.zero_steps = 0;
        self.chatter = ChatterTracker::new(self.sys.stops.len());
        let cand = candidates(self.sys, &self.acc, &self.y);
        let phase = self.phase();
        let (pressed, parting) = soft::contacts(self.sys, &self.acc, &self.y);
        let soft = Key { pressed, parting, ..Key::FREE };
        self.key = settle(self.sys, &self.acc, &mut self.cache, &self.y, phase, cand, 0, soft, false)?;
        self.snap()
    }

    /// The least margin by which every guard of the current mode stays off
    /// zero along the mode's flow from the current state, for all later time
    /// (the guards' own zero tolerances taken off): positive means no event
    /// ever ends the flow, so that it is the motion forever. A guard is
    /// `g(u) = Σ_t Re(w_t e^{λ_t u} β_t)` over the flow's terms (its
    /// eigenvalues λ, the forcing harmonics' included); where no term grows
    /// (no secular power, Re λ at most rounding of |λ|), `g(u)` is at least
    /// its constant part less `Σ w_t |β_t|` of the others, the least it can
    /// reach when their phases are independent. `None` where a term the
    /// state excites may grow (a drifting rigid mode, a negative damping),
    /// or the mode could not be built; a free mass at rest excites no drift.
    pub(crate) fn guard_margin(&mut self) -> Option<f64> {
        let acc = self.acc;
        let (mode, start, modal) = self.modal_start()?;
        let terms = mode.spectral.terms();
        let excited = excited(&start);
        let bounded = |(t, size): (&crate::spectral::Term, f64)| {
            t.constant || size <= excited || (t.power == 0 && t.lambda.re <= 1e-12 * t.lambda.norm())
        };
        if !terms.iter().zip(modal.magnitudes()).all(bounded) {
            return None;
        }
        let magnitudes = start.abs();
        let mut beta = vec![C64::new(0.0, 0.0); terms.len()];
        let margin = mode.guards.iter().map(|g| {
            modal.functional_into(&g.entries, &mut beta);
            let (constant, varying) = terms.iter().zip(&beta).fold((0.0, 0.0), |(c, v), (t, b)| match t.constant {
                true => (c + t.weight * b.re, v),
                false => (c, v + t.weight * b.norm()),
            });
            let tol = crate::flow::value_tol(&acc, g.kind.is_gap(), g.row_abs.dot(&magnitudes));
            constant - varying - tol
        });
        Some(margin.fold(f64::INFINITY, f64::min))
    }

    /// Whether the current mode's flow from the current state comes back to
    /// it after `span` exactly: every term the state excites neither grows
    /// nor decays over it and turns by a whole number of turns, within
    /// [`CLOSURE`] (the forcing harmonics' always do over whole periods; a
    /// free oscillation's where its frequency is commensurate).
    pub(crate) fn closes_after(&mut self, span: f64) -> bool {
        let Some((mode, start, modal)) = self.modal_start() else {
            return false;
        };
        let excited = excited(&start);
        // Bound before it is returned: the terms' iterator borrows `modal`.
        let closes = mode.spectral.terms().iter().zip(modal.magnitudes()).all(|(t, size)| {
            let turns = t.lambda.im * span / std::f64::consts::TAU;
            t.constant
                || size <= excited
                || (t.power == 0 && (t.lambda.re * span).abs() <= CLOSURE && (turns - turns.round()).abs() <= CLOSURE)
        });
        closes
    }

    /// How fast each free stop's gap changes along the current mode's flow
    /// from here by drift alone, per unit time: the secular part of its
    /// guard, `Re(w ν β)` of a rigid mode's term `ν u` (a free mass's
    /// velocity), by stop index; 0 where nothing drifts, whatever the
    /// oscillations beside it do. `None` where the mode cannot be built.
    pub(crate) fn gap_drifts(&mut self) -> Option<Vec<(usize, f64)>> {
        let (mode, _, modal) = self.modal_start()?;
        let terms = mode.spectral.terms();
        let mut beta = vec![C64::new(0.0, 0.0); terms.len()];
        let gaps = mode.guards.iter().filter(|g| g.kind == GuardKind::Gap);
        let drifts = gaps.map(|g| {
            modal.functional_into(&g.entries, &mut beta);
            let rate = terms.iter().zip(&beta).filter_map(|(t, b)| t.drift().map(|w| w * b.re)).sum();
            (g.target.index(), rate)
        });
        Some(drifts.collect())
    }

    /// The current mode, the augmented state it starts from here, and that
    /// state's modal coefficients. `None` where the mode cannot be built.
    fn modal_start(&mut self) -> Option<(&Mode, DVector<f64>, crate::spectral::Modal)> {
        let phase = self.phase();
        let mode = self.cache.get(self.sys, self.key).ok()??;
        let start = mode.project(&self.y, phase);
        let modal = mode.spectral.modal(&start);
        Some((mode, start, modal))
    }

    fn phase(&self) -> f64 {
        self.sys.omega * self.clock + self.sys.tau
    }

    /// Absolute time.
    pub fn time(&self) -> f64 {
        self.periods as f64 * self.sys.period + self.clock
    }

    /// Projects the state onto the constraints of held stops and stuck contacts.
    fn snap(&mut self) -> Result<(), Halt> {
        if self.key.constrained() {
            let phase = self.phase();
            let mode = self.cache.get(self.sys, self.key)?.ok_or(Halt::Stalled)?;
            let start = &mut self.buffers.start;
            mode.project_into(&self.y, phase, start);
            mode.lift_into(start, &mut self.y);
        }
        Ok(())
    }

    /// Simulates one forcing period. `samples` are extra times within the period
    /// (ascending, in `(0, T)`) at which the observer gets the state; with `half`
    /// the record keeps the state at `T/2`.
    pub fn run_period(
        &mut self,
        samples: &[f64],
        half: bool,
        obs: &mut dyn EventObserver,
    ) -> Result<PeriodRecord, Halt> {
        let period = self.sys.period;
        let mut rec = self.new_record();
        let mut targets = std::mem::take(&mut self.buffers.targets);
        targets.clear();
        targets.extend(samples.iter().copied().filter(|&t| t > self.clock && t < period));
        if half && self.clock < period / 2.0 {
            targets.push(period / 2.0);
        }
        targets.sort_by(f64::total_cmp);
        targets.dedup();
        targets.push(period);
        let result = self.run_to_targets(&targets, &[], half, &mut rec, obs);
        self.buffers.targets = targets;
        result?;
        self.end_period(rec, obs)
    }

    /// [`Simulator::run_period`] without a half-period state, with the
    /// observer's `samples` (strictly ascending times within the period; those
    /// not after the current time or not before `T` are skipped) taken inside
    /// each flow segment from its closed form rather than by stopping there:
    /// the trajectory is, bit for bit, that of a period without samples, and a
    /// sample costs one evaluation of the flow instead of an advance. A sample
    /// at the time of an event gets the state after it. With RK4, whose
    /// segments have no closed form, the steps stop at the samples as in
    /// [`Simulator::run_period`].
    pub(crate) fn run_period_sampled(
        &mut self,
        samples: &[f64],
        obs: &mut dyn EventObserver,
    ) -> Result<PeriodRecord, Halt> {
        debug_assert!(samples.windows(2).all(|w| w[0] < w[1]), "samples must be strictly ascending");
        if self.method != Method::Exact {
            return self.run_period(samples, false, obs);
        }
        let mut rec = self.new_record();
        let period = [self.sys.period];
        self.run_to_targets(&period, samples, false, &mut rec, obs)?;
        self.end_period(rec, obs)
    }

    /// The record of a period starting now (in a recycled record's buffers
    /// where there is one; its end state is written by `end_period`).
    fn new_record(&mut self) -> PeriodRecord {
        let (mut impacts, end) = match self.spare.take() {
            Some(spare) => (spare.impacts, spare.end),
            None => (Vec::new(), DVector::zeros(0)),
        };
        impacts.clear();
        impacts.resize(self.sys.stops.len(), 0);
        PeriodRecord {
            impacts,
            held: self.key.held | self.key.pressed | self.key.parting,
            stuck: self.key.stuck,
            end,
            end_key: Key::FREE,
            // The count at the period's start, made the period's own by `end_period`.
            events: self.events,
            half: None,
            half_tangent: None,
        }
    }

    /// Closes the period just simulated: the clock restarts, the record gets
    /// the end state, the observer its sample at the period's end.
    /// A state that is no longer finite (an overflow) halts the simulation.
    fn end_period(&mut self, mut rec: PeriodRecord, obs: &mut dyn EventObserver) -> Result<PeriodRecord, Halt> {
        if let Some(v) = self.y.iter().find(|v| !v.is_finite()) {
            return Err(Halt::Error(SolverError::OutOfRange {
                message: format!("the state became {v} after {} periods (an overflow)", self.periods),
            }));
        }
        self.clock = 0.0;
        self.periods += 1;
        assign(&mut rec.end, &self.y);
        rec.end_key = self.key;
        rec.events = self.events - rec.events;
        obs.sample(self.time(), &self.y);
        Ok(rec)
    }

    /// Simulates from the current time through the ascending `targets` of this
    /// period (the last is the period's end), recording into `rec`. The
    /// strictly ascending `inside` times of the period after the current time
    /// are sampled from the closed form of the segment they fall in; `inside`
    /// must be empty unless the flow is exact.
    fn run_to_targets(
        &mut self,
        targets: &[f64],
        inside: &[f64],
        half: bool,
        rec: &mut PeriodRecord,
        obs: &mut dyn EventObserver,
    ) -> Result<(), Halt> {
        let sys = self.sys;
        let period = sys.period;
        let mut ti = 0;
        debug_assert!(inside.is_empty() || self.method == Method::Exact);
        let mut si = inside.partition_point(|&t| t <= self.clock);
        while ti < targets.len() {
            let target = targets[ti];
            let phase = self.phase();
            let allowance = self.budget.saturating_sub(self.work());
            let mode = self.cache.get(sys, self.key)?.ok_or(Halt::Stalled)?;
            let b = &mut self.buffers;
            mode.project_into(&self.y, phase, &mut b.start);
            let (advance, cost) = self.method.advance(
                mode,
                &b.start,
                target - self.clock,
                &self.acc,
                allowance,
                &mut self.work,
                &mut b.end,
            );
            self.step_work += cost;
            // The samples inside the segment just flown, before its end.
            let end = match advance {
                Advance::Horizon => target,
                Advance::Event { time, .. } => self.clock + time,
                Advance::Stalled | Advance::Budget => self.clock,
            };
            if obs.wants_segments() && self.method == Method::Exact && end > self.clock {
                if b.segment.len() != b.start.len() {
                    b.segment = DVector::zeros(b.start.len());
                }
                obs.segment(&mut Segment {
                    periods: self.periods,
                    clock: self.clock,
                    span: end - self.clock,
                    held: self.key.held,
                    stuck: self.key.stuck,
                    pressed: self.key.pressed,
                    parting: self.key.parting,
                    mode,
                    work: &mut self.work,
                    scratch: &mut b.segment,
                    full: self.y.len(),
                });
            }
            let here = si + inside[si..].partition_point(|&t| t < end);
            let (s, y) = &mut b.sample;
            if here > si && (s.len(), y.len()) != (b.start.len(), self.y.len()) {
                (*s, *y) = (DVector::zeros(b.start.len()), DVector::zeros(self.y.len()));
            }
            for &t in &inside[si..here] {
                self.work.state_at(mode, t - self.clock, s);
                mode.lift_into(s, y);
                obs.sample(self.periods as f64 * period + t, y);
            }
            si = here;
            match advance {
                Advance::Horizon => {
                    if let Some(t) = self.tangent.as_mut() {
                        transition(mode, &self.work, target - self.clock, &mut b.factors, &mut b.flow);
                        multiply(&b.flow, t, &mut b.product);
                        std::mem::swap(t, &mut b.product);
                    }
                    mode.lift_into(&b.end, &mut self.y);
                    self.clock = target;
                    ti += 1;
                    // Targets are copied, never computed: compare them bit for bit.
                    if half && target.to_bits() == (period / 2.0).to_bits() {
                        rec.half = Some(self.y.clone());
                        rec.half_tangent = self.tangent.clone();
                    }
                    if target < period {
                        obs.sample(self.time(), &self.y);
                    }
                }
                Advance::Event { guard, time } => {
                    let g = &mode.guards[guard];
                    let (kind, stop) = (g.kind, g.target.index());
                    // Flow to the event, and what the saltation needs from before it.
                    let before = self.tangent.is_some().then(|| {
                        let mut flow = std::mem::take(&mut b.flow);
                        transition(mode, &self.work, time, &mut b.factors, &mut flow);
                        Saltation::before(mode, guard, &b.end, flow, &mut b.salt)
                    });
                    mode.lift_into(&b.end, &mut self.y);
                    self.clock = (self.clock + time).min(target);
                    self.count_event(time)?;
                    let was = self.key;
                    self.handle(kind, stop, rec, obs)?;
                    if let Some(before) = before {
                        self.saltate(before)?;
                    }
                    rec.held |= self.key.held;
                    rec.stuck |= self.key.stuck;
                    obs.event(self.time(), &self.y);
                    let named = self.name_event(kind, stop, was);
                    obs.named_event(self.time(), named, &self.y);
                }
                Advance::Stalled => return Err(Halt::Stalled),
                Advance::Budget => return Err(Halt::Budget),
            }
        }
        Ok(())
    }

    /// Counts an event after `time` of flow: the budget and the stall guard
    /// (more than 64 events in a row without time passing).
    fn count_event(&mut self, time: f64) -> Result<(), Halt> {
        self.events += 1;
        self.zero_steps = if time > 0.0 { 0 } else { self.zero_steps + 1 };
        if self.work() > self.budget {
            return Err(Halt::Budget);
        }
        if self.zero_steps > 64 {
            return Err(Halt::Stalled);
        }
        Ok(())
    }

    /// What the event of guard `kind` at stop or contact `stop`, just
    /// handled from mode `was`, turned out to be.
    fn name_event(&self, kind: GuardKind, stop: usize, was: Key) -> EventKind {
        let bit = 1 << stop;
        match kind {
            GuardKind::Touch if self.key.pressed & !was.pressed & bit != 0 => EventKind::Contact(stop),
            GuardKind::Touch => EventKind::Grazing(stop),
            GuardKind::Gap => match self.buffers.hits.first() {
                Some(h) => EventKind::Impact(h.stop),
                None if self.key.held & !was.held & (1 << stop) != 0 => EventKind::Stick(stop),
                None => EventKind::Grazing(stop),
            },
            GuardKind::Reaction => EventKind::Release(stop),
            GuardKind::Grip => EventKind::Breakaway(stop),
            GuardKind::Slip if self.key.stuck & !was.stuck & (1 << stop) != 0 => EventKind::FrictionStick(stop),
            GuardKind::Slip => EventKind::SlipReversal(stop),
            GuardKind::Push => EventKind::Separation(stop),
            GuardKind::Overlap => EventKind::Reopen(stop),
            GuardKind::Return => EventKind::Return(stop),
        }
    }

    /// Handles an event of soft stop `stop` ([`soft::after`]): a contact begun
    /// counts in the record as the stop's impact (reported to the observer
    /// with the state unchanged), a gap reopened clears the stop from the
    /// period's closed stops. Beside rigid stops, which stops hold is then
    /// decided again (a contact's force may press a mass onto a rigid stop
    /// or pull it off).
    fn handle_soft(
        &mut self,
        kind: GuardKind,
        stop: usize,
        rec: &mut PeriodRecord,
        obs: &mut dyn EventObserver,
    ) -> Result<(), Halt> {
        let (sys, bit) = (self.sys, 1 << stop);
        let phase = self.phase();
        soft::snap(sys, stop, &mut self.y);
        let key = soft::after(sys, &self.acc, &mut self.cache, self.key, kind, stop, &self.y, phase)?;
        let closed = |k: Key| (k.pressed | k.parting) & bit != 0;
        if !closed(self.key) && closed(key) {
            rec.impacts[stop] += 1;
            obs.impact(self.time(), stop, &self.y, &self.y);
        }
        if closed(self.key) && !closed(key) {
            rec.held &= !bit;
        }
        self.key = key;
        if sys.has_rigid_stops() {
            self.resettle(0, 0)
        } else {
            Ok(())
        }
    }

    fn handle(
        &mut self,
        kind: GuardKind,
        stop: usize,
        rec: &mut PeriodRecord,
        obs: &mut dyn EventObserver,
    ) -> Result<(), Halt> {
        let sys = self.sys;
        self.applied.clear();
        match kind {
            GuardKind::Touch | GuardKind::Push | GuardKind::Overlap | GuardKind::Return => {
                return self.handle_soft(kind, stop, rec, obs)
            }
            GuardKind::Gap => {
                let t = self.time();
                let b = &mut self.buffers;
                b.contacts.clear();
                b.contacts
                    .extend((0..sys.stops.len()).filter(|&k| {
                        k == stop || (sys.stops[k].law.impacts() && touching(sys, &self.acc, k, &self.y))
                    }));
                assign(&mut b.before, &self.y);
                // The event judged this stop's normal rate zero or closing: a rate
                // below the stick velocity, of either sign, is a plastic contact.
                if sys.gap_rate(stop, &self.y) >= -self.acc.stick_velocity {
                    impact::apply(sys, stop, 0.0, &mut self.y);
                    self.applied.push((stop, 0.0));
                }
                impact::resolve(sys, &b.contacts, self.acc.stick_velocity, &mut self.y, &mut self.applied, &mut b.hits);
                let mut accumulate = 0u32;
                for h in &b.hits {
                    rec.impacts[h.stop] += 1;
                    if let Some(until) = self.chatter.record(h.stop, t, h.speed, self.acc.chatter_velocity) {
                        accumulate |= 1 << h.stop;
                        obs.accumulates(h.stop, t, until);
                    }
                }
                if let Some(h) = b.hits.first() {
                    obs.impact(t, h.stop, &b.before, &self.y);
                }
                // The rest of a geometric chatter sequence is the sticking motion it converges to.
                for k in (0..sys.stops.len()).filter(|k| accumulate & (1 << k) != 0) {
                    impact::apply(sys, k, 0.0, &mut self.y);
                    self.applied.push((k, 0.0));
                }
            }
            GuardKind::Reaction => self.key.held &= !(1 << stop),
            GuardKind::Grip | GuardKind::Slip => {}
        }
        // A stop released by its reaction (zero and decreasing) cannot hold now,
        // nor can a contact that broke away stick at once.
        let released = if kind == GuardKind::Reaction { 1 << stop } else { 0 };
        let broke = if kind == GuardKind::Grip { 1 << stop } else { 0 };
        if sys.has_soft_stops() && !self.applied.is_empty() {
            // Impulses at rigid stops change the rates of soft contacts: a
            // contact whose force no longer pushes parts (or ends), one that
            // pushes again resumes.
            let (pressed, parting) = soft::contacts(sys, &self.acc, &self.y);
            let closed = self.key.pressed | self.key.parting;
            (self.key.pressed, self.key.parting) = (pressed & closed, parting & closed);
        }
        self.resettle(released, broke)
    }

    /// Decides which rigid stops hold and each friction contact's state
    /// after an event ([`settle`], soft stops kept as they are), except the
    /// stops `released` by it and the contacts that `broke` away, and
    /// projects the state onto the new mode's constraints.
    fn resettle(&mut self, released: u32, broke: u32) -> Result<(), Halt> {
        let sys = self.sys;
        let cand = (candidates(sys, &self.acc, &self.y) | self.key.held) & !released;
        let phase = self.phase();
        let recurring = self.zero_steps >= RECURRING;
        let key = settle(sys, &self.acc, &mut self.cache, &self.y, phase, cand, broke, self.key, recurring)?;
        for k in 0..sys.stops.len() {
            if key.held & !self.key.held & (1 << k) != 0 {
                self.chatter.reset(k);
            }
        }
        self.key = key;
        self.snap()
    }

    /// Jacobian `J` of the reset just handled, into the saltation buffers'
    /// `jump`: the impulses applied, then the projection onto the new mode's
    /// constraints.
    fn jump(&mut self) -> Result<(), Halt> {
        let dim = self.y.len();
        let b = &mut self.buffers.salt;
        if b.jump.shape() != (dim, dim) {
            b.jump = DMatrix::zeros(dim, dim);
        }
        b.jump.fill_with_identity();
        for &(k, r) in &self.applied {
            let at = match b.impulses.iter().position(|e| e.0 == k && e.1 == r.to_bits()) {
                Some(at) => at,
                None => {
                    b.impulses.push((k, r.to_bits(), impact::jacobian(self.sys, k, r)));
                    b.impulses.len() - 1
                }
            };
            multiply(&b.impulses[at].2, &b.jump, &mut b.spare);
            std::mem::swap(&mut b.jump, &mut b.spare);
        }
        if self.key.constrained() {
            let mode = self.cache.get(self.sys, self.key)?.ok_or(Halt::Stalled)?;
            multiply(mode.constraint_projection(), &b.jump, &mut b.spare);
            std::mem::swap(&mut b.jump, &mut b.spare);
        }
        Ok(())
    }

    /// Composes the tracked tangent with the flow to the event just handled and
    /// its saltation matrix `S = J + (f⁺ - J f⁻) ∇hᵀ / ḣ`, from what was taken
    /// before the event (each product the one of nalgebra's operators, in
    /// their order, into kept buffers: the same matrix bit for bit).
    fn saltate(&mut self, before: Saltation) -> Result<(), Halt> {
        let Saltation { flow, f_before, grad, rate } = before;
        self.jump()?;
        // At grazing (ḣ = 0) the map is not differentiable: keep the jump.
        if rate.abs() > 1e-12 * (1.0 + grad.amax() * f_before.amax()) {
            let phase = self.phase();
            let mode = self.cache.get(self.sys, self.key)?.ok_or(Halt::Stalled)?;
            let b = &mut self.buffers.salt;
            mode.project_into(&self.y, phase, &mut b.projected);
            apply(&mode.aug, &b.projected, &mut b.field);
            apply(mode.lift_matrix(), &b.field, &mut b.f_after);
            apply(&b.jump, &f_before, &mut b.moved);
            b.f_after -= &b.moved;
            if b.slope.len() != grad.len() {
                b.slope = RowDVector::zeros(grad.len());
            }
            for (o, g) in b.slope.iter_mut().zip(grad.iter()) {
                *o = g / rate;
            }
            // The kick (f⁺ − J f⁻) ∇hᵀ/ḣ, then S = J + kick in `jump`.
            let n = b.f_after.len();
            if b.spare.shape() != (n, n) {
                b.spare = DMatrix::zeros(n, n);
            }
            b.spare.gemm(1.0, &b.f_after, &b.slope, 0.0);
            b.spare += &b.jump;
            std::mem::swap(&mut b.jump, &mut b.spare);
        }
        let b = &mut self.buffers;
        if let Some(t) = self.tangent.as_mut() {
            multiply(&b.salt.jump, &flow, &mut b.product);
            multiply(&b.product, t, &mut b.next);
            std::mem::swap(t, &mut b.next);
        }
        (b.flow, b.salt.f_before, b.salt.grad) = (flow, f_before, grad);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{forced_oscillator, system};

    /// The least margin of a guard, against the closed form (issue 62): on
    /// the undamped single stop `x'' + x = cos ωt`, `x ≤ σ`, the motion from
    /// `(x₀, v₀)` at `t = 0` is `X cos ωt + A cos(t + θ)` with `X = 1/(1 − ω²)`
    /// and `A = |(x₀ − X, v₀)|`, whose gap `σ − x` comes as near as
    /// `σ − |X| − A` (ω irrational: the two phases independent); less the
    /// contact tolerance. Damped, the free part decays and the bound holds
    /// still. A mass held by no spring that drifts has no bound.
    #[test]
    fn the_guard_margin_is_the_closed_form_reach() {
        let acc = Accuracy::default();
        for (sigma, omega, x0, v0) in [(0.3, 6f64.sqrt(), -0.2, 0.05), (2.0, 0.7, 0.4, -0.3), (0.1, 2.5, 0.0, 0.0)] {
            let sys = system("single-stop.toml", &[("sigma", sigma), ("omega", omega)]);
            let mut sim = Simulator::new(&sys, acc, Method::Exact, &[x0, v0]).unwrap();
            let big_x = 1.0 / (1.0 - omega * omega);
            let reach = big_x.abs() + (x0 - big_x).hypot(v0);
            let margin = sim.guard_margin().unwrap();
            assert!((margin - (sigma - reach - acc.contact_tol)).abs() < 1e-12, "σ {sigma}: {margin} against {reach}");
        }
        let damped = system("single-stop.toml", &[("sigma", 4.0), ("omega", 0.7), ("zeta", 0.05)]);
        let mut sim = Simulator::new(&damped, acc, Method::Exact, &[0.4, -0.3]).unwrap();
        assert!(sim.guard_margin().is_some_and(|m| m > 0.0 && m < 4.0), "{:?}", sim.guard_margin());
        let free = system("impact-damper.toml", &[]);
        let mut sim = Simulator::new(&free, acc, Method::Exact, &[0.0, 0.0, 0.5, 0.1]).unwrap();
        assert_eq!(sim.guard_margin(), None, "a free mass drifting at 0.1 meets its wall");
        // Its gaps `δ ∓ (x2 − x1)` drift at ∓0.1 per unit time (the gap's
        // normal times the free mass's velocity), whatever the host (on its
        // spring, at 0.5) does; at rest, not at all.
        let drifts = sim.gap_drifts().unwrap();
        assert_eq!(drifts.len(), 2);
        for (k, rate) in drifts {
            let expected = free.stops[k].normal[1] * 0.1;
            assert!((expected.abs() - 0.1).abs() < 1e-15 && (rate - expected).abs() < 1e-12, "stop {k}: {rate}");
        }
        let mut rest = Simulator::new(&free, acc, Method::Exact, &[0.0, 0.0, 0.5, 0.0]).unwrap();
        assert!(rest.gap_drifts().unwrap().iter().all(|(_, rate)| rate.abs() < 1e-12));
        // The free mass at rest at x2 = 1 in a wide cavity (δ = 100) beside
        // its undamped host `x1 = X sin ωt + A cos(t + θ)`, X = 1/(1 − ω²) = −1
        // at ω = √2: the gaps `δ ∓ (x2 − x1)` come as near as
        // `δ − |x2| − |X| − A`, no drift excited.
        let omega = 2f64.sqrt();
        let wide = system("impact-damper.toml", &[("delta", 100.0), ("zeta", 0.0), ("omega", omega)]);
        let mut sim = Simulator::new(&wide, acc, Method::Exact, &[0.3, 1.0, 0.2, 0.0]).unwrap();
        let big_x = 1.0 / (1.0 - omega * omega);
        let amplitude = 0.3f64.hypot(0.2 - big_x * omega);
        let margin = sim.guard_margin().unwrap();
        let expected = 100.0 - 1.0 - big_x.abs() - amplitude - acc.contact_tol;
        assert!((margin - expected).abs() < 1e-9, "{margin} against {expected}");
    }

    /// The closure of an undamped flow, against the closed form (issue 62):
    /// on the single stop at ω = 3 the free oscillation (period 2π) turns a
    /// third of a turn each forcing period (2π/3), so that the motion closes
    /// after 3 periods, not 1 or 2; at ω = 3.0001 after none of them (its
    /// free turns 1.0000333… in 3 periods); unexcited (the start on the forced orbit,
    /// `x = X = −1/8` at rest) after one. Damped, never.
    #[test]
    fn an_undamped_flow_closes_after_commensurate_spans() {
        let acc = Accuracy::default();
        let closes = |omega: f64, zeta: f64, y0: [f64; 2], n: f64| {
            let sys = system("single-stop.toml", &[("sigma", 1.0), ("omega", omega), ("zeta", zeta)]);
            Simulator::new(&sys, acc, Method::Exact, &y0).unwrap().closes_after(n * sys.period)
        };
        let away = [-0.3, 0.1];
        assert!(closes(3.0, 0.0, away, 3.0) && closes(3.0, 0.0, away, 6.0));
        assert!(!closes(3.0, 0.0, away, 1.0) && !closes(3.0, 0.0, away, 2.0));
        assert!(!closes(3.0001, 0.0, away, 3.0));
        assert!(closes(3.0, 0.0, [-0.125, 0.0], 1.0));
        assert!(!closes(3.0, 0.01, away, 3.0));
    }

    /// Every event, named.
    #[derive(Default)]
    struct Names(Vec<EventKind>, Vec<(usize, DVector<f64>, DVector<f64>)>);
    impl EventObserver for Names {
        fn impact(&mut self, _t: f64, stop: usize, before: &DVector<f64>, after: &DVector<f64>) {
            self.1.push((stop, before.clone(), after.clone()));
        }
        fn named_event(&mut self, _t: f64, kind: EventKind, _y: &DVector<f64>) {
            self.0.push(kind);
        }
    }

    /// Every sample, with its time.
    #[derive(Default)]
    struct Samples(Vec<(f64, DVector<f64>)>);
    impl EventObserver for Samples {
        fn sample(&mut self, t: f64, y: &DVector<f64>) {
            self.0.push((t, y.clone()));
        }
    }

    /// A probe flies as its parent does, its scratch empty where the
    /// parent's is warm, and a record recycled into the next period holds
    /// what a new one would: the same periods, tangent maps included, bit for
    /// bit, in scenes with held stops, friction and a free mass.
    #[test]
    fn a_probe_and_recycled_records_fly_as_the_parent_does() {
        let scenes: [(&str, &[(&str, f64)]); 3] =
            [("multi-stop.toml", &[("omega", 1.2)]), ("dry-friction.toml", &[]), ("impact-damper.toml", &[])];
        for (scene, sets) in scenes {
            let sys = system(scene, sets);
            let y0 = sys.model.initial_state();
            let mut parent = Simulator::new(&sys, Accuracy::default(), Method::Exact, &y0).unwrap();
            for _ in 0..20 {
                parent.run_period(&[], false, &mut Ignore).unwrap();
            }
            parent.track_tangent();
            let mut probe = parent.probe();
            for k in 0..40 {
                let a = parent.run_period(&[], sys.model.symmetric, &mut Ignore).unwrap();
                let b = probe.run_period(&[], sys.model.symmetric, &mut Ignore).unwrap();
                let bits = |r: &PeriodRecord| r.end.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                assert_eq!((bits(&a), &a.impacts, a.events), (bits(&b), &b.impacts, b.events), "{scene}, period {k}");
                assert_eq!(parent.tangent(), probe.tangent(), "{scene}, period {k}");
                probe.recycle(b);
            }
            assert!(parent.events() > 0, "{scene}: no event to test");
        }
    }

    /// Without an event a period ends on the closed form of
    /// `x'' + 2ζx' + x = cos ωt` (the textbook solution from rest at x0).
    #[test]
    fn a_period_without_events_follows_the_closed_form() {
        let (zeta, omega, x0) = (0.05, 1.7, 0.3);
        let sys = system("single-stop.toml", &[("zeta", zeta), ("omega", omega), ("sigma", 100.0)]);
        let mut sim = Simulator::new(&sys, Accuracy::default(), Method::Exact, &[x0, 0.0]).unwrap();
        let rec = sim.run_period(&[], false, &mut Ignore).unwrap();
        let x = forced_oscillator(zeta, omega, x0, 0.0, sys.period);
        assert!((rec.end[0] - x).abs() < 1e-12, "{} against {x}", rec.end[0]);
        assert_eq!((rec.impacts.as_slice(), sim.events(), sim.periods()), (&[0u32][..], 0, 1));
    }

    /// Impacts follow Newton's law at the stop: the mass is on it, its speed
    /// reverses with factor r, and the events are named impacts of that stop.
    #[test]
    fn impacts_reverse_the_approach_with_the_restitution() {
        let r = 0.8;
        let sys = system("single-stop.toml", &[("r", r)]);
        let mut sim = Simulator::new(&sys, Accuracy::default(), Method::Exact, &sys.model.initial_state()).unwrap();
        let mut names = Names::default();
        for _ in 0..5 {
            sim.run_period(&[], false, &mut names).unwrap();
        }
        assert!(!names.1.is_empty());
        for (stop, before, after) in &names.1 {
            assert_eq!(*stop, 0);
            assert!(sys.gap(0, before).abs() <= 1e-10, "on the stop: gap {}", sys.gap(0, before));
            assert!((after[1] + r * before[1]).abs() <= 1e-12 * (1.0 + before[1].abs()));
        }
        assert!(names.0.iter().all(|k| *k == EventKind::Impact(0)), "{:?}", names.0);
    }

    /// The event budget halts a simulation once exceeded, and the stall
    /// guard never fires on ordinary motion.
    #[test]
    fn the_budget_halts_the_simulation() {
        let sys = system("multi-stop.toml", &[("omega", 0.33), ("delta", 0.6)]);
        let mut sim = Simulator::new(&sys, Accuracy::default(), Method::Exact, &sys.model.initial_state()).unwrap();
        sim.set_budget(20 * EVENT_WORK);
        let mut halted = None;
        for _ in 0..10 {
            if let Err(h) = sim.run_period(&[], false, &mut Ignore) {
                halted = Some(h);
                break;
            }
        }
        assert_eq!(halted, Some(Halt::Budget));
        assert_eq!(sim.events(), 21);
    }

    /// Sample times within a period reach the observer in order, and the
    /// half-period state is the state sampled at `T/2`.
    #[test]
    fn samples_and_the_half_period_state_are_taken_on_time() {
        let sys = system("single-stop.toml", &[("sigma", 100.0)]);
        let mut sim = Simulator::new(&sys, Accuracy::default(), Method::Exact, &[0.1, 0.0]).unwrap();
        let t = sys.period;
        let mut samples = Samples::default();
        let rec = sim.run_period(&[0.25 * t, 0.75 * t], true, &mut samples).unwrap();
        let times: Vec<f64> = samples.0.iter().map(|s| s.0).collect();
        assert_eq!(times, vec![0.25 * t, 0.5 * t, 0.75 * t, t]);
        assert_eq!(rec.half.as_ref(), Some(&samples.0[1].1));
        assert_eq!(rec.end, samples.0[3].1);
    }

    /// Samples taken inside the segments leave the trajectory as it is without
    /// samples, bit for bit, through impacts, held stops (multi-stop) and
    /// stuck friction contacts (dry friction), whose modes have a smaller
    /// augmented state; each is the state that stopping there gives (to
    /// rounding), and without events the closed form's.
    #[test]
    fn samples_inside_segments_leave_the_trajectory_alone() {
        let impacting = system("multi-stop.toml", &[("omega", 1.2), ("delta", 0.3)]);
        let sticking = system("dry-friction.toml", &[("fk", 0.3)]);
        for sys in [&impacting, &sticking] {
            let y0 = sys.model.initial_state();
            let times: Vec<f64> = (1..64).map(|i| sys.period * i as f64 / 64.0).collect();
            let start = || Simulator::new(sys, Accuracy::default(), Method::Exact, &y0).unwrap();
            let (mut plain, mut inside, mut stopping) = (start(), start(), start());
            let (mut got, mut want) = (Samples::default(), Samples::default());
            let mut held_or_stuck = false;
            for _ in 0..5 {
                let rec = plain.run_period(&[], false, &mut Ignore).unwrap();
                let sampled = inside.run_period_sampled(&times, &mut got).unwrap();
                stopping.run_period(&times, false, &mut want).unwrap();
                assert_eq!(sampled, rec);
                held_or_stuck |= rec.held != 0 || rec.stuck != 0;
            }
            assert_eq!(inside.events(), plain.events());
            assert!(inside.events() > 5, "{}: {} events", sys.model.name, inside.events());
            assert!(held_or_stuck, "{}: no constrained mode", sys.model.name);
            assert_eq!(got.0.len(), want.0.len());
            for ((tg, yg), (tw, yw)) in got.0.iter().zip(&want.0) {
                assert_eq!(tg.to_bits(), tw.to_bits(), "sample times");
                assert!((yg - yw).amax() <= 1e-9 * (1.0 + yw.amax()), "at t = {tg}: {yg} against {yw}");
            }
        }

        let (zeta, omega, x0) = (0.05, 1.7, 0.3);
        let free = system("single-stop.toml", &[("zeta", zeta), ("omega", omega), ("sigma", 100.0)]);
        let mut sim = Simulator::new(&free, Accuracy::default(), Method::Exact, &[x0, 0.0]).unwrap();
        let mut samples = Samples::default();
        let t = free.period;
        sim.run_period_sampled(&[0.3 * t, 0.7 * t], &mut samples).unwrap();
        for (time, y) in &samples.0 {
            let x = forced_oscillator(zeta, omega, x0, 0.0, *time);
            assert!((y[0] - x).abs() < 1e-12, "at t = {time}: {} against {x}", y[0]);
        }
        assert_eq!(samples.0.len(), 3);
    }
}
