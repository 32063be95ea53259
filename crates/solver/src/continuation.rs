//! Natural continuation of a periodic orbit along one parameter, with the
//! location of its bifurcations.
//!
//! From each converged point the next is solved by Newton from a secant
//! prediction; a step that fails is halved (down to 1/64 of the grid step).
//! Between two points the test function `ψ = max|μ| - 1` of the solved map's
//! multipliers is watched: a sign change is a loss (or gain) of stability,
//! located by the Illinois variant of regula falsi on ψ to `PARAM_TOL`, and
//! named by where the crossing multiplier sits on the unit circle
//! ([`crate::floquet::kind`]). Where Newton fails even at the smallest step,
//! the edge of the solvable branch is located by bisection to `PARAM_TOL`.
//! When the impact pattern changes past it, it is a grazing, placed at the
//! root of the orbit's grazing margin (the solver's `grazing` module, smooth
//! through the grazing, where Newton's method is not), and the branch goes
//! on with the new pattern when Newton converges past it; otherwise the
//! branch folds (SN: a multiplier tends to +1), where natural continuation
//! stops, or is lost.

use crate::accuracy::Accuracy;
use crate::floquet::{kind, spectral_radius, Bifurcation};
use crate::grazing;
use crate::newton::{Failure, MapKind};
use crate::orbit::{solve_orbit, solve_orbit_watched, Orbit};
use crate::system::System;
use nalgebra::DVector;
use num_complex::Complex64 as C64;

/// Parameter tolerance of located bifurcations.
pub const PARAM_TOL: f64 = 1e-9;

/// A multiplier of the solved map this close to +1 where Newton's method
/// stops converging marks a fold.
const FOLD_DISTANCE: f64 = 0.05;

/// |ψ| below this is a neutral multiplier on the unit circle, not a crossing.
const NEUTRAL: f64 = 1e-7;

/// One converged point of a branch.
#[derive(Debug, Clone)]
pub struct BranchPoint {
    /// Parameter value.
    pub value: f64,
    /// The orbit there.
    pub orbit: Orbit,
}

/// A located bifurcation.
#[derive(Debug, Clone)]
pub struct Located {
    /// Its kind.
    pub kind: Bifurcation,
    /// Parameter value.
    pub value: f64,
    /// Multipliers of the n-period map there.
    pub multipliers: Vec<C64>,
    /// The crossing multiplier of the solved map (for grazing: the largest).
    pub critical: C64,
}

/// A followed branch.
#[derive(Debug, Clone, Default)]
pub struct Branch {
    /// Converged points, in continuation order (the requested grid values and
    /// any intermediate values taken by step halving).
    pub points: Vec<BranchPoint>,
    /// Bifurcations found, in continuation order.
    pub bifurcations: Vec<Located>,
    /// Why the branch ended before the last value, if it did.
    pub ended: Option<String>,
}

impl Located {
    /// A bifurcation of `kind` at `value`, with the orbit there and the
    /// multiplier of the solved map that crosses.
    pub fn new(kind: Bifurcation, value: f64, orbit: &Orbit, critical: C64) -> Located {
        Located { kind, value, multipliers: orbit.multipliers.clone(), critical }
    }

    /// A bifurcation of `kind` at `value` whose critical multiplier is the
    /// leading one of the orbit there.
    pub fn at_leading(kind: Bifurcation, value: f64, orbit: &Orbit) -> Located {
        Located::new(kind, value, orbit, leading(orbit))
    }

    /// A change of stability at `value`, named by where the leading multiplier
    /// of the solved map sits on the unit circle.
    pub fn stability(value: f64, orbit: &Orbit) -> Located {
        let critical = leading(orbit);
        Located::new(kind(critical, orbit.map == MapKind::Half), value, orbit, critical)
    }
}

/// The system at a parameter value (`None`: the value is not admissible).
pub type Family<'a> = dyn Fn(f64) -> Option<System> + 'a;

/// The leading multiplier of the solved map (NaN when none was computed).
fn leading(o: &Orbit) -> C64 {
    o.map_multipliers.first().copied().unwrap_or(C64::new(f64::NAN, f64::NAN))
}

/// The stability test function `max|μ| - 1` of the solved map.
pub(crate) fn psi(o: &Orbit) -> f64 {
    spectral_radius(&o.map_multipliers) - 1.0
}

fn predict(points: &[BranchPoint], v: f64) -> DVector<f64> {
    let last = &points[points.len() - 1];
    match points.len() {
        1 => last.orbit.solution.x.clone(),
        _ => {
            let prev = &points[points.len() - 2];
            let w = (v - last.value) / (last.value - prev.value);
            &last.orbit.solution.x + (&last.orbit.solution.x - &prev.orbit.solution.x) * w
        }
    }
}

/// Solves at `v` from `x0`, keeping the pattern of `like` unless `free`.
fn try_at(
    family: &Family,
    acc: &Accuracy,
    like: &Orbit,
    v: f64,
    x0: &DVector<f64>,
    free: bool,
) -> Result<Orbit, Failure> {
    let sys = family(v).ok_or(Failure::Simulation)?;
    let pattern = (!free).then_some(&like.solution.pattern);
    solve_orbit(&sys, acc, x0, like.map, like.n, pattern)
}

fn solve_at(family: &Family, acc: &Accuracy, like: &Orbit, v: f64, x0: &DVector<f64>, free: bool) -> Option<Orbit> {
    try_at(family, acc, like, v, x0, free).ok()
}

/// Locates the root of ψ between points `a` and `b` (ψ of opposite signs).
fn locate_crossing(family: &Family, acc: &Accuracy, a: &BranchPoint, b: &BranchPoint) -> Located {
    let (mut lo, mut hi) = (a.clone(), b.clone());
    let (mut f_lo, mut f_hi) = (psi(&lo.orbit), psi(&hi.orbit));
    let mut side = 0i32;
    for _ in 0..200 {
        if (hi.value - lo.value).abs() <= PARAM_TOL * (1.0 + lo.value.abs()) {
            break;
        }
        let mut v = (lo.value * f_hi - hi.value * f_lo) / (f_hi - f_lo);
        if !v.is_finite() || (v - lo.value) * (v - hi.value) >= 0.0 {
            v = 0.5 * (lo.value + hi.value);
        }
        let w = (v - lo.value) / (hi.value - lo.value);
        let x0 = &lo.orbit.solution.x + (&hi.orbit.solution.x - &lo.orbit.solution.x) * w;
        let Some(o) = solve_at(family, acc, &lo.orbit, v, &x0, false) else { break };
        let f = psi(&o);
        let p = BranchPoint { value: v, orbit: o };
        if (f < 0.0) == (f_lo < 0.0) {
            lo = p;
            f_lo = f;
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        } else {
            hi = p;
            f_hi = f;
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        }
    }
    let at = if f_lo.abs() <= f_hi.abs() { &lo } else { &hi };
    Located::stability(0.5 * (lo.value + hi.value), &at.orbit)
}

/// Locates where the branch stops being solvable between `good` and `v_bad`;
/// the last good point and why Newton fails just past it.
fn locate_boundary(family: &Family, acc: &Accuracy, good: &BranchPoint, mut v_bad: f64) -> (BranchPoint, Failure) {
    let mut good = good.clone();
    let mut why = Failure::Diverged;
    for _ in 0..100 {
        if (v_bad - good.value).abs() <= PARAM_TOL * (1.0 + good.value.abs()) {
            break;
        }
        let v = 0.5 * (good.value + v_bad);
        match try_at(family, acc, &good.orbit, v, &good.orbit.solution.x, false) {
            Ok(o) => good = BranchPoint { value: v, orbit: o },
            Err(e) => {
                v_bad = v;
                why = e;
            }
        }
    }
    (good, why)
}

/// Most secant steps of [`locate_grazing`].
const GRAZING_STEPS: usize = 8;

/// How far short of the secant's root a step solves the orbit, as a share
/// of the way there.
const GRAZING_SHORT: f64 = 0.999;

/// A root within this of the last orbit solved (relative) stands: the
/// margin's curvature moves it by about the square of this.
const GRAZING_CLOSE: f64 = 1e-7;

/// Most halvings of one secant step of [`locate_grazing`] whose orbit
/// Newton's method does not reach (each such try costs a failed solve).
const GRAZING_HALVINGS: usize = 4;

/// Farthest a grazing may lie from the last orbit solved before it (in the
/// parameter): the margin's curvature then moves the root by about the
/// square of this, far below `PARAM_TOL`.
const GRAZING_REACH: f64 = 1e-4;

/// Places the grazing of the branch's last orbit between its value and
/// `v_bad`, where Newton's method keeping its impact pattern fails: at the
/// root of its margin ([`grazing::margin`], smooth and linear in the
/// parameter near the grazing), by secant steps from the orbit's side, each
/// solving the orbit there from the line through the last two (a step that
/// fails is halved towards the last solved orbit, at most
/// [`GRAZING_HALVINGS`] times, after which the root stands). The root is taken once
/// two successive secant roots agree to `PARAM_TOL / 100` (the margin's
/// curvature then moves it by less). The grazed stops and the orbit's side
/// come from the map evaluated past the last orbit ([`grazing::crossing`]).
/// The grazing's value; `None` (where no pattern change, margin or
/// converging step is found) leaves the grazing to [`locate_boundary`]. The
/// branch's point stays the bisection's last orbit (`points`' last), short
/// of the root: from there Newton's method reaches nearby orbits from a
/// prediction, as curves need (see `curve::line`).
fn locate_grazing(family: &Family, acc: &Accuracy, points: &[BranchPoint], v_bad: f64) -> Option<f64> {
    let last = points.last()?;
    let crossing = (0..4).find_map(|k| {
        let v = last.value + (v_bad - last.value) * f64::powi(2.0, k);
        let sys = family(v)?;
        grazing::crossing(&sys, acc, &last.orbit).ok()?
    })?;
    let (stops, side) = (crossing.stops, crossing.side?);
    let margin = |p: &BranchPoint| grazing::margin(&family(p.value)?, acc, &p.orbit, &stops, side);
    // The orbit at v from x0, keeping `like`'s pattern, its margin measured as it is described.
    let solve = |v: f64, x0: &DVector<f64>, like: &Orbit| -> Option<(BranchPoint, f64)> {
        let sys = family(v)?;
        let mut watch = grazing::Margins::new(&sys, &stops, side);
        let pattern = Some(&like.solution.pattern);
        let orbit = solve_orbit_watched(&sys, acc, x0, like.map, like.n, pattern, &mut watch).ok()?;
        let m = watch.of(&orbit)?;
        Some((BranchPoint { value: v, orbit }, m))
    };
    // The point before: the branch's, where it is the same orbit; else one solved behind.
    let (before, m_before) = match points.len() {
        n if n >= 2 && points[n - 2].orbit.solution.pattern == last.orbit.solution.pattern => {
            (points[n - 2].clone(), margin(&points[n - 2])?)
        }
        _ => solve(last.value - (v_bad - last.value), &last.orbit.solution.x, &last.orbit)?,
    };
    let (mut p0, mut p1) = (before, last.clone());
    let (mut m0, mut m1) = (m_before, margin(&p1)?);
    let mut bad = v_bad;
    let mut root: Option<f64> = None;
    for _ in 0..GRAZING_STEPS {
        let slope = (m1 - m0) / (p1.value - p0.value);
        let r = p1.value - m1 / slope;
        // The margin must fall towards the failure, its root between.
        if !(r.is_finite() && (r - p1.value) * (bad - p1.value) >= 0.0) {
            return None;
        }
        let tol = 1e-2 * PARAM_TOL * (1.0 + r.abs());
        let close = GRAZING_CLOSE * (1.0 + r.abs());
        if m1 <= 0.0 || root.is_some_and(|q| (q - r).abs() <= tol) || (r - p1.value).abs() <= close {
            return within(p1.value, r, v_bad);
        }
        root = Some(r);
        // Just short of the root: an orbit there still clears the stop by
        // more than the prediction's error, so Newton's method reaches it.
        let short = p1.value + GRAZING_SHORT * (r - p1.value);
        let mut v = if (r - bad) * (p1.value - bad) > 0.0 { short } else { 0.5 * (p1.value + bad) };
        for halving in 0..=GRAZING_HALVINGS {
            let w = (v - p1.value) / (p1.value - p0.value);
            let x0 = &p1.orbit.solution.x + (&p1.orbit.solution.x - &p0.orbit.solution.x) * w;
            match solve(v, &x0, &p1.orbit) {
                Some((p, m)) => {
                    (p0, m0, p1, m1) = (p1, m1, p, m);
                    break;
                }
                None if halving == GRAZING_HALVINGS => return within(p1.value, r, v_bad),
                None => {
                    bad = v;
                    v = 0.5 * (p1.value + v);
                    if (v - p1.value).abs() <= tol {
                        return within(p1.value, r, v_bad);
                    }
                }
            }
        }
    }
    root.and_then(|r| within(p1.value, r, v_bad))
}

/// The root `r` where it lies between `last` (the value of the last orbit
/// solved) and `bad` (where Newton's method failed) and within
/// [`GRAZING_REACH`] of `last`, else `None`: a root beyond the failure, or
/// one the orbit was not solved near (it folds first), is no grazing of this
/// orbit.
fn within(last: f64, r: f64, bad: f64) -> Option<f64> {
    ((r - last) * (bad - r) >= 0.0 && (r - last).abs() <= GRAZING_REACH).then_some(r)
}

/// How precisely a followed branch places its grazings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Grazings {
    /// At the root of the orbit's grazing margin, to [`PARAM_TOL`].
    Exact,
    /// At the edge where Newton's method stops reaching the orbit (short of
    /// the grazing by up to about 1e-4): enough where only the branch's
    /// end matters (a segment its orbit is carried along).
    Edge,
}

/// Follows `start` (the orbit at `values[0]`) over `values`.
pub fn follow(family: &Family, acc: &Accuracy, values: &[f64], start: Orbit) -> Branch {
    follow_with(family, acc, values, start, true, Grazings::Exact)
}

/// [`follow`] up to the first change of the impact pattern (a grazing placed
/// as `grazings` says, its last orbit the branch's last point): the
/// bifurcations of `start`'s own orbit only.
pub fn follow_own(family: &Family, acc: &Accuracy, values: &[f64], start: Orbit, grazings: Grazings) -> Branch {
    follow_with(family, acc, values, start, false, grazings)
}

/// [`follow`], going on past a grazing with the new pattern when `past`.
fn follow_with(
    family: &Family,
    acc: &Accuracy,
    values: &[f64],
    start: Orbit,
    past: bool,
    grazings: Grazings,
) -> Branch {
    let mut branch = Branch { points: vec![BranchPoint { value: values[0], orbit: start }], ..Branch::default() };
    for &target in &values[1..] {
        let mut depth = 0;
        while branch.points.last().is_some_and(|p| p.value.to_bits() != target.to_bits()) {
            let last = branch.points.last().unwrap().clone();
            let step = (target - last.value) / f64::powi(2.0, depth);
            let v = if depth == 0 { target } else { last.value + step };
            let x0 = predict(&branch.points, v);
            match solve_at(family, acc, &last.orbit, v, &x0, false) {
                Some(o) => {
                    let next = BranchPoint { value: v, orbit: o };
                    let (a, b) = (psi(&last.orbit), psi(&next.orbit));
                    // Multipliers pinned at the unit circle (a free body's drift)
                    // are neutral, not crossing: their ψ is rounding noise. Across a
                    // grazing the map itself changes: no crossing is located there.
                    let same = last.orbit.solution.pattern == next.orbit.solution.pattern;
                    if same && (a < 0.0) != (b < 0.0) && a.abs().min(b.abs()) > NEUTRAL {
                        branch.bifurcations.push(locate_crossing(family, acc, &last, &next));
                    }
                    branch.points.push(next);
                    depth = 0;
                }
                None if depth < 6 => depth += 1,
                None => {
                    let (edge, why) = locate_boundary(family, acc, &last, v);
                    // Past a grazing the impact pattern changes; on a smooth
                    // branch Newton fails at a fold, where a multiplier tends to +1.
                    let one = C64::new(1.0, 0.0);
                    let fold = edge.orbit.map_multipliers.iter().any(|m| (m - one).norm() < FOLD_DISTANCE);
                    // A grazing: placed at the root of its margin, from the
                    // edge where Newton's method stops reaching the orbit.
                    // Exactly placed, the margin decides what Newton's
                    // failure does not: near a grazing Newton may diverge
                    // before it sees the pattern change, and near a fold the
                    // iterates may change the pattern of an orbit that folds
                    // before it grazes (no root within reach: a fold).
                    let mut at = edge.value;
                    let mut grazes = why == Failure::Pattern;
                    if grazings == Grazings::Exact && (grazes || !fold) {
                        // The last two points serve (their orbits, not the whole branch's, cloned).
                        let mut points = branch.points[branch.points.len().saturating_sub(2)..].to_vec();
                        if edge.value.to_bits() != last.value.to_bits() {
                            points.push(edge.clone());
                        }
                        match locate_grazing(family, acc, &points, v) {
                            Some(root) => (at, grazes) = (root, true),
                            None => grazes &= !fold,
                        }
                    }
                    if !grazes {
                        let value = edge.value;
                        if fold {
                            branch.bifurcations.push(Located::at_leading(Bifurcation::SaddleNode, value, &edge.orbit));
                        }
                        branch.points.push(edge);
                        branch.ended = Some(if fold {
                            format!("the branch folds back at {value:.9} (natural continuation stops at a fold)")
                        } else {
                            format!("Newton's method lost the branch at {value:.9} without a fold or grazing")
                        });
                        return branch;
                    }
                    branch.bifurcations.push(Located::at_leading(Bifurcation::Grazing, at, &edge.orbit));
                    let new = edge.value.to_bits() != last.value.to_bits();
                    if !past {
                        branch.ended = Some(format!("the impact pattern changes at {at:.9} (grazing)"));
                        if new {
                            branch.points.push(edge);
                        }
                        return branch;
                    }
                    // Go on past the grazing with the new event sequence.
                    match solve_at(family, acc, &edge.orbit, v, &edge.orbit.solution.x, true) {
                        Some(o) => {
                            if new {
                                branch.points.push(edge);
                            }
                            branch.points.push(BranchPoint { value: v, orbit: o });
                            depth = 0;
                        }
                        None => {
                            branch.ended = Some(format!("no orbit past the grazing at {at:.9}"));
                            return branch;
                        }
                    }
                }
            }
        }
    }
    branch
}
