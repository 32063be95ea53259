//! Corrector paths (lines and arcs): where a point of a curve is looked
//! for, and how the orbit of the point before reaches them.
//!
//! A curve's orbit is the orbit of its first point, continued: a later point
//! is located on a corrector path by carrying the orbit of the point before
//! (Newton from point to point along a straight segment of the plane, its
//! period, map and impact pattern kept) to the path's start, on the side of
//! the curve the orbit was continued from, and continuing it along the path
//! across the curve. The point is the first bifurcation of the curve's kind
//! that this orbit meets there before its impact pattern changes (for a
//! grazing: that change itself), so that a curve never takes a bifurcation
//! of another orbit for its own.

use super::meet::{fold_test, FOLD_MARGIN};
use super::{CurvePoint, Missed, Plane2, Start, Tracing, LINE_POINTS};
use crate::continuation::{follow_own, Branch, Grazings, Located};
use crate::floquet::Bifurcation;
use crate::grazing::{crossing, grazed, Crossing};
use crate::orbit::{orbit_of_cell, solve_orbit, Orbit};
use crate::system::System;
use scene::Named;

/// Points of the continuation along a step's corrector path (a line or an
/// arc: the curve is near its middle; a first point's line has
/// [`LINE_POINTS`]).
const STEP_POINTS: usize = 24;

/// Points of the segment an orbit is carried along (Newton from each to the
/// next; a failed step is halved by [`Tracing::follow`](crate::curve::Tracing::follow)).
const CARRY_POINTS: usize = 5;

/// The orbit of a point of a fold curve, and the orbit a grazing curve's
/// next point is carried from, is that of the branch's point nearest the
/// bifurcation at least this far from it (in the units of its corrector
/// path): at a fold Newton's method is singular, and within about 1e-9 of a
/// grazing its first iterate from the orbit already touches the stop, so that
/// a carry from there changes the impact pattern at once (and the step is
/// halved down to the smallest, for every point).
const INSIDE: f64 = 1e-3;

/// A bifurcation of the curve's kind met by a carried orbit this close to
/// the segment's start (as a fraction of the segment) is the point it was
/// carried from.
const CARRY_START: f64 = 1e-4;

/// A path of the plane, parameterised by `s`, in the plane's scaled units.
#[derive(Debug, Clone, Copy)]
pub(super) enum Path {
    /// `(a, b) = origin + s · direction · scale` (`origin` unscaled,
    /// `direction` a unit vector in scaled units).
    Line { origin: [f64; 2], direction: [f64; 2] },
    /// `(a, b) = center + radius · (cos s, sin s) · scale` (`center`
    /// unscaled, `radius` scaled).
    Arc { center: [f64; 2], radius: f64 },
}

impl Path {
    /// The point at `s`.
    pub fn at(&self, s: f64, scale: [f64; 2]) -> [f64; 2] {
        let (o, v) = match *self {
            Path::Line { origin, direction } => (origin, [s * direction[0], s * direction[1]]),
            Path::Arc { center, radius } => (center, [radius * s.cos(), radius * s.sin()]),
        };
        [o[0] + v[0] * scale[0], o[1] + v[1] * scale[1]]
    }

    /// The unit vector (scaled) along the path at `s`, towards larger `s`.
    pub fn direction(&self, s: f64) -> [f64; 2] {
        match *self {
            Path::Line { direction, .. } => direction,
            Path::Arc { .. } => [-s.sin(), s.cos()],
        }
    }

    /// Where the path is, for messages: a line's middle, an arc's centre.
    fn anchor(&self) -> [f64; 2] {
        match *self {
            Path::Line { origin, .. } => origin,
            Path::Arc { center, .. } => center,
        }
    }
}

/// `n` values from `from` to `to`.
fn values(from: f64, to: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| from + (to - from) * i as f64 / (n - 1) as f64).collect()
}

/// Whether `q` is the orbit `p` continued: the same period, map and impact
/// pattern.
pub(super) fn same_orbit(p: &Orbit, q: &Orbit) -> bool {
    p.n == q.n && p.map == q.map && p.solution.pattern == q.solution.pattern
}

/// The labels of an orbit, e.g. `M1 1-3-3, M2 1-0-3`.
fn labels(o: &Orbit) -> String {
    o.labels.iter().map(|l| format!("{} {l}", l.mass)).collect::<Vec<_>>().join(", ")
}

impl Tracing {
    /// [`Tracing::locate_on`] for each of `kinds`, the orbit found from
    /// `start` at an end of the line (the upper one first) and continued
    /// across it; the continuation from an end is run once, when a kind first
    /// needs it, and serves every kind. A kind's point is its bifurcation
    /// nearest the line's middle among those of the orbit continued, up to
    /// its first change of impact pattern ([`follow_own`]).
    pub(super) fn locate_each(
        &self,
        plane: &Plane2,
        line: Path,
        start: Start,
        kinds: &[Bifurcation],
    ) -> Vec<Result<CurvePoint, Missed>> {
        let family = |s: f64| {
            let [a, b] = line.at(s, self.scale);
            plane(a, b)
        };
        let run = |from: f64| -> Option<Branch> {
            let sys = family(from)?;
            let orbit = self.orbit_at(&sys, start)?;
            Some(follow_own(&family, &self.acc, &values(from, -from, LINE_POINTS), orbit, Grazings::Exact))
        };
        let first = run(1.0);
        let holds = |k: Bifurcation| first.as_ref().is_some_and(|b| b.bifurcations.iter().any(|x| x.kind == k));
        let second = if kinds.iter().all(|&k| holds(k)) { None } else { run(-1.0) };
        let branches = [(1.0, first), (-1.0, second)];
        kinds
            .iter()
            .map(|&kind| {
                let mut seen = Vec::new();
                for (from, branch) in &branches {
                    let Some(branch) = branch else { continue };
                    let nearest = branch
                        .bifurcations
                        .iter()
                        .filter(|b| b.kind == kind)
                        .min_by(|x, y| x.value.abs().total_cmp(&y.value.abs()));
                    match nearest {
                        Some(best) => return Ok(self.point_on(plane, line, -*from, branch, best)),
                        None => seen.extend(branch.bifurcations.iter().map(|o| self.position(line, o))),
                    }
                }
                let [a, b] = line.anchor();
                Err(Missed { why: format!("no {} within one window of ({a}, {b})", kind.name()), others: seen })
            })
            .collect()
    }

    /// The periodic orbit of `sys` reached from `start` (see [`Start`]).
    fn orbit_at(&self, sys: &System, start: Start) -> Option<Orbit> {
        let cell = |y0: &[f64]| {
            let y0 = if sys.admits(y0) { y0.to_vec() } else { sys.model.initial_state() };
            orbit_of_cell(sys, &self.acc, &y0, self.n).ok()
        };
        match start {
            Start::Fresh => cell(&sys.model.initial_state()),
            Start::State(y) => cell(y),
            Start::Orbit(o) => solve_orbit(sys, &self.acc, &o.solution.x, o.map, o.n, Some(&o.solution.pattern)).ok(),
        }
    }

    /// Kind and position `(a, b)` of a bifurcation located on `line`.
    fn position(&self, line: Path, o: &Located) -> (Bifurcation, f64, f64) {
        let [a, b] = line.at(o.value, self.scale);
        (o.kind, a, b)
    }

    /// The point of `best`, located on `path` by `branch` (continued
    /// towards larger `s` where `travel` is positive, else smaller): its
    /// orbit solved there (from the branch's nearest point, which it stays
    /// when Newton fails), the other bifurcations of the branch's own orbit,
    /// the side it came from, and for a grazing the stops that it grazes.
    fn point_on(&self, plane: &Plane2, path: Path, travel: f64, branch: &Branch, best: &Located) -> CurvePoint {
        let family = |s: f64| {
            let [a, b] = path.at(s, self.scale);
            plane(a, b)
        };
        let sign = if travel < 0.0 { -1.0 } else { 1.0 };
        let (orbit, inside) = match best.kind {
            // At a fold Newton's method is singular: its orbit is the branch's
            // last point before it.
            Bifurcation::SaddleNode => self.before(branch, best.value, INSIDE),
            // Next to a grazing Newton's method reaches the orbit from a
            // prediction only a little short of it: its orbit is the branch's
            // last, where the search for the grazing started.
            Bifurcation::Grazing => self.before(branch, best.value, 0.0),
            _ => (self.orbit_near(&family, branch, best.value), best.value),
        };
        let [a, b] = path.at(best.value, self.scale);
        let others =
            branch.bifurcations.iter().filter(|o| o.kind != best.kind).map(|o| self.position(path, o)).collect();
        let grazes = match best.kind {
            Bifurcation::Grazing => self.grazing_stops(&family, best.value, sign, &orbit),
            _ => Vec::new(),
        };
        let d = path.direction(best.value);
        let side = [-sign * d[0], -sign * d[1]];
        let orbit_at = path.at(inside, self.scale);
        let carry_start = (best.kind == Bifurcation::Grazing).then(|| {
            let (orbit, inside) = self.before(branch, best.value, INSIDE);
            (orbit, path.at(inside, self.scale))
        });
        CurvePoint { a, b, located: best.clone(), orbit, orbit_at, carry_start, others, side, grazes }
    }

    /// The orbit of the point of `branch` nearest `value` at least `inside`
    /// from it, among those of the branch's own orbit (its first point's
    /// period, map and impact pattern), and where it is.
    fn before(&self, branch: &Branch, value: f64, inside: f64) -> (Orbit, f64) {
        let start = &branch.points[0].orbit;
        let near = branch
            .points
            .iter()
            .filter(|p| same_orbit(&p.orbit, start) && (p.value - value).abs() >= inside)
            .min_by(|p, q| (p.value - value).abs().total_cmp(&(q.value - value).abs()))
            .unwrap_or(&branch.points[0]);
        (near.orbit.clone(), near.value)
    }

    /// The orbit of `branch` at `value`: Newton from the branch's point
    /// nearest it, before its pattern changes there (that point's orbit when
    /// Newton fails).
    fn orbit_near(&self, family: &dyn Fn(f64) -> Option<System>, branch: &Branch, value: f64) -> Orbit {
        let start = &branch.points[0].orbit;
        let near = branch
            .points
            .iter()
            .filter(|p| same_orbit(&p.orbit, start))
            .min_by(|p, q| (p.value - value).abs().total_cmp(&(q.value - value).abs()))
            .unwrap_or(&branch.points[0]);
        let o = &near.orbit;
        if near.value.to_bits() == value.to_bits() {
            return o.clone();
        }
        family(value)
            .and_then(|sys| solve_orbit(&sys, &self.acc, &o.solution.x, o.map, o.n, Some(&o.solution.pattern)).ok())
            .unwrap_or_else(|| o.clone())
    }

    /// The stops whose impacts change across the grazing of `orbit` at
    /// `value` of `family`: one map evaluation from its state a little past it
    /// (in the direction of `towards`), further and further until the pattern
    /// changes. Empty when it does not.
    fn grazing_stops(
        &self,
        family: &dyn Fn(f64) -> Option<System>,
        value: f64,
        towards: f64,
        orbit: &Orbit,
    ) -> Vec<usize> {
        for k in 0..7 {
            let Some(sys) = family(value + towards * 10f64.powi(k - 9)) else { return Vec::new() };
            match crossing(&sys, &self.acc, orbit) {
                Ok(Some(Crossing { stops, side })) => {
                    return match (side, family(value)) {
                        (Some(side), Some(here)) => grazed(&here, &self.acc, orbit, stops, side),
                        _ => stops,
                    }
                }
                Ok(None) => {}
                Err(_) => return Vec::new(),
            }
        }
        Vec::new()
    }

    /// The names of `stops`, e.g. `A1, A12`.
    fn stop_names(&self, plane: &Plane2, p: &CurvePoint, stops: &[usize]) -> String {
        let names = plane(p.a, p.b).map(|s| s.model.stops.iter().map(|x| x.name.clone()).collect::<Vec<_>>());
        let name = |k: usize| names.as_ref().and_then(|n| n.get(k).cloned()).unwrap_or_else(|| format!("stop {k}"));
        stops.iter().map(|&k| name(k)).collect::<Vec<_>>().join(", ")
    }

    /// The span `[from, to]` of the line through the prediction along
    /// `direction`: from `reach` (scaled) on `last`'s side of its middle to
    /// the end on the other side.
    pub(super) fn span(last: &CurvePoint, direction: [f64; 2], reach: f64) -> [f64; 2] {
        let sign = if last.side[0] * direction[0] + last.side[1] * direction[1] < 0.0 { -1.0 } else { 1.0 };
        [sign * reach, -sign]
    }

    /// The point of the curve on `path` that continues `last`'s orbit: the
    /// orbit carried from `last` to the path at `from` (on `last`'s side of
    /// the curve), then continued along it to `to`; the first bifurcation of
    /// the curve's kind of that orbit, at most `tol` from `s = 0` when given.
    /// Refused, with why and the other bifurcations of the orbit met (where
    /// the curve may end), when the orbit cannot be carried there, holds no
    /// such bifurcation there, its first grazing there is of other stops
    /// than `last`'s, or its orbit folds as it grazes (its fold test function
    /// fallen below [`FOLD_MARGIN`]: there the fold is taken for a grazing).
    pub(super) fn continue_on(
        &self,
        plane: &Plane2,
        last: &CurvePoint,
        path: Path,
        [from, to]: [f64; 2],
        tol: Option<f64>,
    ) -> Result<CurvePoint, Missed> {
        let orbit = self.carry(plane, last, path.at(from, self.scale))?;
        let family = |s: f64| {
            let [a, b] = path.at(s, self.scale);
            plane(a, b)
        };
        let branch = follow_own(&family, &self.acc, &values(from, to, STEP_POINTS), orbit, Grazings::Exact);
        let own = &branch.bifurcations;
        let others = || own.iter().filter(|o| o.kind != self.kind).map(|o| self.position(path, o)).collect();
        let [a, b] = path.anchor();
        let Some(best) = own.iter().find(|o| o.kind == self.kind) else {
            let why = format!("its orbit has no {} on the corrector path at ({a}, {b})", self.kind.name());
            return Err(Missed { why, others: others() });
        };
        let p = self.point_on(plane, path, to - from, &branch, best);
        if !p.grazes.is_empty() && !last.grazes.is_empty() && p.grazes != last.grazes {
            let (now, before) = (self.stop_names(plane, &p, &p.grazes), self.stop_names(plane, &p, &last.grazes));
            let why = format!("its orbit grazes {now} (not {before}) first, at ({}, {})", p.a, p.b);
            return Err(Missed { why, others: vec![(Bifurcation::Grazing, p.a, p.b)] });
        }
        if self.kind == Bifurcation::Grazing
            && fold_test(&last.orbit) >= FOLD_MARGIN
            && fold_test(&p.orbit) < FOLD_MARGIN
        {
            let why = format!("its orbit folds as it grazes at ({}, {})", p.a, p.b);
            return Err(Missed { why, others: vec![(Bifurcation::SaddleNode, p.a, p.b)] });
        }
        if tol.is_some_and(|tol| best.value.abs() > tol) || !same_orbit(&last.orbit, &p.orbit) {
            let why = format!(
                "the {} of its orbit near ({a}, {b}) is off the curve, at ({}, {})",
                self.kind.name(),
                p.a,
                p.b
            );
            return Err(Missed { why, others: others() });
        }
        Ok(p)
    }

    /// `last`'s orbit carried along the segment from where it is to `to` (Newton
    /// from point to point, its impact pattern kept): the orbit at `to`. The
    /// carry fails where the orbit changes its impact pattern (grazes), folds
    /// or is lost on the way, or meets a bifurcation of the curve's kind
    /// (which puts `to` across the curve, or on another one); a grazing of
    /// other stops than the curve's own, or a fold, is returned as a
    /// bifurcation the curve may end at.
    fn carry(&self, plane: &Plane2, last: &CurvePoint, to: [f64; 2]) -> Result<Orbit, Missed> {
        let (start, [a0, b0]) = match &last.carry_start {
            Some((orbit, at)) => (orbit, *at),
            None => (&last.orbit, last.orbit_at),
        };
        let at = |t: f64| [a0 + t * (to[0] - a0), b0 + t * (to[1] - b0)];
        let family = |t: f64| {
            let [a, b] = at(t);
            plane(a, b)
        };
        let ts: Vec<f64> = (0..CARRY_POINTS).map(|i| i as f64 / (CARRY_POINTS - 1) as f64).collect();
        let branch = follow_own(&family, &self.acc, &ts, start.clone(), Grazings::Edge);
        let lost = |why: String, others: Vec<(Bifurcation, f64, f64)>| {
            Err(Missed { why: format!("its orbit ({}) cannot be continued: {why}", labels(&last.orbit)), others })
        };
        for x in &branch.bifurcations {
            let [a, b] = at(x.value);
            match x.kind {
                Bifurcation::Grazing => {
                    let (orbit, _) = self.before(&branch, x.value, 0.0);
                    let stops = self.grazing_stops(&family, x.value, 1.0, &orbit);
                    let own = self.kind == Bifurcation::Grazing
                        && (stops.is_empty() || last.grazes.is_empty() || stops == last.grazes);
                    let why = format!("its impact pattern changes at ({a}, {b})");
                    return lost(why, if own { Vec::new() } else { vec![(x.kind, a, b)] });
                }
                k if k == self.kind && x.value > CARRY_START => {
                    return lost(format!("it meets another {} at ({a}, {b}) on the way", k.name()), Vec::new());
                }
                _ => {}
            }
        }
        if branch.ended.is_some() {
            let [a, b] = at(branch.points.last().map_or(0.0, |p| p.value));
            return match branch.bifurcations.iter().any(|x| x.kind == Bifurcation::SaddleNode) {
                true if self.kind != Bifurcation::SaddleNode => {
                    lost(format!("it folds at ({a}, {b})"), vec![(Bifurcation::SaddleNode, a, b)])
                }
                true => lost(format!("it folds at ({a}, {b})"), Vec::new()),
                false => lost(format!("Newton's method loses it at ({a}, {b})"), Vec::new()),
            };
        }
        match branch.points.last() {
            Some(p) if p.value.to_bits() == 1f64.to_bits() && same_orbit(&p.orbit, &last.orbit) => Ok(p.orbit.clone()),
            _ => lost("Newton's method does not reach the corrector path".into(), Vec::new()),
        }
    }
}
