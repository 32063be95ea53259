//! The extremes of a function of the state within one segment of the exact
//! flow, from its closed form ([`Segment::state`]): what the quantities of
//! the steady motion and the margins of a grazing measure.

use crate::simulate::Segment;
use nalgebra::DVector;

/// The largest value of `f` (of the segment, as it stands at a time, and
/// the state there) on `[a, b]` by Brent's method (parabolic steps,
/// golden-section ones where they stall): the value's error is quadratic in
/// the time's, so at rounding once the time is known to `√ε`.
pub(crate) fn peak(
    seg: &mut Segment<'_>,
    (a, b): (f64, f64),
    y: &mut DVector<f64>,
    f: impl Fn(&Segment<'_>, &DVector<f64>) -> f64,
) -> f64 {
    const C: f64 = 0.381_966_011_250_105_1;
    let mut g = |u: f64, y: &mut DVector<f64>| {
        seg.state(u, y);
        -f(seg, y)
    };
    let (mut a, mut b) = (a, b);
    let mut x = a + C * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = g(x, y);
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e): (f64, f64) = (0.0, 0.0);
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        let tol = 1.5e-8 * x.abs().max(1.0);
        if (x - m).abs() <= 2.0 * tol - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol {
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - a < 2.0 * tol || b - u < 2.0 * tol {
                    d = if m > x { tol } else { -tol };
                }
                golden = false;
            }
        }
        if golden {
            e = if x < m { b - x } else { a - x };
            d = C * e;
        }
        let u = if d.abs() >= tol { x + d } else { x + tol.copysign(d) };
        let fu = g(u, y);
        if fu <= fx {
            if u < x {
                b = x;
            } else {
                a = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w.to_bits() == x.to_bits() {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v.to_bits() == x.to_bits() || v.to_bits() == w.to_bits() {
                (v, fv) = (u, fu);
            }
        }
    }
    -fx
}
