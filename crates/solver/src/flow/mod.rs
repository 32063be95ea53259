//! Integrators: advance a mode's augmented state to a horizon or to its first
//! event.
//!
//! The integrator is a closed set of two, the variants of [`Method`] (exported
//! as `solver::Method`; this module is private): [`Method::Exact`], the
//! closed-form flow of [`crate::spectral`] with guaranteed event location
//! ([`exact`]), and [`Method::Rk4`], the fixed-step Runge–Kutta method of the
//! literature with step-back refinement ([`rk4`]), kept to compare accuracy
//! and speed against. There is no integrator trait and nothing to plug in from
//! outside the crate: the simulator calls [`Method::advance`] once per flow
//! segment, and it dispatches with a `match` to [`exact::advance`] or
//! [`rk4::advance`]. Either reports why it stopped as an [`Advance`]; the
//! exact flow costs nothing of the cell's event budget (the simulation counts
//! its events), RK4's steps count against it. A third integrator is a third
//! variant, an arm in [`Method::advance`], and its name in `Method::parse`
//! and `Method::name` (the name stored in files).
//!
//! Shared by both, and by the contact and sticking decisions of the
//! simulation: how a guard that starts at zero behaves ([`classify_start`] on
//! its [`derivatives`], with [`start_tolerances`] and [`value_tol`];
//! [`guard_start`] does all three), and the time to which events are located
//! ([`time_resolution`]).

pub mod exact;
pub mod rk4;

use crate::accuracy::Accuracy;
use crate::mode::{Guard, Mode};
use nalgebra::{DMatrix, DVector};

/// Why an advance stopped (the augmented state where it stopped is written to
/// the advance's output vector).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Advance {
    /// The horizon was reached with no event.
    Horizon,
    /// Guard `guard` of the mode reached zero after `time`.
    Event {
        /// Index into [`Mode::guards`].
        guard: usize,
        /// Time since the start of the advance.
        time: f64,
    },
    /// The step budget of one advance ran out (a stalled event search).
    Stalled,
    /// The cell's event budget ran out during the advance (RK4's steps count
    /// against it, [`rk4::FULL_STEP_WORK`], [`rk4::REFINED_STEP_WORK`]).
    Budget,
}

scene::named_enum! {
    /// Which integrator a simulation uses.
    #[derive(Debug, Clone, Copy, PartialEq, Eq)]
    pub enum Method {
        /// Closed-form flow, conservative advancement and refinement to `event_tol`.
        Exact = "exact",
        /// Classic RK4 with step `rk4_step`, step-back refinement to `rk4_min_step`.
        Rk4 = "rk4",
    }
}

impl Method {
    /// Advances `s0` in `mode` for at most `horizon`, stopping at the first
    /// event; the augmented state where it stops is written to `out` (resized to
    /// the mode's dimension). `allowance`: what is left of the cell's event
    /// budget, in thousandths of an event; returns why the advance stopped and
    /// what it cost of the budget (RK4's steps; the exact flow costs nothing,
    /// its events are counted by the simulation).
    #[allow(clippy::too_many_arguments)]
    pub fn advance(
        self,
        mode: &Mode,
        s0: &DVector<f64>,
        horizon: f64,
        acc: &Accuracy,
        allowance: u64,
        work: &mut exact::Workspace,
        out: &mut DVector<f64>,
    ) -> (Advance, u64) {
        if out.len() != s0.len() {
            *out = DVector::zeros(s0.len());
        }
        match self {
            Method::Exact => (exact::advance(mode, s0, horizon, acc, work, out), 0),
            Method::Rk4 => rk4::advance(mode, s0, horizon, acc, allowance, out),
        }
    }
}

/// How a guard that starts at zero behaves, from its first non-negligible derivative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Start {
    /// The guard is positive: nothing special.
    Clear,
    /// At zero and moving to negative values: an event now.
    Approaching,
    /// At zero and moving to positive values; `order`-th derivative `rate > 0`
    /// (order 0 when every derivative up to the fourth vanishes).
    Departing {
        /// Order of the first non-negligible derivative.
        order: usize,
        /// Its value.
        rate: f64,
    },
}

/// Classifies a guard from its value and derivatives `d[0..=4]` at one instant.
/// `tol[j]` is the size below which the j-th derivative counts as zero.
pub fn classify_start(d: &[f64; 5], tol: &[f64; 5]) -> Start {
    if d[0] > tol[0] {
        return Start::Clear;
    }
    for j in 1..5 {
        if d[j].abs() > tol[j] {
            return if d[j] < 0.0 { Start::Approaching } else { Start::Departing { order: j, rate: d[j] } };
        }
    }
    Start::Departing { order: 0, rate: 0.0 }
}

/// A guard's value and first four derivatives `ℓ·Â^j·s`, with their scales
/// `|ℓ|·|Â^j s|`, at augmented state `s` (computed by matrix powers).
pub fn derivatives(guard: &Guard, aug: &DMatrix<f64>, s: &DVector<f64>) -> ([f64; 5], [f64; 5]) {
    let mut d = [0.0; 5];
    let mut scale = [0.0; 5];
    let (mut p, mut next, mut p_abs) = (s.clone(), s.clone(), s.clone());
    let row_abs = &guard.row_abs;
    for j in 0..5 {
        if j > 0 {
            aug.mul_to(&p, &mut next);
            std::mem::swap(&mut p, &mut next);
        }
        d[j] = guard.row.dot(&p);
        p_abs.zip_apply(&p, |a, x| *a = x.abs());
        scale[j] = row_abs.dot(&p_abs);
    }
    (d, scale)
}

/// How a guard behaves from augmented state `s` ([`classify_start`] on its
/// [`derivatives`]), with its value and magnitude.
pub fn guard_start(acc: &Accuracy, guard: &Guard, aug: &DMatrix<f64>, s: &DVector<f64>) -> (Start, f64, f64) {
    let (d, scale) = derivatives(guard, aug, s);
    let start = classify_start(&d, &start_tolerances(acc, guard.kind.is_gap(), &scale, &d));
    (start, d[0], scale[0])
}

/// Value below which a guard counts as zero: the contact tolerance for a gap
/// (a length), rounding level of its own `magnitude` for a reaction (a force,
/// located in time like any root so that a released stop starts exactly at rest).
pub fn value_tol(acc: &Accuracy, is_gap: bool, magnitude: f64) -> f64 {
    if is_gap {
        acc.contact_tol
    } else {
        1e-12 * (1.0 + magnitude)
    }
}

/// The time to which events are located, by either integrator: the coarser of
/// `event_tol` and `rk4_min_step`.
pub fn time_resolution(acc: &Accuracy) -> f64 {
    acc.event_tol.max(acc.rk4_min_step)
}

/// Tolerances of [`classify_start`] for a guard with derivatives `d` and
/// bounds `scale` (`scale[0]`: magnitude of the guard): [`value_tol`] for its
/// value, the stick velocity for a gap's rate (less where the approach could
/// carry the gap past the contact tolerance), and for every derivative the
/// larger of rounding level and what the next derivative changes within 100 time
/// resolutions (the coarser of `event_tol` and `rk4_min_step`), so that the
/// residual of an event located to that resolution counts as zero.
pub fn start_tolerances(acc: &Accuracy, is_gap: bool, scale: &[f64; 5], d: &[f64; 5]) -> [f64; 5] {
    let mut tol = [value_tol(acc, is_gap, scale[0]), 0.0, 0.0, 0.0, 0.0];
    for j in 1..5 {
        tol[j] = derivative_tol(acc, is_gap, j, scale[j], if j < 4 { d[j + 1] } else { 0.0 });
    }
    tol
}

/// The tolerance of [`start_tolerances`] for derivative `j` ≥ 1 of a guard,
/// its bound `scale` and the next derivative's value `next` (0 for the last).
pub fn derivative_tol(acc: &Accuracy, is_gap: bool, j: usize, scale: f64, next: f64) -> f64 {
    let tol = (1e-11 * scale).max(100.0 * time_resolution(acc) * next.abs()).max(1e-300);
    if is_gap && j == 1 {
        // An approach slower than the stick velocity is a landing, not a miss,
        // only while it cannot carry the gap past the contact tolerance before
        // the acceleration turns it: `d1² / (2 |d2|) <= contact_tol`. (Under
        // very slow forcing every velocity is below the stick velocity, and a
        // slow approach with a tiny acceleration would otherwise pass through
        // the stop.)
        let landing = (2.0 * acc.contact_tol * next.abs()).sqrt();
        tol.max(acc.stick_velocity.min(landing))
    } else {
        tol
    }
}
