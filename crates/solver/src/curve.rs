//! Bifurcation curves in a plane of two parameters `(a, b)`.
//!
//! A point of a curve is a bifurcation of one kind (PD, SN, PF, NS, grazing)
//! of one periodic orbit, located by one-parameter continuation
//! ([`crate::continuation::follow`]) along a short line of the plane (a
//! corrector line) to [`crate::continuation::PARAM_TOL`] by the
//! exact-Jacobian test functions of `continue`. The first point's orbit is
//! found at one end of its line (from a given state, else the scene's initial
//! state) and continued across it; the bifurcation of the kind nearest the
//! line's middle is the point.
//!
//! Every later point continues the orbit of the point before ([`line`]): that
//! orbit is carried by Newton's method along a straight segment of the plane
//! to the corrector line, on the side of the curve it was continued from,
//! keeping its period, map and impact pattern, then continued along the line
//! across the curve; the first bifurcation of the kind that this orbit meets
//! there (for a grazing, the first change of its impact pattern, of the same
//! stops as before) is the point. A step whose orbit cannot be carried to its
//! line, or that finds no such bifurcation, or one farther from the
//! prediction than allowed, is refused, never taken as the point: the located
//! points do not depend on the step settings, only on the orbit.
//!
//! The curve is followed in two ways. While it can, it steps `b` by equal
//! steps and locates the point on the line of constant `b` (natural
//! continuation: the points fall on the requested values of `b`), the first
//! predicted along the curve's tangent (from a point located a sixteenth of a
//! step away), the others along the secant, each within half a window of its
//! prediction. Where that fails (the curve turns back in `b`, becomes too steep
//! for the line, or its orbit does not reach a window's width beyond it), it
//! goes on by pseudo-arclength: a predictor along the secant of the last two
//! points, in units of the plane's scales (`a` in window widths, `b` in steps),
//! and a corrector that locates the point on the line normal to the secant
//! through the prediction, the orbit carried to it a step's length from the
//! prediction and the point at most a step's length from it. Steps are halved
//! where the corrector is refused, down to a sixteenth; a refused sixteenth
//! ends the curve with why (its orbit grazes other stops, folds, changes its
//! pattern, or shows no bifurcation of the kind near the prediction).
//!
//! Codimension-two points are recorded where two bifurcations of the curve's
//! orbit meet on the curve: another kind located on the orbit within
//! [`CODIM2_TOL`] (a fraction of the line) of a curve point (e.g. where a PD
//! curve meets a grazing), where the curve ends at a bifurcation of its orbit
//! that stops it (a grazing of other stops, a fold; where a grazing curve's
//! orbit folds as it grazes, the meeting is extrapolated from points of the
//! curve near it, in `meet`), and where, between two
//! consecutive points, one more of the orbit's other multipliers (all but the
//! critical one, or pair) leaves or enters the unit circle: named after where
//! it crosses (`SN` at +1, `PD` at -1, `NS` off the real axis), placed by
//! linear interpolation of `|μ| - 1` between the two points. On a
//! Neimark–Sacker curve, the strong resonances `1:3` and `1:4` are recorded
//! where the critical pair `e^{±iθ}` of the period map passes θ = 2π/3 and
//! π/2 (placed by linear interpolation of θ); the resonances 1:1 and 1:2 are
//! where such a curve meets a fold (`NS-SN`) or a flip (`NS-PD`) as its pair
//! reaches +1 or −1, and a fold meeting a flip (`SN-PD`) is the fold–flip
//! point. Bifurcations of other orbits met on a line (past a change of the
//! impact pattern) are not the curve's.

mod line;
mod meet;
#[cfg(test)]
mod tests;

use crate::accuracy::Accuracy;
use crate::continuation::Located;
use crate::executor::run_cell;
use crate::floquet::Bifurcation;
use crate::flow::Method;
use crate::label::{MassLabel, Symmetry};
use crate::orbit::Orbit;
use crate::system::System;
use line::Path;
use num_complex::Complex64 as C64;
use scene::Named;

/// Points of the continuation across a corrector line: an even number, so
/// that the line's middle (the prediction) is not a grid point (a bifurcation
/// exactly on a grid point is neutral there, not a crossing).
const LINE_POINTS: usize = 40;

/// Two bifurcations closer than this (in units of the plane's scales, the
/// corrector line's half-width along `a`) form a codimension-two point.
pub const CODIM2_TOL: f64 = 1e-3;

/// Smallest step, as a fraction of the requested one.
const MIN_STEP: f64 = 1.0 / 256.0;

/// Largest turn of the curve within a step (between the tangent at its
/// start and the chord to its new point, in scaled units) before the step is
/// halved; at the smallest step a sharper turn (a corner of the curve) is
/// taken.
const MAX_TURN: f64 = std::f64::consts::PI / 6.0;

/// Where the orbit of a corrector line comes from.
#[derive(Debug, Clone, Copy)]
pub enum Start<'a> {
    /// A cell simulated from the scene's initial state.
    Fresh,
    /// A cell simulated from this state (e.g. a stored cell's final state).
    State(&'a [f64]),
    /// Newton's method from this orbit, keeping its map, period and impact
    /// pattern (no simulated cell: another orbit is never taken for it).
    Orbit(&'a Orbit),
}

/// The systems of a plane of two parameters `(a, b)` (`None`: not admissible).
pub type Plane2<'a> = dyn Fn(f64, f64) -> Option<System> + Sync + 'a;

/// How a curve is followed.
#[derive(Debug, Clone)]
pub struct Tracing {
    /// The bifurcation followed.
    pub kind: Bifurcation,
    /// Accuracy of the orbits.
    pub acc: Accuracy,
    /// Period of the orbit (default: the period its cell settles on).
    pub n: Option<usize>,
    /// Units of `a` and `b`: the half-width of a corrector line along `a`, and
    /// the step in `b`. Distances along the curve are measured in them.
    pub scale: [f64; 2],
    /// The region followed, `[[a_min, a_max], [b_min, b_max]]`: the curve ends
    /// where it leaves it.
    pub bounds: [[f64; 2]; 2],
    /// Largest number of points.
    pub max_points: usize,
}

/// A located point of a curve.
#[derive(Debug, Clone)]
pub struct CurvePoint {
    /// `a` there.
    pub a: f64,
    /// `b` there.
    pub b: f64,
    /// The bifurcation (its multipliers and critical multiplier).
    pub located: Located,
    /// The periodic orbit at the point (the start of the next one).
    pub orbit: Orbit,
    /// Where `orbit` is, `(a, b)`: the point itself, but for a fold the
    /// point of its corrector's continuation before it (at the fold Newton's
    /// method is singular), and for a grazing the last point where Newton's
    /// method reached the orbit keeping its impact pattern (next to the
    /// grazing it does not reach it from a prediction).
    pub orbit_at: [f64; 2],
    /// For a grazing, the orbit of its corrector's continuation nearest it
    /// at least a thousandth of the corrector path before it, and where
    /// that is: the next point's orbit is carried from there (from `orbit`,
    /// within about 1e-9 of the grazing, Newton's first iterate touches the
    /// stop and the carry fails at once). `None`: from `orbit`.
    pub carry_start: Option<(Orbit, [f64; 2])>,
    /// Other bifurcations of the orbit located on the same line (before its
    /// impact pattern changes): kind and position `(a, b)`.
    pub others: Vec<(Bifurcation, f64, f64)>,
    /// Unit vector (in `(a, b)`, scaled units) from the point towards the side
    /// of the curve its orbit was continued from: the next point's orbit is
    /// carried to its line on that side.
    pub side: [f64; 2],
    /// For a grazing: the stops whose impacts change across it (found by one
    /// map evaluation just past it), the same at every point of a curve; empty
    /// for other kinds, or where the change was not seen.
    pub grazes: Vec<usize>,
}

/// Where two bifurcations meet on a curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Codim2 {
    /// The curve's kind and the other, e.g. `PD-SN`, `PD-grazing`.
    pub kind: String,
    /// `a` there.
    pub a: f64,
    /// `b` there.
    pub b: f64,
}

/// A followed curve.
#[derive(Debug, Clone)]
pub struct Curve {
    /// Its kind.
    pub kind: Bifurcation,
    /// Points in order along the curve.
    pub points: Vec<CurvePoint>,
    /// Codimension-two points met, in order along the curve.
    pub codim2: Vec<Codim2>,
    /// Why it ended before its region's edge (`None`: it reached the edge in
    /// `b`).
    pub ended: Option<String>,
}

impl Curve {
    /// One curve of two followed from the same point in opposite directions:
    /// `back`'s points reversed, then `ahead`'s (their shared first point
    /// once); the codimension-two points in the same order, and the reasons
    /// either ended joined by `; `.
    pub fn join(back: Curve, ahead: Curve) -> Curve {
        let first = [ahead.points[0].a.to_bits(), ahead.points[0].b.to_bits()];
        // Both halves record the codimension-two points of the shared first point.
        let mut codim2: Vec<_> =
            back.codim2.into_iter().filter(|c| [c.a.to_bits(), c.b.to_bits()] != first).rev().collect();
        codim2.extend(ahead.codim2);
        let mut points: Vec<_> = back.points.into_iter().skip(1).rev().collect();
        points.extend(ahead.points);
        let ended = [back.ended, ahead.ended].into_iter().flatten().collect::<Vec<_>>();
        Curve { kind: ahead.kind, points, codim2, ended: (!ended.is_empty()).then(|| ended.join("; ")) }
    }
}

/// The labels of the motion a map shows on either side of a curve point:
/// fresh cells (from the scene's initial state) a quarter of the corrector
/// line away, below and above in `a` (or along the line's direction).
#[derive(Debug, Clone)]
pub struct Sides {
    /// Labels and symmetry below (towards smaller `a`).
    pub below: Option<(Vec<MassLabel>, Option<Symmetry>)>,
    /// Labels and symmetry above.
    pub above: Option<(Vec<MassLabel>, Option<Symmetry>)>,
}

/// Why a corrector line holds no bifurcation of the curve's kind, and the
/// other bifurcations it holds (kind and position `(a, b)`).
#[derive(Debug, Clone)]
pub struct Missed {
    /// What went wrong.
    pub why: String,
    /// Bifurcations of other kinds on the line.
    pub others: Vec<(Bifurcation, f64, f64)>,
}

impl std::fmt::Display for Missed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.why)
    }
}

impl Tracing {
    /// Locates the bifurcation nearest `(a, b)` along `a` (a line of constant
    /// `b`, half-width one unit of `a`), the orbit found from `start`.
    pub fn locate(&self, plane: &Plane2, a: f64, b: f64, start: Start) -> Result<CurvePoint, Missed> {
        self.locate_on(plane, Path::Line { origin: [a, b], direction: [1.0, 0.0] }, start)
    }

    /// Per kind of `kinds`, the bifurcation of that kind nearest `(a, b)`
    /// along `a` (or along `b`, `along_b`), each as [`Tracing::locate`] finds
    /// it with that kind, from continuations of the line shared by all the
    /// kinds (one per end of the line tried, not one per kind).
    pub fn locate_kinds(
        &self,
        plane: &Plane2,
        [a, b]: [f64; 2],
        along_b: bool,
        start: Start,
        kinds: &[Bifurcation],
    ) -> Vec<Result<CurvePoint, Missed>> {
        let direction = if along_b { [0.0, 1.0] } else { [1.0, 0.0] };
        self.locate_each(plane, Path::Line { origin: [a, b], direction }, start, kinds)
    }

    /// The bifurcation of the curve's kind of `from`'s orbit on the line
    /// through `at` along `direction` (in `(a, b)`, scaled units; half-width
    /// one unit): the orbit carried from `from` to the line, on `from`'s side
    /// of the curve, and continued across it, as a curve's steps locate their
    /// points (see [`line`]). A point of another curve located again from a
    /// point of this one shows whether the two curves are one.
    pub fn locate_from(
        &self,
        plane: &Plane2,
        from: &CurvePoint,
        at: [f64; 2],
        direction: [f64; 2],
    ) -> Result<CurvePoint, Missed> {
        let n = direction[0].hypot(direction[1]);
        let direction = [direction[0] / n, direction[1] / n];
        let span = Tracing::span(from, direction, 1.0);
        self.continue_on(plane, from, Path::Line { origin: at, direction }, span, None)
    }

    /// The labels on either side of `p`, along `a`.
    pub fn sides(&self, plane: &Plane2, p: &CurvePoint) -> Sides {
        let cell = |da: f64| {
            let sys = plane(p.a + da, p.b)?;
            let cell = run_cell(&sys, &self.acc, Method::Exact, &sys.model.initial_state());
            Some((cell.labels, cell.symmetry))
        };
        Sides { below: cell(-self.scale[0] / 4.0), above: cell(self.scale[0] / 4.0) }
    }

    /// The bifurcation of the curve's kind nearest the middle of `line`
    /// (half-width one scaled unit): the orbit found at one end, continued
    /// across; failing that, from the other end.
    fn locate_on(&self, plane: &Plane2, line: Path, start: Start) -> Result<CurvePoint, Missed> {
        self.locate_each(plane, line, start, &[self.kind]).pop().expect("one kind asked, one answer")
    }

    /// Follows the curve through `first` (a located point) from `b = first.b`
    /// towards `to` (infinite: until the curve ends), in steps of one unit of
    /// `b` while the curve allows, then by pseudo-arclength.
    pub fn follow(&self, plane: &Plane2, first: CurvePoint, to: f64) -> Curve {
        let sign = if to >= first.b { 1.0 } else { -1.0 };
        let initial = self.initial_tangent(plane, &first, [0.0, sign]);
        let mut curve = self.begin(first);
        if self.natural(plane, &mut curve, to, initial).is_err() {
            self.arclength(plane, &mut curve, initial);
        }
        curve
    }

    /// Follows the curve through `first` by pseudo-arclength only, leaving it
    /// in the direction of `towards` (in `(a, b)`, scaled units).
    pub fn follow_along(&self, plane: &Plane2, first: CurvePoint, towards: [f64; 2]) -> Curve {
        let initial = self.initial_tangent(plane, &first, towards);
        let mut curve = self.begin(first);
        self.arclength(plane, &mut curve, initial);
        curve
    }

    /// A curve of one point.
    fn begin(&self, first: CurvePoint) -> Curve {
        let mut curve = Curve { kind: self.kind, points: vec![first], codim2: Vec::new(), ended: None };
        self.record_coincidences(&mut curve, 0);
        curve
    }

    /// The unit tangent (scaled) of the curve at `first`, oriented along
    /// `towards`: the secant to the point of the curve on the line parallel to
    /// the one `first` was located on, [`MIN_STEP`] away in the direction of
    /// `towards`; `towards` itself where that point is not found.
    fn initial_tangent(&self, plane: &Plane2, first: &CurvePoint, towards: [f64; 2]) -> [f64; 2] {
        let unit = |v: [f64; 2]| {
            let n = v[0].hypot(v[1]);
            if n > 0.0 {
                [v[0] / n, v[1] / n]
            } else {
                [0.0, 1.0]
            }
        };
        let side = unit(first.side);
        let mut across = [-side[1], side[0]];
        if across[0] * towards[0] + across[1] * towards[1] < 0.0 {
            across = [-across[0], -across[1]];
        }
        let here = self.scaled(first);
        let middle = [here[0] + MIN_STEP * across[0], here[1] + MIN_STEP * across[1]];
        let line = Path::Line { origin: [middle[0] * self.scale[0], middle[1] * self.scale[1]], direction: side };
        match self.continue_on(plane, first, line, [1.0, -1.0], None) {
            Ok(p) => {
                let q = self.scaled(&p);
                unit([q[0] - here[0], q[1] - here[1]])
            }
            Err(_) => unit(towards),
        }
    }

    /// Natural continuation in `b` (steps of one unit, the first predicted
    /// along `initial`, the others along the secant): `Ok` when the curve
    /// reached `to` or ended, `Err` when a point could not be located (left
    /// to arclength).
    fn natural(&self, plane: &Plane2, curve: &mut Curve, to: f64, initial: [f64; 2]) -> Result<(), ()> {
        let b0 = curve.points[0].b;
        let sign = if to >= b0 { 1.0 } else { -1.0 };
        let steps = match to.is_finite() {
            // A last step shorter than one unit still reaches `to`.
            true if (to - b0).abs() > 0.0 => (((to - b0).abs() / self.scale[1]).round() as usize).max(1),
            true => 0,
            false => usize::MAX,
        };
        let b_at = |k: usize| match to.is_finite() {
            true => b0 + (to - b0) * k as f64 / steps as f64,
            false => b0 + sign * k as f64 * self.scale[1],
        };
        if initial[1].abs() < 0.1 {
            return Err(());
        }
        for k in 1..=steps {
            if curve.points.len() >= self.max_points {
                curve.ended = Some(format!("{} points", self.max_points));
                return Ok(());
            }
            let b = b_at(k);
            let n = curve.points.len();
            let last = &curve.points[n - 1];
            let guess = match n {
                1 => last.a + initial[0] / initial[1] * (b - last.b) / self.scale[1] * self.scale[0],
                _ => 2.0 * last.a - curve.points[n - 2].a,
            };
            // Half a window from the prediction at most: farther is another curve.
            let line = Path::Line { origin: [guess, b], direction: [1.0, 0.0] };
            match self.continue_on(plane, last, line, Tracing::span(last, [1.0, 0.0], 1.0), Some(0.5)) {
                Ok(p) if self.inside(&p) => {
                    curve.points.push(p);
                    self.after_step(curve);
                }
                Ok(_) => {
                    curve.ended = Some(format!("leaves the region after ({}, {})", last.a, last.b));
                    return Ok(());
                }
                Err(_) => return Err(()),
            }
        }
        Ok(())
    }

    /// Pseudo-arclength from the last points of `curve` (see the module doc),
    /// until it leaves the region, or ends where no step, down to the
    /// smallest, continues its orbit.
    fn arclength(&self, plane: &Plane2, curve: &mut Curve, initial: [f64; 2]) {
        let mut h = 1.0;
        while curve.points.len() < self.max_points {
            let tangent = self.tangent(curve, initial);
            match self.step(plane, curve, tangent, h) {
                Ok(p) if !self.inside(&p) => {
                    self.end_at_edge(plane, curve, &p);
                    return;
                }
                Ok(p) => {
                    curve.points.push(p);
                    self.after_step(curve);
                    h = (1.5 * h).min(1.0);
                }
                Err(_) if h > MIN_STEP => h /= 2.0,
                Err(missed) => match self.turn_corner(plane, curve, tangent, h) {
                    Some(p) if self.inside(&p) => {
                        curve.points.push(p);
                        self.after_step(curve);
                    }
                    _ => {
                        self.end_at_meeting(plane, curve, tangent, h, &missed);
                        return;
                    }
                },
            }
        }
        curve.ended = Some(format!("{} points", self.max_points));
    }

    /// One step of length `h` (scaled) from the end of `curve`, ahead along
    /// `tangent`: the point that continues its orbit on the arc of radius `h`
    /// around it, the orbit carried to the arc on its side of the curve and
    /// continued along the arc, turning towards `tangent`, across the curve
    /// ([`Tracing::continue_on`]). Where the curve bends, even by a corner,
    /// the arc finds it where a line normal to a lagging tangent would not.
    fn step(&self, plane: &Plane2, curve: &Curve, tangent: [f64; 2], h: f64) -> Result<CurvePoint, Missed> {
        let last = curve.points.last().expect("a curve has a point");
        self.step_from(plane, last, last.side, tangent, h)
    }

    /// [`Tracing::step`] from `last`, its orbit carried to the arc along
    /// `side` (a direction, scaled, into the side of the curve it lies on).
    fn step_from(
        &self,
        plane: &Plane2,
        last: &CurvePoint,
        side: [f64; 2],
        tangent: [f64; 2],
        h: f64,
    ) -> Result<CurvePoint, Missed> {
        let turn = if side[0] * tangent[1] - side[1] * tangent[0] < 0.0 { -1.0 } else { 1.0 };
        let from = side[1].atan2(side[0]);
        let arc = Path::Arc { center: [last.a, last.b], radius: h };
        let p = self.continue_on(plane, last, arc, [from, from + turn * std::f64::consts::PI], None)?;
        let (here, there) = (self.scaled(last), self.scaled(&p));
        let chord = [there[0] - here[0], there[1] - here[1]];
        let cos = (chord[0] * tangent[0] + chord[1] * tangent[1]) / chord[0].hypot(chord[1]);
        if h > MIN_STEP && cos < MAX_TURN.cos() {
            let why = format!("the curve turns by {:.0}° within a step", cos.clamp(-1.0, 1.0).acos().to_degrees());
            return Err(Missed { why, others: Vec::new() });
        }
        if h > MIN_STEP {
            self.bends_gently(plane, last, &p)?;
        }
        Ok(p)
    }

    /// Whether the curve between its points `last` and `p` bends no more than
    /// an arc turning by [`MAX_TURN`]: the point of `last`'s orbit on the
    /// line normal to the chord through its middle lies within that arc's
    /// sagitta of the chord. A step that passed a turn of the curve (a
    /// feature smaller than the step, e.g. a tongue of another motion)
    /// fails it.
    fn bends_gently(&self, plane: &Plane2, last: &CurvePoint, p: &CurvePoint) -> Result<(), Missed> {
        let (u, v) = (self.scaled(last), self.scaled(p));
        let chord = (v[0] - u[0]).hypot(v[1] - u[1]);
        let normal = [-(v[1] - u[1]) / chord, (v[0] - u[0]) / chord];
        let sagitta = 0.5 * chord * (0.5 * MAX_TURN).tan();
        let origin = [0.5 * (u[0] + v[0]) * self.scale[0], 0.5 * (u[1] + v[1]) * self.scale[1]];
        let [from, _] = Tracing::span(last, normal, 2.0 * sagitta);
        let line = Path::Line { origin, direction: normal };
        self.continue_on(plane, last, line, [from, -from], Some(sagitta)).map(|_| ())
    }

    /// Ends `curve` where a step left its region at `outside`: on the edge
    /// crossed (the line of constant `a` or `b` there, through the point
    /// where the segment to `outside` crosses it), its orbit continued to it
    /// as in a step. A curve ended on an edge of `b` reached it (`ended`
    /// stays `None`).
    fn end_at_edge(&self, plane: &Plane2, curve: &mut Curve, outside: &CurvePoint) {
        let last = curve.points.last().expect("a curve has a point");
        let (p, q) = ([last.a, last.b], [outside.a, outside.b]);
        // The first edge crossed from p to q: fraction along the segment, axis, value.
        let crossing = (0..2)
            .flat_map(|i| self.bounds[i].iter().map(move |&e| (i, e)))
            .filter(|&(i, e)| (p[i] - e) * (q[i] - e) <= 0.0 && (q[i] - p[i]).abs() > 0.0)
            .map(|(i, e)| ((e - p[i]) / (q[i] - p[i]), i, e))
            .min_by(|x, y| x.0.total_cmp(&y.0));
        let left = format!("leaves the region after ({}, {})", last.a, last.b);
        let Some((t, axis, edge)) = crossing else {
            curve.ended = Some(left);
            return;
        };
        let mut origin = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
        origin[axis] = edge;
        let direction = if axis == 1 { [1.0, 0.0] } else { [0.0, 1.0] };
        let line = Path::Line { origin, direction };
        match self.continue_on(plane, last, line, Tracing::span(last, direction, 1.0), Some(1.0)) {
            Ok(e) if self.inside(&e) => {
                let (a, b) = (e.a, e.b);
                curve.points.push(e);
                self.after_step(curve);
                curve.ended =
                    (axis == 0).then(|| format!("reaches the region's edge in its first parameter at ({a}, {b})"));
            }
            _ => curve.ended = Some(left),
        }
    }

    /// A smallest step `h` past a corner of the curve at its last point,
    /// where the side the step carries its orbit along (the previous
    /// corrector's normal) leaves the region of the orbit at once: the step
    /// again with that side turned by 30° and 60° either way.
    fn turn_corner(&self, plane: &Plane2, curve: &Curve, tangent: [f64; 2], h: f64) -> Option<CurvePoint> {
        let last = curve.points.last().expect("a curve has a point");
        let [x, y] = last.side;
        [30.0f64, -30.0, 60.0, -60.0].iter().find_map(|deg| {
            let (sin, cos) = deg.to_radians().sin_cos();
            self.step_from(plane, last, [x * cos - y * sin, x * sin + y * cos], tangent, h).ok()
        })
    }

    /// Ends `curve`, which cannot be followed a step `h` past its last point
    /// along `tangent` (`missed`: why, and the bifurcations of its orbit met
    /// on the last try). Where one of those lies within that step, the curve
    /// ends where they meet (a codimension-two point, e.g. a fold or doubling
    /// that meets a grazing, or two grazings): the last point of the curve
    /// before it is found by bisection of the step (twelve halvings), and the
    /// meeting recorded there; for a grazing curve meeting a fold, where the
    /// fold test function of its orbit extrapolates to zero
    /// ([`Tracing::fold_meeting`]; the bisection's point where that fails).
    /// The meeting supersedes one of its kind recorded near it. Otherwise it
    /// ends with why.
    fn end_at_meeting(&self, plane: &Plane2, curve: &mut Curve, tangent: [f64; 2], h: f64, missed: &Missed) {
        let p = curve.points.last().expect("a curve has a point");
        let here = self.scaled(p);
        let distance = |o: &(Bifurcation, f64, f64)| {
            ((o.1 / self.scale[0] - here[0]).powi(2) + (o.2 / self.scale[1] - here[1]).powi(2)).sqrt()
        };
        let meeting =
            missed.others.iter().filter(|o| distance(o) <= 2.0 * h).min_by(|x, y| distance(x).total_cmp(&distance(y)));
        let Some(&(kind, ..)) = meeting else {
            curve.ended = Some(format!("stops after ({}, {}), no step continues its orbit: {}", p.a, p.b, missed.why));
            return;
        };
        let (mut lo, mut hi, mut best) = (0.0, h, None);
        for _ in 0..12 {
            let mid = 0.5 * (lo + hi);
            match self.step(plane, curve, tangent, mid) {
                Ok(q) if self.inside(&q) => {
                    lo = mid;
                    best = Some(q);
                }
                _ => hi = mid,
            }
        }
        if let Some(q) = best {
            curve.points.push(q);
            self.after_step(curve);
        }
        let end = curve.points.last().expect("a curve has a point");
        let [a, b] = match (self.kind, kind) {
            (Bifurcation::Grazing, Bifurcation::SaddleNode) => {
                self.fold_meeting(plane, curve, self.tangent(curve, tangent)).unwrap_or([end.a, end.b])
            }
            _ => [end.a, end.b],
        };
        let name = format!("{}-{}", self.kind.name(), kind.name());
        curve.ended = Some(format!("ends where it meets a {} at ({a}, {b}) ({name})", kind.name()));
        let meeting = Codim2 { kind: name, a, b };
        // It supersedes one of its kind recorded near it (by a crossing).
        if curve.codim2.last().is_some_and(|d| self.near(d, &meeting)) {
            curve.codim2.pop();
        }
        curve.codim2.push(meeting);
    }

    /// Records a codimension-two point, once: not where the last one recorded
    /// is of the same kind and within [`CODIM2_TOL`] of it.
    fn record(&self, curve: &mut Curve, c: Codim2) {
        if !curve.codim2.last().is_some_and(|d| self.near(d, &c)) {
            curve.codim2.push(c);
        }
    }

    /// Whether `d` and `c` are of the same kind and within [`CODIM2_TOL`].
    fn near(&self, d: &Codim2, c: &Codim2) -> bool {
        d.kind == c.kind && ((d.a - c.a) / self.scale[0]).hypot((d.b - c.b) / self.scale[1]) <= CODIM2_TOL
    }

    /// A point in scaled units.
    fn scaled(&self, p: &CurvePoint) -> [f64; 2] {
        [p.a / self.scale[0], p.b / self.scale[1]]
    }

    /// The unit tangent (scaled) at the end of `curve`: of the parabola
    /// through its last three points (by chord length; where the curve turns
    /// fast, the secant lags behind it), the secant of its last two points
    /// where the curve turns by more than a right angle between them or has
    /// only two, or `initial` for a single point.
    fn tangent(&self, curve: &Curve, initial: [f64; 2]) -> [f64; 2] {
        let unit = |v: [f64; 2]| {
            let n = v[0].hypot(v[1]);
            (n > 0.0).then(|| [v[0] / n, v[1] / n])
        };
        let n = curve.points.len();
        let p: Vec<[f64; 2]> = curve.points[n.saturating_sub(3)..].iter().map(|p| self.scaled(p)).collect();
        let chord = |i: usize| unit([p[i + 1][0] - p[i][0], p[i + 1][1] - p[i][1]]);
        let t = match p.len() {
            3 => match (chord(0), chord(1)) {
                (Some(d1), Some(d2)) if d1[0] * d2[0] + d1[1] * d2[1] > 0.0 => {
                    let (s1, s2) =
                        ((p[1][0] - p[0][0]).hypot(p[1][1] - p[0][1]), (p[2][0] - p[1][0]).hypot(p[2][1] - p[1][1]));
                    let w = s2 / (s1 + s2);
                    unit([d2[0] + (d2[0] - d1[0]) * w, d2[1] + (d2[1] - d1[1]) * w])
                }
                (_, d2) => d2,
            },
            2 => chord(0),
            _ => unit(initial),
        };
        t.unwrap_or([0.0, 1.0])
    }

    fn inside(&self, p: &CurvePoint) -> bool {
        let [[a0, a1], [b0, b1]] = self.bounds;
        let tol = 1e-9;
        p.a >= a0 - tol * (1.0 + a0.abs())
            && p.a <= a1 + tol * (1.0 + a1.abs())
            && p.b >= b0 - tol * (1.0 + b0.abs())
            && p.b <= b1 + tol * (1.0 + b1.abs())
    }

    /// Codimension-two points of the newest point of `curve`: coincidences on
    /// its line, and crossings of the other multipliers since the point before.
    fn after_step(&self, curve: &mut Curve) {
        let n = curve.points.len();
        self.record_coincidences(curve, n - 1);
        let (p, q) = (&curve.points[n - 2], &curve.points[n - 1]);
        let found: Vec<Codim2> = self.crossing(p, q).into_iter().chain(self.resonances(p, q)).collect();
        for c in found {
            self.record(curve, c);
        }
    }

    /// The strong resonances 1:3 and 1:4 passed between two consecutive
    /// points `p` and `q` of a Neimark–Sacker curve: where the angle θ of
    /// the critical pair of multipliers of the period map passes 2π/3 or
    /// π/2 (linear in θ between them).
    fn resonances(&self, p: &CurvePoint, q: &CurvePoint) -> Vec<Codim2> {
        if self.kind != Bifurcation::NeimarkSacker {
            return Vec::new();
        }
        let (Some(tp), Some(tq)) = (rotation(&p.located), rotation(&q.located)) else { return Vec::new() };
        [(3.0, "1:3"), (4.0, "1:4")]
            .into_iter()
            .filter_map(|(order, name)| {
                let target = std::f64::consts::TAU / order;
                ((tp - target) * (tq - target) < 0.0).then(|| {
                    let t = (target - tp) / (tq - tp);
                    Codim2 { kind: name.to_string(), a: p.a + t * (q.a - p.a), b: p.b + t * (q.b - p.b) }
                })
            })
            .collect()
    }

    /// Other bifurcations located on the line of point `i`, within
    /// [`CODIM2_TOL`] of the line's length of it.
    fn record_coincidences(&self, curve: &mut Curve, i: usize) {
        let p = &curve.points[i];
        let close = |a: f64, b: f64| {
            let d = (((a - p.a) / self.scale[0]).powi(2) + ((b - p.b) / self.scale[1]).powi(2)).sqrt();
            d <= CODIM2_TOL
        };
        let found: Vec<Codim2> = p
            .others
            .iter()
            .filter(|o| close(o.1, o.2))
            .map(|o| Codim2 { kind: format!("{}-{}", self.kind.name(), o.0.name()), a: p.a, b: p.b })
            .collect();
        for c in found {
            self.record(curve, c);
        }
    }

    /// A second multiplier crossing the unit circle between points `p` and `q`.
    fn crossing(&self, p: &CurvePoint, q: &CurvePoint) -> Option<Codim2> {
        let (t, other) = crossed(&others(&p.located), &others(&q.located))?;
        Some(Codim2 {
            kind: format!("{}-{}", self.kind.name(), other.name()),
            a: p.a + t * (q.a - p.a),
            b: p.b + t * (q.b - p.b),
        })
    }
}

/// Where between two points (0 at the first, 1 at the second) one of the
/// multipliers `mp` of the first became one of `mq` of the second by
/// crossing the unit circle, and the kind of that crossing; `None` where as
/// many lie outside the circle at both. The kind is the multiplier's outside
/// the circle, on the side with more outside (the nearest the circle of
/// those): inside, a real multiplier that crossed −1 may already have met
/// another and left the real line as a complex pair (a 3-2-0 orbit of the
/// single stop on a grazing curve: −1.008 and −0.202 on one side, −0.428 ±
/// 0.146i on the other; a doubling, which a pair inside the circle alone
/// would call Neimark–Sacker). Where, by |μ| − 1 of the nearest the circle
/// on either side, linearly.
fn crossed(mp: &[C64], mq: &[C64]) -> Option<(f64, Bifurcation)> {
    let outside = |m: &[C64]| m.iter().filter(|z| z.norm() > 1.0).count();
    if mp.len() != mq.len() || outside(mp) == outside(mq) {
        return None;
    }
    let more = if outside(mp) > outside(mq) { mp } else { mq };
    let out = more.iter().copied().filter(|z| z.norm() > 1.0).min_by(|x, y| x.norm().total_cmp(&y.norm()))?;
    let near = |m: &[C64]| m.iter().copied().min_by(|x, y| (x.norm() - 1.0).abs().total_cmp(&(y.norm() - 1.0).abs()));
    let (fp, fq) = (near(mp)?.norm() - 1.0, near(mq)?.norm() - 1.0);
    let t = if (fp - fq).abs() > 0.0 { (fp / (fp - fq)).clamp(0.0, 1.0) } else { 0.5 };
    Some((t, crate::floquet::kind(out, false)))
}

/// The angle θ in (0, π) of the critical pair `e^{±iθ}` of the period map
/// at a located Neimark–Sacker bifurcation: of its multiplier in the upper
/// half plane nearest the unit circle (the solved map's critical one, or
/// its square on a half map). `None` without such a multiplier.
fn rotation(l: &Located) -> Option<f64> {
    l.multipliers
        .iter()
        .filter(|z| z.im > 0.0)
        .min_by(|x, y| (x.norm() - 1.0).abs().total_cmp(&(y.norm() - 1.0).abs()))
        .map(|z| z.arg())
}

/// The multipliers of the n-period map at a located bifurcation but the
/// critical one (and its conjugate, for a complex one).
fn others(l: &Located) -> Vec<C64> {
    let mut m = l.multipliers.clone();
    if l.kind == Bifurcation::Grazing || !l.critical.norm().is_finite() {
        return m;
    }
    // The critical multiplier is of the solved map; of the n-period map it is
    // that or its square (half map): remove the nearest of either.
    for target in [l.critical, l.critical.conj()] {
        let Some(i) = (0..m.len()).min_by(|&i, &j| {
            let d = |z: C64| (z - target).norm().min((z - target * target).norm());
            d(m[i]).total_cmp(&d(m[j]))
        }) else {
            break;
        };
        m.remove(i);
        if l.critical.im.abs() <= 1e-12 {
            break;
        }
    }
    m
}
