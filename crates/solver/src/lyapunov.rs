//! The largest Lyapunov exponent of a motion, and the test that tells a
//! quasi-periodic motion from a chaotic one.
//!
//! The tangent map of each forcing period (flow transition and saltation
//! matrices, [`Simulator::track_tangent`]) is applied to a tangent vector that
//! is renormalised every period: `λ = Σ ln|Φ_k v_{k-1}| / (K T)`. For a periodic
//! orbit this tends to `ln|μ_max| / (nT)`; it is clearly positive for chaos and
//! zero for a motion on an invariant torus (quasi-periodic impacts), whose
//! period-section points then fill a closed curve.

use crate::simulate::{Halt, Ignore, Simulator};
use nalgebra::{DMatrix, DVector};

/// Largest Lyapunov exponent (per unit time) over `periods` forcing periods from
/// the simulator's state, after `warmup` periods that only align the tangent
/// vector with the most expanding direction; and the period-section points
/// visited. The simulator goes on from where it is.
pub fn largest_exponent(
    sim: &mut Simulator<'_>,
    warmup: usize,
    periods: usize,
) -> Result<(f64, Vec<DVector<f64>>), Halt> {
    let dim = sim.state().len();
    sim.track_tangent();
    let mut v = DVector::from_element(dim, 1.0 / (dim as f64).sqrt());
    let mut sum = 0.0;
    let mut points = Vec::with_capacity(periods);
    for k in 0..warmup + periods {
        sim.reset_tangent();
        sim.run_period(&[], false, &mut Ignore)?;
        let w: DVector<f64> = sim.tangent().ok_or(Halt::Stalled)? * &v;
        let norm = w.norm();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(Halt::Stalled);
        }
        v = w / norm;
        if k >= warmup {
            sum += norm.ln();
            points.push(sim.state().clone());
        }
    }
    Ok((sum / (periods as f64 * sim.period()), points))
}

/// Whether the points lie on one closed curve: in the plane of their two
/// principal directions, sorted by angle about their centroid, they cover every
/// direction (no angular gap above π/4) and the polygon through them is no
/// longer than twice the perimeter of their bounding ellipse (a scattered cloud
/// zig-zags and is many times longer).
pub fn fills_closed_curve(points: &[DVector<f64>]) -> bool {
    let n = points.len();
    if n < 16 {
        return false;
    }
    let dim = points[0].len();
    let mean = points.iter().fold(DVector::zeros(dim), |a, p| a + p) / n as f64;
    let mut cov = DMatrix::zeros(dim, dim);
    for p in points {
        let d = p - &mean;
        cov += &d * d.transpose();
    }
    let eig = nalgebra::SymmetricEigen::new(cov / n as f64);
    let mut order: Vec<usize> = (0..dim).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let (e1, e2) = (eig.eigenvectors.column(order[0]), eig.eigenvectors.column(order[1]));
    let (s1, s2) = (eig.eigenvalues[order[0]].max(0.0).sqrt(), eig.eigenvalues[order[1]].max(0.0).sqrt());
    if s2 <= 1e-9 * (1.0 + mean.amax()) {
        return false;
    }
    let mut plane: Vec<(f64, f64, f64)> = points
        .iter()
        .map(|p| {
            let d = p - &mean;
            let (u, w) = (d.dot(&e1) / s1, d.dot(&e2) / s2);
            (w.atan2(u), u, w)
        })
        .collect();
    plane.sort_by(|a, b| a.0.total_cmp(&b.0));
    let gap =
        plane.windows(2).map(|w| w[1].0 - w[0].0).fold(plane[0].0 + std::f64::consts::TAU - plane[n - 1].0, f64::max);
    let length: f64 = (0..n)
        .map(|i| {
            let (a, b) = (plane[i], plane[(i + 1) % n]);
            ((a.1 - b.1).powi(2) + (a.2 - b.2).powi(2)).sqrt()
        })
        .sum();
    // In whitened coordinates the points of an ellipse lie near the circle of
    // radius √2 (unit variance in each direction): perimeter 2π√2.
    gap < std::f64::consts::FRAC_PI_4 && length < 2.0 * std::f64::consts::TAU * std::f64::consts::SQRT_2
}
