//! Periodic orbits by Newton's method on the n-period map, with its exact Jacobian.
//!
//! The period map `P` takes the state at `t = kT` to the state at `t = (k+1)T`;
//! a period-n orbit is a zero of `F(x) = Pⁿ(x) - x`. Newton's iteration
//! `x ← x - (DPⁿ - I)⁻¹ F(x)` converges quadratically, also to unstable orbits,
//! where brute-force simulation contracts only like `|μ|^k` (μ the leading
//! Floquet multiplier). `DPⁿ` is the simulator's tangent map (flow transition
//! matrices and saltation matrices, see [`Simulator::track_tangent`]).
//!
//! A symmetric orbit of a mirror-symmetric scene (`x → -x` with a half-period
//! shift) is a fixed point of the half map `H(x) = -Φ_{T/2}(x)`, with
//! `P = H∘H`: solving `H` keeps the symmetry exactly, and its multipliers tell a
//! symmetry-breaking pitchfork (−1 of `H`) from a period doubling.
//!
//! Every evaluation must keep the orbit's impact pattern (impacts per stop in
//! each period), so that the iteration stays on one smooth branch of the map.

use crate::simulate::{Halt, Ignore, Simulator};
use nalgebra::{DMatrix, DVector};

/// Impacts per stop in each of the n periods: the event pattern an orbit must keep.
pub type Pattern = Vec<Vec<u32>>;

/// Which map a fixed point is sought of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapKind {
    /// `Pⁿ`, n forcing periods.
    Periods(usize),
    /// The half map `H(x) = -Φ_{T/2}(x)` of a symmetric period-one orbit.
    Half,
}

impl MapKind {
    /// Forcing periods simulated per evaluation.
    fn periods(self) -> usize {
        match self {
            MapKind::Periods(n) => n,
            MapKind::Half => 1,
        }
    }
}

/// One evaluation of a map: image, exact Jacobian, impact pattern.
#[derive(Debug, Clone)]
pub struct Image {
    /// The image of the state.
    pub value: DVector<f64>,
    /// Its Jacobian.
    pub jacobian: DMatrix<f64>,
    /// Impacts per stop in each simulated period.
    pub pattern: Pattern,
}

/// Evaluates `map` at `x` with `sim` (which must track its tangent).
pub fn evaluate(sim: &mut Simulator<'_>, x: &DVector<f64>, map: MapKind) -> Result<Image, Halt> {
    sim.restart(x.as_slice())?;
    let mut pattern = Vec::with_capacity(map.periods());
    let mut half = None;
    for _ in 0..map.periods() {
        let rec = sim.run_period(&[], map == MapKind::Half, &mut Ignore)?;
        pattern.push(rec.impacts);
        if map == MapKind::Half {
            half = rec.half.zip(rec.half_tangent);
        }
    }
    let (value, jacobian) = match map {
        MapKind::Periods(_) => (sim.state().clone(), sim.tangent().ok_or(Halt::Stalled)?.clone()),
        MapKind::Half => {
            let (y, j) = half.ok_or(Halt::Stalled)?;
            (-y, -j)
        }
    };
    Ok(Image { value, jacobian, pattern })
}

fn scaled(v: &DVector<f64>, x: &DVector<f64>) -> f64 {
    v.amax() / (1.0 + x.amax())
}

/// A converged fixed point.
#[derive(Debug, Clone)]
pub struct Solution {
    /// The fixed point.
    pub x: DVector<f64>,
    /// The map's Jacobian there.
    pub jacobian: DMatrix<f64>,
    /// The impact pattern there.
    pub pattern: Pattern,
    /// Final residual `|F(x)|/(1 + |x|)`.
    pub residual: f64,
    /// Newton steps taken.
    pub iterations: usize,
}

/// Why Newton's method stopped without a fixed point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Failure {
    /// An evaluation had another impact pattern than the one kept.
    Pattern,
    /// A step was too large or singular, or the iteration did not converge.
    Diverged,
    /// The simulation itself failed (budget, stall).
    Simulation,
}

/// When Newton's method stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// The residual `|F(x)|/(1 + |x|)` of a solution.
    pub tol: f64,
    /// Most steps.
    pub max_iter: usize,
    /// Largest step, relative to `1 + |x|`: a larger one fails.
    pub max_step: f64,
    /// Steps without a new least residual after which the iteration fails
    /// while that least residual is above 1e-8 (`None`: it runs
    /// to `max_iter`). Near a change of the impact pattern Newton's method
    /// can wander at residuals of 1e-6 to 1e-3 for every step allowed,
    /// without a fixed point of the kept pattern to reach.
    pub stall: Option<usize>,
}

/// A least residual at or below this is rounding, not a stall: an orbit
/// whose residual hovers a little above a tolerance near rounding level
/// gets every step it is allowed to reach it.
pub(crate) const STALL_FLOOR: f64 = 1e-8;

/// The least residual of an iteration so far, and the steps since it fell.
#[derive(Debug, Clone, Copy)]
struct Progress {
    least: f64,
    since: usize,
}

impl Default for Progress {
    fn default() -> Progress {
        Progress { least: f64::INFINITY, since: 0 }
    }
}

impl Progress {
    /// Records the residual of a step; whether the iteration has stalled:
    /// `limit` steps without a new least residual, that least above
    /// [`STALL_FLOOR`] (never, without a limit).
    fn stalled(&mut self, residual: f64, limit: Option<usize>) -> bool {
        if residual < self.least {
            (self.least, self.since) = (residual, 0);
        } else {
            self.since += 1;
        }
        limit.is_some_and(|k| self.since >= k && self.least > STALL_FLOOR)
    }
}

/// Solves `map(x) = x` from `x0` within `limits`, keeping `pattern` when
/// given (otherwise the pattern of the first evaluation). `None` when an
/// evaluation fails, the pattern changes, a step is too large or it does not
/// converge.
pub fn solve(
    sim: &mut Simulator<'_>,
    x0: &DVector<f64>,
    map: MapKind,
    pattern: Option<&Pattern>,
    limits: Limits,
) -> Option<Solution> {
    try_solve(sim, x0, map, pattern, limits).ok()
}

/// [`solve`], telling why it failed.
pub fn try_solve(
    sim: &mut Simulator<'_>,
    x0: &DVector<f64>,
    map: MapKind,
    pattern: Option<&Pattern>,
    limits: Limits,
) -> Result<Solution, Failure> {
    if sim.tangent().is_none() {
        sim.track_tangent();
    }
    let dim = x0.len();
    let mut x = x0.clone();
    let mut keep: Option<Pattern> = pattern.cloned();
    let mut progress = Progress::default();
    for iterations in 0..=limits.max_iter {
        let image = evaluate(sim, &x, map).map_err(|_| Failure::Simulation)?;
        if keep.get_or_insert_with(|| image.pattern.clone()) != &image.pattern {
            return Err(Failure::Pattern);
        }
        let r = &image.value - &x;
        let residual = scaled(&r, &x);
        if residual <= limits.tol {
            return Ok(Solution { x, jacobian: image.jacobian, pattern: image.pattern, residual, iterations });
        }
        if progress.stalled(residual, limits.stall) || iterations == limits.max_iter {
            break;
        }
        let jac = &image.jacobian - DMatrix::identity(dim, dim);
        let dx = jac.lu().solve(&(-&r)).ok_or(Failure::Diverged)?;
        if !dx.iter().all(|v| v.is_finite()) || scaled(&dx, &x) > limits.max_step {
            return Err(Failure::Diverged);
        }
        x += dx;
    }
    Err(Failure::Diverged)
}

/// Solves `Pⁿ(x) = x` from `x0`, keeping `pattern`; returns the solution once
/// `|F|` is below `tol` and the orbit is stable (every eigenvalue of `DPⁿ`
/// inside the unit circle), or `None`: a transient that lingers near an
/// unstable orbit must not be labelled by it. (The acceleration of
/// [`crate::run_cell`].)
pub fn fixed_point(
    probe: &mut Simulator<'_>,
    x0: &DVector<f64>,
    n: usize,
    pattern: &Pattern,
    tol: f64,
) -> Option<Solution> {
    let sol =
        solve(probe, x0, MapKind::Periods(n), Some(pattern), Limits { tol, max_iter: 6, max_step: 0.1, stall: None })?;
    let mu = crate::floquet::multipliers(&sol.jacobian);
    (!mu.is_empty() && mu.iter().all(|m| m.norm() < 1.0)).then_some(sol)
}

#[cfg(test)]
mod tests {
    use super::Progress;

    /// The step at which an iteration with these residuals stalls, for a
    /// limit of 8 steps.
    fn stalls_at(residuals: &[f64]) -> Option<usize> {
        let mut p = Progress::default();
        residuals.iter().position(|&r| p.stalled(r, Some(8)))
    }

    /// Residuals of Newton's method recorded by `curves` on the reference
    /// map: one that wanders without a fixed point of its impact pattern
    /// (stopped at its ninth step without a new least residual, where 40
    /// were spent), one that jumps away and converges (a new least only at
    /// its sixth step), and one that hovers at rounding level above the
    /// tolerance until it reaches it (never a stall: below the floor).
    #[test]
    fn a_wandering_iteration_stalls_and_converging_ones_do_not() {
        let wander = [
            6.2e-4, 2.0e-4, 1.4e-4, 4.0e-4, 1.5e-4, 2.9e-4, 1.3e-4, 3.1e-3, 8.3e-4, 2.5e-4, 1.3e-4, 6.0e-2, 1.5e-2,
            4.3e-3, 1.2e-3, 3.4e-4, 1.4e-4, 5.6e-4,
        ];
        assert_eq!(stalls_at(&wander), Some(14));
        let converges = [2.6e-5, 2.3e-3, 5.5e-4, 1.3e-4, 2.7e-5, 3.0e-6, 6.7e-8, 3.5e-11, 4.1e-16];
        assert_eq!(stalls_at(&converges), None);
        let rounding = [
            1.8e-11, 1.3e-11, 3.5e-12, 1.2e-12, 1.7e-12, 1.0e-12, 7.8e-12, 2.2e-12, 1.0e-12, 2.3e-11, 6.0e-12, 1.8e-12,
            1.0e-12, 2.2e-11, 5.8e-12, 1.7e-12,
        ];
        assert_eq!(stalls_at(&rounding), None);
        let mut unlimited = Progress::default();
        assert!(wander.iter().all(|&r| !unlimited.stalled(r, None)));
    }
}
