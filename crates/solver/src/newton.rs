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

/// Solves `map(x) = x` from `x0` to residual `tol` (relative to `1 + |x|`) in at
/// most `max_iter` steps, keeping `pattern` when given (otherwise the pattern of
/// the first evaluation). `None` when an evaluation fails, the pattern changes,
/// a step is too large (more than `max_step` relative) or it does not converge.
pub fn solve(
    sim: &mut Simulator<'_>,
    x0: &DVector<f64>,
    map: MapKind,
    pattern: Option<&Pattern>,
    tol: f64,
    max_iter: usize,
    max_step: f64,
) -> Option<Solution> {
    try_solve(sim, x0, map, pattern, tol, max_iter, max_step).ok()
}

/// [`solve`], telling why it failed.
pub fn try_solve(
    sim: &mut Simulator<'_>,
    x0: &DVector<f64>,
    map: MapKind,
    pattern: Option<&Pattern>,
    tol: f64,
    max_iter: usize,
    max_step: f64,
) -> Result<Solution, Failure> {
    if sim.tangent().is_none() {
        sim.track_tangent();
    }
    let dim = x0.len();
    let mut x = x0.clone();
    let mut keep: Option<Pattern> = pattern.cloned();
    for iterations in 0..=max_iter {
        let image = evaluate(sim, &x, map).map_err(|_| Failure::Simulation)?;
        if keep.get_or_insert_with(|| image.pattern.clone()) != &image.pattern {
            return Err(Failure::Pattern);
        }
        let r = &image.value - &x;
        let residual = scaled(&r, &x);
        if residual <= tol {
            return Ok(Solution { x, jacobian: image.jacobian, pattern: image.pattern, residual, iterations });
        }
        if iterations == max_iter {
            break;
        }
        let jac = &image.jacobian - DMatrix::identity(dim, dim);
        let dx = jac.lu().solve(&(-&r)).ok_or(Failure::Diverged)?;
        if !dx.iter().all(|v| v.is_finite()) || scaled(&dx, &x) > max_step {
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
    let sol = solve(probe, x0, MapKind::Periods(n), Some(pattern), tol, 6, 0.1)?;
    let mu = crate::floquet::multipliers(&sol.jacobian);
    (!mu.is_empty() && mu.iter().all(|m| m.norm() < 1.0)).then_some(sol)
}
