//! Classic fourth-order Runge–Kutta with fixed step and step-back refinement,
//! the method of the literature: step `h` (0.01); when a guard changes sign over
//! a step, go back and divide the step by 10 until it is below `rk4_min_step`
//! (1e-10); the event is then placed at the end of that step. Grazing events
//! between two samples are missed, as in the literature. A guard that starts at
//! zero and moves away (just after an impact) counts as crossed when it falls
//! below its starting value less the contact tolerance, so that a bounce shorter
//! than one step is still caught at its landing. The forcing `sin φ`,
//! `cos φ` is evaluated exactly at each stage, not integrated.
//!
//! Every step counts against the cell's event budget (`max_events`, issue 30):
//! a full step costs [`FULL_STEP_WORK`], a step of the refinement (shorter than
//! `rk4_step`) [`REFINED_STEP_WORK`] thousandths of an event. A located event
//! takes about 50 refinement steps (at most ten per decade from `rk4_step` to
//! `rk4_min_step`), so an RK4 event costs about six events of the budget; a
//! crossing that vanishes at the finer step (the refinement then creeps on at
//! `rk4_min_step`) ends the cell `unresolved` with the budget's reason after at
//! most `10 max_events` such steps, instead of running for hours. The full
//! steps between events are bounded by the length of the records, as the exact
//! flow is; their small cost bounds them by the budget too (`1000 max_events`),
//! whatever `rk4_step`.

use super::{guard_start, value_tol, Advance, Start};
use crate::accuracy::Accuracy;
use crate::mode::Mode;
use nalgebra::{DMatrix, DVector};

/// Steps allowed in one advance before it is declared stalled.
const MAX_STEPS: usize = 50_000_000;

/// Cost of a full step (of `rk4_step`, or the shorter last step to the
/// horizon) against the event budget, in thousandths of an event
/// ([`crate::simulate::EVENT_WORK`]).
pub const FULL_STEP_WORK: u64 = 1;

/// Cost of a step of the event refinement (shorter than `rk4_step`), in
/// thousandths of an event: ten steps, about the time one event of the exact
/// integrator takes, cost one event.
pub const REFINED_STEP_WORK: u64 = 100;

/// The classic RK4 step of `s' = Â s` with the forcing `(sin kφ, cos kφ)` of
/// every harmonic k set exactly at each stage's time, on reused buffers (no
/// allocation per step).
struct Stepper<'m> {
    a: &'m DMatrix<f64>,
    /// Per harmonic: the indices of `sin kφ` and `cos kφ` in the augmented
    /// state, their values at the start of the advance and the rate `kω`.
    harmonics: Vec<Harmonic>,
    /// The forcing at a step's middle and end, per harmonic.
    mid: Vec<(f64, f64)>,
    end: Vec<(f64, f64)>,
    k: [DVector<f64>; 4],
    tmp: DVector<f64>,
}

/// One harmonic of the forcing in the augmented state.
#[derive(Debug, Clone, Copy)]
struct Harmonic {
    isin: usize,
    icos: usize,
    start: (f64, f64),
    rate: f64,
}

impl Harmonic {
    /// `(sin kφ, cos kφ)` at time `u` of the advance.
    fn at(&self, u: f64) -> (f64, f64) {
        let (sin0, cos0) = self.start;
        let (su, cu) = (self.rate * u).sin_cos();
        (sin0 * cu + cos0 * su, cos0 * cu - sin0 * su)
    }
}

impl<'m> Stepper<'m> {
    /// The harmonics at `indices` (of `sin kφ` and `cos kφ`), whose rotation
    /// blocks `[[0, kω], [-kω, 0]]` in `a` give their rates.
    fn new(a: &'m DMatrix<f64>, s0: &DVector<f64>, indices: impl Iterator<Item = (usize, usize)>) -> Self {
        let dim = s0.len();
        let harmonics: Vec<Harmonic> = indices
            .map(|(isin, icos)| Harmonic { isin, icos, start: (s0[isin], s0[icos]), rate: a[(isin, icos)] })
            .collect();
        let zero = || DVector::zeros(dim);
        let n = harmonics.len();
        Stepper {
            a,
            harmonics,
            mid: vec![(0.0, 0.0); n],
            end: vec![(0.0, 0.0); n],
            k: [zero(), zero(), zero(), zero()],
            tmp: zero(),
        }
    }

    /// The derivative of `s` into `d`, the forcing rows zeroed (they are set, not integrated).
    fn deriv(a: &DMatrix<f64>, harmonics: &[Harmonic], s: &DVector<f64>, d: &mut DVector<f64>) {
        a.mul_to(s, d);
        for h in harmonics {
            d[h.isin] = 0.0;
            d[h.icos] = 0.0;
        }
    }

    /// One step of length `hh` from `s` at time `u` (ending at `t_next`) into `next`.
    fn step(&mut self, s: &DVector<f64>, u: f64, hh: f64, t_next: f64, next: &mut DVector<f64>) {
        for ((h, mid), end) in self.harmonics.iter().zip(&mut self.mid).zip(&mut self.end) {
            (*mid, *end) = (h.at(u + hh / 2.0), h.at(t_next));
        }
        let (a, hs, mid, end) = (self.a, &self.harmonics[..], &self.mid[..], &self.end[..]);
        let [k1, k2, k3, k4] = &mut self.k;
        let tmp = &mut self.tmp;
        // A stage's state `s + c k` at the forcing `f` of its time.
        let stage = |tmp: &mut DVector<f64>, c: f64, k: &DVector<f64>, f: &[(f64, f64)]| {
            tmp.copy_from(s);
            tmp.axpy(c, k, 1.0);
            for (h, &(sn, cs)) in hs.iter().zip(f) {
                tmp[h.isin] = sn;
                tmp[h.icos] = cs;
            }
        };
        Self::deriv(a, hs, s, k1);
        stage(tmp, hh / 2.0, k1, mid);
        Self::deriv(a, hs, tmp, k2);
        stage(tmp, hh / 2.0, k2, mid);
        Self::deriv(a, hs, tmp, k3);
        stage(tmp, hh, k3, end);
        Self::deriv(a, hs, tmp, k4);
        for i in 0..s.len() {
            next[i] = s[i] + (k1[i] + k2[i] * 2.0 + k3[i] * 2.0 + k4[i]) * (hh / 6.0);
        }
        for (h, &(sn, cs)) in hs.iter().zip(end) {
            next[h.isin] = sn;
            next[h.icos] = cs;
        }
    }
}

/// The value below which each guard counts as crossed: zero, or for a guard
/// that starts at zero and moves away, its start less the contact tolerance.
/// `Err(g)`: guard `g` is at zero and approaching, an event now.
fn thresholds(mode: &Mode, s0: &DVector<f64>, acc: &Accuracy) -> Result<Vec<f64>, usize> {
    let mut threshold = vec![0.0; mode.guards.len()];
    for (gi, g) in mode.guards.iter().enumerate() {
        match guard_start(acc, g, &mode.aug, s0) {
            (Start::Clear, _, _) => {}
            (Start::Approaching, _, _) => return Err(gi),
            (Start::Departing { .. }, value, magnitude) => {
                threshold[gi] = value.min(0.0) - value_tol(acc, g.kind.is_gap(), magnitude)
            }
        }
    }
    Ok(threshold)
}

/// Advances `s0` for at most `horizon` in `mode` (see the module doc), with
/// `allowance` thousandths of an event of the cell's budget left: the steps'
/// cost may reach it but not exceed it. The state where it stops is written to
/// `out` (of the length of `s0`); returns why it stopped and what its steps cost.
pub fn advance(
    mode: &Mode,
    s0: &DVector<f64>,
    horizon: f64,
    acc: &Accuracy,
    allowance: u64,
    out: &mut DVector<f64>,
) -> (Advance, u64) {
    let threshold = match thresholds(mode, s0, acc) {
        Ok(t) => t,
        Err(guard) => {
            out.copy_from(s0);
            return (Advance::Event { guard, time: 0.0 }, 0);
        }
    };
    let mut stepper = Stepper::new(&mode.aug, s0, mode.harmonic_indices());
    let (mut s, mut next) = (s0.clone(), DVector::zeros(s0.len()));
    let mut u = 0.0;
    let mut h = acc.rk4_step;
    let mut cost = 0;
    for _ in 0..MAX_STEPS {
        let remaining = horizon - u;
        if remaining <= 0.0 {
            break;
        }
        cost += if h < acc.rk4_step { REFINED_STEP_WORK } else { FULL_STEP_WORK };
        if cost > allowance {
            out.copy_from(&s);
            return (Advance::Budget, cost);
        }
        let hh = h.min(remaining);
        // The last step lands exactly on the horizon.
        let t_next = if hh >= remaining { horizon } else { u + hh };
        stepper.step(&s, u, hh, t_next, &mut next);
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
                return (Advance::Event { guard: gi, time: t_next }, cost);
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
        (Advance::Horizon, cost)
    } else {
        (Advance::Stalled, cost)
    }
}
