//! Exact flow with guaranteed event location (conservative advancement).
//!
//! Between events each guard is `g(u) = Σ_t Re(f_t(u) β_t)` (see
//! [`crate::spectral`]). From the current time, the guard cannot vanish before
//! the first positive root of the lower bound `g + g' h - G₂ h²/2`, where `G₂`
//! bounds `|g''|` over the rest of the horizon from the modal amplitudes. Stepping
//! by that root never jumps over a root, including a grazing one (a gap dipping
//! to zero between samples), and converges quadratically onto transversal roots.
//! (A cubic bound with the true curvature was measured: its steps are not long
//! enough to pay for finding its root.) A guard whose constant part exceeds the
//! bound of everything that varies cannot vanish before the horizon and is not
//! looked at again in this segment. A guard starting at zero and moving away
//! is masked for the time in which its leading Taylor term provably dominates
//! (`g >= g^(j) u^j/j! - G_{j+1} u^{j+1}/(j+1)!`).
//!
//! Cost, for the next engineer: an advance is prepared once
//! (`Workspace::prepare`: modal coefficients of the start, each guard's terms
//! and bounds), then every step pays one exponential factor per eigenvalue
//! (libm `exp` and `sincos`, the largest single cost) and one pass over each
//! watched guard's terms; a guard at contact is classified out of line
//! (`at_contact`). Every sum is taken in a fixed order, so results are
//! bit for bit reproducible; a change that reorders one changes the last bits
//! of every atlas (the snapshot test, `tests/data/snapshot.*`, will say so).

use super::{classify_start, derivative_tol, start_tolerances, value_tol, Advance, Start};
use crate::accuracy::Accuracy;
use crate::mode::Mode;
use crate::spectral::{bound, differentiate_into, evaluate, Modal, Term};
use nalgebra::DVector;
use num_complex::Complex64 as C64;

/// Steps allowed in one advance before it is declared stalled, plus
/// [`STEPS_PER_OSCILLATION`] for every oscillation of the fastest mode over the
/// horizon (a stiff light mass under slow forcing oscillates thousands of times
/// per period, and conservative advancement needs a few steps for each).
const MAX_STEPS: usize = 20_000;
/// Extra steps allowed per oscillation of the fastest mode.
const STEPS_PER_OSCILLATION: f64 = 64.0;
/// Derivative levels kept per guard: value, rate, acceleration.
const LEVELS: usize = 3;

/// One term of one guard, as the step loop reads it: the coefficients of the
/// guard and of its rate, and the moduli (`|re| + |im|`, an upper bound of the
/// modulus) of the guard's coefficient (0 for a constant term, which enters the
/// global bound by value) and of its acceleration's (for `G₂`).
#[derive(Debug, Clone, Copy, Default)]
struct Coef {
    value: C64,
    rate: C64,
    varying: f64,
    accel: f64,
}

/// What the step loop keeps of one guard between steps.
#[derive(Debug, Clone, Copy, Default)]
struct Watch {
    /// Time before which the guard provably stays positive.
    masked: f64,
    /// Value below which it counts as zero ([`value_tol`]).
    zero: f64,
    /// Its constant part (the constant terms, which do not vary).
    constant: f64,
    /// `|row|·|s0|`, the magnitude of the guard.
    magnitude: f64,
}

/// Buffers reused by every advance of a simulation (no allocation once warm).
#[derive(Debug, Clone, Default)]
pub struct Workspace {
    modal: Modal,
    f: Vec<C64>,
    fb: Vec<f64>,
    /// Per guard: coefficients of the guard, its rate and its acceleration.
    beta: Vec<C64>,
    /// Per guard and term: what the step loop reads (see [`Coef`]).
    coef: Vec<Coef>,
    watch: Vec<Watch>,
    /// `|s0|` entrywise.
    start_abs: DVector<f64>,
    high: Vec<C64>,
    high_moduli: Vec<f64>,
    /// The time (since the start of the last advance) of the factors in `f`:
    /// where that advance stopped, or the last sample taken ([`Workspace::state_at`]).
    at: Option<f64>,
}

impl Workspace {
    /// Sizes the buffers for `mode` and computes, from the start `s0`, the modal
    /// coefficients and each guard's coefficients, bounds and tolerances. Out of
    /// line: once per advance, against the step loop's many iterations.
    #[inline(never)]
    fn prepare(&mut self, mode: &Mode, s0: &DVector<f64>, acc: &Accuracy) {
        let sp = &mode.spectral;
        let terms = sp.terms();
        let nt = terms.len();
        let ng = mode.guards.len();
        let Workspace { modal, f, fb, beta, coef, watch, start_abs, high, high_moduli, at } = self;
        *at = None;
        sp.modal_into(s0.as_slice(), modal);
        f.resize(nt, C64::new(0.0, 0.0));
        fb.resize(nt, 0.0);
        beta.resize(LEVELS * nt * ng, C64::new(0.0, 0.0));
        coef.resize(nt * ng, Coef::default());
        high.resize(6 * nt, C64::new(0.0, 0.0));
        high_moduli.resize(6 * nt, 0.0);
        if start_abs.len() != s0.len() {
            *start_abs = DVector::zeros(s0.len());
        }
        start_abs.zip_apply(s0, |a, x| *a = x.abs());
        watch.clear();
        for ((g, b), c) in mode.guards.iter().zip(beta.chunks_exact_mut(LEVELS * nt)).zip(coef.chunks_exact_mut(nt)) {
            modal.functional_into(&g.entries, &mut b[..nt]);
            for j in 1..LEVELS {
                let (done, rest) = b.split_at_mut(j * nt);
                differentiate_into(terms, &done[(j - 1) * nt..], &mut rest[..nt]);
            }
            for (t, c) in c.iter_mut().enumerate() {
                *c = Coef {
                    value: b[t],
                    rate: b[nt + t],
                    // Constant terms do not vary: they enter the global bound by value.
                    varying: if terms[t].constant { 0.0 } else { b[t].l1_norm() },
                    accel: b[2 * nt + t].l1_norm(),
                };
            }
            let magnitude = g.row_abs.dot(start_abs);
            watch.push(Watch {
                masked: 0.0,
                zero: value_tol(acc, g.kind.is_gap(), magnitude),
                // The constant terms' factors are their (real) weights at every time.
                constant: (0..nt).filter(|&t| terms[t].constant).map(|t| terms[t].weight * b[t].re).sum(),
                magnitude,
            });
        }
    }

    /// The augmented state of `mode` (lift it with [`Mode::lift_into`]) at time
    /// `u` after the start of the last advance, from the closed form of the
    /// flow: a sample inside a segment that does not end it. The last advance
    /// must have been an exact one of `mode`, and `u` (in the scene's time
    /// units) at most the time where it stopped; `out` has the mode's augmented
    /// length. Only the factor buffer is overwritten, which the next advance
    /// prepares again.
    pub fn state_at(&mut self, mode: &Mode, u: f64, out: &mut DVector<f64>) {
        debug_assert_eq!(self.f.len(), mode.spectral.terms().len(), "the last advance was not one of this mode");
        mode.spectral.factors(u, &mut self.f);
        self.at = Some(u);
        self.modal.state_into(&self.f, out.as_mut_slice());
    }

    /// The flow's factors at time `u` of the last advance where they are at
    /// hand: where it stopped (its event's time, or its horizon), unless a
    /// sample was taken since (none for a simulation by RK4, which never
    /// advances here). Those [`crate::spectral::Spectral::factors`]
    /// computes, bit for bit (the same exponentials, sines and cosines, in
    /// the same products).
    pub fn factors_at(&self, u: f64) -> Option<&[C64]> {
        (self.at.map(f64::to_bits) == Some(u.to_bits())).then_some(self.f.as_slice())
    }
}

/// What a guard at zero does next (see [`Start`]): `true` when it approaches
/// (an event now); when it departs it is masked for as long as it provably stays
/// positive. Kept out of line: contact is rare, and inlined into the step loop
/// it costs the loop registers (1 % more instructions on the 24 × 24 grid).
#[allow(clippy::too_many_arguments)]
#[inline(never)]
fn at_contact(
    terms: &[Term],
    beta: &[C64],
    high: &mut [C64],
    high_moduli: &mut [f64],
    f: &[C64],
    fb: &[f64],
    is_gap: bool,
    magnitude: f64,
    acc: &Accuracy,
    u: f64,
    horizon: f64,
    masked: &mut f64,
) -> bool {
    let nt = terms.len();
    // The usual case first, from the kept levels alone: a guard off zero
    // after all (clear), or one whose rate decides (an approach, an event
    // now; a departure, held for as long as its acceleration's bound allows
    // and long enough not to creep). The values are those of the general
    // case below, bit for bit, which decides everything else.
    let level = |j: usize| &beta[j * nt..(j + 1) * nt];
    if evaluate(f, level(0)) > value_tol(acc, is_gap, magnitude) {
        return false;
    }
    for (m, b) in high_moduli[..LEVELS * nt].iter_mut().zip(beta) {
        *m = b.l1_norm();
    }
    let rate = evaluate(f, level(1));
    let next = evaluate(f, level(2));
    if rate.abs() > derivative_tol(acc, is_gap, 1, bound(fb, &high_moduli[nt..2 * nt]), next) {
        if rate < 0.0 {
            return true;
        }
        let g_next = bound(fb, &high_moduli[2 * nt..3 * nt]);
        let first = if g_next > 0.0 { 2.0 * rate / g_next } else { horizon };
        if !creeps(1, rate, first, value_tol(acc, is_gap, magnitude)) {
            *masked = u + 0.5 * first.max(acc.event_tol);
            return false;
        }
    }
    // Coefficients of derivatives 0..=5: the kept levels, then two more here.
    high[..LEVELS * nt].copy_from_slice(beta);
    for j in LEVELS..6 {
        let (done, rest) = high.split_at_mut(j * nt);
        differentiate_into(terms, &done[(j - 1) * nt..], &mut rest[..nt]);
    }
    for (m, b) in high_moduli.iter_mut().zip(high.iter()) {
        *m = b.l1_norm();
    }
    let coef = |j: usize| &high[j * nt..(j + 1) * nt];
    let modl = |j: usize| &high_moduli[j * nt..(j + 1) * nt];
    let d =
        [evaluate(f, coef(0)), evaluate(f, coef(1)), evaluate(f, coef(2)), evaluate(f, coef(3)), evaluate(f, coef(4))];
    let scale = [magnitude, bound(fb, modl(1)), bound(fb, modl(2)), bound(fb, modl(3)), bound(fb, modl(4))];
    let tol = start_tolerances(acc, is_gap, &scale, &d);
    match classify_start(&d, &tol) {
        Start::Clear => false,
        Start::Approaching => true,
        Start::Departing { order, rate } => {
            let escape = if order == 0 {
                // Every derivative vanishes: a guard bounded below its zero
                // tolerance over the rest of the horizon never crosses (a held stop
                // with an identically zero reaction); otherwise creep past it.
                if bound(fb, modl(0)) <= value_tol(acc, is_gap, 0.0) {
                    2.0 * (horizon - u)
                } else {
                    acc.event_tol * 1e3
                }
            } else {
                let g_next = bound(fb, modl(order + 1));
                let first = if g_next > 0.0 { (order + 1) as f64 * rate / g_next } else { horizon };
                hold(order, rate, first, &d, &tol, &scale)
            };
            *masked = u + 0.5 * escape.max(acc.event_tol);
            false
        }
    }
}

/// Holds of a departing guard, at most, that may carry it out of its zero band
/// before the bound of more orders is used ([`hold`]).
const CREEP_STEPS: f64 = 1000.0;

/// How long a guard departing from zero at derivative `order` (value
/// `rate > 0`) is held: `first`, the root of the first order's bound (the
/// caller's), unless holds of half of it would take more than
/// [`CREEP_STEPS`] steps to carry the guard out of its zero band `tol[0]`
/// (they would exhaust the step budget: a stall); then the longer of it and
/// [`departure`]'s.
fn hold(order: usize, rate: f64, first: f64, d: &[f64; 5], tol: &[f64; 5], bounds: &[f64; 5]) -> f64 {
    if creeps(order, rate, first, tol[0]) {
        first.max(departure(order, rate, d, tol, bounds))
    } else {
        first
    }
}

/// Whether holds of half of `first` would take more than [`CREEP_STEPS`]
/// steps to carry a guard departing at derivative `order` (value `rate`)
/// out of its zero band `zero` (see [`hold`]).
fn creeps(order: usize, rate: f64, first: f64, zero: f64) -> bool {
    let factorial = (1..=order).product::<usize>() as f64;
    let per_hold = rate * (0.5 * first).powi(order as i32) / factorial;
    per_hold * CREEP_STEPS < zero
}

/// How long a guard departing from zero at derivative `order` (value
/// `rate > 0`; those below it zero) provably stays positive, by the lower
/// bounds of more than one order: for `k` in `order + 2 ..= 4`, the Taylor
/// polynomial up to `k − 1` with each derivative beyond `order` lowered by its
/// tolerance, less the bound `bounds[k]` of the k-th derivative over the rest
/// of the horizon, `rate s^o/o! + Σ_{o<j<k} (d_j − tol_j) s^j/j! − bounds[k] s^k/k!`.
/// Where every lowered derivative is non-negative the polynomial has one
/// positive root (one change of sign, Descartes' rule) and is positive before
/// it: the latest such root, 0 when no `k` qualifies. The root of `k = order + 1`
/// is the caller's.
fn departure(order: usize, rate: f64, d: &[f64; 5], tol: &[f64; 5], bounds: &[f64; 5]) -> f64 {
    let mut best = 0.0f64;
    let mut factorial = (1..=order).product::<usize>() as f64;
    // The polynomial's coefficients over s^order: rate/order!, then the lowered derivatives'.
    let mut coef = [0.0; 5];
    coef[0] = rate / factorial;
    for k in order + 1..5 {
        factorial *= k as f64;
        if k > order + 1 {
            let g = bounds[k] / factorial;
            if g > 0.0 {
                // q(s) = Σ coef[i] s^i − g s^(k−order): positive at 0, one root.
                let kept = &coef[..k - order];
                let q = |s: f64| kept.iter().rev().fold(0.0, |acc, c| acc * s + c) - g * s.powi((k - order) as i32);
                let mut hi = (coef[0] / g).powf(1.0 / (k - order) as f64);
                let mut lo = 0.0;
                while q(hi) > 0.0 && hi.is_finite() {
                    (lo, hi) = (hi, 2.0 * hi);
                }
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if q(mid) > 0.0 {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                best = best.max(lo);
            }
        }
        let lowered = d[k] - tol[k];
        if lowered < 0.0 {
            break;
        }
        coef[k - order] = lowered / factorial;
    }
    best
}

/// First positive root of `g + g' h - G₂ h²/2` (`g > 0`), infinite when none.
fn quadratic_root(g: f64, gd: f64, g2: f64) -> f64 {
    if g2 > 0.0 {
        (gd + (gd * gd + 2.0 * g2 * g).sqrt()) / g2
    } else if gd < 0.0 {
        g / -gd
    } else {
        f64::INFINITY
    }
}

/// Advances `s0` for at most `horizon` in `mode` (see the module doc).
/// The state where it stops is written to `out` (of the length of `s0`).
///
/// One function of about a hundred lines on purpose: it is the step loop,
/// where nearly all of a simulation's time goes, and its locals (the time, the
/// step, the global bound, each watched guard's value and rate) stay in
/// registers across iterations while the loop is one body. Its rare path, a
/// guard at contact, is already out of line (`at_contact`: inlined, it cost
/// the loop registers and instructions); what remains is the loop itself.
pub fn advance(
    mode: &Mode,
    s0: &DVector<f64>,
    horizon: f64,
    acc: &Accuracy,
    w: &mut Workspace,
    out: &mut DVector<f64>,
) -> Advance {
    let sp = &mode.spectral;
    let terms = sp.terms();
    let nt = terms.len();
    w.prepare(mode, s0, acc);
    let Workspace { modal, f, fb, beta, coef, watch, high, high_moduli, at, .. } = w;
    let event = |modal: &Modal, f: &[C64], out: &mut DVector<f64>, at: &mut Option<f64>, guard: usize, time: f64| {
        if time > 0.0 {
            modal.state_into(f, out.as_mut_slice());
        } else {
            out.copy_from(s0);
        }
        *at = Some(time);
        Advance::Event { guard, time }
    };

    let budget = MAX_STEPS + (STEPS_PER_OSCILLATION * horizon * sp.fastest() / std::f64::consts::TAU) as usize;
    let mut u = 0.0f64;
    for _ in 0..budget {
        sp.factors_and_bounds(u, horizon, f, fb);
        let mut h = horizon - u;
        let mut bounded = false;
        for (gi, (c, watch)) in coef.chunks_exact(nt).zip(watch.iter_mut()).enumerate() {
            let cand = if u < watch.masked {
                watch.masked - u
            } else {
                // One pass over the terms: the guard, its rate, the bound of what
                // varies and the bound G₂ of its acceleration (the sums of
                // `evaluate` and `bound`, term by term in their order, so the
                // values are theirs bit for bit).
                let (mut g, mut gd, mut varying, mut g2) = (-0.0, -0.0, -0.0, -0.0);
                for ((term, ft), bt) in c.iter().zip(f.iter()).zip(fb.iter()) {
                    g += ft.re * term.value.re - ft.im * term.value.im;
                    gd += ft.re * term.rate.re - ft.im * term.rate.im;
                    varying += bt * term.varying;
                    g2 += bt * term.accel;
                }
                if g <= watch.zero {
                    let is_gap = mode.guards[gi].kind.is_gap();
                    let b = &beta[LEVELS * nt * gi..LEVELS * nt * (gi + 1)];
                    if at_contact(
                        terms,
                        b,
                        high,
                        high_moduli,
                        f,
                        fb,
                        is_gap,
                        watch.magnitude,
                        acc,
                        u,
                        horizon,
                        &mut watch.masked,
                    ) {
                        return event(modal, f, out, at, gi, u);
                    }
                    watch.masked - u
                } else {
                    // Global bound: the constant part less everything that varies.
                    if watch.constant - varying > watch.zero {
                        watch.masked = horizon;
                        continue;
                    }
                    // The lower bound is concave: still positive a little past the
                    // step already chosen, its root lies beyond it (no square root).
                    let past = h * (1.0 + 1e-6);
                    if g + past * (gd - 0.5 * g2 * past) > 0.0 {
                        continue;
                    }
                    let root = quadratic_root(g, gd, g2);
                    if root <= acc.event_tol && root < h {
                        // Converged onto the root: the event is within event_tol.
                        let t = u + root;
                        sp.factors_and_bounds(t, horizon, f, fb);
                        return event(modal, f, out, at, gi, t);
                    }
                    root
                }
            };
            if cand < h {
                h = cand;
                bounded = true;
            }
        }
        if !bounded {
            sp.factors_and_bounds(horizon, horizon, f, fb);
            modal.state_into(f, out.as_mut_slice());
            *at = Some(horizon);
            return Advance::Horizon;
        }
        u += h;
    }
    Advance::Stalled
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mode::{Key, Mode};
    use crate::testing::{forced_oscillator, system};
    use proptest::prelude::*;

    /// A departure at order 1 that its acceleration speeds up is held positive
    /// until the root of `r + a s/2 − G s²/6` (the closed form), not only until
    /// `2r/G₂`; the bound is positive before that root and not after; a
    /// departure that its acceleration turns back gets no longer hold (0).
    #[test]
    fn a_departure_sped_up_is_held_until_the_root_of_its_next_bound() {
        let (r, a, g3): (f64, f64, f64) = (2e-9, 1e-4, 5.0);
        let d = [0.0, r, a, 0.0, 0.0];
        let tol = [1e-12, 1e-9, 1e-15, 0.0, 0.0];
        let bounds = [1.0, 1.0, 1.0, g3, 0.0];
        let lowered = a - tol[2];
        let (b, c) = (lowered / 2.0, g3 / 6.0);
        let closed = (b + (b * b + 4.0 * c * r).sqrt()) / (2.0 * c);
        let s = departure(1, r, &d, &tol, &bounds);
        assert!((s - closed).abs() <= 1e-12 * closed, "{s} against {closed}");
        assert!(s > 1e4 * 2.0 * r / 5.0, "{s}: no longer than the first order's hold");
        let q = |s: f64| r + b * s - c * s * s;
        assert!(q(s) >= 0.0 && q(s * (1.0 + 1e-9)) < 0.0);
        let turned = [0.0, r, -a, 0.0, 0.0];
        assert!(departure(1, r, &turned, &tol, &bounds).to_bits() == 0, "no hold beyond the first order's");
    }

    /// The free mode of the single-stop oscillator with its stop at `sigma`.
    fn free_mode(omega: f64, zeta: f64, sigma: f64) -> Mode {
        Mode::new(&system("single-stop.toml", &[("omega", omega), ("zeta", zeta), ("sigma", sigma)]), Key::FREE)
            .unwrap()
            .unwrap()
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        /// The exact flow is a flow: advancing by t1 then by t2 gives the state
        /// that advancing by t1 + t2 gives (the stop out of reach, so that no
        /// event interrupts either), to rounding.
        #[test]
        fn the_exact_flow_composes(omega in 0.05f64..5.0, zeta in 0.0f64..0.5, x0 in -1.0f64..1.0, v0 in -1.0f64..1.0,
                                   t1 in 0.0f64..20.0, t2 in 0.0f64..20.0) {
            let mode = free_mode(omega, zeta, 1e6);
            let acc = Accuracy::default();
            let s0 = mode.project(&DVector::from_vec(vec![x0, v0]), 0.3);
            let (mut w, mut s1, mut s2, mut s12) = (Workspace::default(), s0.clone(), s0.clone(), s0.clone());
            prop_assert!(matches!(advance(&mode, &s0, t1, &acc, &mut w, &mut s1), Advance::Horizon));
            prop_assert!(matches!(advance(&mode, &s1, t2, &acc, &mut w, &mut s2), Advance::Horizon));
            prop_assert!(matches!(advance(&mode, &s0, t1 + t2, &acc, &mut w, &mut s12), Advance::Horizon));
            let scale = 1.0 + s12.amax();
            prop_assert!((&s2 - &s12).amax() <= 1e-11 * scale, "{} vs {}", s2, s12);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        /// The factors an advance ends with, which the tangent's transition
        /// takes ([`Workspace::factors_at`]), are those
        /// [`crate::spectral::Spectral::factors`] computes at its end, bit for
        /// bit, whether it ends at an event (the stop within reach) or at its
        /// horizon; at any other time, and after a sample, there are none.
        #[test]
        fn an_advance_ends_with_the_factors_of_its_end(omega in 0.05f64..5.0, zeta in 0.0f64..0.5,
                                                       sigma in 0.1f64..3.0, x0 in -1.0f64..1.0, v0 in -1.0f64..1.0,
                                                       horizon in 0.1f64..20.0) {
            let mode = free_mode(omega, zeta, sigma);
            let acc = Accuracy::default();
            let s0 = mode.project(&DVector::from_vec(vec![x0.min(0.9 * sigma), v0]), 0.3);
            let (mut w, mut out) = (Workspace::default(), s0.clone());
            let end = match advance(&mode, &s0, horizon, &acc, &mut w, &mut out) {
                Advance::Horizon => horizon,
                Advance::Event { time, .. } => time,
                other => return Err(TestCaseError::fail(format!("{other:?}"))),
            };
            let mut f = vec![C64::new(0.0, 0.0); mode.spectral.terms().len()];
            mode.spectral.factors(end, &mut f);
            let kept = w.factors_at(end).expect("the factors of the advance's end");
            let bits = |f: &[C64]| f.iter().flat_map(|c| [c.re.to_bits(), c.im.to_bits()]).collect::<Vec<_>>();
            prop_assert_eq!(bits(kept), bits(&f));
            prop_assert!(w.factors_at(0.5 * end).is_none() || end == 0.0);
            w.state_at(&mode, 0.5 * end, &mut out);
            prop_assert!(w.factors_at(end).is_none() || end == 0.0);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        /// Grazing: the stop is put a hair `ε` (1e-10 to 1e-3) below the
        /// highest point the free motion reaches within the horizon, found by
        /// dense sampling of the closed form (1e-5 apart) refined by golden
        /// section; sampling the motion at RK4's step (0.01) can miss such a
        /// contact for small ε. The advance must stop at an event no later than
        /// the first time the closed form reaches the stop (to the sampling).
        #[test]
        fn a_grazing_contact_is_never_missed(omega in 0.2f64..3.0, zeta in 0.0f64..0.3, x0 in -1.0f64..1.0,
                                              v0 in -1.0f64..1.0, log_eps in -10.0f64..-3.0) {
            let x = |t: f64| forced_oscillator(zeta, omega, x0, v0, t);
            let horizon = 6.0;
            let samples = (horizon / 1e-5) as usize;
            let i_top = (0..=samples).max_by(|&a, &b| x(a as f64 * 1e-5).total_cmp(&x(b as f64 * 1e-5))).unwrap();
            // A crest inside the horizon (not the motion's start or end).
            prop_assume!(i_top > 0 && i_top < samples);
            let (mut lo, mut hi) = ((i_top as f64 - 1.0) * 1e-5, (i_top as f64 + 1.0) * 1e-5);
            for _ in 0..60 {
                let (a, b) = (lo + 0.382 * (hi - lo), lo + 0.618 * (hi - lo));
                if x(a) > x(b) { hi = b } else { lo = a }
            }
            let top = x(0.5 * (lo + hi));
            let sigma = top - 10f64.powf(log_eps);
            prop_assume!(sigma - x0 > 1e-3);
            let first = (0..=samples).map(|i| i as f64 * 1e-5).find(|&t| x(t) >= sigma).unwrap();
            let mode = free_mode(omega, zeta, sigma);
            let s0 = mode.project(&DVector::from_vec(vec![x0, v0]), std::f64::consts::FRAC_PI_2);
            let mut out = s0.clone();
            let got = advance(&mode, &s0, horizon, &Accuracy::default(), &mut Workspace::default(), &mut out);
            match got {
                Advance::Event { time, .. } => prop_assert!(time <= first + 1e-5, "event at {time}, contact from {first}"),
                other => prop_assert!(false, "contact at {first} missed: {other:?}"),
            }
        }
    }
}
