//! Bifurcation curves in a plane of two parameters `(a, b)`.
//!
//! A point of a curve is a bifurcation of one kind (PD, SN, PF, NS, grazing)
//! located by one-parameter continuation ([`crate::continuation::follow`])
//! along a short line of the plane: the orbit is found at one end of the
//! line (from a given state, else the scene's initial state) and continued
//! across it, and the bifurcation of the kind nearest the line's middle is
//! located to [`crate::continuation::PARAM_TOL`] by the exact-Jacobian test
//! functions of `continue`.
//!
//! The curve is followed in two ways. While it can, it steps `b` by equal
//! steps and locates the point on the line of constant `b` (natural
//! continuation: the points fall on the requested values of `b`). Where that
//! fails (the curve turns back in `b`, or becomes too steep for the line), it
//! goes on by pseudo-arclength: a predictor along the secant of the last two
//! points, in units of the plane's scales (`a` in window widths, `b` in steps),
//! and a corrector that locates the point on the line normal to the secant
//! through the prediction. Steps are halved where the corrector fails, down
//! to a sixteenth.
//!
//! Codimension-two points are recorded where two bifurcations meet on the
//! curve: another kind located within [`CODIM2_TOL`] (a fraction of the line)
//! of a curve point (e.g. where a PD curve meets a grazing), and where, between
//! two consecutive points, one more of the orbit's other multipliers (all but
//! the critical one, or pair) leaves or enters the unit circle: named after
//! where it crosses (`SN` at +1, `PD` at -1, `NS` off the real axis), placed by
//! linear interpolation of `|μ| - 1` between the two points.

use crate::accuracy::Accuracy;
use crate::continuation::{follow, Branch, Located};
use crate::executor::run_cell;
use crate::floquet::Bifurcation;
use crate::flow::Method;
use crate::label::{MassLabel, Symmetry};
use crate::orbit::{orbit_of_cell, solve_orbit, Orbit};
use crate::system::System;
use num_complex::Complex64 as C64;

/// Points of the continuation across a corrector line: an even number, so
/// that the line's middle (the prediction) is not a grid point (a bifurcation
/// exactly on a grid point is neutral there, not a crossing).
const LINE_POINTS: usize = 40;

/// Two bifurcations closer than this (in units of the plane's scales, the
/// corrector line's half-width along `a`) form a codimension-two point.
pub const CODIM2_TOL: f64 = 1e-3;

/// Smallest step, as a fraction of the requested one.
const MIN_STEP: f64 = 1.0 / 16.0;

/// Where the orbit of a corrector line comes from.
#[derive(Debug, Clone, Copy)]
pub enum Start<'a> {
    /// A cell simulated from the scene's initial state.
    Fresh,
    /// A cell simulated from this state (e.g. a stored cell's final state).
    State(&'a [f64]),
    /// Newton's method from this orbit (the previous point's), keeping its
    /// map, period and impact pattern; failing that, a cell from its state.
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
    /// Other bifurcations located on the same line: kind and position `(a, b)`.
    pub others: Vec<(Bifurcation, f64, f64)>,
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

/// A line of the plane: `(a, b) = origin + s · direction · scale`.
#[derive(Debug, Clone, Copy)]
struct Line {
    origin: [f64; 2],
    /// Unit vector in scaled units.
    direction: [f64; 2],
}

impl Line {
    fn at(&self, s: f64, scale: [f64; 2]) -> [f64; 2] {
        [self.origin[0] + s * self.direction[0] * scale[0], self.origin[1] + s * self.direction[1] * scale[1]]
    }
}

impl Tracing {
    /// Locates the bifurcation nearest `(a, b)` along `a` (a line of constant
    /// `b`, half-width one unit of `a`), the orbit found from `start`.
    pub fn locate(&self, plane: &Plane2, a: f64, b: f64, start: Start) -> Result<CurvePoint, Missed> {
        self.locate_on(plane, Line { origin: [a, b], direction: [1.0, 0.0] }, start)
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
        self.locate_each(plane, Line { origin: [a, b], direction }, start, kinds)
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
    fn locate_on(&self, plane: &Plane2, line: Line, start: Start) -> Result<CurvePoint, Missed> {
        self.locate_each(plane, line, start, &[self.kind]).pop().expect("one kind asked, one answer")
    }

    /// [`Tracing::locate_on`] for each of `kinds`: the continuation from an
    /// end of the line is run once, when a kind first needs it, and serves
    /// every kind.
    fn locate_each(
        &self,
        plane: &Plane2,
        line: Line,
        start: Start,
        kinds: &[Bifurcation],
    ) -> Vec<Result<CurvePoint, Missed>> {
        let family = |s: f64| {
            let [a, b] = line.at(s, self.scale);
            plane(a, b)
        };
        let at = |o: &Located| {
            let [oa, ob] = line.at(o.value, self.scale);
            (o.kind, oa, ob)
        };
        let run = |(from, to): (f64, f64)| -> Option<Branch> {
            let sys = family(from)?;
            let orbit = self.orbit_at(&sys, start)?;
            let values: Vec<f64> =
                (0..LINE_POINTS).map(|i| from + (to - from) * i as f64 / (LINE_POINTS - 1) as f64).collect();
            Some(follow(&family, &self.acc, &values, orbit))
        };
        // From the upper end; from the lower one only for kinds it lacks.
        let first = run((1.0, -1.0));
        let holds = |k: Bifurcation| first.as_ref().is_some_and(|b| b.bifurcations.iter().any(|x| x.kind == k));
        let second = if kinds.iter().all(|&k| holds(k)) { None } else { run((-1.0, 1.0)) };
        let branches = [first, second];
        kinds
            .iter()
            .map(|&kind| {
                let mut seen = Vec::new();
                for branch in branches.iter().flatten() {
                    let nearest = |k: Bifurcation| {
                        branch
                            .bifurcations
                            .iter()
                            .filter(|b| b.kind == k)
                            .min_by(|x, y| x.value.abs().total_cmp(&y.value.abs()))
                    };
                    let Some(best) = nearest(kind) else {
                        seen.extend(branch.bifurcations.iter().map(at));
                        continue;
                    };
                    let [a, b] = line.at(best.value, self.scale);
                    let orbit = branch
                        .points
                        .iter()
                        .min_by(|p, q| (p.value - best.value).abs().total_cmp(&(q.value - best.value).abs()))
                        .expect("a branch has its start")
                        .orbit
                        .clone();
                    let others = branch.bifurcations.iter().filter(|o| o.kind != kind).map(at).collect();
                    return Ok(CurvePoint { a, b, located: best.clone(), orbit, others });
                }
                let [a, b] = line.origin;
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
            Start::Orbit(o) => {
                let x = &o.solution.x;
                solve_orbit(sys, &self.acc, x, o.map, o.n, Some(&o.solution.pattern))
                    .ok()
                    .or_else(|| cell(x.as_slice()))
            }
        }
    }

    /// Follows the curve through `first` (a located point) from `b = first.b`
    /// towards the end of the region in `b` in the direction of `to`, in steps
    /// of one unit of `b` while the curve allows, then by pseudo-arclength.
    pub fn follow(&self, plane: &Plane2, first: CurvePoint, to: f64) -> Curve {
        let sign = if to >= first.b { 1.0 } else { -1.0 };
        let mut curve = self.begin(first);
        if self.natural(plane, &mut curve, to).is_err() {
            self.arclength(plane, &mut curve, [0.0, sign]);
        }
        curve
    }

    /// Follows the curve through `first` by pseudo-arclength only, leaving it
    /// along `tangent` (in `(a, b)`, scaled units).
    pub fn follow_along(&self, plane: &Plane2, first: CurvePoint, tangent: [f64; 2]) -> Curve {
        let mut curve = self.begin(first);
        self.arclength(plane, &mut curve, tangent);
        curve
    }

    /// A curve of one point.
    fn begin(&self, first: CurvePoint) -> Curve {
        let mut curve = Curve { kind: self.kind, points: vec![first], codim2: Vec::new(), ended: None };
        self.record_coincidences(&mut curve, 0);
        curve
    }

    /// Natural continuation in `b`: `Ok` when the curve reached `to`, `Err`
    /// when a point could not be located (left to arclength).
    fn natural(&self, plane: &Plane2, curve: &mut Curve, to: f64) -> Result<(), ()> {
        let b0 = curve.points[0].b;
        let steps = ((to - b0).abs() / self.scale[1]).round() as usize;
        for k in 1..=steps {
            if curve.points.len() >= self.max_points {
                curve.ended = Some(format!("{} points", self.max_points));
                return Ok(());
            }
            let b = b0 + (to - b0) * k as f64 / steps as f64;
            let n = curve.points.len();
            let guess = match n {
                1 => curve.points[0].a,
                _ => 2.0 * curve.points[n - 1].a - curve.points[n - 2].a,
            };
            let last = &curve.points[n - 1];
            // A point far from a secant prediction, or of another orbit, is on
            // another curve: left to arclength.
            let near = |p: &CurvePoint| n == 1 || (p.a - guess).abs() <= 0.5 * self.scale[0];
            match self.locate(plane, guess, b, Start::Orbit(&last.orbit)) {
                Ok(p) if !near(&p) || !self.continues(last, &p) => return Err(()),
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
    /// until it leaves the region or a point cannot be located.
    fn arclength(&self, plane: &Plane2, curve: &mut Curve, initial: [f64; 2]) {
        let mut h = 1.0;
        while curve.points.len() < self.max_points {
            let tangent = self.tangent(curve, initial);
            match self.step(plane, curve, tangent, h) {
                Ok(p) if !self.inside(&p) => {
                    let last = curve.points.last().expect("a curve has a point");
                    curve.ended = Some(format!("leaves the region after ({}, {})", last.a, last.b));
                    return;
                }
                Ok(p) => {
                    curve.points.push(p);
                    self.after_step(curve);
                    h = (1.5 * h).min(1.0);
                }
                Err(_) if h > MIN_STEP => h /= 2.0,
                Err(others) => {
                    self.end_at_meeting(plane, curve, tangent, h, &others);
                    return;
                }
            }
        }
        curve.ended = Some(format!("{} points", self.max_points));
    }

    /// One pseudo-arclength step of length `h` (scaled) along `tangent` from
    /// the end of `curve`: the point located on the line normal to the
    /// tangent through the prediction, when it continues the curve forwards
    /// within two steps; else the other bifurcations found on that line.
    fn step(
        &self,
        plane: &Plane2,
        curve: &Curve,
        tangent: [f64; 2],
        h: f64,
    ) -> Result<CurvePoint, Vec<(Bifurcation, f64, f64)>> {
        let last = curve.points.last().expect("a curve has a point");
        let here = self.scaled(last);
        let predicted = [here[0] + h * tangent[0], here[1] + h * tangent[1]];
        let origin = [predicted[0] * self.scale[0], predicted[1] * self.scale[1]];
        let line = Line { origin, direction: [-tangent[1], tangent[0]] };
        let p = self.locate_on(plane, line, Start::Orbit(&last.orbit)).map_err(|m| m.others)?;
        let s = self.scaled(&p);
        let ahead = (s[0] - here[0]) * tangent[0] + (s[1] - here[1]) * tangent[1];
        let distance = ((s[0] - here[0]).powi(2) + (s[1] - here[1]).powi(2)).sqrt();
        if self.continues(last, &p) && ahead > 0.25 * h && distance < 2.0 * h {
            Ok(p)
        } else {
            Err(Vec::new())
        }
    }

    /// Ends `curve`, which cannot be followed a step `h` past its last point
    /// along `tangent`. Where another bifurcation found on the last line tried
    /// lies within that step, the curve ends where they meet (a
    /// codimension-two point, e.g. a fold or doubling that meets a grazing):
    /// the last point of the curve before it is found by bisection of the
    /// step (twelve halvings), and the meeting recorded there.
    fn end_at_meeting(
        &self,
        plane: &Plane2,
        curve: &mut Curve,
        tangent: [f64; 2],
        h: f64,
        others: &[(Bifurcation, f64, f64)],
    ) {
        let p = curve.points.last().expect("a curve has a point");
        let here = self.scaled(p);
        let distance = |o: &(Bifurcation, f64, f64)| {
            ((o.1 / self.scale[0] - here[0]).powi(2) + (o.2 / self.scale[1] - here[1]).powi(2)).sqrt()
        };
        let meeting =
            others.iter().filter(|o| distance(o) <= 2.0 * h).min_by(|x, y| distance(x).total_cmp(&distance(y)));
        let Some(&(kind, ..)) = meeting else {
            curve.ended = Some(format!("no {} found beyond ({}, {})", self.kind.name(), p.a, p.b));
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
        let name = format!("{}-{}", self.kind.name(), kind.name());
        curve.ended = Some(format!("ends where it meets a {} at ({}, {}) ({name})", kind.name(), end.a, end.b));
        curve.codim2.push(Codim2 { kind: name, a: end.a, b: end.b });
    }

    /// Whether `p` lies on the curve of `prev`: the same orbit (period, map
    /// and impact pattern), but for grazing curves, where the pattern changes
    /// across the curve.
    fn continues(&self, prev: &CurvePoint, p: &CurvePoint) -> bool {
        let (o, q) = (&prev.orbit, &p.orbit);
        self.kind == Bifurcation::Grazing || (o.n == q.n && o.map == q.map && o.solution.pattern == q.solution.pattern)
    }

    /// A point in scaled units.
    fn scaled(&self, p: &CurvePoint) -> [f64; 2] {
        [p.a / self.scale[0], p.b / self.scale[1]]
    }

    /// The unit tangent (scaled) at the end of `curve`: the secant of its last
    /// two points, or `initial` (normalised) for a single point.
    fn tangent(&self, curve: &Curve, initial: [f64; 2]) -> [f64; 2] {
        let n = curve.points.len();
        let (da, db) = if n < 2 {
            (initial[0], initial[1])
        } else {
            let (p, q) = (self.scaled(&curve.points[n - 2]), self.scaled(&curve.points[n - 1]));
            (q[0] - p[0], q[1] - p[1])
        };
        let norm = (da * da + db * db).sqrt();
        if norm > 0.0 {
            [da / norm, db / norm]
        } else {
            [0.0, 1.0]
        }
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
        if let Some(c) = self.crossing(p, q) {
            curve.codim2.push(c);
        }
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
        curve.codim2.extend(found);
    }

    /// A second multiplier crossing the unit circle between points `p` and `q`.
    fn crossing(&self, p: &CurvePoint, q: &CurvePoint) -> Option<Codim2> {
        let (mp, mq) = (others(&p.located), others(&q.located));
        let outside = |m: &[C64]| m.iter().filter(|z| z.norm() > 1.0).count();
        if mp.len() != mq.len() || outside(&mp) == outside(&mq) {
            return None;
        }
        // The multiplier nearest the unit circle at q crossed; where, by |μ| - 1.
        let near =
            |m: &[C64]| m.iter().copied().min_by(|x, y| (x.norm() - 1.0).abs().total_cmp(&(y.norm() - 1.0).abs()));
        let (zp, zq) = (near(&mp)?, near(&mq)?);
        let (fp, fq) = (zp.norm() - 1.0, zq.norm() - 1.0);
        let t = if (fp - fq).abs() > 0.0 { (fp / (fp - fq)).clamp(0.0, 1.0) } else { 0.5 };
        let other = crate::floquet::kind(zq, false);
        Some(Codim2 {
            kind: format!("{}-{}", self.kind.name(), other.name()),
            a: p.a + t * (q.a - p.a),
            b: p.b + t * (q.b - p.b),
        })
    }
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
