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
use crate::error::SolverError;
use crate::flow::{guard_start, Start};
use crate::mode::{GuardKind, Key};
use crate::stick::ModeCache;
use crate::system::System;
use nalgebra::DVector;
use scene::StopLaw;

/// The pressed and parting soft stops at full state `y` (bit masks), for a
/// motion that starts there: closed beyond the contact tolerance with a
/// positive force, or closing at the clearance, a stop is pressed; closed
/// without force, parting; otherwise free.
pub fn contacts(sys: &System, acc: &Accuracy, y: &DVector<f64>) -> (u32, u32) {
    let (mut pressed, mut parting) = (0, 0);
    for (k, stop) in sys.stops.iter().enumerate() {
        let StopLaw::Soft { stiffness, damping } = stop.law else { continue };
        let (g, rate) = (sys.gap(k, y), sys.gap_rate(k, y));
        if g > acc.contact_tol {
            continue;
        }
        let force = -stiffness * g - damping * rate;
        if force > 0.0 && (g < -acc.contact_tol || rate < 0.0) {
            pressed |= 1 << k;
        } else if g < -acc.contact_tol {
            parting |= 1 << k;
        }
    }
    (pressed, parting)
}

/// The key after event `kind` of soft stop `stop` at full state `y` and
/// forcing phase `phase`, from `key`: the gap closed (pressed, unless the
/// force would pull at once: a grazing touch stays free), the force fell to
/// zero (free, or parting while the gap is still closed), a parting stop's gap
/// reopened (free) or its force pushes again (pressed).
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
    Ok(match kind {
        GuardKind::Gap => {
            let pressed = Key { pressed: key.pressed | bit, ..key };
            if pushes(sys, acc, cache, pressed, stop, y, phase)? {
                pressed
            } else {
                key
            }
        }
        GuardKind::Push => {
            let mut next = Key { pressed: key.pressed & !bit, ..key };
            if sys.gap(stop, y) < -acc.contact_tol {
                next.parting |= bit;
            }
            next
        }
        GuardKind::Overlap => Key { parting: key.parting & !bit, ..key },
        _ => Key { parting: key.parting & !bit, pressed: key.pressed | bit, ..key },
    })
}

/// Whether soft stop `stop`, pressed in `key`'s mode at `y`, pushes from now
/// on: its force is positive, or zero and growing.
fn pushes(
    sys: &System,
    acc: &Accuracy,
    cache: &mut ModeCache,
    key: Key,
    stop: usize,
    y: &DVector<f64>,
    phase: f64,
) -> Result<bool, SolverError> {
    let Some(mode) = cache.get(sys, key)? else { return Ok(false) };
    let Some(guard) = mode.guards.iter().find(|g| g.kind == GuardKind::Push && g.target.index() == stop) else {
        return Ok(false);
    };
    let s = mode.project(y, phase);
    Ok(guard_start(acc, guard, &mode.aug, &s).0 != Start::Approaching)
}
