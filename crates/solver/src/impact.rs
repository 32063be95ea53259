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
use nalgebra::{DMatrix, DVector};
use std::ops::AddAssign;

/// Applies the impact law of `stop` with restitution `restitution` to the velocities of `y`.
pub fn apply(sys: &System, stop: usize, restitution: f64, y: &mut DVector<f64>) {
    let m = sys.dof();
    let s = &sys.stops[stop];
    let vn = sys.gap_rate(stop, y);
    let j = -(1.0 + restitution) * vn / s.inv_effective_mass;
    let mut v = y.rows_mut(m, m);
    v.axpy(j, &s.inv_mass_normal, 1.0);
}

/// Jacobian `∂y+/∂y-` of [`apply`]: positions kept, velocities mapped by
/// `I - (1 + R) M^{-1} n nᵀ / (nᵀ M^{-1} n)`.
pub fn jacobian(sys: &System, stop: usize, restitution: f64) -> DMatrix<f64> {
    let m = sys.dof();
    let s = &sys.stops[stop];
    let mut j = DMatrix::identity(2 * m, 2 * m);
    let update = &s.inv_mass_normal * s.normal.transpose() * (-(1.0 + restitution) / s.inv_effective_mass);
    j.view_mut((m, m), (m, m)).add_assign(&update);
    j
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
/// their restitution (and are reported); slower ones are made plastic. Every
/// impulse applied, `(stop, restitution)` in order, is appended to `applied`;
/// the bounces are written to `hits`.
pub fn resolve(
    sys: &System,
    contacts: &[usize],
    stick_velocity: f64,
    y: &mut DVector<f64>,
    applied: &mut Vec<(usize, f64)>,
    hits: &mut Vec<Hit>,
) {
    hits.clear();
    for _round in 0..64 {
        let mut any = false;
        for &k in contacts {
            let vn = sys.gap_rate(k, y);
            if vn < -stick_velocity {
                apply(sys, k, sys.restitution(k), y);
                applied.push((k, sys.restitution(k)));
                hits.push(Hit { stop: k, speed: -vn });
                any = true;
            } else if vn < 0.0 {
                apply(sys, k, 0.0, y);
                applied.push((k, 0.0));
            }
        }
        if !any {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn system(m1: f64, m2: f64, r: f64) -> System {
        let text = format!(
            "name = \"t\"\n[parameters]\nomega = 1\n[forcing]\nomega = \"omega\"\n[[masses]]\nname = \"A\"\nmass = {m1}\n[[masses]]\nname = \"B\"\nmass = {m2}\n\
             [[stops]]\nname = \"AB\"\nmasses = [\"A\", \"B\"]\ngap = 0.5\nrestitution = {r}\n[[stops]]\nname = \"F\"\nmass = \"A\"\nside = \"below\"\nposition = -1\nrestitution = {r}\n"
        );
        let model = scene::Scene::parse(&text).unwrap().evaluate(&[]).unwrap();
        System::new(model).unwrap()
    }

    proptest! {
        /// Issue 5: at every impact momentum (two masses) and the restitution law
        /// hold, and kinetic energy never increases.
        #[test]
        fn impact_laws(m1 in 0.01f64..100.0, m2 in 0.01f64..100.0, r in 0.0f64..=1.0, v1 in -10.0f64..10.0, v2 in -10.0f64..10.0) {
            let sys = system(m1, m2, r);
            let mut y = DVector::from_vec(vec![0.0, -0.5, v1, v2]);
            let before = y.clone();
            apply(&sys, 0, r, &mut y);
            let (pb, pa) = (sys.momentum(&before), sys.momentum(&y));
            prop_assert!((pa - pb).abs() <= 1e-12 * (1.0 + pb.abs() + m1 * v1.abs() + m2 * v2.abs()));
            prop_assert!((sys.gap_rate(0, &y) + r * sys.gap_rate(0, &before)).abs() <= 1e-12 * (1.0 + v1.abs() + v2.abs()));
            prop_assert!(sys.kinetic_energy(&y) <= sys.kinetic_energy(&before) * (1.0 + 1e-14) + 1e-300);
            // A frame stop: v+ = -R v-.
            let mut z = before.clone();
            apply(&sys, 1, r, &mut z);
            prop_assert!((z[2] + r * v1).abs() <= 1e-12 * (1.0 + v1.abs()));
            prop_assert!(z[3].to_bits() == v2.to_bits(), "the other mass is untouched");
        }
    }
}
