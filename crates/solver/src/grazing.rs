//! How far a periodic orbit is from grazing given stops: a margin that is
//! smooth in the parameters and falls to 0 at the grazing, so that
//! [`crate::continuation`] places a grazing at a root of it rather than
//! where Newton's method stops reaching the orbit (near a grazing, Newton's
//! first iterate from a neighbouring orbit already touches the stop, and a
//! bisection on its failures stops short by as much as 1e-5 of the line).
//!
//! A stop's switching function is its gap `g` (length; positive while open)
//! where its mass is free of it, and a pressed soft stop's contact force per
//! stiffness `(−k g − c ġ)/k` (length; positive while it pushes). A grazing
//! adds or removes a pair of events at a stop; the orbit on either side has
//! its own margin ([`Side`]), each linear in the distance to the grazing:
//!
//! - **approach**, the orbit without the pair: the least interior minimum
//!   of the switching function over the orbit (a flight that comes near the
//!   stop without touching it, a contact that comes near releasing its mass
//!   without doing so), found at the exact extremum of the closed form
//!   (Brent's search), never at a sample;
//! - **excursion**, the orbit with it: at a rigid stop, the normal speed of
//!   its slowest impact (an impacting orbit near grazing strikes at a speed
//!   that grows like the distance past it); at a soft stop, the largest
//!   value of the switching function over its shallowest excursion, a
//!   contact or a flight that begins and ends with an event of the stop.

use crate::accuracy::Accuracy;
use crate::contact::Contact;
use crate::extremum::peak;
use crate::flow::Method;
use crate::newton::evaluate;
use crate::orbit::Orbit;
use crate::simulate::{EventKind, EventObserver, Halt, Segment, Simulator};
use crate::system::System;
use nalgebra::DVector;
use std::f64::consts::TAU;

/// Samples of the switching function per turn of the flow's fastest term,
/// between which its extremes are bracketed for Brent's search.
const SAMPLES_PER_TURN: f64 = 4.0;

/// Most samples of one segment.
const MOST_SAMPLES: usize = 256;

/// Which side of a grazing an orbit is on, and so which margin it has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Side {
    /// The orbit lacks the events the grazing adds: its closest approach.
    Approach,
    /// The orbit has them: its slowest impact or shallowest excursion.
    Excursion,
}

/// How an orbit's impact pattern changes past a grazing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Crossing {
    /// The stops whose counts of events change.
    pub stops: Vec<usize>,
    /// The side of the grazing the orbit is on (`None` where some counts
    /// rise and others fall).
    pub side: Option<Side>,
}

/// How `orbit`'s impact pattern changes where its map is evaluated in
/// `sys` (a neighbouring parameter value) from its fixed point; `Ok(None)`
/// where the pattern stays.
pub(crate) fn crossing(sys: &System, acc: &Accuracy, orbit: &Orbit) -> Result<Option<Crossing>, Halt> {
    let x = &orbit.solution.x;
    let mut sim = Simulator::new(sys, *acc, Method::Exact, x.as_slice())?;
    sim.track_tangent();
    let image = evaluate(&mut sim, x, orbit.map)?;
    let old = &orbit.solution.pattern;
    if image.pattern == *old {
        return Ok(None);
    }
    let count = |p: &[Vec<u32>], k: usize| p.iter().map(|c| c.get(k).copied().unwrap_or(0) as i64).sum::<i64>();
    let stops: Vec<usize> =
        (0..sys.stops.len()).filter(|&k| image.pattern.iter().zip(old).any(|(p, q)| p.get(k) != q.get(k))).collect();
    let (more, fewer) = stops.iter().fold((false, false), |(m, f), &k| {
        let change = count(&image.pattern, k) - count(old, k);
        (m || change > 0, f || change < 0)
    });
    let side = match (more, fewer) {
        (true, false) => Some(Side::Approach),
        (false, true) => Some(Side::Excursion),
        _ => None,
    };
    Ok(Some(Crossing { stops, side }))
}

/// Of the `stops` whose impacts change past `orbit` (found by
/// [`crossing`]), those it grazes: the one of the least margin from `side`,
/// and any other within twice it (where two grazings meet). A pattern
/// evaluated just past a grazing may change at more stops than the one
/// grazed (a slow impact there may end in chatter that changes the
/// impacts of another); a stop without a margin is not grazed, and all of
/// them are where none has one.
pub(crate) fn grazed(sys: &System, acc: &Accuracy, orbit: &Orbit, stops: Vec<usize>, side: Side) -> Vec<usize> {
    if stops.len() < 2 {
        return stops;
    }
    let margins: Vec<f64> =
        stops.iter().map(|&k| margin(sys, acc, orbit, &[k], side).unwrap_or(f64::INFINITY)).collect();
    let least = margins.iter().copied().fold(f64::INFINITY, f64::min);
    if least.is_infinite() {
        return stops;
    }
    stops.into_iter().zip(margins).filter(|&(_, m)| m <= 2.0 * least).map(|(k, _)| k).collect()
}

/// The orbit's margin to grazing `stops` from `side` (see the module's
/// doc), over its `n` periods from its fixed point; `None` where the orbit
/// has no such approach or excursion, or cannot be simulated.
pub(crate) fn margin(sys: &System, acc: &Accuracy, orbit: &Orbit, stops: &[usize], side: Side) -> Option<f64> {
    let mut obs = Margins::new(sys, stops, side);
    if obs.wants_segments() {
        let mut sim = Simulator::new(sys, *acc, Method::Exact, orbit.solution.x.as_slice()).ok()?;
        for _ in 0..orbit.n {
            sim.run_period(&[], false, &mut obs).ok()?;
        }
    }
    obs.of(orbit)
}

/// The observer of [`margin`]: the switching functions of `stops` sampled
/// over each segment, their extremes refined on its closed form (none where
/// the margin is a rigid stop's impact speed, which the orbit lists).
pub(crate) struct Margins<'s> {
    sys: &'s System,
    stops: Vec<usize>,
    side: Side,
    /// The least margin so far.
    least: f64,
    /// Per stop: whether the segment now flown began with one of its events.
    began: Vec<bool>,
    /// Per stop: what the last segment's end gives, kept until it is known
    /// whether an event of the stop ended it (approach: its value at the end
    /// where that is a minimum; excursion: the segment's largest value).
    pending: Vec<Option<f64>>,
    samples: Vec<(f64, f64)>,
    y: DVector<f64>,
}

impl<'s> Margins<'s> {
    /// The observer of the margin to grazing `stops` of `sys` from `side`.
    pub(crate) fn new(sys: &'s System, stops: &[usize], side: Side) -> Margins<'s> {
        let count = stops.len();
        Margins {
            sys,
            stops: stops.to_vec(),
            side,
            least: f64::INFINITY,
            began: vec![false; count],
            pending: vec![None; count],
            samples: Vec::new(),
            y: DVector::zeros(0),
        }
    }

    /// Takes a pending value that no event of its stop followed (approach:
    /// the function is continuous through a period's end).
    fn settle(&mut self) {
        for i in 0..self.stops.len() {
            if let Some(v) = self.pending[i].take() {
                if self.side == Side::Approach {
                    self.least = self.least.min(v);
                }
            }
        }
    }

    /// The margin of `orbit`, whose n periods from its fixed point this
    /// observed (where it samples).
    pub(crate) fn of(mut self, orbit: &Orbit) -> Option<f64> {
        if !self.wants_segments() {
            let stops = &self.stops;
            let slowest = orbit.impacts.iter().filter(|i| stops.contains(&i.stop)).map(|i| i.velocity.0.abs());
            return slowest.min_by(f64::total_cmp);
        }
        self.settle();
        self.least.is_finite().then_some(self.least)
    }
}

/// Stop `k`'s switching function at `y` in a segment where `pressed` (bit
/// k: its contact pushes), in units of length: the gap, or a pushing soft
/// contact's force per stiffness.
fn switching(sys: &System, k: usize, pressed: u32, y: &DVector<f64>) -> f64 {
    match sys.stops[k].law.spring() {
        Some(spring) if pressed & (1 << k) != 0 => sys.contact_force(k, y) / spring.stiffness,
        _ => sys.gap(k, y),
    }
}

impl EventObserver for Margins<'_> {
    fn wants_segments(&self) -> bool {
        self.side == Side::Approach || self.stops.iter().any(|&k| !self.sys.stops[k].law.impacts())
    }

    fn segment(&mut self, seg: &mut Segment<'_>) {
        // A value pending from the segment before: no event of its stop came between.
        self.settle();
        let sys = self.sys;
        let fastest = seg.fastest().max(sys.omega * sys.harmonic_orders() as f64);
        let count = ((seg.span * fastest / TAU * SAMPLES_PER_TURN).ceil() as usize).clamp(8, MOST_SAMPLES);
        let mut y = std::mem::take(&mut self.y);
        let mut samples = std::mem::take(&mut self.samples);
        let pressed = seg.pressed;
        for i in 0..self.stops.len() {
            let k = self.stops[i];
            if seg.held & (1 << k) != 0 {
                self.began[i] = false;
                continue;
            }
            let f = |y: &DVector<f64>| switching(sys, k, pressed, y);
            samples.clear();
            for j in 0..=count {
                let u = seg.span * j as f64 / count as f64;
                seg.state(u, &mut y);
                samples.push((u, f(&y)));
            }
            match self.side {
                Side::Approach => {
                    for j in 1..count {
                        let (prev, here, next) = (samples[j - 1].1, samples[j].1, samples[j + 1].1);
                        if here > 0.0 && here <= prev && here <= next && here < self.least {
                            let low = -peak(seg, (samples[j - 1].0, samples[j + 1].0), &mut y, |_, y| -f(y));
                            self.least = self.least.min(low);
                        }
                    }
                    // An end that is a minimum: the least there where the
                    // function goes on through a period's end (an event of
                    // the stop, where it is 0, drops it).
                    let (first, second) = (samples[0].1, samples[1].1);
                    if first > 0.0 && first <= second && !self.began[i] {
                        self.least = self.least.min(first);
                    }
                    let (last, before) = (samples[count].1, samples[count - 1].1);
                    self.pending[i] = (last > 0.0 && last <= before).then_some(last);
                }
                Side::Excursion => {
                    let j = (0..=count).max_by(|&a, &b| samples[a].1.total_cmp(&samples[b].1)).unwrap_or(0);
                    let mut high = samples[j].1;
                    if j > 0 && j < count {
                        high = high.max(peak(seg, (samples[j - 1].0, samples[j + 1].0), &mut y, |_, y| f(y)));
                    }
                    // Kept only if an event of the stop ends the segment and one began it.
                    self.pending[i] = (self.began[i] && high > 0.0).then_some(high);
                }
            }
            self.began[i] = false;
        }
        self.y = y;
        self.samples = samples;
    }

    fn named_event(&mut self, _time: f64, kind: EventKind, _y: &DVector<f64>) {
        let Some(i) = kind.stop().and_then(|k| self.stops.iter().position(|&s| s == k)) else { return };
        if let Some(v) = self.pending[i].take() {
            if self.side == Side::Excursion {
                self.least = self.least.min(v);
            }
        }
        self.began[i] = true;
    }
}
