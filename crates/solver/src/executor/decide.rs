//! Phase 2's decision: the largest Lyapunov exponent of a record without a
//! period, measured longer while it does not decide, and the torus, locked
//! and off-section tests that tell a torus from chaos ([`Executor::decide`]).

use super::quiet::closing_drift;
use super::{Executor, Reached, Steady, Unresolved};
use crate::circle::{
    folded_torus_loops, gain, on_folded_loops, on_loops, torus_loops, turns_on_torus, Rotation, MOST_LOOPS, SETTLED,
    TORUS_GAIN,
};
use crate::flow::Method;
use crate::label::Class;
use crate::lyapunov::Exponent;
use crate::simulate::{EventObserver, Halt, Simulator};
use nalgebra::DVector;

/// Periods of tangent alignment before the Lyapunov exponent is averaged.
pub(super) const LYAPUNOV_WARMUP: usize = 10;

/// Times the exponent's measurement of a cell without a period is doubled
/// while its interval contains 0, beside one more for every two of
/// `extensions` (standard: 4, to `lyapunov_periods` × 16 periods; fast: 2).
pub(super) const EXPONENT_DOUBLINGS: usize = 2;

/// Times more the exponent's measurement is doubled where it is still
/// undecided after the doublings of [`EXPONENT_DOUBLINGS`] (standard: to
/// `lyapunov_periods` × 64 periods): on the impact damper's plane most such
/// records are reaching a torus slowly, their section points already on a
/// closed curve and their rotation number converging only in the later
/// points; a record ten times longer shows the torus.
pub(super) const UNDECIDED_DOUBLINGS: usize = 2;

/// Times more, in a scene that dissipates nothing, the exponent's
/// measurement is doubled where it is still undecided after
/// [`UNDECIDED_DOUBLINGS`] and its tangent grew faster than a polynomial
/// (standard: to `lyapunov_periods` × 1 024 = 102 400 periods). Over 6 400
/// periods chaos weaker than about λT = 4e-4 gains no more than a sheared
/// torus may, and a torus's growth swings past the bound on some stretch;
/// on the lossless multi-stop (ζ = 0, R = 1) 29 of 51 such records were
/// chaotic and 14 regular over 64 000 periods. Four times longer, 19 of
/// them are shown to diverge and 15 grow no faster than a polynomial: an
/// independent simulator finds the 19 chaotic and 14 of the 15 regular,
/// the last undecided. Scenes with losses are not measured on so (their
/// undecided records are tori still being reached), but for points on a
/// torus with too few events to tell ([`SPARSE_DOUBLINGS`]). Taken
/// [`LONGER_STEP`] at a time, each time the measurement is still
/// undecided (standard: to 25 600 periods, then to 102 400): of the
/// lossless multi-stop's 8 records still undecided at 25 600 periods,
/// 5 are shown to diverge by 102 400, 2 grow no faster than a polynomial
/// and 1 is cut short by the event budget.
const LOSSLESS_DOUBLINGS: usize = 4;

/// Doublings taken at a time where a measurement is measured on past
/// [`UNDECIDED_DOUBLINGS`] ([`LOSSLESS_DOUBLINGS`], [`SPARSE_DOUBLINGS`]):
/// four times longer.
const LONGER_STEP: usize = 2;

/// Times more the exponent's measurement is doubled, in a scene that
/// dissipates, where its points lie on a torus but its last half held too
/// few events ([`TOLD_EVENTS`]) for the tangent to tell a torus from chaos
/// (standard: to 102 400 periods, [`LONGER_STEP`] at a time).
const SPARSE_DOUBLINGS: usize = 4;

/// Fewest section points per island for [`Executor::decide`] to test a
/// record whose rotation number is locked at p/q for a torus of q loops.
const ISLAND_POINTS: usize = 16;

/// The phases of the period, as fractions of it, at which
/// [`Executor::torus_off_the_section`] samples a motion whose period section
/// lies on no torus: three, so that impacts at two phases half a period
/// apart (a symmetric motion's at its two stops) leave one clear.
const OFF_SECTION: [f64; 3] = [0.25, 0.5, 0.75];

/// Periods of each sample of [`Executor::torus_off_the_section`]: twice
/// [`SETTLED`], the fewest points a torus is told by on their own.
const OFF_SECTION_PERIODS: usize = 2 * SETTLED;

/// Samples of [`OFF_SECTION_PERIODS`] that [`Executor::torus_off_the_section`]
/// takes at most, each tested with those before it.
const OFF_SECTION_ROUNDS: usize = 2;

/// What [`Executor::torus_off_the_section`] found.
pub(super) enum OffSection {
    /// The motion lies on a torus at one of [`OFF_SECTION`]'s phases.
    Torus,
    /// At none of them, over this many periods sampled.
    NoTorus { periods: usize },
    /// The probe halted (the event budget, an error) before it was told.
    Halted,
}

/// Fewest events (impacts, contacts, sticks, releases) in the last half of a
/// measurement, where it holds any, for its tangent's growth to tell a torus
/// in a scene that dissipates: two for each block of the exponent's
/// interval (a chaotic motion with rare impacts gains about 1.6 in `ln` an
/// impact on the single stop with ζ = 0, the polynomial bound 2 ln 2).
pub(super) const TOLD_EVENTS: u64 = 20;

/// Largest error of a converged rotation number, in turns per forcing period
/// (see [`Rotation`]): the section points of a torus give it to this within a
/// few hundred periods (1e-7 on smooth tori of the reference plane, 1e-5 on
/// a stick-slip torus of dry friction); those of a chaotic motion, whose
/// error falls like `K^(−1/2)`, mostly to 1e-3 or worse (on the reference
/// plane's 120 × 80 both-sweep atlas, of the chaotic records not locked at a
/// fraction, 2 of 570 came within 1e-4, at 1e-5 and 2.5e-5 over 1 600
/// periods: this alone does not tell a torus, see `turns_on_torus`).
pub(super) const ROTATION_TOL: f64 = 1e-4;

/// The loops of the torus that section points lie on, `None` for none: k
/// where every k-th of them lies on one of its k loops (k ≤ 8; 1, its
/// closed curve) with a converged rotation number ([`torus_loops`],
/// [`ROTATION_TOL`]), else 1 where their rotation number alone tells a torus
/// ([`turns_on_torus`]; `rotation` is [`Rotation::of`] the points).
pub(super) fn on_torus(rotation: Option<&Rotation>, points: &[DVector<f64>]) -> Option<usize> {
    torus_loops(points, ROTATION_TOL)
        .or_else(|| rotation.is_some_and(|r| turns_on_torus(r, points, ROTATION_TOL)).then_some(1))
}

impl<'s> Executor<'s> {
    /// Phase 2: the largest Lyapunov exponent of the motion from the main
    /// simulator's state, measured on a probe that is returned to extend it;
    /// why not when its run halts. With `keep`, the probe keeps its periods'
    /// records ([`Exponent::take_kept`]) where they are the ones the record
    /// would simulate, for a record that goes on from the same state to take
    /// ([`Executor::look_ahead`]).
    pub(super) fn exponent(&mut self, keep: bool) -> Result<(Simulator<'s>, Exponent), Halt> {
        let periods = self.acc.lyapunov_periods;
        // The probe goes on at the main simulation's time (which a
        // chattering stop's impacts are timed by); the records of its
        // periods are the record's own where it simulates as the record
        // does: the exact flow, no half periods.
        let keep = keep && !self.sys.model.symmetric && self.sim.method() == Method::Exact;
        // The records of its last periods, a window's and the period before
        // it, for a record to go on to where the motion reached a torus
        // within the measurement ([`Executor::go_on_to_torus`]).
        let last = self.acc.n_max + 1;
        let mut tangent = self.sim.probe_in_time();
        let e = self.budget.spend(&mut self.sim, &mut tangent, |t| {
            Exponent::measure_keeping(t, LYAPUNOV_WARMUP, periods, keep, last)
        })?;
        Ok((tangent, e))
    }

    /// The class of a record whose section repeated near an unstable orbit
    /// in a scene that dissipates nothing, measured on from there as a
    /// record without a period ([`Executor::decide`], with its final say):
    /// `C` or `Q` with its exponent (per unit time) where the exponent's and
    /// the torus's tests decide it; `None` where they do not, where the
    /// measurement halted, and in a scene that dissipates (the cell is then
    /// [`Unresolved::Unstable`]). Where nothing dissipates nothing attracts:
    /// a motion can stay near a weakly unstable orbit for longer than a
    /// record, and a chaotic one passes near those embedded in it. Where
    /// something does, a motion leaving an unstable orbit is a transient
    /// towards an attractor (the damper's 2-2-2 at |μ| = 1.057, beside
    /// which its cell's other samples reach 4-4-4), and a measurement
    /// started there takes the orbit's own instability for divergence.
    pub(super) fn beyond_unstable(&mut self) -> Option<(Class, f64)> {
        if !self.sys.lossless() {
            return None;
        }
        let (tangent, e) = self.exponent(false).ok()?;
        let decided = self.decide(tangent, e, true);
        // The record is over: it goes on from no measurement's end.
        self.quiet_end = None;
        match decided {
            Steady::Aperiodic(class @ (Class::Chaotic | Class::Quasiperiodic), l, None) => Some((class, l)),
            _ => None,
        }
    }

    /// The class of a record without a period from its exponent (measured on
    /// `tangent`), and the reason when it is undecided: chaotic when the
    /// interval of `λT` is above 0 and the tangent is shown to grow
    /// exponentially, not like a sheared torus's ([`Exponent::diverges`]).
    /// Otherwise the exponent is measured twice as long, `2 + extensions / 2`
    /// times (the budget of a record without a decision), and
    /// [`UNDECIDED_DOUBLINGS`] more while still undecided: it may be a torus,
    /// an orbit not yet reached (locked on a torus or not), or chaos too weak
    /// to tell. A record that contracts (the interval below 0), or is still
    /// undecided after the last doubling, is searched for a stable orbit of
    /// period up to [`LONGEST_ORBIT`](super::orbits::LONGEST_ORBIT) that its section points contract onto
    /// ([`Executor::orbit_among`]: periodic). Without one, the contracting
    /// record is a transient longer than the record, unless its points lie
    /// on a torus (then measured on) or, with `final_say` (no extension of
    /// the record left, which a transient would draw on), it approaches a
    /// stable orbit from farther ([`Executor::approached_orbit`]:
    /// periodic); the other is
    /// quasi-periodic when its section points lie on a torus
    /// ([`on_torus`]), whatever the sign of its finite-time exponent, or, in
    /// a scene that dissipates nothing, when its tangent grew no faster than
    /// a polynomial ([`Exponent::polynomial`]: a torus of any dimension),
    /// there measured four times longer at a time, up to
    /// [`LOSSLESS_DOUBLINGS`] doublings more, where it grew faster but is
    /// not shown to diverge (likewise, in a scene that dissipates, up to
    /// [`SPARSE_DOUBLINGS`] more, points on a torus whose last half held
    /// too few events to tell, [`TOLD_EVENTS`]), and unresolved otherwise,
    /// with the test that failed. In a scene without damping, a
    /// measurement that ends quiet on one linear flow that is the motion
    /// for all time (a torus clear of every stop, or a flow that closes) is
    /// that flow's: `Q`, or, where the record had events, the record goes
    /// on from the measurement's end (`quiet_end`, [`Executor::go_on_quiet`]).
    /// Where the impacts are the only loss, a record locked at p/q beyond
    /// `n_max` on a flow that closes after q periods, touching its stop at
    /// most once in each q periods of the last half without its tangent
    /// shown to grow, is that flow's too: `Q`, where no orbit is found. A
    /// record that contracts only where it stuck, its flights between the
    /// sticks beyond the precision ([`crate::Flights::beyond_precision`]),
    /// is `C`, its flights' exponent, rather than a transient.
    pub(super) fn decide(&mut self, mut tangent: Simulator<'s>, mut e: Exponent, final_say: bool) -> Steady {
        let mut doublings = 0;
        let first = EXPONENT_DOUBLINGS + self.acc.extensions / 2;
        let mut limit = first;
        // The loops of a torus that the first measurement's points lay on
        // where its tangent grew too fast for a torus's (see below).
        let mut deferred = None;
        let lossless = self.sys.lossless();
        loop {
            self.exponent_events = Some(e.events());
            let growth = e.interval();
            if e.chaotic() {
                return Steady::Aperiodic(Class::Chaotic, e.per_time(), None);
            }
            let last = doublings == limit;
            // Below 0 beyond its uncertainty: contracting, except in a scene
            // that dissipates nothing, whose map preserves volume (its
            // finite-time exponent, biased low, is about 0 there).
            let contracts = growth.high() < 0.0 && !lossless;
            if contracts || last {
                if let Some(n) = self.orbit_among(&e.points) {
                    return Steady::Periodic(n);
                }
            }
            // Contracting onto no orbit found, and not on a torus's closed
            // curve, once measured as long as an undecided record's first
            // measurement: a transient longer than the record. Before that,
            // measured on: a torus's finite-time exponent may lie below 0 for
            // a while, and its points tell a torus only once they are many
            // (issue 62: damper cells called transients over 100 points lay
            // on one closed curve).
            if contracts && last && on_torus(Rotation::of(&e.points).as_ref(), &e.points).is_none() {
                // Approaching, from farther than the search above reaches, a
                // stable orbit whose multiplier is near 1, with no extension
                // of the record left to reach it: the orbit (a node's points
                // creep along its weakest direction).
                if let Some(n) = final_say.then(|| self.approached_orbit(&e.points)).flatten() {
                    return Steady::Periodic(n);
                }
                // Contracting only where it stuck, each stick erasing the
                // tangent, while its flights between the sticks expand the
                // error of their impacts past where the next stick is
                // decided: chaos whose sticks rest on the computation's
                // error, its flights' exponent.
                if let Some(flights) = e.flights().filter(|f| f.beyond_precision(self.acc.contact_tol)) {
                    return Steady::Aperiodic(Class::Chaotic, flights.per_time(), None);
                }
                let stuck = Some(e.erased()).filter(|&k| k > 0);
                let why = Unresolved::Contracting { growth: growth.mean, stuck };
                return Steady::Aperiodic(Class::Unresolved, e.per_time(), Some(why));
            }
            if last {
                let rotation = Rotation::of(&e.points);
                // Locked at p/q (over all the points, the fraction's q
                // clearest): no torus of one loop, whose rotation number is
                // irrational; a torus of q loops (islands about an orbit of
                // period q) where every q-th point lies on one, or of a
                // multiple of q up to 8 where those points are locked again
                // (on the damper at ω = 1.03846, μ = 0.29828: locked at 1/2,
                // every second point at 1/2 too, every fourth on a loop that
                // its principal plane folds, every eighth on a closed curve).
                let locked = rotation.filter(|r| r.error <= ROTATION_TOL).and_then(|r| r.locked()).map(|(_, q)| q);
                // The motion may have reached its torus only after the first
                // points: the last half, or the last quarter, on one.
                let n = e.points.len();
                // The last `1/part` of the points, from the first of them,
                // where they are enough to tell a torus by ([`SETTLED`]).
                let tail = |part: usize| {
                    let from = n - n / part;
                    let points = &e.points[from..];
                    (points.len() >= SETTLED).then_some((from, points))
                };
                let settled =
                    |part: usize| tail(part).is_some_and(|(_, p)| on_torus(Rotation::of(p).as_ref(), p).is_some());
                // Whether the motion reached its torus within the
                // measurement: its points on one over the last half or
                // quarter only, in a scene that dissipates (where nothing
                // does, nothing attracts: a motion stays on the invariant
                // set it starts on).
                let mut within = false;
                // Where the points lie on islands over the last half or
                // quarter only: the first of those points.
                let mut islands_from = None;
                let loops = match locked {
                    None => on_torus(rotation.as_ref(), &e.points).or_else(|| {
                        let late = settled(2) || settled(4);
                        within = late && !lossless;
                        late.then_some(1)
                    }),
                    Some(q) => {
                        // The multiples once the measurement is as long as an
                        // undecided record's, after the search for an orbit
                        // there (on the main job's plane, ω = 1.07, δ = 1.94:
                        // an orbit of 968 periods locked on the torus).
                        // Loops that fold in their principal plane, where no
                        // multiple's loops are closed curves in it (the
                        // held-out chain with 2nd and 3rd harmonics at
                        // ω = 1.73846, h3 = 0.89655, up: locked at 1/2, each
                        // island's 3 200 points turning by 0.4624005770 ±
                        // 4.8e-11, their polygon 11.9 times the limit in the
                        // order of angles and 0.59 of it in the order of
                        // phases; `C` as chaos in 2 bands before, λT 3.3e-4
                        // ± 2.8e-4 over 6 400 periods, a torus for an
                        // independent simulator).
                        let most = if limit == first { q } else { MOST_LOOPS };
                        let multiples = || std::iter::once(q).chain((2 * q..=most).step_by(q));
                        let islands = |on: fn(&[DVector<f64>], usize, f64) -> bool, points: &[DVector<f64>]| {
                            multiples().find(|&k| points.len() / k >= ISLAND_POINTS && on(points, k, ROTATION_TOL))
                        };
                        // Those once measured as long as an undecided
                        // record, as the multiples; in a scene that
                        // dissipates nothing, its tangent and its rotation
                        // number decide (below).
                        let folded = limit != first && !lossless;
                        // Islands reached within the measurement, once as
                        // long as an undecided record's, where something
                        // dissipates: its last half or quarter on them (a
                        // held-out two-mass chain at ω = 1.01379, δ = 1.14211,
                        // up: a torus of 2 loops about the orbit `2-2-2`
                        // past its Neimark–Sacker bifurcation, |μ| = 1.0443,
                        // reached some 1 000 periods into the 6 400 measured;
                        // `U` before, "locked at 1/2 … no stable orbit").
                        let late = || {
                            [2, 4].into_iter().find_map(|part| {
                                tail(part).and_then(|(from, points)| islands(on_loops, points).map(|k| (k, from)))
                            })
                        };
                        islands(on_loops, &e.points)
                            .or_else(|| folded.then(|| islands(on_folded_loops, &e.points)).flatten())
                            .or_else(|| {
                                let (k, from) = folded.then(late).flatten()?;
                                within = true;
                                islands_from = Some(from);
                                Some(k)
                            })
                    }
                };
                // In a scene that dissipates, a torus's tangent stays
                // bounded: points on a torus whose tangent grew faster than
                // a polynomial over the last half of the first measurement
                // as long as an undecided record's are measured on (a thin
                // chaotic band about a torus, or a chaotic transient before
                // an orbit, on the main job's plane at ω = 1.4, δ = 1.34: λT
                // 0.019, its points on one closed curve); a torus still
                // where the longer measurement's last half grew no faster.
                let grew = if lossless { None } else { e.grew_late() };
                // The tangent of a piecewise-linear flow is stretched only at
                // its events; between them it swings within bounds. So the
                // last half's growth tells a torus only where that half held
                // no event (one linear flow) or many: over a few rare impacts
                // a chaotic motion's tangent may grow no faster than a
                // torus's by chance (the single stop with ζ = 0 at
                // ω = 1.98734, σ = 1.24576: 7 impacts in the last 800 of
                // 1 600 periods, a growth of 1.27 there against 14 over the
                // whole; chaotic for an independent simulator, λT 1.2e-2 in
                // every quarter of 100 000 periods). Such a record is
                // measured on as an undecided one, and past that four times
                // longer at a time ([`SPARSE_DOUBLINGS`]); `U` if still so
                // at the end.
                let late_events = e.late_events();
                let sparse = !lossless && late_events > 0 && late_events < TOLD_EVENTS;
                // Locked, on no islands, once measured as long as an
                // undecided record, but not locked over the last quarter,
                // whose points lie on a torus of their own number: a motion
                // still reaching a torus whose number lies near p/q, the
                // approach inflating the error over all the points (see
                // [`Rotation::locked_to_the_end`]; chaos in q bands keeps
                // its lock to the end): a torus of one loop (the impact
                // damper with ζ = 0.13 at ω = 1.57692, up: `C` before, as
                // chaos in 9 bands, λT 1.6e-4 ± 1.2e-4). Unless its points
                // spiral onto an orbit so widely that they still wind about
                // their centroid, which loses the lock too: the orbit is
                // sought first, as a contracting record's is, and the lock
                // judged only once measured as long as an undecided record
                // (the multi-stop at ω = 1.06, δ = 1.85, up: at the first
                // look locked at 1/2 over 1 600 points, not over the last
                // 400, spiralling onto the orbit `2-2-2` that it reaches).
                // In a scene that dissipates, where the last half had
                // events: without, one linear flow, whose torus attracts
                // nothing (below).
                let reached = limit != first
                    && !lossless
                    && late_events > 0
                    && locked.is_some()
                    && loops.is_none()
                    && rotation.and_then(|r| r.locked_to_the_end(&e.points, ROTATION_TOL)).is_none()
                    && settled(4);
                if reached {
                    if let Some(n) = self.approached_orbit(&e.points) {
                        return Steady::Periodic(n);
                    }
                }
                let loops = loops.or(reached.then_some(1));
                within |= reached;
                let defer = limit == first && (grew.is_some() || sparse);
                if defer {
                    deferred = loops;
                }
                // Growth kept up over both halves of the measurement is no
                // attracting torus's bounded tangent, however long measured
                // (the impact damper at ω = 1.66456, δ = 2.32203: on 8 loops
                // over 6 400 periods, its tangent grew by 3.70 over the last
                // 3 200 and 19.4 over the first; chaotic for an independent
                // simulator over 30 000 periods, it reaches an orbit of 705
                // periods after 17 384 over ten times the record). Where
                // the motion reached its islands within the measurement,
                // growth past that bound kept up over both halves of the
                // stretch on them too: the chaotic transient before them
                // grows as chaos does (the held-out chain above: 6.38 over
                // the first 3 200 periods, 1.89 over the last, against
                // 1.38; twins 1e-8 apart on its torus stay within 1.5e-7
                // over 4 000 periods for an independent simulator).
                let kept_growing = grew
                    .filter(|late| e.grew_before(late))
                    .filter(|late| islands_from.is_none_or(|from| e.kept_growing_from(from, late.bound)));
                let untold = sparse || kept_growing.is_some();
                let loops = loops.or(deferred.filter(|_| grew.is_none()));
                if let Some(k) = loops {
                    if let Some(n) = self.focus_of(&e.points, k) {
                        return Steady::Periodic(n);
                    }
                    if !defer && !untold && within {
                        return self.torus_reached_within(tangent, &mut e);
                    }
                    if !defer && !untold {
                        return Steady::Aperiodic(Class::Quasiperiodic, e.per_time(), None);
                    }
                }
                let gain = rotation.as_ref().and_then(|r| gain(r, &e.points));
                // Locked in a scene that dissipates nothing, on no islands
                // the test of q loops can see (each an arc of its loop over
                // n/q points), and not shown to diverge: no attractor to
                // reach (the map preserves volume), so a regular motion
                // where its rotation number converged as a torus's does,
                // faster than any power of the points (chaos in q bands
                // converges like 1/K at best), whatever the sign of a
                // finite-time exponent that a sheared torus's bias keeps
                // above 0. Islands about an orbit of period q, a
                // torus turning by p/q to within its error, or one whose
                // curve does not wind about the points' centroid (a
                // rotation of 0/1 about it). In a scene that dissipates, a
                // locked number is an orbit on the torus that the motion
                // should reach. Told once measured as long as an undecided
                // record is (the first measurement's 1 600 points at
                // standard do not tell a thin chaotic layer from a torus
                // beside it).
                let regular = lossless && locked.is_some() && gain.is_some_and(|g| g >= TORUS_GAIN);
                // In a scene that dissipates nothing, a tangent that grew no
                // faster than a polynomial (regular at the last doubling, below).
                let polynomial = lossless && e.polynomial();
                if regular && limit != first {
                    return Steady::Aperiodic(Class::Quasiperiodic, e.per_time(), None);
                }
                // Locked without an orbit near, not on islands, and shown to
                // expand (the exponent's interval above 0) once measured as
                // long as an undecided record: chaos in q bands, unless
                // regular so far in a scene that dissipates nothing (its
                // rotation number converged as a torus's does, or its
                // tangent grew no faster than a polynomial: measured on, see
                // below). At the first look, where the tangent is not yet
                // shown to diverge, measured on: a slow transient before an
                // orbit of period q keeps a small exponent above 0 for a
                // while (the main job's plane, down, at ω = 1.23, δ = 0.17:
                // λT 2.9e-4 ± 1.1e-4 over 1 600 periods, locked at 1/2, a
                // growth of 0.46 in all; it reaches its orbit of period 2,
                // largest multiplier 0.9975, some 3 000 periods later). An
                // interval about 0 is measured on: a torus's rotation number
                // may lie within its error of a fraction of large q (p/792
                // over 1 600 points) until more points tell.
                if limit != first
                    && locked.is_some()
                    && loops.is_none()
                    && growth.low() > 0.0
                    && !regular
                    && !polynomial
                {
                    return Steady::Aperiodic(Class::Chaotic, e.per_time(), None);
                }
                if limit == first {
                    // Still undecided: a torus still being reached, most often.
                    limit += UNDECIDED_DOUBLINGS;
                } else if polynomial {
                    // In a scene that dissipates nothing, a motion whose
                    // tangent grew no faster than a polynomial over the
                    // whole measurement, its last half and its last quarter
                    // is regular, on a torus whatever its dimension: two
                    // oscillators without losses cross the period section
                    // on surfaces, which no closed curve or rotation number
                    // about a centroid tells (the multi-stop with ζ = 0,
                    // R = 1: over 6 400 periods the tangent gains 0.57 to
                    // 0.89 over the last half, a linear growth's ln 2, and
                    // over 64 000 periods 2 ln 2 / 64 000 per period in the
                    // last half still).
                    return Steady::Aperiodic(Class::Quasiperiodic, e.per_time(), None);
                } else if lossless && limit + LONGER_STEP <= first + UNDECIDED_DOUBLINGS + LOSSLESS_DOUBLINGS {
                    // Grew faster than a polynomial, not yet shown to
                    // diverge: weak chaos or a torus's swing, which a
                    // longer measurement tells apart (one four times as
                    // long at a time).
                    limit += LONGER_STEP;
                } else if sparse
                    && loops.is_some()
                    && limit + LONGER_STEP <= first + UNDECIDED_DOUBLINGS + SPARSE_DOUBLINGS
                {
                    // On a torus's points with too few events in the last
                    // half to tell a torus's tangent from chaos's: measured
                    // on, four times longer at a time, until they are told.
                    limit += LONGER_STEP;
                } else if untold && loops.is_some() {
                    // Too few events to tell by their number, but events
                    // that stretched nothing (the tangent's growth over the
                    // last half within its resolution of 0): a torus
                    // touching its stop at a grazing speed (the single stop
                    // with r = 0.5 at ω = 1.94516, σ = 1.44783: 17 touches
                    // in the last 51 200 of 102 400 periods, λT 4e-10 ±
                    // 1e-9 there).
                    if sparse && kept_growing.is_none() && e.unstretched_late() {
                        return Steady::Aperiodic(Class::Quasiperiodic, e.per_time(), None);
                    }
                    let why = Unresolved::TorusUntold {
                        growth,
                        late: e.late(),
                        events: late_events,
                        grew: kept_growing.map(Box::new),
                    };
                    return Steady::Aperiodic(Class::Unresolved, e.per_time(), Some(why));
                } else if let Some(k) = (!untold).then(|| folded_torus_loops(&e.points, ROTATION_TOL)).flatten() {
                    // Otherwise undecided, on a curve that folds in its
                    // principal plane: the order of angles that the tests
                    // above follow zig-zags along it, the order of the
                    // points' phases does not (a three-mass chain's torus
                    // of two loops, `U` before). A focus that they spiral
                    // onto attracts only where something dissipates.
                    let attracts = !lossless && !self.undamped_linear(self.hist.len());
                    if let Some(n) = attracts.then(|| self.focus_of(&e.points, k)).flatten() {
                        return Steady::Periodic(n);
                    }
                    return Steady::Aperiodic(Class::Quasiperiodic, e.per_time(), None);
                } else {
                    // Lost at impacts alone (no damper, no friction, no
                    // dashpot), locked at p/q beyond `n_max` on a flow that
                    // closes after those q periods, touching its stop at
                    // most once in each q periods of the last half, over
                    // which the tangent is not shown to grow (neither its
                    // interval above 0 nor its growth past a polynomial's):
                    // the flow that closes after q periods, met ever more
                    // gently, each touch taking off what it met; no orbit of
                    // period up to `n_max`. Decided below, where no orbit is
                    // found (the single stop with r = 0.5 at ω = 43/26,
                    // σ = 1.41379, down: locked at 17/43, 74 touches in the
                    // last 3 200 of 6 400 periods, λT −3.5e-5 ± 5.0e-5
                    // there; an independent simulator over 40 000 periods
                    // finds touches that fade, at 4e-11 at most in the last
                    // quarter).
                    let period = self.sys.period;
                    let half = e.periods() / 2;
                    let touches_late = self.sys.loses_at_impacts_alone()
                        && locked.is_some_and(|q| {
                            q > self.acc.n_max && e.touches_sparsely(q) && tangent.closes_after(q as f64 * period)
                        });
                    // Without damping, and quiet over the measurement's last
                    // half: one linear flow from there on, for all time,
                    // where its torus clears every stop, or where its flow
                    // closes after the q periods its section points are
                    // locked at (its last half, thousands of periods, then
                    // repeats them without an event). No search for a
                    // stable orbit finds its orbits, all neutral. It is `Q`,
                    // as a quiet record's torus is, also where it closes
                    // after more than `n_max` periods; where it closes
                    // within them, the record goes on from the
                    // measurement's end ([`Executor::go_on_quiet`]), where
                    // its period is found (the single stop with r = 0.5 at
                    // ω = 1.7, σ = 1.5: impacts for some 1 000 periods,
                    // then its free oscillation turning 10 times in 17
                    // forcing periods, clear of the stop: `17-0-0`; `U`
                    // before, locked at −7/17 on no stable orbit).
                    // Quiet over the last half with a free mass drifting
                    // towards a stop at its end, damped or not: a motion
                    // crossing its cavity slowly, between impacts that will
                    // come (the impact damper at `fast` with R = 0.3,
                    // ω = 1.97692, up: no event in the 1 600 periods
                    // measured, its tangent growing like t, as a drift's
                    // does; chaotic once its mass meets the wall). The
                    // record goes on from the measurement's end too, where
                    // the drift is followed to the wall
                    // ([`Executor::follow_quiet`]).
                    let quiet = late_events == 0;
                    let (closes, linear) = match self.sys.undamped() && quiet {
                        true => {
                            // Closing at least twice within the quiet half.
                            let closes = locked.filter(|&q| 2 * q <= half && tangent.closes_after(q as f64 * period));
                            (closes, closes.is_some() || tangent.guard_margin().is_some_and(|m| m > 0.0))
                        }
                        false => (None, false),
                    };
                    // Where a torus's section may be cut (below): from
                    // where the measurement ended.
                    let off_section = (!untold && !quiet).then(|| tangent.probe_in_time());
                    let go_on = !self.quieted && !self.quiet_history();
                    let drifts = go_on && quiet && closing_drift(self.sys, &mut tangent).is_some();
                    if (linear || drifts) && go_on {
                        self.quiet_end = Some(tangent);
                    } else if linear && closes.is_none_or(|q| q > self.acc.n_max) {
                        self.closes_late |= closes.is_some();
                        return Steady::Aperiodic(Class::Quasiperiodic, e.per_time(), None);
                    }
                    // Locked at p/q, as an orbit of period q turns, in a
                    // scene that dissipates: an orbit still being reached
                    // from farther than the searches above look, its
                    // exponent about 0 while it creeps in (the soft stop at
                    // ω = 0.98354, clearance 0.27119, up: locked at −1/2,
                    // λT −4.6e-4 ± 4.9e-4 over 6 400 periods, reaches its
                    // orbit `2-2-0`, largest multiplier 0.9975, some 2 700
                    // periods after the record; the down sweep's cell is
                    // on it). Sought as for a contracting record, where the
                    // last half had events: without, it is one linear flow,
                    // whose undamped oscillation no orbit attracts.
                    if locked.is_some() && !lossless && late_events > 0 {
                        if let Some(n) = self.approached_orbit(&e.points) {
                            return Steady::Periodic(n);
                        }
                    }
                    // The flow closing beyond `n_max` that its touches leave
                    // (above): `Q`, as that flow is without an event.
                    if touches_late {
                        return Steady::Aperiodic(Class::Quasiperiodic, e.per_time(), None);
                    }
                    // On no torus at the period section, where the motion
                    // meets a stop at that phase on part of its torus: the
                    // state jumps at an impact, and the section's closed
                    // curve is cut into arcs (the impact damper with
                    // τ = 1.86207 at ω = 1.73077, δ = 2, down: its points at
                    // t = kT on three arcs, its impacts' phases and speeds on
                    // one closed curve at each wall). A torus at another
                    // phase of the period ([`Executor::torus_off_the_section`]).
                    let off_section = match off_section.map(|probe| self.torus_off_the_section(probe)) {
                        Some(OffSection::Torus) => {
                            return Steady::Aperiodic(Class::Quasiperiodic, e.per_time(), None);
                        }
                        Some(OffSection::NoTorus { periods }) => Some(periods),
                        Some(OffSection::Halted) | None => None,
                    };
                    let excess = if lossless { e.excess().map(Box::new) } else { None };
                    let why = if growth.low() > 0.0 {
                        Unresolved::Polynomial { growth, late: e.late(), rotation, gain, excess, off_section }
                    } else {
                        Unresolved::Undecided { growth, rotation, gain, lossless, excess, off_section }
                    };
                    return Steady::Aperiodic(Class::Unresolved, e.per_time(), Some(why));
                }
            }
            doublings += 1;
            let more = e.periods();
            // The window's sections are simulated after the decision: their
            // events are kept from the measurement.
            let keep = self.window_work();
            if let Err(halt) = self.budget.spend_keeping(&mut self.sim, &mut tangent, keep, |t| e.extend(t, more)) {
                self.exponent_events = Some(e.events());
                // Cut short by the event budget (a lossless motion at slow
                // forcing: 80 events a period), judged on the periods it
                // measured by the test of every doubling: chaos where it
                // is shown to diverge.
                let budget = halt == Halt::Budget;
                if budget && e.chaotic() {
                    return Steady::Aperiodic(Class::Chaotic, e.per_time(), None);
                }
                let halt = Box::new(Unresolved::of(halt, self.acc));
                let why = Unresolved::NoExponent { halt, measured: budget.then(|| e.interval()) };
                return Steady::Aperiodic(Class::Unresolved, e.per_time(), Some(why));
            }
        }
    }

    /// `Q`, with its exponent (per unit time), for a motion that reached its
    /// torus within the measurement `e` on `probe`: where the measurement
    /// ended, and the records of its last periods, are kept for the record
    /// to go on to ([`Executor::go_on_to_torus`]).
    fn torus_reached_within(&mut self, probe: Simulator<'s>, e: &mut Exponent) -> Steady {
        self.torus_reached = Some(Reached { probe, last: e.take_last() });
        Steady::Aperiodic(Class::Quasiperiodic, e.per_time(), None)
    }

    /// Whether the motion from where `probe` is, sampled at
    /// [`OFF_SECTION`]'s phases of each period (tracking no tangent), lies on
    /// a torus at one of them: its points there on one closed curve, or
    /// turning as a torus does, with a converged rotation number not locked
    /// at a fraction ([`on_torus`]). Sampled over [`OFF_SECTION_PERIODS`]
    /// periods, and where none is told, as many more, all of them tested
    /// (a torus's points may need the longer sample to close their curve,
    /// a slow drift may spoil its number over it). The rotation number is
    /// the torus's at every phase; its section curve is cut only at a phase
    /// where impacts happen on part of the torus.
    pub(super) fn torus_off_the_section(&mut self, mut probe: Simulator<'s>) -> OffSection {
        /// The states at each of [`OFF_SECTION`]'s phases, in turn.
        struct Phases {
            period: f64,
            points: [Vec<DVector<f64>>; OFF_SECTION.len()],
        }
        impl EventObserver for Phases {
            fn sample(&mut self, time: f64, y: &DVector<f64>) {
                let at = time.rem_euclid(self.period) / self.period;
                if let Some(k) = OFF_SECTION.iter().position(|&f| (at - f).abs() < 0.125) {
                    self.points[k].push(y.clone());
                }
            }
        }
        probe.untrack_tangent();
        let period = self.sys.period;
        let times = OFF_SECTION.map(|f| f * period);
        let mut phases = Phases { period, points: Default::default() };
        for _ in 0..OFF_SECTION_ROUNDS {
            let ran = self.budget.spend(&mut self.sim, &mut probe, |p| {
                (0..OFF_SECTION_PERIODS)
                    .try_for_each(|_| p.run_period_sampled(&times, &mut phases).map(|rec| p.recycle(rec)))
            });
            if ran.is_err() {
                return OffSection::Halted;
            }
            if phases.points.iter().any(|points| on_torus(Rotation::of(points).as_ref(), points).is_some()) {
                return OffSection::Torus;
            }
        }
        OffSection::NoTorus { periods: OFF_SECTION_ROUNDS * OFF_SECTION_PERIODS }
    }
}
