//! Period detection on the period (stroboscopic, `t = kT`) section.
//!
//! The records of the last periods are kept in a [`History`]; the period is
//! the smallest `n <= n_max` such that the last `2n` section points each equal
//! the point `n` periods earlier (within `periodic_tol`, relative to `1 + |x|`
//! in the max norm), with the same mode and the same impacts per stop.

use crate::accuracy::Accuracy;
use crate::label::Symmetry;
use crate::simulate::PeriodRecord;
use nalgebra::DVector;
use std::collections::VecDeque;

/// The records of the last periods, oldest first.
pub(crate) type History = VecDeque<PeriodRecord>;

/// Period records kept: enough to test every period up to `n_max` and the
/// 3n-period pattern Newton acceleration needs, and the 3n periods that
/// confirm an orbit longer than `n_max` (up to [`LONGEST_PERIOD`]).
pub(crate) fn history_len(acc: &Accuracy) -> usize {
    3 * acc.n_max.max(LONGEST_PERIOD) + 1
}

/// Distance of two section points, relative to `1 + |a|` (max norm).
pub(crate) fn distance(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    relative_distance(a.as_slice(), b.as_slice())
}

/// [`distance`] of two states given as slices.
fn relative_distance(a: &[f64], b: &[f64]) -> f64 {
    let d = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    d / (1.0 + a.iter().fold(0.0, |m: f64, x| m.max(x.abs())))
}

fn close(a: &DVector<f64>, b: &DVector<f64>, tol: f64) -> bool {
    distance(a, b) <= tol
}

/// Largest distance between each of the last `2n` points and the point `lag` earlier.
fn residual(h: &History, n: usize, lag: usize) -> f64 {
    let len = h.len();
    (len - 2 * n..len).map(|i| distance(&h[i].end, &h[i - lag].end)).fold(0.0, f64::max)
}

fn repeats(h: &History, i: usize, n: usize, tol: f64) -> bool {
    let (a, b) = (&h[i], &h[i - n]);
    a.end_key == b.end_key && a.impacts == b.impacts && close(&a.end, &b.end, tol)
}

/// Smallest n whose last 2n section points repeat with period n. A candidate is
/// refused (and the run goes on) while a proper divisor d of n nearly repeats
/// too, within 1000 times the residual: that is a transient still converging to
/// a period-d orbit (e.g. one that flips sign every period), not a period-n orbit.
pub(crate) fn detect(h: &History, acc: &Accuracy) -> Option<usize> {
    let len = h.len();
    let n = (1..=acc.n_max).find(|&n| {
        len >= 3 * n
            && repeats(h, len - 1, n, acc.periodic_tol)
            && (len - 2 * n..len).all(|i| repeats(h, i, n, acc.periodic_tol))
    })?;
    let res = residual(h, n, n);
    let converging_divisor = (1..n).filter(|d| n % d == 0).any(|d| residual(h, n, d) <= 1e3 * res);
    (!converging_divisor).then_some(n)
}

/// Whether the period-n orbit found by [`detect`] has converged: for every
/// point of its last period, the distance still to go to the fixed point,
/// estimated from its last n-period step `e` and the contraction `ρ` of that
/// step over the one before as `e / (1 - ρ)` (the geometric tail of a
/// contraction by the multiplier ρ), is below `periodic_tol`. A step that did
/// not shrink (`ρ ≥ 1`) is rounding noise within the tolerance, not a
/// contraction: converged. A slowly converging orbit (ρ near 1) passes the
/// repeat test of [`detect`] while still far from its fixed point; its
/// symmetry must not be decided there (issue 28).
pub(crate) fn converged(h: &History, n: usize, acc: &Accuracy) -> bool {
    remaining(h, n).is_none_or(|(to_go, _)| to_go <= acc.periodic_tol)
}

/// A relative step between section points n periods apart at or below this
/// is at rounding level: a few hundred units in the last place.
const ROUNDING_STEP: f64 = 1e-13;

/// Two successive steps at rounding level whose ratio is within this of 1
/// are one drift of rounding repeated, not a contraction: a motion can repeat
/// an ulp step exactly, period after period (the gear pair's teeth, free
/// within the backlash, do; so do 5 % of the cells of the multi-stop
/// reference plane), and the ratio of two equal steps, just below 1, would
/// read as a contraction never done, `to_go` about 1: the record went on for
/// nothing, or strongly contracting orbits ended unresolved. The same rule
/// for every scene (issue 62).
const EQUAL_STEPS: f64 = 1e-6;

/// The largest estimated distance to the fixed point over the last period's
/// points and its contraction ρ (see [`converged`]); `None` when no step
/// contracts (a rounding drift repeated, [`EQUAL_STEPS`], is none) or the
/// record is shorter than 3n periods.
pub(crate) fn remaining(h: &History, n: usize) -> Option<(f64, f64)> {
    let len = h.len();
    if len < 3 * n {
        return None;
    }
    (len - n..len)
        .filter_map(|i| {
            let (e1, e0) = (distance(&h[i].end, &h[i - n].end), distance(&h[i - n].end, &h[i - 2 * n].end));
            let rho = e1 / e0;
            let rounding = e1 <= ROUNDING_STEP && rho > 1.0 - EQUAL_STEPS;
            (rho < 1.0 && !rounding).then(|| (e1 / (1.0 - rho), rho))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0))
}

/// Longest period sought beyond `n_max` in a record without a period (see
/// [`Trail`]).
pub(crate) const LONGEST_PERIOD: usize = 128;

/// Section points a [`Trail`] keeps: three cycles of the longest period.
const TRAIL_POINTS: usize = 3 * LONGEST_PERIOD;

/// The period-section points (states only) of the last [`TRAIL_POINTS`]
/// periods of a record, to tell an orbit longer than `n_max` from a motion
/// without a period: such an orbit, once reached, is never found by
/// [`detect`], however long the record.
#[derive(Debug, Clone)]
pub(crate) struct Trail {
    dim: usize,
    /// Points, oldest first from `oldest` (a ring of [`TRAIL_POINTS`] points once full).
    data: Vec<f64>,
    /// Where the oldest point starts: 0 until the ring is full.
    oldest: usize,
}

impl Trail {
    /// An empty trail of states of dimension `dim`.
    pub(crate) fn new(dim: usize) -> Trail {
        Trail { dim, data: Vec::with_capacity(TRAIL_POINTS * dim), oldest: 0 }
    }

    /// Forgets every point (the record restarts elsewhere).
    pub(crate) fn clear(&mut self) {
        self.data.clear();
        self.oldest = 0;
    }

    /// Appends the section point `x`, dropping the oldest once full.
    pub(crate) fn push(&mut self, x: &DVector<f64>) {
        if self.data.len() < TRAIL_POINTS * self.dim {
            self.data.extend_from_slice(x.as_slice());
        } else {
            self.data[self.oldest..self.oldest + self.dim].copy_from_slice(x.as_slice());
            self.oldest = (self.oldest + self.dim) % self.data.len();
        }
    }

    fn len(&self) -> usize {
        self.data.len() / self.dim
    }

    /// The i-th point, oldest first.
    fn point(&self, i: usize) -> &[f64] {
        let start = (self.oldest + i * self.dim) % self.data.len();
        &self.data[start..start + self.dim]
    }

    /// The smallest period n of the points, when it lies in
    /// `(n_max, LONGEST_PERIOD]`: the last 2n points each equal the point n
    /// periods earlier within `periodic_tol` (the test of [`detect`], on states
    /// alone). An orbit longer than the periods tested.
    pub(crate) fn long_period(&self, acc: &Accuracy) -> Option<usize> {
        let len = self.len();
        let close = |i: usize, n: usize| relative_distance(self.point(i), self.point(i - n)) <= acc.periodic_tol;
        (1..=LONGEST_PERIOD.min(len / 3))
            .find(|&n| (len - 2 * n..len).rev().all(|i| close(i, n)))
            .filter(|&n| n > acc.n_max)
    }
}

/// Symmetric when, for some shift m, the state half a period after the start of
/// period j + m is the mirror image of the state at the start of period j
/// (within ten times `periodic_tol`), over the last n periods of a period-n
/// record.
pub(crate) fn symmetry_of(h: &History, n: usize, acc: &Accuracy) -> Symmetry {
    let len = h.len();
    let tol = 10.0 * acc.periodic_tol;
    let mirrored = |j: usize, m: usize| match &h[j + m].half {
        Some(half) => close(half, &(-&h[j - 1].end), tol),
        None => false,
    };
    let symmetric = (0..n).any(|m| (len - 2 * n..len - n).all(|j| j >= 1 && mirrored(j, m)));
    if symmetric {
        Symmetry::Symmetric
    } else {
        Symmetry::Asymmetric
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mode::Key;

    /// A record ending at the one-dimensional point `x` with `impacts` at one stop.
    fn rec(x: f64, impacts: u32) -> PeriodRecord {
        PeriodRecord {
            impacts: vec![impacts],
            held: 0,
            stuck: 0,
            end: DVector::from_vec(vec![x, 0.0]),
            end_key: Key::FREE,
            events: impacts as usize,
            half: Some(DVector::from_vec(vec![-x, 0.0])),
            half_tangent: None,
        }
    }

    fn history(points: &[(f64, u32)]) -> History {
        points.iter().map(|&(x, i)| rec(x, i)).collect()
    }

    #[test]
    fn the_smallest_repeating_period_is_found() {
        let acc = Accuracy::default();
        let one: Vec<(f64, u32)> = vec![(0.5, 1); 4];
        assert_eq!(detect(&history(&one), &acc), Some(1));
        let two: Vec<(f64, u32)> = (0..8).map(|k| (if k % 2 == 0 { 0.3 } else { -0.2 }, 1)).collect();
        assert_eq!(detect(&history(&two), &acc), Some(2));
        let three: Vec<(f64, u32)> = (0..9).map(|k| ([0.1, 0.4, 0.9][k % 3], 2)).collect();
        assert_eq!(detect(&history(&three), &acc), Some(3));
    }

    #[test]
    fn too_short_a_record_or_a_changing_pattern_is_no_period() {
        let acc = Accuracy::default();
        // Two points only: a period needs 3n records.
        assert_eq!(detect(&history(&[(0.5, 1), (0.5, 1)]), &acc), None);
        // The same point every period, but the impacts alternate: not period one.
        let alternating: Vec<(f64, u32)> = (0..6).map(|k| (0.5, k as u32 % 2)).collect();
        assert_ne!(detect(&history(&alternating), &acc), Some(1));
        let drifting: Vec<(f64, u32)> = (0..12).map(|k| (0.5 + 1e-3 * k as f64, 1)).collect();
        assert_eq!(detect(&history(&drifting), &acc), None);
    }

    #[test]
    fn a_transient_converging_to_a_divisor_is_not_its_multiple() {
        let acc = Accuracy::default();
        let tol = acc.periodic_tol;
        // Alternating by twice the tolerance and drifting slowly: period two
        // repeats within tolerance, but period one nearly does too (within 1000
        // times period two's residual): a transient converging to period one.
        let converging: Vec<(f64, u32)> =
            (0..8).map(|k| (0.5 + (k % 2) as f64 * 2.0 * tol + k as f64 * 0.01 * tol, 1)).collect();
        assert_eq!(detect(&history(&converging), &acc), None);
        // A true period two: the alternation is far beyond the drift.
        let doubled: Vec<(f64, u32)> =
            (0..8).map(|k| (0.5 + (k % 2) as f64 * 0.1 + k as f64 * 1e-3 * tol, 1)).collect();
        assert_eq!(detect(&history(&doubled), &acc), Some(2));
    }

    /// Issue 28: a point that repeats within `periodic_tol` while still
    /// contracting slowly (ρ = 0.99, 50 tolerances from its fixed point) is
    /// found but not converged; one contracting fast, or rounding noise that
    /// does not contract, is converged.
    #[test]
    fn a_slowly_contracting_repeat_is_not_converged() {
        let acc = Accuracy::default();
        let tol = acc.periodic_tol;
        let series = |rho: f64, d0: f64| -> History {
            history(&(0..8).map(|k| (0.5 + d0 * rho.powi(k), 1)).collect::<Vec<_>>())
        };
        // Steps of 0.5 tol (relative to 1.5): repeats, 50 tol still to go.
        let slow = series(0.99, 50.0 * tol * 1.5 / 0.99f64.powi(7));
        assert_eq!(detect(&slow, &acc), Some(1));
        assert!(!converged(&slow, 1, &acc));
        let (to_go, rho) = remaining(&slow, 1).unwrap();
        assert!((rho - 0.99).abs() < 1e-6 && (to_go / tol - 50.0 / 0.99).abs() < 1.0, "{to_go:e} {rho}");
        let fast = series(0.1, 1e-3);
        assert_eq!(detect(&fast, &acc), Some(1));
        assert!(converged(&fast, 1, &acc));
        let noise = history(&(0..8).map(|k| (0.5 + [0.0, 3e-16, 1e-16][k % 3], 1)).collect::<Vec<_>>());
        assert!(converged(&noise, 1, &acc));
    }

    /// Issues 41 and 62: a section point that drifts by the same few ulps
    /// every period (a rigid mode's rounding repeated exactly) is converged,
    /// in every scene: the ratio of its steps (ρ = 1 - 1e-15) is no
    /// contraction.
    #[test]
    fn a_repeated_rounding_drift_is_no_contraction() {
        let acc = Accuracy::default();
        let ulp = f64::EPSILON;
        // Equal steps of 3 machine epsilons: each relative to a point a hair
        // larger than the last, so that their ratio is just below 1.
        let drift = history(&(0..8).map(|k| (0.5 + k as f64 * 3.0 * ulp, 1)).collect::<Vec<_>>());
        assert_eq!(detect(&drift, &acc), Some(1));
        assert!(remaining(&drift, 1).is_none());
        assert!(converged(&drift, 1, &acc));
    }

    #[test]
    fn distance_is_relative_to_the_first_point() {
        let a = DVector::from_vec(vec![3.0, -1.0]);
        let b = DVector::from_vec(vec![3.5, -1.0]);
        assert!((distance(&a, &b) - 0.5 / 4.0).abs() < 1e-16);
    }

    #[test]
    fn a_mirrored_half_period_state_is_symmetric() {
        let acc = Accuracy::default();
        // `rec` stores half = -end: x(t + T/2) = -x(t) for a constant point.
        let h = history(&[(0.5, 1); 4]);
        assert_eq!(symmetry_of(&h, 1, &acc), Symmetry::Symmetric);
        let mut broken = h.clone();
        for r in broken.iter_mut() {
            r.half = Some(DVector::from_vec(vec![0.2, 0.0]));
        }
        assert_eq!(symmetry_of(&broken, 1, &acc), Symmetry::Asymmetric);
    }

    /// A trail finds an orbit longer than `n_max` once it has repeated twice,
    /// not before, and never a motion that does not repeat.
    #[test]
    fn a_trail_finds_orbits_longer_than_n_max() {
        let acc = Accuracy::default();
        let n = acc.n_max + 9;
        let orbit = |k: usize| DVector::from_vec(vec![(k % n) as f64 * 0.01, 1.0 - (k % n) as f64 * 1e-3]);
        let mut trail = Trail::new(2);
        for k in 0..3 * n - 1 {
            trail.push(&orbit(k));
        }
        assert_eq!(trail.long_period(&acc), None, "two cycles and a point short of three");
        trail.push(&orbit(3 * n - 1));
        assert_eq!(trail.long_period(&acc), Some(n));
        // Past the ring's length the oldest points are dropped, the answer stays.
        for k in 3 * n..3 * LONGEST_PERIOD + 7 {
            trail.push(&orbit(k));
        }
        assert_eq!(trail.long_period(&acc), Some(n));
        // A drift of 100 tolerances a cycle is not a repeat; nor is an irrational rotation.
        let mut drifting = Trail::new(2);
        let mut rotation = Trail::new(2);
        for k in 0..3 * LONGEST_PERIOD {
            let p = orbit(k);
            drifting.push(&DVector::from_vec(vec![p[0] + k as f64 * 100.0 * acc.periodic_tol / n as f64, p[1]]));
            let a = k as f64 * std::f64::consts::SQRT_2;
            rotation.push(&DVector::from_vec(vec![a.cos(), a.sin()]));
        }
        assert_eq!(drifting.long_period(&acc), None);
        assert_eq!(rotation.long_period(&acc), None);
        // An orbit of period n_max or less is detect's, not the trail's.
        let mut short = Trail::new(2);
        for k in 0..3 * LONGEST_PERIOD {
            short.push(&orbit(k % 3));
        }
        assert_eq!(short.long_period(&acc), None);
        short.clear();
        assert_eq!(short.long_period(&acc), None);
    }
}
