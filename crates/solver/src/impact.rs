//! Newton's impact law at rigid stops, with momentum exchange for two masses.
//!
//! At stop k with normal n (gap `g = n·x + c`), an impulse `J` along `M^{-1} n`
//! makes the normal velocity `n·v+ = -R n·v-`:
//!
//! ```text
//! v+ = v- - (1 + R) (n·v-) / (nᵀ M^{-1} n) · M^{-1} n .
//! ```
//!
//! For a frame stop this is `v+ = -R v-` of the mass; for two masses it keeps the
//! momentum `M_a v_a + M_b v_b` (the components of n sum to zero) and reverses the
//! relative velocity with factor R. The kinetic energy changes by
//! `-(1 - R²)(n·v-)² / (2 nᵀ M^{-1} n) <= 0`. Simultaneous contacts are resolved by
//! sequential impulses in stop order until no contact is closing.

use crate::system::System;
use nalgebra::DVector;

/// Applies the impact law of `stop` with restitution `restitution` to the velocities of `y`.
pub fn apply(sys: &System, stop: usize, restitution: f64, y: &mut DVector<f64>) {
    let m = sys.dof();
    let s = &sys.stops[stop];
    let vn = sys.gap_rate(stop, y);
    let j = -(1.0 + restitution) * vn / s.inv_effective_mass;
    let mut v = y.rows_mut(m, m);
    v.axpy(j, &s.inv_mass_normal, 1.0);
}

/// One impact of a sequence: stop index and closing speed `-n·v-` (> 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Stop index.
    pub stop: usize,
    /// Closing speed before the impact.
    pub speed: f64,
}

/// Resolves all closing contacts among `contacts` (stops at zero gap) by
/// sequential impulses. Contacts closing faster than `stick_velocity` bounce with
/// their restitution (and are reported); slower ones are made plastic.
pub fn resolve(sys: &System, contacts: &[usize], stick_velocity: f64, y: &mut DVector<f64>) -> Vec<Hit> {
    let mut hits = Vec::new();
    for _round in 0..64 {
        let mut any = false;
        for &k in contacts {
            let vn = sys.gap_rate(k, y);
            if vn < -stick_velocity {
                apply(sys, k, sys.stops[k].restitution, y);
                hits.push(Hit { stop: k, speed: -vn });
                any = true;
            } else if vn < 0.0 {
                apply(sys, k, 0.0, y);
            }
        }
        if !any {
            break;
        }
    }
    hits
}
