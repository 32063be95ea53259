//! Closed-form answers of reference problems, shared by tests and benches.
//!
//! # Free (no-impact) steady state
//! `x'' + 2ζx' + x = sin(ωt + τ)` has the steady amplitude
//! `1/√((1-ω²)² + (2ζω)²)`.
//!
//! # Single-stop (1, n) orbits
//! `x'' + x = cos(ωt)` (ζ = 0), stop `x <= σ`, restitution r: one impact every n
//! forcing periods, `Θ = 2πn/ω`. Between impacts `x = γ cos(ωt) + h(t)` with
//! `γ = 1/(1-ω²)` and `h` a free oscillation. Let the impact be at phase `φ = ωt₀`
//! with speed `V > 0`: `x = σ`, `x'(t₀⁻) = V`, `x'(t₀⁺) = -rV`. As `γ cos` is
//! Θ-periodic, `h(0) = h(Θ) = h₀ = σ - γ cos φ`, `h'(0) = -rV + a`,
//! `h'(Θ) = V + a` with `a = γω sin φ`. With `c = cos Θ`, `s = sin Θ`,
//! `h(Θ) = h₀ c + h'(0) s` and `h'(Θ) = -h₀ s + h'(0) c` give
//! `h'(0) s = h₀(1-c)` and `-h₀ s + h'(0) c = V + a`. Eliminating `h₀` with
//! `s² = (1-c)(1+c)`: `-2a(1-c) = V(1-c)(1-r)`, so `a = -V(1-r)/2`, i.e.
//! `γ sin φ = -V rm/2` with `rm = (1-r)/ω`; and `h₀ = -V cs/2` with
//! `cs = s(1+r)/(1-c)`, i.e. `γ cos φ = σ + V cs/2`. Adding the squares:
//!
//! ```text
//! (cs² + rm²) V²/4 + cs σ V + σ² - γ² = 0 .
//! ```

/// Published labels of M1 in the multi-stop scene at the reference parameters:
/// `(ω, δ, label)` (docs/models.md, section 1), shared by tests and benches.
pub const PUBLISHED_MULTI_STOP: [(f64, f64, &str); 4] =
    [(0.33, 0.6, "1-4-4"), (0.295, 0.6, "1-5-6"), (0.20, 0.6, "1-S-S"), (2.5, 1.2, "1-0-0")];

/// One multi-stop cell per regime, `(name, ω, δ)`: no impact, one impact per
/// stop, several impacts, chattering, complete chattering (sticking).
pub const REGIMES_MULTI_STOP: [(&str, f64, f64); 5] = [
    ("no-impact", 2.5, 1.2),
    ("1-1-1", 1.0, 1.2),
    ("1-4-4", 0.33, 0.6),
    ("chattering", 0.295, 0.6),
    ("sticking", 0.20, 0.6),
];

/// Steady amplitude of `x'' + 2ζx' + x = sin(ωt + τ)`.
pub fn free_amplitude(omega: f64, zeta: f64) -> f64 {
    1.0 / ((1.0 - omega * omega).powi(2) + (2.0 * zeta * omega).powi(2)).sqrt()
}

/// Positive impact speeds `V` of (1, n) orbits of the undamped single-stop
/// oscillator (see the module doc); unstable and inadmissible ones included.
pub fn single_stop_impact_speeds(omega: f64, sigma: f64, r: f64, n: u32) -> Vec<f64> {
    let gamma = 1.0 / (1.0 - omega * omega);
    let theta = 2.0 * std::f64::consts::PI * n as f64 / omega;
    let (s, c) = theta.sin_cos();
    let cs = s * (1.0 + r) / (1.0 - c);
    let rm = (1.0 - r) / omega;
    let (qa, qb, qc) = ((cs * cs + rm * rm) / 4.0, cs * sigma, sigma * sigma - gamma * gamma);
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 {
        return Vec::new();
    }
    let sq = disc.sqrt();
    // Numerically stable pair of roots.
    let q = -0.5 * (qb + qb.signum() * sq);
    let mut roots = vec![q / qa, qc / q];
    roots.retain(|v| v.is_finite() && *v > 0.0);
    roots
}

/// The stop position `σ < 0` where the two (1, n) orbit families of
/// [`single_stop_impact_speeds`] merge and vanish (a saddle-node): the
/// quadratic's discriminant `σ² (c_s² - 4a) + 4aγ²` with `4a = c_s² + r_m²`
/// vanishes at `σ² = (c_s² + r_m²) γ² / r_m²`.
pub fn single_stop_fold_sigma(omega: f64, r: f64, n: u32) -> f64 {
    let gamma = 1.0 / (1.0 - omega * omega);
    let theta = 2.0 * std::f64::consts::PI * n as f64 / omega;
    let (s, c) = theta.sin_cos();
    let cs = s * (1.0 + r) / (1.0 - c);
    let rm = (1.0 - r) / omega;
    -(cs * cs + rm * rm).sqrt() * gamma.abs() / rm
}

/// How far the (1, 1) orbit at the fold of [`single_stop_fold_sigma`] passes
/// beyond its stop between its impacts: the largest `x(t) - σ` over the
/// interior of the period (2 % kept clear of each impact), by sampling (4000
/// points) refined by golden section. Negative while the orbit keeps clear of
/// the stop; where it changes sign the orbit grazes the stop between impacts
/// and the fold curve meets a grazing (a codimension-two point).
///
/// With the impact at `t = 0`, phase `φ`, speed `V` (the double root of the
/// quadratic of the module doc at the fold),
/// `x(t) = γ cos(ωt + φ) + h₀ cos t + (a - rV) sin t` with
/// `γ sin φ = -V r_m/2`, `γ cos φ = σ + V c_s/2`, `h₀ = σ - γ cos φ` and
/// `a = γω sin φ`.
pub fn single_stop_fold_overshoot(omega: f64, r: f64) -> f64 {
    let gamma = 1.0 / (1.0 - omega * omega);
    let theta = 2.0 * std::f64::consts::PI / omega;
    let (s, c) = theta.sin_cos();
    let (cs, rm) = (s * (1.0 + r) / (1.0 - c), (1.0 - r) / omega);
    let sigma = single_stop_fold_sigma(omega, r, 1);
    let v = -cs * sigma / (2.0 * (cs * cs + rm * rm) / 4.0);
    let phi = (-v * rm / 2.0 / gamma).atan2((sigma + v * cs / 2.0) / gamma);
    let h0 = sigma - gamma * phi.cos();
    let rate = gamma * omega * phi.sin() - r * v;
    let x = |t: f64| gamma * (omega * t + phi).cos() + h0 * t.cos() + rate * t.sin();
    let at = |i: usize| theta * (0.02 + 0.96 * i as f64 / 4000.0);
    let i = (0..=4000).max_by(|&i, &j| x(at(i)).total_cmp(&x(at(j)))).unwrap_or(0);
    let (mut lo, mut hi) = (at(i.saturating_sub(1)), at((i + 1).min(4000)));
    for _ in 0..60 {
        let (m1, m2) = (lo + 0.382 * (hi - lo), lo + 0.618 * (hi - lo));
        if x(m1) > x(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    x(0.5 * (lo + hi)) - sigma
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_solve_the_quadratic() {
        let (omega, sigma, r) = (2.5f64, 0.1, 0.8);
        for v in single_stop_impact_speeds(omega, sigma, r, 1) {
            let gamma = 1.0 / (1.0 - omega * omega);
            let th = 2.0 * std::f64::consts::PI / omega;
            let cs = th.sin() * (1.0 + r) / (1.0 - th.cos());
            let rm = (1.0 - r) / omega;
            let res = (cs * cs + rm * rm) * v * v / 4.0 + cs * sigma * v + sigma * sigma - gamma * gamma;
            assert!(res.abs() < 1e-12);
        }
        assert!((free_amplitude(0.0, 0.3) - 1.0).abs() < 1e-15);
        // At the fold the two roots merge; just beyond it there are none.
        let f = single_stop_fold_sigma(omega, r, 1);
        let roots = single_stop_impact_speeds(omega, f * (1.0 - 1e-9), r, 1);
        assert_eq!(roots.len(), 2);
        assert!((roots[0] - roots[1]).abs() < 1e-3 * roots[0]);
        assert!(single_stop_impact_speeds(omega, f * (1.0 + 1e-9), r, 1).is_empty());
    }
}
