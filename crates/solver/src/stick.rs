//! Sticking: which stops hold their masses after an event.
//!
//! A stop is a candidate when its gap and its closing speed are both below the
//! contact and stick tolerances (the end of a chatter sequence, a plastic impact,
//! a mass resting on a stop). Candidates are held together; then, while some held
//! stop's reaction is negative or zero and decreasing (the net force pulls the mass
//! off the stop), the most negative one is released and the rest re-checked. In a
//! single-stop scene this is the literature's condition: M1 stays on A1 while
//! `F1 = (1-f20) sin(ωt+τ) - x1 - 2ζ x1' < 0`.

use crate::accuracy::Accuracy;
use crate::error::SolverError;
use crate::flow::{classify_start, start_tolerances, Start};
use crate::mode::{GuardKind, Mode};
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

/// Stops in contact (gap and closing speed below tolerance) at full state `y`.
pub fn candidates(sys: &System, acc: &Accuracy, y: &DVector<f64>) -> u32 {
    (0..sys.stops.len())
        .filter(|&k| sys.gap(k, y) <= 10.0 * acc.contact_tol && sys.gap_rate(k, y).abs() <= acc.stick_velocity)
        .fold(0, |m, k| m | (1 << k))
}

/// Chooses the held set among `cand` at full state `y` and forcing phase `phase`.
pub fn settle(
    sys: &System,
    acc: &Accuracy,
    cache: &mut ModeCache,
    y: &DVector<f64>,
    phase: f64,
    mut cand: u32,
) -> Result<u32, SolverError> {
    while cand != 0 {
        let Some(mode) = cache.get(sys, cand)? else {
            cand &= !(1 << (31 - cand.leading_zeros()));
            continue;
        };
        let s = mode.project(y, phase);
        match releasing(mode, acc, &s) {
            Some(stop) => cand &= !(1 << stop),
            None => break,
        }
    }
    Ok(cand)
}

/// The held stop whose reaction is most negative, or zero and decreasing.
fn releasing(mode: &Mode, acc: &Accuracy, s: &DVector<f64>) -> Option<usize> {
    let mut worst: Option<(f64, usize)> = None;
    for g in mode.guards.iter().filter(|g| g.kind == GuardKind::Reaction) {
        let mut d = [0.0; 5];
        let mut scale = [0.0; 5];
        let mut p = s.clone();
        d[0] = g.row.dot(&p);
        for j in 1..5 {
            p = &mode.aug * p;
            d[j] = g.row.dot(&p);
            scale[j] = g.row.abs().dot(&p.abs());
        }
        let tol = start_tolerances(acc, false, &scale, &d);
        if classify_start(&d, &tol) == Start::Approaching || d[0] < -tol[0] {
            if worst.is_none_or(|(v, _)| d[0] < v) {
                worst = Some((d[0], g.stop));
            }
        }
    }
    worst.map(|(_, stop)| stop)
}
