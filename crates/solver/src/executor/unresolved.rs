//! Why a cell is `unresolved` ([`Unresolved`]), with its numbers, and the
//! sentence that says so.

use super::decide::{LYAPUNOV_WARMUP, ROTATION_TOL, TOLD_EVENTS};
use super::quiet::DRIFT_REACH;
use crate::accuracy::Accuracy;
use crate::circle::Rotation;
use crate::error::SolverError;
use crate::lyapunov::{polynomial_growth, Interval, Stretch};
use crate::simulate::Halt;
use serde::{Deserialize, Serialize};

/// Why a cell is `unresolved`, with its numbers.
///
/// Serialised (serde) as one object whose `kind` names the variant in
/// snake case and whose other fields are the variant's, e.g.
/// `{"kind": "unsettled", "periods": 2251, "multiplier": 0.992, "distance":
/// 1.3e-7}`; a non-finite number is the text `inf`, `-inf` or `nan`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
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
        #[serde(with = "crate::number")]
        growth: f64,
        /// The measured periods in which a mass stuck to its stop, each
        /// erasing the tangent (counted as `ln` of the least double, −708,
        /// in `λT`, which they then dominate); none where no period did.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        stuck: Option<usize>,
    },
    /// No period; the exponent's confidence interval contains 0 after every
    /// doubling of its measurement, and the period section is not one closed
    /// curve: neither chaos nor a torus can be told.
    Undecided {
        /// The estimate of `λT` (growth per forcing period) and its interval.
        growth: Interval,
        /// The rotation number of the section points about their centroid,
        /// where it can be measured, and its error (not converged, or the
        /// points not on one closed curve).
        rotation: Option<Rotation>,
        /// How many times better the rotation number of all the points
        /// converged than that of their last quarter (a torus's: 10 and more).
        #[serde(default, with = "crate::number::optional")]
        gain: Option<f64>,
        /// Whether the scene dissipates nothing ([`System::lossless`](crate::system::System::lossless)), where
        /// a rotation number locked at p/q is told regular by its
        /// convergence alone (no orbit on a torus attracts); absent when
        /// false.
        #[serde(default, skip_serializing_if = "std::ops::Not::not")]
        lossless: bool,
        /// In a scene that dissipates nothing, the stretch of the
        /// measurement over which the tangent grew faster than a regular
        /// motion's may (see `Exponent::excess`); absent elsewhere.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        excess: Option<Box<Stretch>>,
        /// The forcing periods over which the motion, simulated on from the
        /// measurement's end, was sampled at a quarter, a half and three
        /// quarters of the period and lay on no torus at any of them (a
        /// torus whose period section impacts cut is told there); absent
        /// where it was not sampled (a last half of fewer than 20 events,
        /// or a probe that halted) and in files written before 2026-12-07.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        off_section: Option<usize>,
    },
    /// No period; the exponent's interval is above 0, but the tangent's
    /// growth is not shown to be exponential (see `Exponent::diverges`):
    /// over the last half of the measurement it grew by no more than a
    /// polynomial growth (a sheared torus's) could, and the section points
    /// do not lie on a torus: neither chaos nor a torus is shown.
    Polynomial {
        /// The estimate of `λT` over the whole measurement and its interval.
        growth: Interval,
        /// The same over its last half.
        late: Interval,
        /// The rotation number of the section points, where it can be measured.
        rotation: Option<Rotation>,
        /// As for [`Unresolved::Undecided`].
        #[serde(default, with = "crate::number::optional")]
        gain: Option<f64>,
        /// As for [`Unresolved::Undecided`].
        #[serde(default, skip_serializing_if = "Option::is_none")]
        excess: Option<Box<Stretch>>,
        /// As for [`Unresolved::Undecided`].
        #[serde(default, skip_serializing_if = "Option::is_none")]
        off_section: Option<usize>,
    },
    /// No period; the section points lie on a torus, in a scene that
    /// dissipates, but the tangent over the last half of the measurement
    /// does not show an attracting torus's, which stays bounded: it grew
    /// faster than a polynomial could, and over the first half too (`grew`,
    /// the last half's stretch: a thin chaotic band about a torus, or a
    /// chaotic transient before an orbit), or the half held too
    /// few events to tell (`events` fewer than 20, at least
    /// one: chaos whose tangent is stretched only at its rare impacts may
    /// grow no faster by chance) although measured four times longer at a
    /// time, up to 1 024 times `lyapunov_periods`.
    TorusUntold {
        /// The estimate of `λT` over the whole measurement and its interval.
        growth: Interval,
        /// The same over its last half.
        late: Interval,
        /// Events (impacts, contacts, sticks, releases) in that last half.
        events: u64,
        /// The tangent's growth over that half where it was more than a
        /// polynomial growth gives, as it was over the first half; absent
        /// where it was not.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        grew: Option<Box<Stretch>>,
    },
    /// No period, and the run that measures the exponent halted.
    NoExponent {
        /// Why it halted.
        halt: Box<Unresolved>,
        /// The estimate of `λT` and its interval over the periods measured
        /// before a doubling of the measurement ran out of the event budget
        /// (not shown to diverge); absent where the first measurement
        /// halted, or a doubling for another reason.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        measured: Option<Interval>,
    },
    /// No period up to `n_max`, and the motion contracts onto an orbit of a
    /// longer period (see `n_max`), which no extension of the record would
    /// find and Newton's method did not confirm (a confirmed one is a label).
    LongPeriod {
        /// The orbit's period, in forcing periods.
        n: usize,
        /// The longest period tested (`Accuracy::n_max`).
        n_max: usize,
    },
    /// The section repeated within `periodic_tol`, but the orbit's own
    /// largest Floquet multiplier modulus says that the state is still far
    /// from it: the distance still to go, `e / (1 − |μ|)` from the last step
    /// `e`, is beyond 100 × `periodic_tol`, or infinite where the map
    /// does not contract (|μ| within 1e-9 of 1: a conservative oscillation
    /// that moved too little per period to tell from a fixed point): a
    /// contraction too slow for the record, not a converged orbit
    /// (issue 42). In a scene that dissipates nothing, a neutral orbit that
    /// the motion stays on over a long record is that orbit instead (see
    /// `Executor::left_orbit`), and one it leaves says by how much (`left`).
    Unsettled {
        /// Periods of the record.
        periods: usize,
        /// The largest Floquet multiplier modulus of the period map.
        #[serde(with = "crate::number")]
        multiplier: f64,
        /// The estimated distance to the orbit, relative (infinite when |μ| ≥ 1).
        #[serde(with = "crate::number")]
        distance: f64,
        /// In a scene that dissipates nothing, where the map does not
        /// contract: how far the motion left the orbit's points when
        /// simulated on to check it (absent elsewhere, and from files
        /// written before 2026-12-05).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        left: Option<Departure>,
    },
    /// The section repeated, but the orbit is unstable (its largest Floquet
    /// multiplier modulus beyond 1.01): the record only passed near it
    /// (issue 42).
    Unstable {
        /// Periods of the record.
        periods: usize,
        /// The largest Floquet multiplier modulus of the period map.
        #[serde(with = "crate::number")]
        multiplier: f64,
    },
    /// No period, chaotic or quasi-periodic by its exponent, but not one
    /// event over the record, nor over the exponent's measurement of the
    /// periods after it: one linear flow, which is never chaotic (a
    /// positive exponent is the transient growth of a record shorter than
    /// the system's slowest motion), and whose torus (an undamped
    /// oscillation beside the forcing) attracts nothing (issue 42). Where a
    /// free mass drifts towards a stop, the record was extended to meet it
    /// while extensions remained, and the drift followed past the budget as
    /// far as 100 `max_periods` allow; `closing` and `meets` say how far it was.
    /// Where an undamped oscillation's torus reaches past a stop, the motion
    /// meets it again once the phases of its free oscillation and of the
    /// forcing come near alignment: followed there once (the motion recorded
    /// afresh after the event); `overlap` and `followed` say how far it
    /// reaches and how long it was followed without meeting the stop.
    Linear {
        /// Periods of the record without an event.
        periods: usize,
        /// The fastest closing of a stop's gap per forcing period at the
        /// record's end (a free mass drifting towards it), if any.
        #[serde(default, with = "crate::number::optional")]
        closing: Option<f64>,
        /// Forcing periods until that gap closes at that rate.
        #[serde(default, with = "crate::number::optional")]
        meets: Option<f64>,
        /// How far the torus of an undamped oscillation beside the forcing
        /// reaches past a stop (the bound of its terms beyond the gap, in
        /// the stop's length units), where it does.
        #[serde(default, skip_serializing_if = "Option::is_none", with = "crate::number::optional")]
        overlap: Option<f64>,
        /// Forcing periods that motion was followed past the record without
        /// meeting the stop, where the follow reached its end.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        followed: Option<u64>,
    },
    /// No period, and the motion leaves every stop behind without bound: no
    /// event over the last periods of the record, a rigid mode (a mass held
    /// by no spring), and every gap growing from period to period (issue 42).
    Unbounded {
        /// Periods without an event over which every gap grew.
        periods: usize,
        /// The largest growth of a position per forcing period at the end.
        #[serde(with = "crate::number")]
        drift: f64,
    },
    /// A reason known by its text alone: one read from an atlas written
    /// before reasons were stored with their numbers. The solver never
    /// gives it.
    Described {
        /// The reason as that atlas wrote it.
        text: String,
    },
}

impl Unresolved {
    pub(super) fn of(halt: Halt, acc: &Accuracy) -> Unresolved {
        match halt {
            Halt::Budget => Unresolved::Budget { max_events: acc.max_events },
            Halt::Stalled => Unresolved::Stalled,
            Halt::Error(e) => Unresolved::Failed(e),
        }
    }
}

/// How far a motion left the points of a neutral orbit of period n over
/// `periods` periods simulated on from the record's end: the largest
/// distance of a section point from the point of its phase among the last
/// n, relative to 1 + the point's size (max norm), as `periodic_tol` is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Departure {
    /// Periods simulated on.
    pub periods: usize,
    /// The largest distance, relative.
    #[serde(with = "crate::number")]
    pub distance: f64,
}

impl std::fmt::Display for Unresolved {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unresolved::Budget { max_events } => write!(f, "event budget of {max_events} events exhausted"),
            Unresolved::Stalled => write!(f, "event location stalled at a degenerate contact"),
            Unresolved::Failed(e) => write!(f, "{e}"),
            Unresolved::Contracting { growth, stuck } => {
                write!(f, "no period within the record, and the motion still contracts (λT = {growth:.3e})")?;
                match stuck {
                    None => write!(f, ": a transient longer than"),
                    Some(stuck) => write!(
                        f,
                        ", but only where it stuck to a stop: in {stuck} of the periods measured, each erasing the tangent (counted as −708); its flights between the sticks came back to no orbit within"
                    ),
                }?;
                write!(f, " max_periods x (1 + extensions)")
            }
            Unresolved::Undecided { growth, rotation, gain, lossless, excess, off_section } => {
                write!(
                    f,
                    "no period within the record; the largest Lyapunov exponent (λT = {:.3e} ± {:.1e}, 95 % over {} periods) is neither above nor below 0 beyond its uncertainty, no stable orbit was found near its section points, ",
                    growth.mean, growth.half_width, growth.periods
                )?;
                not_a_torus(f, rotation.as_ref(), *gain, *lossless)?;
                nor_off_the_section(f, *off_section)?;
                faster_than_regular(f, excess.as_deref())
            }
            Unresolved::Polynomial { growth, late, rotation, gain, excess, off_section } => {
                let (k, half) = (growth.periods, late.periods);
                write!(
                    f,
                    "no period within the record; the largest Lyapunov exponent (λT = {:.3e} ± {:.1e}, 95 % over {k} periods) is above 0, but its growth is not shown to be exponential: at least {:.2} over the {k} periods and {:.2} over the last {half} (λT = {:.3e} ± {:.1e}), no more than a sheared torus's polynomial growth may give ({:.2} and {:.2}); ",
                    growth.mean,
                    growth.half_width,
                    growth.low() * k as f64,
                    late.low() * half as f64,
                    late.mean,
                    late.half_width,
                    polynomial_growth(LYAPUNOV_WARMUP, 0, k),
                    polynomial_growth(LYAPUNOV_WARMUP, k - half, k),
                )?;
                not_a_torus(f, rotation.as_ref(), *gain, false)?;
                nor_off_the_section(f, *off_section)?;
                faster_than_regular(f, excess.as_deref())
            }
            Unresolved::TorusUntold { growth, late, events, grew } => {
                write!(
                    f,
                    "no period within the record; its section points lie on a torus, but over the last {} of the {} periods measured (λT = {:.3e} ± {:.1e}; over all of them {:.3e} ± {:.1e}) its tangent does not show an attracting torus's, which stays bounded: ",
                    late.periods, growth.periods, late.mean, late.half_width, growth.mean, growth.half_width
                )?;
                match grew {
                    Some(s) => write!(
                        f,
                        "it grew by {:.2} over them and by {:.2} over the {} before, each more than a polynomial growth gives over the last half ({:.2}): growth kept up, no bounded swing (a thin chaotic band about a torus, or a chaotic transient before an orbit)",
                        s.growth,
                        growth.mean * growth.periods as f64 - late.mean * late.periods as f64,
                        growth.periods - late.periods,
                        s.bound
                    ),
                    None => write!(
                        f,
                        "they held only {events} impacts or other events, too few for its growth to tell a torus from chaos whose tangent is stretched only at rare impacts (at least {TOLD_EVENTS} tell)"
                    ),
                }
            }
            Unresolved::LongPeriod { n, n_max } => write!(
                f,
                "no period up to n_max = {n_max}: the motion contracts onto an orbit of period {n}, which Newton's method on the {n}-period map did not confirm (raise n_max to search for it in the record)"
            ),
            Unresolved::Unstable { periods, multiplier } => write!(
                f,
                "the section repeated after {periods} periods, but near an unstable orbit (largest |multiplier| {multiplier:.6}): a transient passing it, not its motion"
            ),
            Unresolved::Unsettled { periods, multiplier, left: Some(left), .. } => write!(
                f,
                "the section repeated after {periods} periods, but the motion does not contract (largest |multiplier| {multiplier:.9}), and simulated on for {} periods it left the orbit's points by {:.1e} (relative), more than periodic_tol: a slow oscillation about the orbit, or the event tolerance's error moving the simulated motion along a neutral orbit",
                left.periods, left.distance
            ),
            Unresolved::Unsettled { periods, multiplier, distance, .. } if distance.is_infinite() => write!(
                f,
                "the section repeated after {periods} periods, but the motion does not contract (largest |multiplier| {multiplier:.9}): a free oscillation that never settles, not a converged orbit"
            ),
            Unresolved::Unsettled { periods, multiplier, distance, .. } => write!(
                f,
                "the section repeated after {periods} periods, but its orbit contracts too slowly to have reached it (largest |multiplier| {multiplier:.12}; still about {distance:.1e} from it, relative)"
            ),
            Unresolved::Linear { periods, overlap: Some(overlap), followed: Some(followed), .. } => write!(
                f,
                "no period, and no impact or other event in the last {periods} periods recorded: an undamped oscillation beside the forcing whose torus reaches {overlap:.1e} past a stop, so it meets the stop again where the phases of its free oscillation and of the forcing align, but not within the {followed} periods it was followed past the record"
            ),
            Unresolved::Linear { periods, overlap: Some(overlap), .. } => write!(
                f,
                "no period, and no impact or other event in the last {periods} periods recorded: an undamped oscillation beside the forcing whose torus reaches {overlap:.1e} past a stop, so it meets the stop again where the phases of its free oscillation and of the forcing align; the motion was followed to such an impact once already and recorded afresh, and went quiet again before its budget ended"
            ),
            Unresolved::Linear { periods, closing: Some(closing), meets: Some(meets), .. } => write!(
                f,
                "no period, and no impact or other event in the last {periods} periods recorded: a free mass drifts towards a stop, its gap closing by {closing:.1e} per period, and would meet it in about {meets:.0} more periods, beyond the record's budget and how far a drift is followed past it ({DRIFT_REACH} x max_periods periods)"
            ),
            Unresolved::Linear { periods, .. } => write!(
                f,
                "no period, but no impact or other event in the {periods} periods recorded: one linear flow, never chaotic, and its torus (an undamped oscillation beside the forcing) attracts nothing"
            ),
            Unresolved::Unbounded { periods, drift } => write!(
                f,
                "the motion is unbounded: no event in the last {periods} periods, every gap growing, a position drifting by {drift:.3e} per forcing period"
            ),
            Unresolved::NoExponent { halt, measured: None } => {
                write!(f, "no period within the record, and its largest Lyapunov exponent could not be measured: {halt}")
            }
            Unresolved::NoExponent { halt, measured: Some(growth) } => write!(
                f,
                "no period within the record, and the measurement of its largest Lyapunov exponent was cut short (λT = {:.3e} ± {:.1e}, 95 % over {} periods, not shown to diverge): {halt}",
                growth.mean, growth.half_width, growth.periods
            ),
            Unresolved::Described { text } => f.write_str(text),
        }
    }
}

/// Where the motion was sampled on at other phases of the period than the
/// section's ([`Executor::torus_off_the_section`](super::Executor::torus_off_the_section)) over `off_section`
/// periods: that it lay on no torus there either, continuing a reason.
fn nor_off_the_section(f: &mut std::fmt::Formatter<'_>, off_section: Option<usize>) -> std::fmt::Result {
    match off_section {
        Some(periods) => write!(
            f,
            "; nor do its states at a quarter, a half and three quarters of each period lie on a torus, sampled over {periods} periods simulated on from the measurement's end (a torus whose section at t = kT its impacts cut is told at those phases)"
        ),
        None => Ok(()),
    }
}

/// In a scene that dissipates nothing, the test of a regular motion that
/// failed, with its numbers (see [`Exponent::excess`](crate::lyapunov::Exponent::excess)), ending a reason.
fn faster_than_regular(f: &mut std::fmt::Formatter<'_>, excess: Option<&Stretch>) -> std::fmt::Result {
    match excess {
        Some(s) => write!(
            f,
            "; nor is it regular, as a motion of a scene that dissipates nothing is where its tangent grows no faster than a polynomial: the tangent grew by {:.2} over the last {} periods, more than such growth gives ({:.2})",
            s.growth, s.periods, s.bound
        ),
        None => Ok(()),
    }
}

/// Which test of a torus section points without a period failed, with its
/// numbers (see [`on_torus`](super::decide::on_torus)), ending a reason.
fn not_a_torus(
    f: &mut std::fmt::Formatter<'_>,
    rotation: Option<&Rotation>,
    gain: Option<f64>,
    lossless: bool,
) -> std::fmt::Result {
    let Some(r) = rotation else {
        return write!(
            f,
            "and its section points have no rotation number (too few, or on a line): not on one closed curve"
        );
    };
    let turns = format!("{:.9} ± {:.1e} turns per period over {} points", r.turns, r.error, r.points);
    match r.locked() {
        _ if r.error > ROTATION_TOL => write!(
            f,
            "and the rotation number of its section points ({turns}) has not converged within {ROTATION_TOL:.0e} (a torus's does in a few hundred periods)"
        ),
        Some((p, q)) => {
            write!(f, "and its section points turn by {turns}, locked at {p}/{q}")?;
            if !lossless {
                return write!(
                    f,
                    ", as an orbit of period {q} (or a multiple) locked on a torus turns, but no stable orbit of such a period was found near them"
                );
            }
            write!(f, ", in a scene that dissipates nothing, where a regular motion — a torus, islands about an orbit of period {q}, or a closed curve that does not wind about the points' centroid — reaches no locked orbit; but ")?;
            match gain {
                Some(g) => write!(
                    f,
                    "their rotation number converged only {g:.1} times better than over their last quarter (a regular motion's, at least 10 times)"
                ),
                None => write!(f, "over too few points (fewer than 400) to tell a regular motion by the convergence of its rotation number"),
            }
        }
        None => {
            write!(f, "and the rotation number of its section points converged ({turns}), but they lie on no closed curve of up to 8 loops, and it converged ")?;
            match gain {
                Some(g) => write!(f, "only {g:.1} times better than over their last quarter (a torus's, at least 10 times)"),
                None => write!(f, "over too few points (fewer than 400) to tell a torus's convergence by it"),
            }
        }
    }
}
