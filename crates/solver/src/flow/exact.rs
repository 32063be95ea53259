//! Exact flow with guaranteed event location (conservative advancement).
//!
//! Between events each guard is `g(u) = Σ_t Re(f_t(u) β_t)` (see
//! [`super::spectral`]). From the current time, the guard cannot vanish before
//! the first positive root of the lower bound `g + g' h - G₂ h²/2`, where `G₂`
//! bounds `|g''|` over the rest of the horizon from the modal amplitudes. Stepping
//! by that root never jumps over a root, including a grazing one (a gap dipping
//! to zero between samples), and converges quadratically onto transversal roots.
//! A guard starting at zero and moving away is masked for the time in which its
//! leading Taylor term provably dominates (`g >= g^(j) u^j/j! - G_{j+1} u^{j+1}/(j+1)!`).

use super::spectral::{bound, differentiate, evaluate};
use super::{classify_start, start_tolerances, Advance, Start};
use crate::accuracy::Accuracy;
use crate::mode::{GuardKind, Mode};
use nalgebra::DVector;
use num_complex::Complex64 as C64;

/// Steps allowed in one advance before it is declared stalled.
const MAX_STEPS: usize = 20_000;

/// Advances `s0` for at most `horizon` in `mode` (see the module doc).
pub fn advance(mode: &Mode, s0: &DVector<f64>, horizon: f64, acc: &Accuracy) -> Advance {
    let sp = &mode.spectral;
    let nt = sp.terms().len();
    let modal = sp.modal(s0);
    // beta[g][j]: coefficients of the j-th derivative of guard g, j = 0..=5.
    let beta: Vec<[Vec<C64>; 6]> = mode
        .guards
        .iter()
        .map(|g| {
            let b0 = modal.functional(&g.row);
            let b1 = differentiate(sp.terms(), &b0);
            let b2 = differentiate(sp.terms(), &b1);
            let b3 = differentiate(sp.terms(), &b2);
            let b4 = differentiate(sp.terms(), &b3);
            let b5 = differentiate(sp.terms(), &b4);
            [b0, b1, b2, b3, b4, b5]
        })
        .collect();
    let mut f = vec![C64::new(0.0, 0.0); nt];
    let mut fb = vec![0.0; nt];
    let mut masked_until = vec![0.0f64; mode.guards.len()];
    let mut u = 0.0f64;

    // Decide, at time u, whether guard gi is at contact and approaching (Some(true)),
    // at contact and departing (masks it; Some(false)), or clear (None).
    let contact = |gi: usize, f: &[C64], fb: &[f64], masked: &mut f64, u: f64| -> Option<bool> {
        let b = &beta[gi];
        let d = [
            evaluate(f, &b[0]),
            evaluate(f, &b[1]),
            evaluate(f, &b[2]),
            evaluate(f, &b[3]),
            evaluate(f, &b[4]),
        ];
        let scale = [
            0.0,
            bound(fb, &b[1]),
            bound(fb, &b[2]),
            bound(fb, &b[3]),
            bound(fb, &b[4]),
        ];
        let tol = start_tolerances(acc, mode.guards[gi].kind == GuardKind::Gap, &scale, &d);
        match classify_start(&d, &tol) {
            Start::Clear => None,
            Start::Approaching => Some(true),
            Start::Departing { order, rate } => {
                let escape = if order == 0 {
                    acc.event_tol * 1e3
                } else {
                    let g_next = bound(fb, &b[order + 1]);
                    if g_next > 0.0 {
                        (order + 1) as f64 * rate / g_next
                    } else {
                        horizon
                    }
                };
                *masked = u + 0.5 * escape.max(acc.event_tol);
                Some(false)
            }
        }
    };

    sp.factors(0.0, &mut f);
    sp.factor_bounds(0.0, horizon, &mut fb);
    for gi in 0..mode.guards.len() {
        if contact(gi, &f, &fb, &mut masked_until[gi], 0.0) == Some(true) {
            return Advance::Event {
                guard: gi,
                time: 0.0,
                state: s0.clone(),
            };
        }
    }

    for _ in 0..MAX_STEPS {
        if u > 0.0 {
            sp.factors(u, &mut f);
            sp.factor_bounds(u, horizon, &mut fb);
        }
        let mut h = horizon - u;
        let mut which = None;
        for gi in 0..mode.guards.len() {
            let cand = if u < masked_until[gi] {
                masked_until[gi] - u
            } else {
                let b = &beta[gi];
                let g = evaluate(&f, &b[0]);
                let gd = evaluate(&f, &b[1]);
                if g <= acc.contact_tol {
                    match contact(gi, &f, &fb, &mut masked_until[gi], u) {
                        Some(true) => {
                            return Advance::Event {
                                guard: gi,
                                time: u,
                                state: modal.state(&f),
                            }
                        }
                        _ => masked_until[gi] - u,
                    }
                } else {
                    let g2 = bound(&fb, &b[2]);
                    let root = if g2 > 0.0 {
                        (gd + (gd * gd + 2.0 * g2 * g).sqrt()) / g2
                    } else if gd < 0.0 {
                        g / -gd
                    } else {
                        f64::INFINITY
                    };
                    if root < h && root <= acc.event_tol {
                        // Converged onto the root: the event is within event_tol.
                        let t = u + root;
                        sp.factors(t, &mut f);
                        return Advance::Event {
                            guard: gi,
                            time: t,
                            state: modal.state(&f),
                        };
                    }
                    root
                }
            };
            if cand < h {
                h = cand;
                which = Some(gi);
            }
        }
        if which.is_none() {
            sp.factors(horizon, &mut f);
            return Advance::Horizon(modal.state(&f));
        }
        u += h;
    }
    Advance::Stalled
}
