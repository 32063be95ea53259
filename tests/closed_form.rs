//! Closed-form checks of the exact solver (issue 2).

use crate::util::{record, system};
use solver::reference::{free_amplitude, single_stop_impact_speeds};
use solver::{run_cell, Accuracy, Class, Method, Preset};

fn tight() -> Accuracy {
    Accuracy::preset(Preset::Precise)
        .with(solver::Knob::PeriodicTol, 1e-13)
        .and_then(|a| a.with(solver::Knob::MaxPeriods, 4000.0))
        .unwrap()
}

/// Issue 2: the no-impact steady-state amplitude of M1 equals 1/√((1-ω²)² + (2ζω)²).
#[test]
fn free_steady_state_amplitude() {
    for &(omega, zeta) in &[(0.5, 0.1), (1.3, 0.1), (2.5, 0.06), (0.9, 0.25)] {
        let sys = system("multi-stop.toml", &[("omega", omega), ("zeta", zeta), ("delta", 8.0)]);
        let cell = run_cell(&sys, &tight(), Method::Exact, &sys.model.initial_state());
        assert_eq!(cell.class, Class::Periodic);
        assert_eq!(cell.labels[0].to_string(), "1-0-0");
        let (x, v) = (cell.final_state[0], cell.final_state[2]);
        let amp = (x * x + (v / omega).powi(2)).sqrt();
        let exact = free_amplitude(omega, zeta);
        assert!((amp - exact).abs() < 1e-10, "omega {omega}: {amp} vs {exact}");
    }
}

/// Issue 2: the single-stop (1, n) orbits' impact speed equals the closed form.
#[test]
fn single_stop_impact_speed() {
    let cases = [
        (2.0, 0.0, 0.8, 1),
        (2.5, 0.0, 0.5, 1),
        (2.5, -0.1, 0.8, 1),
        (2.0, 0.1, 0.5, 1),
        (3.5, 0.0, 0.5, 2),
        (4.0, 0.0, 0.8, 2),
    ];
    for &(omega, sigma, r, n) in &cases {
        let sys = system("single-stop.toml", &[("omega", omega), ("sigma", sigma), ("r", r)]);
        let cell = run_cell(&sys, &tight(), Method::Exact, &sys.model.initial_state());
        assert_eq!(cell.n, Some(n as usize), "omega {omega} sigma {sigma} r {r}");
        assert_eq!(cell.impacts, vec![1]);
        let (rec, _) = record(&sys, &tight(), Method::Exact, &cell.final_state, n as usize);
        let v = rec.impacts[0].before[1];
        let roots = single_stop_impact_speeds(omega, sigma, r, n);
        let best = roots.iter().map(|x| (x - v).abs()).fold(f64::INFINITY, f64::min);
        assert!(best < 1e-9, "omega {omega} sigma {sigma} r {r}: V = {v}, roots {roots:?}");
        // And the rebound follows the restitution law.
        assert!((rec.impacts[0].after[1] + r * v).abs() < 1e-14);
    }
}

/// Issue 2: momentum is conserved and the restitution law holds at every
/// two-mass impact; kinetic energy never increases at an impact.
#[test]
fn impact_laws_hold_at_every_impact() {
    for &(omega, delta, mu_m) in &[(0.33, 0.6, 0.5), (0.295, 0.6, 0.25), (0.2, 0.6, 0.75), (1.1, 0.2, 0.05)] {
        let sys = system("multi-stop.toml", &[("omega", omega), ("delta", delta), ("mu_m", mu_m)]);
        let r = sys.model.parameter("R").unwrap();
        let (rec, _) = record(&sys, &Accuracy::default(), Method::Exact, &sys.model.initial_state(), 40);
        assert!(rec.impacts.len() > 20);
        let mut pair = 0;
        for imp in &rec.impacts {
            let (b, a) = (&imp.before, &imp.after);
            assert!(sys.kinetic_energy(a) <= sys.kinetic_energy(b) * (1.0 + 1e-14));
            if sys.model.stops[imp.stop].name == "A12" {
                pair += 1;
                let (pb, pa) = (sys.momentum(b), sys.momentum(a));
                assert!((pa - pb).abs() <= 1e-13 * (1.0 + pb.abs()), "momentum {pb} -> {pa}");
                let (rb, ra) = (b[2] - b[3], a[2] - a[3]);
                assert!((ra + r * rb).abs() <= 1e-13 * (1.0 + rb.abs()), "relative velocity {rb} -> {ra}");
            }
        }
        assert!(pair > 0, "omega {omega}: no two-mass impact");
    }
}

/// Issue 2: the impact damper's free mass flies on an exact straight line
/// between impacts (zero eigenvalues handled exactly, not perturbed).
#[test]
fn free_mass_flight_is_exact() {
    let sys = system("impact-damper.toml", &[("omega", 1.0), ("delta", 0.5), ("mu", 0.2)]);
    let (rec, _) = record(&sys, &Accuracy::default(), Method::Exact, &[0.3, 0.0, 0.0, 0.7], 30);
    assert!(rec.impacts.len() > 20);
    for w in rec.impacts.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        let dt = b.time - a.time;
        assert!((b.before[3] - a.after[3]).abs() < 1e-13, "velocity changed in flight");
        let x = a.after[1] + a.after[3] * dt;
        assert!((b.before[1] - x).abs() < 1e-11 * (1.0 + dt), "position off the line by {}", b.before[1] - x);
    }
}
