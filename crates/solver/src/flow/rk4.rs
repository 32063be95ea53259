//! Classic fourth-order Runge–Kutta with fixed step and step-back refinement,
//! the method of the literature: step `h` (0.01); when a guard changes sign over
//! a step, go back and divide the step by 10 until it is below `rk4_min_step`
//! (1e-10); the event is then placed at the end of that step. Grazing events
//! between two samples are missed, as in the literature. A guard that starts at
//! zero and moves away (just after an impact) counts as crossed when it falls
//! below its starting value less the contact tolerance, so that a bounce shorter
//! than one step is still caught at its landing. The forcing `sin φ`,
//! `cos φ` is evaluated exactly at each stage, not integrated.

use super::{guard_start, value_tol, Advance, Start};
use crate::accuracy::Accuracy;
use crate::mode::Mode;
use nalgebra::DVector;

/// Steps allowed in one advance before it is declared stalled.
const MAX_STEPS: usize = 50_000_000;

/// Advances `s0` for at most `horizon` in `mode` (see the module doc).
/// The state where it stops is written to `out` (of the length of `s0`).
pub fn advance(mode: &Mode, s0: &DVector<f64>, horizon: f64, acc: &Accuracy, out: &mut DVector<f64>) -> Advance {
    let a = &mode.aug;
    let dim = s0.len();
    let (isin, icos) = (dim - 3, dim - 2);
    let (sin0, cos0) = (s0[isin], s0[icos]);
    let omega = a[(isin, icos)];
    // The forcing `(sin φ, cos φ)` at time `u` of the advance, set into a state.
    let forcing = |u: f64| {
        let (su, cu) = (omega * u).sin_cos();
        (sin0 * cu + cos0 * su, cos0 * cu - sin0 * su)
    };
    let set = |s: &mut DVector<f64>, (sn, cs): (f64, f64)| {
        s[isin] = sn;
        s[icos] = cs;
    };
    // Derivative into a reused buffer: no allocation per step.
    let deriv = |s: &DVector<f64>, d: &mut DVector<f64>| {
        a.mul_to(s, d);
        d[isin] = 0.0;
        d[icos] = 0.0;
    };

    // A guard crosses when it falls below its threshold; at zero and approaching: an event now.
    let mut threshold = vec![0.0; mode.guards.len()];
    for (gi, g) in mode.guards.iter().enumerate() {
        match guard_start(acc, g, a, s0) {
            (Start::Clear, _, _) => {}
            (Start::Approaching, _, _) => {
                out.copy_from(s0);
                return Advance::Event { guard: gi, time: 0.0 };
            }
            (Start::Departing { .. }, value, magnitude) => {
                threshold[gi] = value.min(0.0) - value_tol(acc, g.kind.is_gap(), magnitude)
            }
        }
    }

    // A stage's state `s + c k` at the forcing `f` of its time.
    let stage = |tmp: &mut DVector<f64>, s: &DVector<f64>, c: f64, k: &DVector<f64>, f: (f64, f64)| {
        tmp.copy_from(s);
        tmp.axpy(c, k, 1.0);
        set(tmp, f);
    };
    let mut s = s0.clone();
    let zero = || DVector::zeros(dim);
    let (mut k1, mut k2, mut k3, mut k4, mut tmp, mut next) = (zero(), zero(), zero(), zero(), zero(), zero());
    let mut u = 0.0;
    let mut h = acc.rk4_step;
    for _ in 0..MAX_STEPS {
        let remaining = horizon - u;
        if remaining <= 0.0 {
            break;
        }
        let hh = h.min(remaining);
        // The last step lands exactly on the horizon.
        let t_next = if hh >= remaining { horizon } else { u + hh };
        let (mid, end) = (forcing(u + hh / 2.0), forcing(t_next));
        deriv(&s, &mut k1);
        stage(&mut tmp, &s, hh / 2.0, &k1, mid);
        deriv(&tmp, &mut k2);
        stage(&mut tmp, &s, hh / 2.0, &k2, mid);
        deriv(&tmp, &mut k3);
        stage(&mut tmp, &s, hh, &k3, end);
        deriv(&tmp, &mut k4);
        for i in 0..dim {
            next[i] = s[i] + (k1[i] + k2[i] * 2.0 + k3[i] * 2.0 + k4[i]) * (hh / 6.0);
        }
        set(&mut next, end);
        let crossed = mode
            .guards
            .iter()
            .enumerate()
            .filter(|&(gi, g)| g.row.dot(&next) < threshold[gi])
            .min_by(|a, b| a.1.row.dot(&next).total_cmp(&b.1.row.dot(&next)))
            .map(|(gi, _)| gi);
        match crossed {
            Some(gi) if hh <= acc.rk4_min_step => {
                out.copy_from(&next);
                return Advance::Event { guard: gi, time: t_next };
            }
            Some(_) => h = hh / 10.0,
            None => {
                std::mem::swap(&mut s, &mut next);
                u = t_next;
            }
        }
    }
    if u >= horizon {
        out.copy_from(&s);
        Advance::Horizon
    } else {
        Advance::Stalled
    }
}
