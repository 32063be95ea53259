//! Properties of whole simulations on random parameters (issue 5): states stay
//! finite, stops are never penetrated by more than the contact tolerance, and
//! energy never increases at an impact.

use crate::util::system;
use proptest::prelude::*;
use solver::{Accuracy, Method};

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn random_cells_stay_admissible(mu_m in 0.05f64..0.95, mu_k in 0.05f64..0.95, mu_c in 0.05f64..0.95,
                                    zeta in 0.0f64..0.3, r in 0.0f64..1.0, delta in 0.01f64..2.0, omega in 0.1f64..4.0) {
        let sys = system("multi-stop.toml", &[("mu_m", mu_m), ("mu_k", mu_k), ("mu_c", mu_c), ("zeta", zeta), ("R", r), ("delta", delta), ("omega", omega)]);
        let acc = Accuracy::default().with("max_events", 2e4).unwrap();
        let mut sim = match solver::Simulator::new(&sys, acc, Method::Exact, &sys.model.initial_state()) {
            Ok(s) => s,
            Err(h) => return Err(TestCaseError::fail(format!("{h:?}"))),
        };
        let mut rec = crate::util::Recorder::default();
        for _ in 0..6 {
            if sim.run_period(&[], false, &mut rec).is_err() {
                break; // an exhausted budget is an outcome, not a failure
            }
        }
        let tol = 10.0 * acc.contact_tol();
        for (_, y) in &rec.events {
            prop_assert!(y.iter().all(|v| v.is_finite()));
            for k in 0..sys.stops.len() {
                prop_assert!(sys.gap(k, y) >= -tol, "stop {} penetrated by {}", k, -sys.gap(k, y));
            }
        }
        for imp in &rec.impacts {
            prop_assert!(sys.kinetic_energy(&imp.after) <= sys.kinetic_energy(&imp.before) * (1.0 + 1e-13));
        }
    }
}

/// `x'' + 2ζx' + x = cos ωt` from `x(0) = x0`, `x'(0) = 0`, without the stop:
/// the textbook closed form (ζ < 1), independent of the solver's modal flow.
fn free_single_stop(zeta: f64, omega: f64, x0: f64, t: f64) -> f64 {
    let d = (1.0 - omega * omega).powi(2) + (2.0 * zeta * omega).powi(2);
    let (a, b) = ((1.0 - omega * omega) / d, 2.0 * zeta * omega / d);
    let wd = (1.0 - zeta * zeta).sqrt();
    let c1 = x0 - a;
    let c2 = (zeta * c1 - b * omega) / wd;
    a * (omega * t).cos() + b * (omega * t).sin() + (-zeta * t).exp() * (c1 * (wd * t).cos() + c2 * (wd * t).sin())
}

/// First impact time of a simulation (the first forcing period only).
#[derive(Default)]
struct FirstImpact(Option<f64>);

impl solver::Observer for FirstImpact {
    fn impact(&mut self, time: f64, _: usize, _: &solver::DVector<f64>, _: &solver::DVector<f64>) {
        self.0.get_or_insert(time);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// Issue 21: exact event location never misses a contact, from very slow to
    /// very fast forcing (ω log-uniform in [1e-6, 1e3]) and for stop positions
    /// from 1e-12 to 10 (log-uniform): the first impact the exact solver reports
    /// is no later than the first crossing of the stop found by dense sampling
    /// (200 samples per unit time and per forcing period) of the textbook closed
    /// form over the first min(T, 60) time units, and every impact it reports
    /// there lies on the stop.
    #[test]
    fn no_contact_is_missed_at_any_frequency(log_omega in -6.0f64..3.0, log_sigma in -12.0f64..1.0, zeta in 0.01f64..0.5) {
        let (omega, sigma) = (10f64.powf(log_omega), 10f64.powf(log_sigma));
        let sys = system("single-stop.toml", &[("omega", omega), ("sigma", sigma), ("zeta", zeta)]);
        let x0 = sigma - 0.5;
        let window = sys.period.min(60.0);
        let step = 1.0 / (200.0 * (1.0f64).max(omega));
        let samples = (window / step).ceil() as usize;
        let crossing = (0..=samples)
            .map(|i| i as f64 * window / samples as f64)
            .find(|&t| free_single_stop(zeta, omega, x0, t) >= sigma + 1e-7);
        let acc = Accuracy::default().with("max_events", 2e5).unwrap();
        let mut sim = solver::Simulator::new(&sys, acc, Method::Exact, &[x0, 0.0]).unwrap();
        let mut first = FirstImpact::default();
        // The first impact ends the comparison: after it the flow is no longer free.
        let _ = sim.run_period(&[], false, &mut first);
        if let Some(t) = crossing {
            let te = first.0;
            prop_assert!(te.is_some_and(|te| te <= t + 1e-9), "ω {omega:e} σ {sigma:e}: crossing at {t} missed (first impact {te:?})");
        }
        if let Some(te) = first.0.filter(|&te| te <= window) {
            let x = free_single_stop(zeta, omega, x0, te);
            prop_assert!((x - sigma).abs() <= 1e-7 * (1.0 + sigma), "ω {omega:e} σ {sigma:e}: impact at {te} off the stop (x = {x})");
        }
    }
}
