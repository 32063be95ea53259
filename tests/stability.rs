//! Exact Jacobians, Newton orbits, Floquet multipliers (issue 6).

use crate::util::system;
use solver::{multipliers, solve, Accuracy, Complex64, DMatrix, DVector, Ignore, MapKind, Method, Simulator, System};

/// Converged stable state of a cell (plain simulation) and its period.
fn settled(sys: &System) -> (Vec<f64>, usize) {
    let acc = Accuracy::default();
    let cell = solver::run_cell(sys, &acc, Method::Exact, &sys.model.initial_state());
    (cell.final_state, cell.n.expect("periodic cell"))
}

/// Central finite differences of the n-period map at `x`.
fn finite_differences(sys: &System, x: &DVector<f64>, n: usize) -> DMatrix<f64> {
    let mut sim = Simulator::new(sys, Accuracy::default(), Method::Exact, x.as_slice()).unwrap();
    let mut image = |y: &DVector<f64>| {
        sim.restart(y.as_slice()).unwrap();
        for _ in 0..n {
            sim.run_period(&[], false, &mut Ignore).unwrap();
        }
        sim.y.clone()
    };
    let dim = x.len();
    let mut jac = DMatrix::zeros(dim, dim);
    for j in 0..dim {
        let h = 1e-6 * (1.0 + x[j].abs());
        let (mut a, mut b) = (x.clone(), x.clone());
        a[j] += h;
        b[j] -= h;
        jac.set_column(j, &((image(&a) - image(&b)) / (2.0 * h)));
    }
    jac
}

/// The exact n-period map Jacobian at the Newton fixed point from a settled state.
fn orbit(sys: &System, map: MapKind) -> solver::Solution {
    let (y, _) = settled(sys);
    let mut sim = Simulator::new(sys, Accuracy::default(), Method::Exact, &y).unwrap();
    solve(&mut sim, &DVector::from_vec(y), map, None, 1e-13, 20, 0.5).expect("Newton converges")
}

/// Issue 6: without impacts the multipliers are `exp(λ_i T)` of the linear
/// oscillator's eigenvalues, to 1e-12.
#[test]
fn linear_oscillator_multipliers_are_exponentials() {
    for (omega, zeta) in [(2.5, 0.1), (0.7, 0.05), (1.3, 0.3)] {
        let sys = system("multi-stop.toml", &[("omega", omega), ("delta", 50.0), ("zeta", zeta)]);
        let sol = orbit(&sys, MapKind::Periods(1));
        let m = sys.dof();
        let minv = DMatrix::from_diagonal(&sys.mass.map(|v| 1.0 / v));
        let mut a = DMatrix::zeros(2 * m, 2 * m);
        a.view_mut((0, m), (m, m)).fill_with_identity();
        a.view_mut((m, 0), (m, m)).copy_from(&(-&minv * &sys.stiffness));
        a.view_mut((m, m), (m, m)).copy_from(&(-&minv * &sys.damping));
        let mut want: Vec<Complex64> = a.complex_eigenvalues().iter().map(|l| (l * sys.period).exp()).collect();
        let got = multipliers(&sol.jacobian);
        assert_eq!(got.len(), want.len());
        for g in &got {
            // Pair each multiplier with the nearest exponential not yet taken.
            let i = (0..want.len()).min_by(|&i, &j| (g - want[i]).norm().total_cmp(&(g - want[j]).norm())).unwrap();
            let w = want.swap_remove(i);
            assert!((g - w).norm() < 1e-12, "ω = {omega}: {g} against {w}");
        }
    }
}

/// Issue 6: the exact Jacobian through impacts (and stick/slip) equals finite
/// differences of the simulated map, so the multipliers agree to 1e-6.
#[test]
fn jacobian_through_events_matches_finite_differences() {
    let cases: [(&str, Vec<(&str, f64)>); 4] = [
        ("single-stop.toml", vec![("omega", 2.5)]),
        ("single-stop.toml", vec![("omega", 1.7), ("zeta", 0.05)]),
        ("multi-stop.toml", vec![("omega", 0.33), ("delta", 0.6)]),
        ("dry-friction.toml", vec![("omega", 2.0), ("fk", 0.1)]),
    ];
    for (file, sets) in cases {
        let sys = system(file, &sets);
        let (_, n) = settled(&sys);
        let sol = orbit(&sys, MapKind::Periods(n));
        let fd = finite_differences(&sys, &sol.x, n);
        let err = (&sol.jacobian - &fd).amax() / (1.0 + fd.amax());
        assert!(err < 1e-6, "{file} {sets:?}: Jacobian differs from finite differences by {err:e}");
        let (a, b) = (multipliers(&sol.jacobian), multipliers(&fd));
        for (x, y) in a.iter().zip(&b) {
            assert!((x.norm() - y.norm()).abs() < 1e-6, "{file} {sets:?}: |μ| {} against {}", x.norm(), y.norm());
        }
    }
}
