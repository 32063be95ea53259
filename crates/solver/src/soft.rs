//! Soft stops: which contacts push, and what their events change.
//!
//! A soft stop acts beyond its clearance (gap `g = n·x + c < 0`) with the force
//! `λ = -k g - c g'` along its normal while `λ > 0`: it never pulls. A soft
//! stop is therefore in one of three states ([`crate::mode::Key`]'s bits):
//! free (`g >= 0`, watched by its gap), *pressed* (`λ > 0`, watched by `λ`)
//! or *parting* (`g < 0` but `λ <= 0`, as damping makes a contact end before
//! its gap reopens; watched by `-g` and by `-λ`). The vector field is
//! continuous at every transition except where a contact begins with damping
//! (`λ = -c g'` at once), so the event loop's saltation matrix is the identity
//! there, and the jump of the damping force where a contact begins.

use crate::accuracy::Accuracy;
use crate::contact::Contact;
use crate::error::SolverError;
use crate::flow::{classify_start, derivatives, start_tolerances, time_resolution, Start};
use crate::mode::{GuardKind, Key, Target};
use crate::stick::ModeCache;
use crate::system::System;
use nalgebra::DVector;

/// Moves the positions of `y` along soft stop `stop`'s normal onto its
/// clearance (`g = 0`) when its gap is within rounding of it (an event located
/// there), so that the stop's state is decided from the rates, not from the
/// sign of a rounding error.
pub fn snap(sys: &System, stop: usize, y: &mut DVector<f64>) {
    let m = sys.dof();
    let row = &sys.stops[stop];
    let g = sys.gap(stop, y);
    let scale = row.normal.abs().dot(&y.rows(0, m).abs()) + row.offset.abs();
    if g != 0.0 && g.abs() <= 1e-12 * (1.0 + scale) {
        let shift = &row.normal * (-g / row.normal.norm_squared());
        let mut x = y.rows_mut(0, m);
        x += shift;
    }
}

/// The pressed and parting soft stops at full state `y` (bit masks), for a
/// motion that starts there: closed beyond the contact tolerance with a
/// positive force, or closing at the clearance, a stop is pressed; closed
/// without force, parting; otherwise free.
pub fn contacts(sys: &System, acc: &Accuracy, y: &DVector<f64>) -> (u32, u32) {
    let (mut pressed, mut parting) = (0, 0);
    for (k, stop) in sys.stops.iter().enumerate() {
        if stop.law.spring().is_none() {
            continue;
        }
        let (g, rate) = (sys.gap(k, y), sys.gap_rate(k, y));
        if g > acc.contact_tol {
            continue;
        }
        let force = sys.contact_force(k, y);
        if force > 0.0 && (g < -acc.contact_tol || rate < 0.0) {
            pressed |= 1 << k;
        } else if g < -acc.contact_tol {
            parting |= 1 << k;
        }
    }
    (pressed, parting)
}

/// The key after event `kind` of soft stop `stop` at full state `y` and
/// forcing phase `phase`, from `key`. The natural successor first: the gap
/// closed → pressed; the force fell to zero → parting while the gap is closed
/// (damping), else free; a parting stop's gap reopened → free, its force
/// pushes again → pressed. The first of the stop's states (natural one first)
/// whose guards for this stop do not vanish at once ([`consistent`]) is
/// taken: at a tangency (the force falling to zero just as the gap closes,
/// which a stiff contact ringing in its transient meets) the natural
/// successor may turn back at once, and a state that does not is the motion's
/// next; the natural one when none is.
#[allow(clippy::too_many_arguments)]
pub fn after(
    sys: &System,
    acc: &Accuracy,
    cache: &mut ModeCache,
    key: Key,
    kind: GuardKind,
    stop: usize,
    y: &DVector<f64>,
    phase: f64,
) -> Result<Key, SolverError> {
    let bit = 1 << stop;
    let g = sys.gap(stop, y);
    let base = Key { pressed: key.pressed & !bit, parting: key.parting & !bit, ..key };
    let (free, pressed, parting) =
        (base, Key { pressed: base.pressed | bit, ..base }, Key { parting: base.parting | bit, ..base });
    let order = match kind {
        GuardKind::Touch => [pressed, free, parting],
        GuardKind::Push if g < 0.0 => [parting, free, pressed],
        GuardKind::Push => [free, parting, pressed],
        GuardKind::Overlap => [free, pressed, parting],
        _ => [pressed, parting, free],
    };
    for candidate in order {
        if consistent(sys, acc, cache, candidate, stop, y, phase)? {
            return Ok(candidate);
        }
    }
    Ok(order[0])
}

/// Whether none of soft stop `stop`'s guards in `key`'s mode vanishes at
/// once from `y` or starts below zero. A guard's value counts as zero within
/// rounding and within what its rate moves it in 100 time resolutions (as a
/// held stop's reaction does, [`crate::stick`]): an event located in time to
/// rounding leaves a fast contact's gap a few 1e-12 from zero, which at a
/// closing speed of thousands is 1e-15 in time.
fn consistent(
    sys: &System,
    acc: &Accuracy,
    cache: &mut ModeCache,
    key: Key,
    stop: usize,
    y: &DVector<f64>,
    phase: f64,
) -> Result<bool, SolverError> {
    let Some(mode) = cache.get(sys, key)? else { return Ok(false) };
    let s = mode.project(y, phase);
    Ok(mode.guards.iter().filter(|g| g.target == Target::Stop(stop)).all(|g| {
        let (d, scale) = derivatives(g, &mode.aug, &s);
        let mut tol = start_tolerances(acc, false, &scale, &d);
        tol[0] = tol[0].max(100.0 * time_resolution(acc) * d[1].abs());
        d[0] >= -tol[0] && classify_start(&d, &tol) != Start::Approaching
    }))
}
