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
use scene::Named;

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
            .map(|schur| block_eigenvalues(&schur.unpack().1).into_iter().map(|l| l - shift).collect::<Vec<C64>>())
    }) else {
        return Vec::new();
    };
    mu.sort_by(|a, b| b.norm().total_cmp(&a.norm()).then(b.re.total_cmp(&a.re)).then(b.im.total_cmp(&a.im)));
    mu
}

/// The eigenvalues of the quasi-triangular Schur form `t`: its 1 × 1
/// blocks, and each 2 × 2 block's pair, `(a + d)/2 ± √D` with
/// `D = bc + ((a − d)/2)²`. A pair is complex where `D < 0` and real where
/// `D ≥ 0`: a defective eigenvalue (a Jordan block, such as a rigid mode's
/// multipliers 1) can leave a 2 × 2 block whose `D` rounds above 0, where
/// nalgebra's `complex_eigenvalues` (which takes every block as complex)
/// gives a NaN imaginary part. Elsewhere the same numbers as it, bit for bit.
fn block_eigenvalues(t: &DMatrix<f64>) -> Vec<C64> {
    let n = t.nrows();
    let mut out = Vec::with_capacity(n);
    let mut m = 0;
    while m < n {
        if m + 1 == n || t[(m + 1, m)] == 0.0 {
            out.push(C64::new(t[(m, m)], 0.0));
            m += 1;
            continue;
        }
        let (a, b, c, d) = (t[(m, m)], t[(m, m + 1)], t[(m + 1, m)], t[(m + 1, m + 1)]);
        let val = (a - d) * 0.5;
        let discr = c * b + val * val;
        let half = C64::new((d + a) * 0.5, 0.0);
        if discr >= 0.0 {
            let root = discr.sqrt();
            out.extend([half + root, half - root]);
        } else {
            let root = C64::new(0.0, (-discr).sqrt());
            out.extend([half + root, half - root]);
        }
        m += 2;
    }
    out
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

impl Named for Bifurcation {
    const ALL: &'static [Bifurcation] = &[
        Bifurcation::PeriodDoubling,
        Bifurcation::SaddleNode,
        Bifurcation::Pitchfork,
        Bifurcation::NeimarkSacker,
        Bifurcation::Grazing,
    ];

    /// Short name, as files and JSON store it: `PD`, `SN`, `PF`, `NS`, `grazing`.
    fn name(self) -> &'static str {
        match self {
            Bifurcation::PeriodDoubling => "PD",
            Bifurcation::SaddleNode => "SN",
            Bifurcation::Pitchfork => "PF",
            Bifurcation::NeimarkSacker => "NS",
            Bifurcation::Grazing => "grazing",
        }
    }

    fn help(self) -> &'static str {
        match self {
            Bifurcation::PeriodDoubling => "Period doubling.",
            Bifurcation::SaddleNode => "Saddle-node (fold).",
            Bifurcation::Pitchfork => "Symmetry-breaking pitchfork.",
            Bifurcation::NeimarkSacker => "Neimark–Sacker (torus).",
            Bifurcation::Grazing => "Grazing.",
        }
    }

    /// The kind of a short name in either case (`pd`, `PD`).
    fn parse(name: &str) -> Option<Bifurcation> {
        Bifurcation::ALL.iter().copied().find(|b| b.name().eq_ignore_ascii_case(name))
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

    /// A Jordan block at 1 (a free mass's position and velocity over a
    /// period without events) beside a complex pair: every multiplier is
    /// finite, the two at 1 within the square root of the rounding, and the
    /// spectral radius 1 (nalgebra's `complex_eigenvalues` gave NaN for the
    /// pair at 1 of the damper's resting free mass at ω = 1.35, and the
    /// radius of the pair alone, 0.628).
    #[test]
    fn a_jordan_block_has_finite_multipliers() {
        let jac = DMatrix::from_row_slice(
            4,
            4,
            &[
                -0.11401319028343625,
                2.15501395319308e-16,
                -0.6289387777645101,
                9.669301306143277e-16,
                1.1875659104115477e-16,
                1.0,
                9.921973608076105e-17,
                4.654211338651545,
                0.6289387777645116,
                -2.2837295036015564e-16,
                0.011774565269465829,
                -4.481585556997624e-16,
                2.8803099718043126e-19,
                -1.788460119153784e-18,
                1.218484440894464e-17,
                0.9999999999999999,
            ],
        );
        let mu = multipliers(&jac);
        assert_eq!(mu.len(), 4);
        assert!(mu.iter().all(|l| l.re.is_finite() && l.im.is_finite()), "{mu:?}");
        assert!((spectral_radius(&mu) - 1.0).abs() < 1e-7, "{mu:?}");
        assert_eq!(mu.iter().filter(|l| (*l - 1.0).norm() < 1e-7).count(), 2, "{mu:?}");
        // The pair of the primary: 0.6278706319 in modulus, as `orbit` gives it.
        assert!(mu.iter().filter(|l| (l.norm() - 0.6278706319).abs() < 1e-9).count() == 2, "{mu:?}");
    }

    use super::*;

    #[test]
    fn kinds_read_back_from_their_names_in_either_case() {
        for &b in Bifurcation::ALL {
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
