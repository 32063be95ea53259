//! The largest Lyapunov exponent of a motion.
//!
//! The tangent map of each forcing period (flow transition and saltation
//! matrices, [`Simulator::track_tangent`]) is applied to a tangent vector that
//! is renormalised every period: `λ = Σ ln|Φ_k v_{k-1}| / (K T)`. For a periodic
//! orbit this tends to `ln|μ_max| / (nT)`; it is clearly positive for chaos and
//! zero for a motion on an invariant torus (quasi-periodic impacts), whose
//! period-section points then fill a closed curve ([`crate::circle`]). The estimate carries its
//! own uncertainty ([`Exponent::interval`]), so that a motion is called chaotic
//! only when its exponent is positive beyond it.

use crate::simulate::{apply, Halt, Ignore, Moment, PeriodRecord, Simulator};
use nalgebra::DVector;
use std::collections::VecDeque;

/// Blocks the measured periods are split into for the exponent's uncertainty.
const BLOCKS: usize = 10;

/// Student's t at 97.5 % for `BLOCKS - 1` degrees of freedom: the half-width
/// of the two-sided 95 % interval of a mean of `BLOCKS` block means, in their
/// standard errors.
const T_975_9: f64 = 2.262;

/// Highest degree of the polynomial growth a regular motion's tangent may
/// show: on a sheared torus (an undamped oscillation whose frequency depends
/// on its amplitude, the free mass of a lossless impact pair) neighbouring
/// motions turn at different rates and separate like `t`; a degree more is
/// kept in hand. [`Exponent::diverges`] asks more of chaos than such growth
/// can give.
const POLYNOMIAL_DEGREE: f64 = 2.0;

/// The growth of a period whose tangent map is zero (a stuck contact erased
/// every perturbation, where the exponent is -∞): `ln` of the least positive
/// double, about -708.
const ERASED: f64 = -708.3964185322641;

/// Whether a period's growth is [`ERASED`]'s: its tangent map was zero.
fn is_erased(growth: &f64) -> bool {
    growth.to_bits() == ERASED.to_bits()
}

/// Smallest half-width of the interval of `λT`: the resolution of the
/// estimate. A neutral motion whose tangent map is a rotation (an undamped
/// oscillator away from its stops) grows by exactly 0 each period, up to
/// rounding; its interval must still contain 0.
const RESOLUTION: f64 = 1e-9;

/// The largest Lyapunov exponent of a motion, being measured on its own
/// simulator: the growth of a renormalised tangent vector in each forcing
/// period, and the period-section points visited. Its uncertainty comes from
/// the spread of the means over ten consecutive blocks of periods
/// (batch means: blocks of ten or more periods are nearly independent in a
/// chaotic motion; on a torus the growth telescopes, the block means cancel
/// and the interval is wide about 0).
#[derive(Debug, Clone)]
pub struct Exponent {
    /// `ln |Φ_k v_{k-1}|`, the growth of each measured period.
    growth: Vec<f64>,
    /// The tangent vector after the last period (unit length).
    v: DVector<f64>,
    /// The tangent vector's image over the period being measured (its buffer).
    w: DVector<f64>,
    /// The forcing period `T`.
    period: f64,
    /// Periods of alignment before the measured ones (counted in the time
    /// since the tangent was started, see [`Exponent::diverges`]).
    warmup: usize,
    /// Period-section points visited, one per measured period.
    pub points: Vec<DVector<f64>>,
    /// Events (impacts, contacts, sticks, releases) of each measured period.
    events: Vec<u32>,
    /// The records of the periods simulated so far, warm-up included, where
    /// they are kept ([`Exponent::measure_keeping`]).
    kept: Option<Vec<(PeriodRecord, Moment)>>,
    /// The records of the last periods simulated that `kept` did not take,
    /// at most `last_len` ([`Exponent::measure_keeping`],
    /// [`Exponent::take_last`]).
    last: VecDeque<PeriodRecord>,
    /// How many of the last periods' records are kept in `last` (0: none).
    last_len: usize,
}

/// A 95 % confidence interval of `λT`, the growth per forcing period.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Interval {
    /// The estimate, `λT`.
    #[serde(with = "crate::number")]
    pub mean: f64,
    /// Half the interval's width: at least 1e-9, the estimate's resolution;
    /// infinite when fewer than ten periods are measured.
    #[serde(with = "crate::number")]
    pub half_width: f64,
    /// Forcing periods measured.
    pub periods: usize,
}

impl Interval {
    /// Its lower end.
    pub fn low(&self) -> f64 {
        self.mean - self.half_width
    }

    /// Its upper end.
    pub fn high(&self) -> f64 {
        self.mean + self.half_width
    }
}

impl Exponent {
    /// Measures over `periods` forcing periods from the simulator's state,
    /// after `warmup` periods that only align the tangent vector with the
    /// most expanding direction. The simulator goes on from where it is.
    pub fn measure(sim: &mut Simulator<'_>, warmup: usize, periods: usize) -> Result<Exponent, Halt> {
        Exponent::measured(sim, warmup, periods, None, 0)
    }

    /// As [`Exponent::measure`], keeping records of the periods it
    /// simulates. With `all`, the record of every period of this
    /// measurement, warm-up included ([`Exponent::take_kept`]): the motion's
    /// next periods from where `sim` started, which a record going on from
    /// there need not simulate again. Of the other periods, this
    /// measurement's and its extensions', the records of the last `last`
    /// ([`Exponent::take_last`]): the motion the measurement ends on.
    pub(crate) fn measure_keeping(
        sim: &mut Simulator<'_>,
        warmup: usize,
        periods: usize,
        all: bool,
        last: usize,
    ) -> Result<Exponent, Halt> {
        let kept = all.then(|| Vec::with_capacity(warmup + periods));
        Exponent::measured(sim, warmup, periods, kept, last)
    }

    /// The records [`Exponent::measure_keeping`] kept, in order, each with
    /// where the simulation was at its end; none are kept after this.
    pub(crate) fn take_kept(&mut self) -> Vec<(PeriodRecord, Moment)> {
        self.kept.take().unwrap_or_default()
    }

    /// The records of the last periods simulated that
    /// [`Exponent::take_kept`] did not take, in order, at most the `last`
    /// that [`Exponent::measure_keeping`] was asked for; none are kept after
    /// this.
    pub(crate) fn take_last(&mut self) -> VecDeque<PeriodRecord> {
        self.last_len = 0;
        std::mem::take(&mut self.last)
    }

    fn measured(
        sim: &mut Simulator<'_>,
        warmup: usize,
        periods: usize,
        kept: Option<Vec<(PeriodRecord, Moment)>>,
        last_len: usize,
    ) -> Result<Exponent, Halt> {
        let dim = sim.state().len();
        sim.track_tangent();
        let mut e = Exponent {
            growth: Vec::with_capacity(periods),
            v: DVector::from_element(dim, 1.0 / (dim as f64).sqrt()),
            w: DVector::zeros(dim),
            period: sim.period(),
            warmup,
            points: Vec::with_capacity(periods),
            events: Vec::with_capacity(periods),
            kept,
            last: VecDeque::with_capacity(last_len),
            last_len,
        };
        for _ in 0..warmup {
            e.step(sim)?;
        }
        e.extend(sim, periods)?;
        Ok(e)
    }

    /// Measures `periods` more forcing periods with `sim`, which must be the
    /// simulator it was measured with, where it stopped.
    pub fn extend(&mut self, sim: &mut Simulator<'_>, periods: usize) -> Result<(), Halt> {
        for _ in 0..periods {
            let (growth, events) = self.step(sim)?;
            self.growth.push(growth);
            self.events.push(events);
            self.points.push(sim.state().clone());
        }
        Ok(())
    }

    /// One forcing period of the tangent: its growth and its events.
    fn step(&mut self, sim: &mut Simulator<'_>) -> Result<(f64, u32), Halt> {
        sim.reset_tangent();
        let rec = sim.run_period(&[], false, &mut Ignore)?;
        let events = u32::try_from(rec.events).unwrap_or(u32::MAX);
        match self.kept.as_mut() {
            Some(kept) => kept.push((rec, sim.moment())),
            None if self.last_len > 0 => {
                if self.last.len() == self.last_len {
                    if let Some(old) = self.last.pop_front() {
                        sim.recycle(old);
                    }
                }
                self.last.push_back(rec);
            }
            None => sim.recycle(rec),
        }
        apply(sim.tangent().ok_or(Halt::Stalled)?, &self.v, &mut self.w);
        let norm = self.w.norm();
        if !norm.is_finite() {
            return Err(Halt::Stalled);
        }
        if norm == 0.0 {
            // Every perturbation erased: a mass stuck to its stop forgets how
            // it came there, and its motion from the release on is the same
            // whatever came before. λ is -∞: counted as the least growth a
            // double shows, the vector kept for the next period.
            return Ok((ERASED, events));
        }
        std::mem::swap(&mut self.v, &mut self.w);
        self.v /= norm;
        Ok((norm.ln(), events))
    }

    /// The largest Lyapunov exponent, per unit time:
    /// `λ = Σ ln|Φ_k v_{k-1}| / (K T)`.
    pub fn per_time(&self) -> f64 {
        self.interval().mean / self.period
    }

    /// Forcing periods measured.
    pub fn periods(&self) -> usize {
        self.growth.len()
    }

    /// The 95 % confidence interval of `λT` from the means of ten equal
    /// blocks of the measured periods (the first `K mod 10` periods count in
    /// the estimate, not in the blocks).
    pub fn interval(&self) -> Interval {
        interval_of(&self.growth)
    }

    /// Whether the tangent is shown to grow exponentially, beyond what a
    /// polynomial growth `t^d` (`d` ≤ 2, a sheared torus's and a degree in hand) could give:
    /// over all the measured periods, or over their last half, its growth
    /// (the lower end of its 95 % interval, times the periods) exceeds
    /// `d ln(t₁/t₀)`, with `t₀` and `t₁` the periods since the tangent was
    /// started at the stretch's ends. A positive finite-time exponent alone
    /// is no proof of chaos: on a sheared torus the tangent grows like `t`,
    /// its exponent over `K` periods is `ln K / K`, positive beyond any
    /// interval and falling; over the last half of any record such growth
    /// gains `ln 2` at most, chaos `λT K / 2`.
    pub fn diverges(&self) -> bool {
        let k = self.growth.len();
        let shown = |from: usize| {
            let stretch = interval_of(&self.growth[from..]);
            stretch.low() * (k - from) as f64 > polynomial_growth(self.warmup, from, k)
        };
        k >= 2 * BLOCKS && (shown(0) || shown(k / 2))
    }

    /// Whether the measurement shows chaos: its interval above 0 and the
    /// tangent shown to grow exponentially ([`Exponent::diverges`]).
    pub fn chaotic(&self) -> bool {
        self.interval().low() > 0.0 && self.diverges()
    }

    /// Events (impacts, contacts, sticks, releases) over the measured periods.
    pub fn events(&self) -> u64 {
        self.events.iter().map(|&n| u64::from(n)).sum()
    }

    /// Events (impacts, contacts, sticks, releases) over the last half of
    /// the measured periods: the tangent of a piecewise-linear flow grows
    /// beyond a linear flow's bounded swing only at them.
    pub fn late_events(&self) -> u64 {
        self.events[self.events.len() / 2..].iter().map(|&n| u64::from(n)).sum()
    }

    /// Measured periods in which the tangent was erased (a mass held at its
    /// stop: each counts `ln` of the least positive double, about −708).
    pub fn erased(&self) -> usize {
        self.growth.iter().filter(|g| is_erased(g)).count()
    }

    /// The flights of a motion that sticks: the runs of measured periods
    /// between two that erased the tangent ([`Exponent::erased`]), each the
    /// whole periods of a flight from one release (from rest at the stop, at
    /// one phase of the forcing) to the next stick; `longest` leaves out the
    /// parts flown in the periods of the release and the stick, and starts
    /// from the vector kept over the stick, so it errs low. `per_period`
    /// counts every period flown, the runs cut by the measurement's ends
    /// included. `None` where no flight lies wholly within the measurement.
    pub fn flights(&self) -> Option<Flights> {
        let (first, last) = (self.growth.iter().position(is_erased)?, self.growth.iter().rposition(is_erased)?);
        let longest = self.growth[first..=last]
            .split(is_erased)
            .filter(|flight| !flight.is_empty())
            .map(|flight| flight.iter().sum::<f64>())
            .max_by(f64::total_cmp)?;
        let flown: f64 = self.growth.iter().filter(|g| !is_erased(g)).sum();
        let per_period = flown / (self.growth.len() - self.erased()) as f64;
        Some(Flights { longest, per_period, period: self.period })
    }

    /// Whether the tangent did not grow at all over the last half of the
    /// measured periods, to the estimate's resolution: its interval there
    /// at its narrowest (1e-9) and its mean within it. Events there (a
    /// stop touched at a grazing speed, where the map is the jump alone)
    /// stretched nothing; chaos's impacts stretch its tangent by an amount
    /// of order one each.
    pub fn unstretched_late(&self) -> bool {
        let late = self.late();
        late.half_width <= RESOLUTION && late.mean.abs() <= RESOLUTION
    }

    /// Whether the last half of the measured periods met a stop at most
    /// once in each `q` periods, at least once, with a tangent not shown to
    /// grow there: neither its interval above 0 nor its growth past a
    /// polynomial's ([`Exponent::grew_late`]). A flow that closes after `q`
    /// periods touching its stop ever more gently does this; chaos in `q`
    /// bands meets its stop more often, or stretches its tangent at the
    /// touches.
    pub fn touches_sparsely(&self, q: usize) -> bool {
        let events = self.late_events();
        events > 0
            && events <= (self.periods() / 2).div_ceil(q) as u64
            && self.late().low() <= 0.0
            && self.grew_late().is_none()
    }

    /// The exponent over the last half of the measured periods (`λT` and its
    /// interval): near the whole's in chaos, falling like `1/K` on a torus.
    pub fn late(&self) -> Interval {
        interval_of(&self.growth[self.growth.len() / 2..])
    }

    /// Whether the tangent grew no faster than a polynomial `t^d` could
    /// over the whole measurement, its last half and its last quarter (at
    /// least 20 periods; see [`Exponent::excess`]): a regular motion's
    /// growth, however long it is measured.
    pub fn polynomial(&self) -> bool {
        self.growth.len() >= 2 * BLOCKS && self.excess().is_none()
    }

    /// The first of the whole measurement, its last half and its last
    /// quarter over which the tangent grew (the sum of the measured growths,
    /// the estimate itself rather than its interval's lower end as in
    /// [`Exponent::diverges`]) by more than a polynomial growth `t^d` could
    /// (`d ln(t₁/t₀)`, d = 2, as there); `None` where it did over none. A
    /// sheared torus's tangent grows like `t`: over the last half of any
    /// measurement it gains `ln 2`, over the last quarter `ln 4/3`, and a
    /// bounded swing about that; chaos of `λT` gains `λT K/2` and
    /// `λT K/4`, beyond those bounds (`2 ln 2`, `2 ln 4/3`) once `λT K` is
    /// above about 2.3 (`λT` above about 4e-4 over 6 400 periods). Weaker chaos
    /// is not told from a torus by `K` periods.
    pub fn excess(&self) -> Option<Stretch> {
        let k = self.growth.len();
        [0, k / 2, k - k / 4].into_iter().find_map(|from| self.beyond_polynomial(from))
    }

    /// The last half of the measurement where the tangent grew over it by
    /// more than a polynomial growth could (as in [`Exponent::excess`]).
    /// In a scene that dissipates, the tangent along an attracting torus
    /// stays bounded (the torus's circle map is conjugate to a rotation), so
    /// such growth over a torus's points is no torus: a thin chaotic band
    /// about one, or a chaotic transient still wandering before an orbit.
    pub fn grew_late(&self) -> Option<Stretch> {
        let k = self.growth.len();
        (k >= 2 * BLOCKS).then(|| self.beyond_polynomial(k / 2)).flatten()
    }

    /// Whether the tangent, having grown over the `late` stretch by more than
    /// a polynomial growth could ([`Exponent::grew_late`]'s), grew over the
    /// periods before it by more than that same bound too: growth kept up
    /// throughout. An attracting torus's tangent stays bounded, so it may
    /// swing past the bound over one half (the main job's plane, down, at
    /// ω = 1.66, δ = 0.1: 2.09 over the last 3 200 of 6 400 periods against
    /// 1.38, after −1.07 over the first; a torus for an independent
    /// simulator, its tangent within e^±3 over 100 000 periods) but not
    /// keep growing over both.
    pub fn grew_before(&self, late: &Stretch) -> bool {
        let first: f64 = self.growth[..self.growth.len() - late.periods].iter().sum();
        first > late.bound
    }

    /// Whether the tangent grew by more than `bound` (in `ln`) over both
    /// halves of the measured periods from `from` on, as
    /// [`Exponent::grew_late`] and [`Exponent::grew_before`] ask of the two
    /// halves of the whole measurement: over the stretch where the motion lay
    /// on a torus that it reached within the measurement, the chaotic
    /// transient before it left out (an attracting torus's tangent stays
    /// bounded there, and gains no more than its swing over the stretch).
    pub fn kept_growing_from(&self, from: usize, bound: f64) -> bool {
        let mid = from + (self.growth.len() - from) / 2;
        let over = |part: &[f64]| part.iter().sum::<f64>() > bound;
        over(&self.growth[from..mid]) && over(&self.growth[mid..])
    }

    /// The stretch from measured period `from` to the end where the tangent
    /// grew by more than a polynomial growth could over it.
    fn beyond_polynomial(&self, from: usize) -> Option<Stretch> {
        let k = self.growth.len();
        let growth: f64 = self.growth[from..].iter().sum();
        let bound = polynomial_growth(self.warmup, from, k);
        (growth > bound).then_some(Stretch { periods: k - from, growth, bound })
    }
}

/// The flights of a motion that sticks now and then ([`Exponent::flights`]).
/// Each stick erases every perturbation, so the motion from each release on
/// is one flight, the same whatever came before; where a flight's tangent
/// grows, the error of the computed flight grows with it, and where it
/// grows past the margin by which the next stick is decided
/// ([`Flights::MARGIN`]) the flight's next stick, and so the period of the
/// motion, is the computation's rather than the motion's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flights {
    /// The largest growth of the tangent over the whole periods of one
    /// flight, in `ln`.
    pub longest: f64,
    /// The mean growth of the tangent per period flown (the periods that
    /// did not erase it): the flights' `λT`.
    pub per_period: f64,
    /// The forcing period `T`.
    period: f64,
}

impl Flights {
    /// The error at the end of a flight between two sticks (a free mass's
    /// position and velocity, in the scene's units) beyond which the flight's
    /// next stick is not decided: the median over the 656 flights of the
    /// orbits that stick on the single stop's three planes at `standard`
    /// (ω × σ, ω × r, ω × ζ), each release moved by 1e-16 to 1e-2 four ways,
    /// of the largest move that kept the next stick in its period times the
    /// flight's tangent growth (0.0007 to 0.5 from the 5th to the 95th
    /// percentile).
    pub const MARGIN: f64 = 0.03;

    /// Whether the flights expand, and the longest expands the error of a
    /// computed flight past [`Flights::MARGIN`]: each impact is taken
    /// where the gap is within `contact_tol` of the stop (and at best to
    /// the last bit of a double), an error that the flight's tangent grows
    /// with it (at `standard`, 1e-11, past the margin beyond e^21.8).
    /// Where the motion sticks again is then beyond the simulation's
    /// precision, and it sticks now and then after chaotic flights.
    pub fn beyond_precision(&self, contact_tol: f64) -> bool {
        self.per_period > 0.0 && self.longest > (Flights::MARGIN / contact_tol.max(f64::EPSILON)).ln()
    }

    /// The flights' exponent per unit time: `λT` per period flown over `T`.
    pub fn per_time(&self) -> f64 {
        self.per_period / self.period
    }
}

/// The tangent's growth over the last periods of a measurement, beside the
/// most that a polynomial growth could give over them ([`Exponent::excess`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stretch {
    /// Forcing periods of the stretch (the measurement's last).
    pub periods: usize,
    /// The tangent's growth over them, in `ln` (`λT` times the periods).
    #[serde(with = "crate::number")]
    pub growth: f64,
    /// The most a polynomial growth `t^d` gains over them, in `ln`.
    #[serde(with = "crate::number")]
    pub bound: f64,
}

/// The most a polynomial growth `t^d` (`d` = [`POLYNOMIAL_DEGREE`]) gains,
/// in ln, over measured periods `from` to `to` after `warmup` periods of
/// alignment: `d ln((warmup + to)/(warmup + from))`.
pub(crate) fn polynomial_growth(warmup: usize, from: usize, to: usize) -> f64 {
    POLYNOMIAL_DEGREE * ((warmup + to) as f64 / (warmup + from).max(1) as f64).ln()
}

/// The 95 % confidence interval of the mean of `growth` from the means of ten
/// equal blocks (the first `K mod 10` values count in the estimate, not in
/// the blocks); unbounded for fewer than ten values.
fn interval_of(growth: &[f64]) -> Interval {
    let k = growth.len();
    let mean = growth.iter().sum::<f64>() / k as f64;
    let len = k / BLOCKS;
    if len == 0 {
        return Interval { mean, half_width: f64::INFINITY, periods: k };
    }
    let blocks: Vec<f64> = growth[k % BLOCKS..].chunks(len).map(|b| b.iter().sum::<f64>() / len as f64).collect();
    let centre = blocks.iter().sum::<f64>() / BLOCKS as f64;
    let var = blocks.iter().map(|b| (b - centre).powi(2)).sum::<f64>() / (BLOCKS - 1) as f64;
    Interval { mean, half_width: (T_975_9 * (var / BLOCKS as f64).sqrt()).max(RESOLUTION), periods: k }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn estimate(growth: Vec<f64>) -> Exponent {
        let events = vec![1; growth.len()];
        with_events(growth, events)
    }

    fn with_events(growth: Vec<f64>, events: Vec<u32>) -> Exponent {
        Exponent {
            points: Vec::new(),
            v: DVector::zeros(2),
            w: DVector::zeros(2),
            period: 2.0,
            warmup: 10,
            growth,
            events,
            kept: None,
            last: VecDeque::new(),
            last_len: 0,
        }
    }

    /// A reproducible noise, uniform in [-1, 1) (SplitMix64 of `k`).
    fn noise(k: usize) -> f64 {
        let mut z = (k as u64).wrapping_add(1).wrapping_mul(0x9E3779B97F4A7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        2.0 * ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 - 1.0
    }

    /// Chaos: independent growths of mean 0.02 and spread 0.3. Over 100
    /// periods the interval contains 0 (undecided); over 6 400 it lies above
    /// 0, contains the mean, and is about eight times narrower (`1/√K`).
    #[test]
    fn a_positive_mean_is_told_once_measured_long_enough() {
        let short = estimate((0..100).map(|k| 0.02 + 0.3 * noise(k)).collect()).interval();
        assert!(short.low() < 0.0 && short.high() > 0.0, "{short:?}");
        let long = estimate((0..6400).map(|k| 0.02 + 0.3 * noise(k)).collect()).interval();
        assert!(long.low() > 0.0 && long.low() < 0.02 && long.high() > 0.02, "{long:?}");
        assert!((4.0..16.0).contains(&(short.half_width / long.half_width)), "{short:?} {long:?}");
        assert_eq!(long.periods, 6400);
    }

    /// Issue 62: a sheared torus's tangent grows like `t` (each period's
    /// growth `ln((W + k + 1)/(W + k))`): over 100 periods its exponent lies
    /// above 0 beyond its interval (such cells were `C`), but its growth is
    /// never shown to be exponential, however long it is measured; chaos (mean 0.01, spread 0.3 per period) is,
    /// once measured long enough (not over 100 periods, where 1 is within
    /// what `t²` gains); a quadratic growth is not either.
    #[test]
    fn polynomial_growth_is_not_divergence() {
        let power =
            |d: f64, k: usize| estimate((0..k).map(|i| d * ((11.0 + i as f64) / (10.0 + i as f64)).ln()).collect());
        for d in [1.0, 2.0] {
            assert!(power(d, 100).interval().low() > 0.0, "t^{d}: {:?}", power(d, 100).interval());
            for k in [100, 400, 1600, 6400] {
                assert!(!power(d, k).diverges(), "t^{d} over {k}: {:?}", power(d, k).interval());
            }
        }
        let chaos = |k: usize| estimate((0..k).map(|i| 0.01 + 0.3 * noise(i)).collect());
        assert!(!chaos(100).diverges());
        assert!(chaos(6400).diverges(), "{:?} {:?}", chaos(6400).interval(), chaos(6400).late());
        // Strong chaos is shown at once.
        assert!(estimate((0..100).map(|i| 0.5 + 0.3 * noise(i)).collect()).diverges());
    }

    /// Issue 62: a regular motion's tangent, growing like `t` with a bounded
    /// swing (of 0.1 in `ln`, as on the multi-stop without losses, whose
    /// tangents gain 0.21 to 0.39 over the last quarter of 6 400 periods
    /// against `ln 4/3` = 0.29), grows no faster than a polynomial over the
    /// whole, the last half and the last quarter of the measurement; a
    /// swing of 0.5 may exceed the bound over the last quarter (2 ln 4/3 =
    /// 0.57 however long the measurement: it does over 1 600 periods); chaos
    /// of `λT` = 2e-3 (spread 0.05 a period) does over 6 400 periods (its
    /// last half gains about 6.4 against 2 ln 2: `excess` names the first
    /// stretch that exceeds); over 400 periods it is not told from a torus.
    /// A tangent whose growth rounds to 0 is within.
    #[test]
    fn a_regular_motion_grows_no_faster_than_a_polynomial() {
        let sheared = |swing: f64, k: usize| {
            let level = |k: usize| ((10 + k) as f64).ln() + swing * (0.7 * k as f64).sin();
            estimate((1..=k).map(|i| level(i) - level(i - 1)).collect())
        };
        for k in [400, 1600, 6400, 64_000] {
            assert!(sheared(0.1, k).polynomial(), "over {k}: {:?}", sheared(0.1, k).excess());
        }
        assert!(!sheared(0.5, 1600).polynomial());
        let chaos = |k: usize| estimate((0..k).map(|i| 2e-3 + 0.05 * noise(i)).collect());
        let excess = chaos(6400).excess().expect("chaos grows faster than a polynomial");
        let from = 6400 - excess.periods;
        assert!([0, 3200, 4800].contains(&from), "{excess:?}");
        let growth: f64 = chaos(6400).growth[from..].iter().sum();
        assert_eq!(excess.growth.to_bits(), growth.to_bits());
        assert!((excess.bound - 2.0 * (6410.0 / (10 + from) as f64).ln()).abs() < 1e-12, "{excess:?}");
        assert!(excess.growth > excess.bound && !chaos(6400).polynomial());
        assert!(chaos(400).polynomial(), "{:?}", chaos(400).excess());
        assert!(estimate(vec![1e-17; 100]).polynomial());
        // Fewer than 20 periods tell nothing.
        assert!(!estimate(vec![0.0; 19]).polynomial());
    }

    /// Issue 62: a flow closing after q = 43 periods, touched once in each
    /// 43 over the last half of 6 400 periods, its tangent level a bounded
    /// swing (as on the single stop with r = 0.5 at ω = 43/26), touches its
    /// stop sparsely. Not where the last half met no stop, met it once in
    /// each 21 periods (chaos in bands meets its stop more often) or for a
    /// q of 86; not where the tangent grew there: chaos of `λT` = 2e-3
    /// (interval above 0, growth past a polynomial's), a steady growth of
    /// 2e-4 a period (interval above 0 alone: a gain of 0.64 over the last
    /// half, within `2 ln 2`), or a growth of 2e-3 a period beneath a
    /// swing of 2 in `ln` (past a polynomial's, its interval still about 0).
    #[test]
    fn a_torus_touched_rarely_touches_sparsely_and_chaos_does_not() {
        let every = |k: usize, gap: usize| (0..k).map(|i| u32::from(i >= k / 2 && i % gap == 0)).collect::<Vec<u32>>();
        let swing = |k: usize| {
            let level = |i: usize| 1e-5 * noise(i);
            (1..=k).map(|i| level(i) - level(i - 1)).collect::<Vec<f64>>()
        };
        let torus = with_events(swing(6400), every(6400, 43));
        assert_eq!(torus.late_events(), 74);
        assert!(torus.touches_sparsely(43), "{:?}", torus.late());
        assert!(!torus.touches_sparsely(86));
        assert!(!with_events(swing(6400), vec![0; 6400]).touches_sparsely(43));
        assert!(!with_events(swing(6400), every(6400, 21)).touches_sparsely(43));
        let chaos = with_events((0..6400).map(|i| 2e-3 + 0.05 * noise(i)).collect(), every(6400, 43));
        assert!(chaos.late().low() > 0.0 && chaos.grew_late().is_some());
        assert!(!chaos.touches_sparsely(43));
        let steady = with_events((0..6400).map(|i| 2e-4 + 1e-6 * noise(i)).collect(), every(6400, 43));
        assert!(steady.late().low() > 0.0 && steady.grew_late().is_none(), "{:?}", steady.late());
        assert!(!steady.touches_sparsely(43));
        let level = |i: usize| 2e-3 * i as f64 + 2.0 * (0.37 * i as f64).sin();
        let swinging = (1..=6400).map(|i| level(i) - level(i - 1)).collect();
        let band = with_events(swinging, every(6400, 43));
        assert!(band.late().low() <= 0.0 && band.grew_late().is_some(), "{:?}", band.late());
        assert!(!band.touches_sparsely(43));
    }

    /// A dissipative torus's tangent stays bounded: its growths telescope
    /// to a bounded level (here a swing of 0.6 in `ln`, which a noisy
    /// per-period growth of spread 0.3 rides on), and over no last half
    /// does it gain more than `2 ln 2`; a thin chaotic band of `λT` = 0.006
    /// with the same spread gains 5 over the last 800 of 1 600 periods
    /// while its interval still contains 0 (not shown to diverge); a
    /// chaotic transient that ended in the first half does not.
    #[test]
    fn a_bounded_tangent_never_grows_late_and_chaos_does() {
        // The tangent's level `ln|v_k|`: a chaotic rise of `rise` a period
        // for the first `chaotic` periods, then a bounded swing with noise.
        let tangent = |k: usize, rise: f64, chaotic: usize| {
            let level = |k: usize| rise * k.min(chaotic) as f64 + 0.6 * (0.37 * k as f64).sin() + 0.3 * noise(k);
            estimate((1..=k).map(|i| level(i) - level(i - 1)).collect())
        };
        let bounded = |k: usize| tangent(k, 0.0, 0);
        for k in [100, 1600, 6400] {
            assert!(bounded(k).grew_late().is_none(), "over {k}: {:?}", bounded(k).late());
        }
        let band = estimate((0..1600).map(|i| 0.006 + 0.3 * noise(i)).collect());
        let grew = band.grew_late().expect("chaos grows over the last half");
        assert_eq!(grew.periods, 800);
        assert!(grew.growth > grew.bound && !band.diverges(), "{grew:?} {:?}", band.interval());
        let transient = tangent(1600, 0.05, 800);
        assert!(transient.grew_late().is_none() && transient.excess().is_some(), "{:?}", transient.late());
        // Fewer than 20 periods tell nothing.
        assert!(estimate(vec![1.0; 19]).grew_late().is_none());
    }

    /// A torus: the growths telescope (`ln|v_k| - ln|v_{k-1}|` of a bounded
    /// oscillation), so the mean falls like `1/K` and the interval contains 0
    /// however long the measurement; too few periods for the blocks leave it
    /// unbounded, and a growth of exactly 0 up to rounding stays undecided.
    #[test]
    fn a_torus_stays_about_zero() {
        let level = |k: usize| (0.7 * k as f64).sin();
        for k in [100, 1600] {
            let growth = estimate((1..=k).map(|i| level(i) - level(i - 1)).collect()).interval();
            assert!(growth.low() < 0.0 && growth.high() > 0.0 && growth.mean.abs() < 2.0 / k as f64, "{growth:?}");
        }
        let neutral = estimate(vec![-1e-17; 100]).interval();
        assert!(neutral.low() < 0.0 && neutral.high() > 0.0, "rounding is not contraction: {neutral:?}");
        let few = estimate(vec![0.1; 9]).interval();
        assert!(few.half_width.is_infinite() && (few.mean - 0.1).abs() < 1e-15);
        assert!((estimate(vec![0.1; 10]).per_time() - 0.05).abs() < 1e-15);
    }

    /// The flights of a motion that sticks are the runs of periods between
    /// two erased ones: the first run (begun before the measurement) and
    /// the last (not ended within it) are no whole flights, and a run of
    /// stuck periods holds none. The flights' `λT` is the mean over every
    /// period flown.
    #[test]
    fn flights_are_the_runs_between_sticks() {
        let x = ERASED;
        assert_eq!(estimate(vec![0.5; 40]).flights(), None);
        assert_eq!(estimate(vec![0.5, x, 0.5, 0.5]).flights(), None);
        assert_eq!(estimate(vec![0.5, x, x, 0.5]).flights(), None);
        let f = estimate(vec![9.0, x, 1.0, 2.0, x, x, 4.0, 0.5, 0.5, x, 40.0]).flights().unwrap();
        assert_eq!(f.longest.to_bits(), 5f64.to_bits());
        assert_eq!(f.per_period.to_bits(), (57.0f64 / 7.0).to_bits());
        assert_eq!(f.per_time().to_bits(), (57.0f64 / 7.0 / 2.0).to_bits());
    }

    /// A flight is beyond the simulation's precision where its tangent
    /// grows the error of its impacts, `contact_tol` (at best the last bit
    /// of a double), past the margin by which its next stick is decided:
    /// at `standard` beyond e^21.8, at `fast` e^17.2, at `precise` e^24.1.
    #[test]
    fn a_flight_is_beyond_precision_once_it_grows_its_impacts_error_past_the_margin() {
        let flights = |longest: f64, per_period: f64| Flights { longest, per_period, period: 1.0 };
        for (preset, threshold) in
            [(crate::Preset::Fast, 17.2), (crate::Preset::Standard, 21.8), (crate::Preset::Precise, 24.1)]
        {
            let tol = crate::Accuracy::preset(preset).contact_tol;
            assert!(!flights(threshold, 0.5).beyond_precision(tol), "{preset:?}");
            assert!(flights(threshold + 0.1, 0.5).beyond_precision(tol), "{preset:?}");
        }
        // No finer than the last bit of a double: e^32.5.
        assert!(!flights(32.5, 0.5).beyond_precision(1e-30));
        assert!(flights(32.7, 0.5).beyond_precision(1e-30));
        // Flights that contract on the whole are no chaos, however long one grew.
        assert!(!flights(50.0, -0.1).beyond_precision(1e-11));
    }

    /// A mass stuck to its stop forgets how it came there: over a period
    /// that holds it, the tangent map is zero (issue 62: the measurement
    /// stopped there, "event location stalled", and 233 cells of the
    /// undamped single stop's ω × σ plane were `unresolved`). The single stop
    /// at ω = 1.45, σ = −0.45 settles on an orbit of 23 periods that sticks
    /// (23-S-0, at `standard`, at `precise` and over ten times the record);
    /// measured along it, every stuck period counts [`ERASED`], `ln` of the
    /// least positive double, and the exponent is far below 0.
    #[test]
    fn a_stuck_mass_erases_its_tangent() {
        use crate::{run_cell, Accuracy, Class, Method};
        assert_eq!(ERASED.to_bits(), f64::MIN_POSITIVE.ln().to_bits());
        let sys = crate::testing::system("single-stop.toml", &[("omega", 1.45), ("sigma", -0.45)]);
        let acc = Accuracy::default();
        let cell = run_cell(&sys, &acc, Method::Exact, &sys.model.initial_state());
        assert_eq!((cell.class, cell.n), (Class::Periodic, Some(23)), "{:?}", cell.reason);
        assert_eq!(cell.labels[0].label.to_string(), "23-S-0");
        let mut sim = Simulator::new(&sys, acc, Method::Exact, &cell.final_state).unwrap();
        let e = Exponent::measure(&mut sim, 0, 46).unwrap();
        let erased = e.erased();
        assert!(erased >= 2 && erased.is_multiple_of(2), "{erased} periods erased of 46");
        assert!(e.interval().mean < -30.0, "{:?}", e.interval());
    }
}
