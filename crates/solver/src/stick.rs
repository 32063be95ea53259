//! Sticking: which stops hold their masses after an event.
//!
//! A stop is a candidate when its gap and its closing speed are both below the
//! contact and stick tolerances (the end of a chatter sequence, a plastic impact,
//! a mass resting on a stop). Among the candidates, the held set satisfies the
//! complementarity conditions of rigid contact (see [`settle`]): held stops push
//! (reaction >= 0), released ones do not close. In a single-stop scene this is the
//! literature's condition: M1 stays on A1 while
//! `F1 = (1-f20) sin(ωt+τ) - x1 - 2ζ x1' < 0`.

use crate::accuracy::Accuracy;
use crate::error::SolverError;
use crate::flow::{guard_start, value_tol, Start};
use crate::mode::{Guard, GuardKind, Mode};
use crate::system::System;
use nalgebra::DVector;

/// Lazily built modes of one system, keyed by the mask of held stops.
#[derive(Debug, Clone, Default)]
pub struct ModeCache {
    modes: Vec<(u32, Option<Mode>)>,
}

impl ModeCache {
    /// The mode holding `held`, or `None` when those constraints are dependent.
    pub fn get(&mut self, sys: &System, held: u32) -> Result<Option<&Mode>, SolverError> {
        let i = match self.modes.iter().position(|(h, _)| *h == held) {
            Some(i) => i,
            None => {
                self.modes.push((held, Mode::new(sys, held)?));
                self.modes.len() - 1
            }
        };
        Ok(self.modes[i].1.as_ref())
    }
}

/// Whether stop `k` touches at full state `y`: its gap is within the contact
/// band (ten contact tolerances, penetration included).
pub fn touching(sys: &System, acc: &Accuracy, k: usize, y: &DVector<f64>) -> bool {
    sys.gap(k, y) <= 10.0 * acc.contact_tol
}

/// Stops in contact (touching, closing speed below the stick velocity) at full state `y`.
pub fn candidates(sys: &System, acc: &Accuracy, y: &DVector<f64>) -> u32 {
    (0..sys.stops.len())
        .filter(|&k| touching(sys, acc, k, y) && sys.gap_rate(k, y).abs() <= acc.stick_velocity)
        .fold(0, |m, k| m | (1 << k))
}

/// Chooses the held set among the candidate stops `cand` at full state `y` and
/// forcing phase `phase`: the largest subset (ties: smallest mask) whose
/// constraints are independent, whose reactions are not negative (nor zero and
/// decreasing), and whose released candidates do not accelerate into their
/// stops — the complementarity conditions of rigid contact. With more than six
/// candidates, or no consistent subset, the most negative reaction is released
/// one at a time instead.
pub fn settle(
    sys: &System,
    acc: &Accuracy,
    cache: &mut ModeCache,
    y: &DVector<f64>,
    phase: f64,
    mut cand: u32,
) -> Result<u32, SolverError> {
    let stops: Vec<usize> = (0..32).filter(|k| cand & (1 << k) != 0).collect();
    if stops.len() <= 6 {
        let mut subsets: Vec<u32> = (0..1u32 << stops.len())
            .map(|bits| {
                stops.iter().enumerate().filter(|(i, _)| bits & (1 << i) != 0).fold(0, |m, (_, &k)| m | (1 << k))
            })
            .collect();
        subsets.sort_by_key(|m| (std::cmp::Reverse(m.count_ones()), *m));
        for mask in subsets {
            let Some(mode) = cache.get(sys, mask)? else { continue };
            let s = mode.project(y, phase);
            let consistent = mode.guards.iter().all(|g| match g.kind {
                GuardKind::Reaction => !releasing(mode, acc, g, &s),
                GuardKind::Gap => cand & (1 << g.stop) == 0 || start(mode, acc, g, &s) != Start::Approaching,
            });
            if consistent {
                return Ok(mask);
            }
        }
    }
    while cand != 0 {
        let Some(mode) = cache.get(sys, cand)? else {
            cand &= !(1 << (31 - cand.leading_zeros()));
            continue;
        };
        let s = mode.project(y, phase);
        let worst = mode
            .guards
            .iter()
            .filter(|g| g.kind == GuardKind::Reaction && releasing(mode, acc, g, &s))
            .map(|g| (g.row.dot(&s), g.stop))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match worst {
            Some((_, stop)) => cand &= !(1 << stop),
            None => break,
        }
    }
    Ok(cand)
}

/// How guard `g` of `mode` behaves from augmented state `s`.
fn start(mode: &Mode, acc: &Accuracy, g: &Guard, s: &DVector<f64>) -> Start {
    guard_start(acc, g, &mode.aug, s).0
}

/// Whether a held stop's reaction is negative, or zero and decreasing.
fn releasing(mode: &Mode, acc: &Accuracy, g: &Guard, s: &DVector<f64>) -> bool {
    let (start, value, magnitude) = guard_start(acc, g, &mode.aug, s);
    value < -value_tol(acc, false, magnitude) || start == Start::Approaching
}
