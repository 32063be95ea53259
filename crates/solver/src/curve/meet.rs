//! Where a grazing curve meets a fold of its own orbit (`grazing-SN`),
//! located from points of the curve rather than from where its steps stop.
//!
//! Along a grazing curve the fold test function `f = 1 - Re μ` of its orbit
//! ([`fold_test`]) falls to zero, linearly in arclength, where the orbit
//! folds as it grazes: the meeting. Within [`FOLD_MARGIN`] of it Newton's
//! method cannot tell the grazing from the fold (the fold is taken for a
//! change of pattern), so the curve takes no point there; the meeting is the
//! zero of `f`, extrapolated from three points of the curve at `f` near
//! [`FIT_TARGETS`] (reached from its last point by secant steps along the
//! curve) by quadratic interpolation of `a` and `b` in `f`. Each of those
//! points is located on the curve to [`crate::continuation::PARAM_TOL`], so
//! the meeting depends on the curve only, not on the step settings.

use super::{Curve, CurvePoint, Plane2, Tracing};
use crate::orbit::Orbit;

/// A grazing whose orbit's fold test function [`fold_test`] has fallen below
/// this (from above it at the point before) is not a point of the curve: the
/// orbit folds there as it grazes.
pub(super) const FOLD_MARGIN: f64 = 1e-4;

/// The values of [`fold_test`] aimed at by the points the meeting is
/// extrapolated from: far enough from zero for Newton's method, near enough
/// for quadratic extrapolation to 1e-8 of the curve's units.
const FIT_TARGETS: [f64; 3] = [8.0 * FOLD_MARGIN, 4.0 * FOLD_MARGIN, 2.0 * FOLD_MARGIN];

/// The fold test function of `o`: `1 - Re μ` for the multiplier μ of its
/// solved map nearest +1 (dimensionless; positive on the stable side of a
/// fold, zero at it; `+∞` without multipliers).
pub(super) fn fold_test(o: &Orbit) -> f64 {
    let one = num_complex::Complex64::new(1.0, 0.0);
    o.map_multipliers
        .iter()
        .min_by(|x, y| (**x - one).norm().total_cmp(&(**y - one).norm()))
        .map_or(f64::INFINITY, |m| 1.0 - m.re)
}

/// The value at `x = 0` of the quadratic through the three points `(x, y)`.
fn quadratic_at_zero(p: &[(f64, f64); 3]) -> f64 {
    (0..3)
        .map(|i| {
            let others = (0..3).filter(|&j| j != i);
            p[i].1 * others.map(|j| p[j].0 / (p[j].0 - p[i].0)).product::<f64>()
        })
        .sum()
}

impl Tracing {
    /// Where the grazing curve `curve` meets the fold of its orbit, `(a, b)`
    /// (see the module doc): the zero of [`fold_test`] extrapolated from
    /// points of the curve stepped to from its last point (by secant on the
    /// distance along the curve), forward along `tangent` or back; the last
    /// point itself for a target it is within a quarter of. `None` where its
    /// last point's orbit is not on the stable side of the fold by
    /// [`FOLD_MARGIN`], a point is not located, or the test function does
    /// not fall steadily towards the meeting.
    pub(super) fn fold_meeting(&self, plane: &Plane2, curve: &Curve, tangent: [f64; 2]) -> Option<[f64; 2]> {
        let [.., prev, p] = &curve.points[..] else { return None };
        let fp = fold_test(&p.orbit);
        // The fall of the test function per scaled unit of distance along the curve.
        let mut slope = (fold_test(&prev.orbit) - fp) / self.distance(prev, p);
        if fp < FOLD_MARGIN || !(slope > 0.0 && slope.is_finite()) {
            return None;
        }
        let mut fit = [(0.0, [0.0; 2]); 3];
        for (k, target) in FIT_TARGETS.into_iter().enumerate() {
            fit[k] = if (fp - target).abs() <= 0.25 * target {
                (fp, [p.a, p.b])
            } else {
                let h = (fp - target) / slope;
                let q = self.along(plane, p, tangent, h)?;
                let fq = fold_test(&q.orbit);
                slope = (fp - fq) / h;
                (fq, [q.a, q.b])
            };
        }
        let falls = fit[0].0 > fit[1].0 && fit[1].0 > fit[2].0 && fit[2].0 > 0.0;
        let at = |i: usize| quadratic_at_zero(&fit.map(|(f, x)| (f, x[i])));
        falls.then(|| [at(0), at(1)])
    }

    /// The point of the curve a signed distance `h` (scaled) from its point
    /// `p`: ahead along `tangent` where positive, back where negative.
    fn along(&self, plane: &Plane2, p: &CurvePoint, tangent: [f64; 2], h: f64) -> Option<CurvePoint> {
        let towards = if h >= 0.0 { tangent } else { [-tangent[0], -tangent[1]] };
        self.step_from(plane, p, p.side, towards, h.abs()).ok()
    }

    /// The distance of `p` and `q` in scaled units.
    fn distance(&self, p: &CurvePoint, q: &CurvePoint) -> f64 {
        let (u, v) = (self.scaled(p), self.scaled(q));
        (u[0] - v[0]).hypot(u[1] - v[1])
    }
}
