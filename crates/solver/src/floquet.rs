//! Floquet multipliers of periodic orbits and the kind of a lost stability.
//!
//! The multipliers are the eigenvalues of the monodromy matrix (the Jacobian of
//! the period map at its fixed point). The orbit is stable when all lie inside
//! the unit circle; stability is lost where one crosses it: at +1 a saddle-node
//! (or a pitchfork in a symmetric scene), at −1 a period doubling, as a complex
//! pair a Neimark–Sacker bifurcation (an invariant circle is born). For a
//! symmetric orbit solved through its half map `H` (`P = H∘H`), a −1 of `H` is a
//! symmetry-breaking pitchfork (+1 of `P`), a +1 of `H` a saddle-node, and a
//! pair at `±i` of `H` a period doubling (−1 of `P`).

use nalgebra::DMatrix;
use num_complex::Complex64 as C64;

/// Eigenvalues of `m`, largest modulus first (ties: larger real part, then
/// larger imaginary part); empty when `m` is not finite or the QR iteration
/// does not converge even with shifts (nalgebra's plain `complex_eigenvalues`
/// may never return).
pub fn multipliers(m: &DMatrix<f64>) -> Vec<C64> {
    if !m.iter().all(|v| v.is_finite()) {
        return Vec::new();
    }
    // The QR iteration can cycle on a matrix with eigenvalues exactly on the
    // unit circle (an undamped rotation); a shift `m + sI` moves them off it,
    // and `s` is subtracted again.
    let scale = m.amax().max(1e-300);
    let n = m.nrows();
    let Some(mut mu) = [0.0, 0.123_456_7, -0.314_159_3].iter().find_map(|&f| {
        let shift = f * scale;
        let shifted = m + DMatrix::identity(n, n) * shift;
        nalgebra::Schur::try_new(shifted, f64::EPSILON, 1000 * n.max(1))
            .map(|schur| schur.complex_eigenvalues().iter().map(|l| l - shift).collect::<Vec<C64>>())
    }) else {
        return Vec::new();
    };
    mu.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(b.re.total_cmp(&a.re)).then(b.im.total_cmp(&a.im)));
    mu
}

/// Largest modulus of `mu` (0 when empty).
pub fn spectral_radius(mu: &[C64]) -> f64 {
    mu.iter().map(|m| m.norm()).fold(0.0, f64::max)
}

/// A local bifurcation of a periodic orbit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bifurcation {
    /// Period doubling (a multiplier of the period map at −1).
    PeriodDoubling,
    /// Saddle-node (fold) (+1, the symmetry kept).
    SaddleNode,
    /// Symmetry-breaking pitchfork (+1 of the period map, −1 of the half map).
    Pitchfork,
    /// Neimark–Sacker (a complex pair on the unit circle).
    NeimarkSacker,
    /// Grazing: a stop's gap touches zero with zero velocity and the event
    /// sequence changes.
    Grazing,
}

impl Bifurcation {
    /// Every kind.
    pub const ALL: [Bifurcation; 5] = [
        Bifurcation::PeriodDoubling,
        Bifurcation::SaddleNode,
        Bifurcation::Pitchfork,
        Bifurcation::NeimarkSacker,
        Bifurcation::Grazing,
    ];

    /// The kind of a short name ([`Bifurcation::name`]), in either case (`pd`, `PD`).
    pub fn parse(name: &str) -> Option<Bifurcation> {
        Bifurcation::ALL.into_iter().find(|b| b.name().eq_ignore_ascii_case(name))
    }

    /// Short name: `PD`, `SN`, `PF`, `NS`, `grazing`.
    pub fn name(self) -> &'static str {
        match self {
            Bifurcation::PeriodDoubling => "PD",
            Bifurcation::SaddleNode => "SN",
            Bifurcation::Pitchfork => "PF",
            Bifurcation::NeimarkSacker => "NS",
            Bifurcation::Grazing => "grazing",
        }
    }
}

/// The kind of bifurcation where multiplier `mu` (of the solved map) sits on
/// the unit circle; `half` when the map is the half map of a symmetric orbit.
/// Arguments within `0.05` rad of 0, π (or ±π/2 for the half map) count as real.
pub fn kind(mu: C64, half: bool) -> Bifurcation {
    let arg = mu.arg().abs();
    let near = |a: f64| (arg - a).abs() < 0.05;
    match (half, near(0.0), near(std::f64::consts::PI), near(std::f64::consts::FRAC_PI_2)) {
        (_, true, _, _) => Bifurcation::SaddleNode,
        (false, _, true, _) => Bifurcation::PeriodDoubling,
        (true, _, true, _) => Bifurcation::Pitchfork,
        (true, _, _, true) => Bifurcation::PeriodDoubling,
        _ => Bifurcation::NeimarkSacker,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_read_back_from_their_names_in_either_case() {
        for b in Bifurcation::ALL {
            assert_eq!(Bifurcation::parse(b.name()), Some(b));
            assert_eq!(Bifurcation::parse(&b.name().to_lowercase()), Some(b));
        }
        assert_eq!(Bifurcation::parse("hopf"), None);
    }

    #[test]
    fn kinds_of_crossings() {
        assert_eq!(kind(C64::new(1.0, 0.0), false), Bifurcation::SaddleNode);
        assert_eq!(kind(C64::new(-1.0, 0.0), false), Bifurcation::PeriodDoubling);
        assert_eq!(kind(C64::new(-1.0, 0.0), true), Bifurcation::Pitchfork);
        assert_eq!(kind(C64::new(0.0, 1.0), true), Bifurcation::PeriodDoubling);
        assert_eq!(kind(C64::from_polar(1.0, 1.0), false), Bifurcation::NeimarkSacker);
    }

    #[test]
    fn multipliers_sorted_by_modulus() {
        let m = DMatrix::from_row_slice(2, 2, &[0.5, 0.0, 0.0, -2.0]);
        let mu = multipliers(&m);
        assert!((mu[0].re + 2.0).abs() < 1e-15 && (mu[1].re - 0.5).abs() < 1e-15);
        assert!((spectral_radius(&mu) - 2.0).abs() < 1e-15);
    }
}
