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
//! the edge of the solvable branch is located by bisection to `PARAM_TOL`: when
//! the impact pattern changes there it is a grazing, and the branch goes on
//! with the new pattern when Newton converges past it; otherwise the branch
//! folds (SN: a multiplier tends to +1), where natural continuation stops.

use crate::accuracy::Accuracy;
use crate::floquet::{kind, spectral_radius, Bifurcation};
use crate::newton::{Failure, MapKind};
use crate::orbit::{solve_orbit, Orbit};
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

/// Follows `start` (the orbit at `values[0]`) over `values`.
pub fn follow(family: &Family, acc: &Accuracy, values: &[f64], start: Orbit) -> Branch {
    follow_with(family, acc, values, start, true)
}

/// [`follow`] up to the first change of the impact pattern (a grazing, its
/// orbit there the branch's last point): the bifurcations of `start`'s own
/// orbit only.
pub fn follow_own(family: &Family, acc: &Accuracy, values: &[f64], start: Orbit) -> Branch {
    follow_with(family, acc, values, start, false)
}

/// [`follow`], going on past a grazing with the new pattern when `past`.
fn follow_with(family: &Family, acc: &Accuracy, values: &[f64], start: Orbit, past: bool) -> Branch {
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
                    if why != Failure::Pattern {
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
                    branch.bifurcations.push(Located::at_leading(Bifurcation::Grazing, edge.value, &edge.orbit));
                    if !past {
                        branch.ended = Some(format!("the impact pattern changes at {:.9} (grazing)", edge.value));
                        branch.points.push(edge);
                        return branch;
                    }
                    // Go on past the grazing with the new event sequence.
                    match solve_at(family, acc, &edge.orbit, v, &edge.orbit.solution.x, true) {
                        Some(o) => {
                            branch.points.push(edge);
                            branch.points.push(BranchPoint { value: v, orbit: o });
                            depth = 0;
                        }
                        None => {
                            branch.ended = Some(format!("no orbit past the grazing at {:.9}", edge.value));
                            return branch;
                        }
                    }
                }
            }
        }
    }
    branch
}
