//! Whether a motion has come to a known periodic orbit ([`reaches`]): the
//! proximity test that lets a basin map stop a start early, in the manner of
//! the proximity mappers of Attractors.jl.
//!
//! The motion is followed period by period from its start. Once
//! `min_transient` periods have passed, each period-section point (the state
//! at a whole number of forcing periods) is compared with the section points
//! of the known orbits; the motion has reached an orbit when `n + 1`
//! consecutive points (n the orbit's number of section points) each lie
//! within `tol (1 + |y|)` (max norm) of one of that orbit's points. Only
//! stable orbits are given: a motion that close to one stays with it.

use crate::{Accuracy, Ignore, Method, Points, Simulator, System};

/// What following a motion toward known orbits found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Proximity {
    /// The motion reached orbit `orbit` after `periods` forcing periods.
    Reached {
        /// Index of the orbit in the list given.
        orbit: usize,
        /// Periods simulated.
        periods: u64,
    },
    /// No orbit within `budget` periods, or the motion could not be followed.
    Not,
}

/// Follows the motion of `sys` from `y0` for at most `budget` periods,
/// until it reaches one of `orbits` (each a stable periodic orbit's
/// period-section points, states `[x…, v…]` at the forcing phase of the
/// start) within `tol` (see the module doc).
pub fn reaches(
    sys: &System,
    acc: &Accuracy,
    method: Method,
    y0: &[f64],
    orbits: &[Points],
    tol: f64,
    budget: u64,
) -> Proximity {
    if orbits.is_empty() {
        return Proximity::Not;
    }
    let Ok(mut sim) = Simulator::new(sys, *acc, method, y0) else { return Proximity::Not };
    let near = |y: &[f64], p: &[f64]| y.iter().zip(p).all(|(a, b)| (a - b).abs() <= tol * (1.0 + b.abs()));
    // The orbit the last points were near, and how many in a row.
    let mut streak: Option<(usize, usize)> = None;
    for period in 1..=budget {
        // With the half-period state where a cell's record takes it (a
        // symmetric scene), which splits the flow there: the same
        // trajectory, bit for bit, as the cell's own run from `y0`.
        if sim.run_period(&[], sys.model.symmetric, &mut Ignore).is_err() {
            return Proximity::Not;
        }
        if (period as usize) < acc.min_transient() {
            continue;
        }
        let y = sim.state().as_slice();
        let hit = orbits.iter().position(|o| o.iter().any(|p| near(y, p)));
        streak = match (hit, streak) {
            (Some(k), Some((j, n))) if k == j => Some((k, n + 1)),
            (Some(k), _) => Some((k, 1)),
            (None, _) => None,
        };
        if let Some((k, n)) = streak {
            if n > orbits[k].len() {
                return Proximity::Reached { orbit: k, periods: period };
            }
        }
    }
    Proximity::Not
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::system;

    #[test]
    fn a_start_near_the_orbit_reaches_it_and_a_far_orbit_is_never_reached() {
        // The single stop where 1-0-0 and 2-1-0 coexist.
        let sys = system("single-stop.toml", &[("omega", 2.5), ("sigma", 1.0), ("zeta", 0.05)]);
        let acc = Accuracy::default();
        // The section points of periods 600 and 601: the orbit the motion
        // reaches (one point, or two of a period-2 orbit).
        let mut sim = Simulator::new(&sys, acc, Method::Exact, &[0.3, 0.0]).unwrap();
        let mut on: Vec<Vec<f64>> = Vec::new();
        for k in 0..601 {
            sim.run_period(&[], false, &mut Ignore).unwrap();
            if k >= 599 {
                on.push(sim.state().as_slice().to_vec());
            }
        }
        let far = Points::from_rows([[50.0, 50.0]]).unwrap();
        let on = Points::from_rows(on).unwrap();
        let found = reaches(&sys, &acc, Method::Exact, &[0.3, 0.0], &[far.clone(), on], 1e-6, 600);
        let Proximity::Reached { orbit, periods } = found else { panic!("{found:?}") };
        assert_eq!(orbit, 1);
        assert!(periods >= acc.min_transient() as u64 && periods < 600, "{periods}");
        assert_eq!(reaches(&sys, &acc, Method::Exact, &[0.3, 0.0], &[far], 1e-6, 600), Proximity::Not);
    }
}
