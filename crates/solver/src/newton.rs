//! Periodic orbits by Newton's method on the n-period map.
//!
//! The period map `P` takes the state at `t = kT` to the state at `t = (k+1)T`;
//! a period-n orbit is a zero of `F(x) = Pⁿ(x) - x`. Newton's iteration
//! `x ← x - (DPⁿ - I)⁻¹ F(x)` converges in a few steps where brute-force
//! simulation contracts only like `|μ|^k` (μ the leading Floquet multiplier,
//! close to 1 near a bifurcation). The Jacobian here is taken by forward
//! differences along each coordinate; every evaluation must keep the impact
//! pattern of the orbit (the same impacts per stop in each period), otherwise
//! the iteration gives up and brute force continues.

use crate::simulate::{Ignore, Simulator};
use nalgebra::{DMatrix, DVector};

/// Impacts per stop in each of the n periods: the event pattern an orbit must keep.
pub type Pattern = Vec<Vec<u32>>;

/// Simulates n periods from `x` with `probe`; the end state and the pattern.
fn map(probe: &mut Simulator<'_>, x: &DVector<f64>, n: usize) -> Option<(DVector<f64>, Pattern)> {
    probe.restart(x.as_slice()).ok()?;
    let mut pattern = Vec::with_capacity(n);
    for _ in 0..n {
        pattern.push(probe.run_period(&[], false, &mut Ignore).ok()?.impacts);
    }
    Some((probe.y.clone(), pattern))
}

fn scaled(v: &DVector<f64>, x: &DVector<f64>) -> f64 {
    v.amax() / (1.0 + x.amax())
}

/// Solves `Pⁿ(x) = x` from `x0`, keeping `pattern`; returns the fixed point once
/// `|F|` is below `tol` (relative to `1 + |x|`) and the orbit is stable (every
/// eigenvalue of the last Jacobian `DPⁿ` inside the unit circle), or `None`: a
/// transient that lingers near an unstable orbit must not be labelled by it.
pub fn fixed_point(
    probe: &mut Simulator<'_>,
    x0: &DVector<f64>,
    n: usize,
    pattern: &Pattern,
    tol: f64,
) -> Option<DVector<f64>> {
    let dim = x0.len();
    let mut x = x0.clone();
    let mut stable = false;
    for _ in 0..6 {
        let (fx, p) = map(probe, &x, n)?;
        if &p != pattern {
            return None;
        }
        let r = &fx - &x;
        if scaled(&r, &x) <= tol {
            return stable.then_some(x);
        }
        let mut jac = DMatrix::<f64>::zeros(dim, dim);
        for j in 0..dim {
            let h = 1e-7 * (1.0 + x[j].abs());
            let mut xp = x.clone();
            xp[j] += h;
            let (fp, pp) = map(probe, &xp, n)?;
            if &pp != pattern {
                return None;
            }
            jac.set_column(j, &((fp - &fx) / h));
        }
        stable = jac.complex_eigenvalues().iter().all(|m| m.norm() < 1.0);
        jac -= DMatrix::identity(dim, dim);
        let dx = jac.lu().solve(&(-&r))?;
        if !dx.iter().all(|v| v.is_finite()) || scaled(&dx, &x) > 0.1 {
            return None;
        }
        x += dx;
    }
    None
}
