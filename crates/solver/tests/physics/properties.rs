//! Properties of whole simulations on random parameters (issue 5): states stay
//! finite, stops are never penetrated by more than the contact tolerance, and
//! energy never increases at an impact.

use crate::common::system;
use proptest::prelude::*;
use solver::{Accuracy, Method};

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn random_cells_stay_admissible(mu_m in 0.05f64..0.95, mu_k in 0.05f64..0.95, mu_c in 0.05f64..0.95,
                                    zeta in 0.0f64..0.3, r in 0.0f64..1.0, delta in 0.01f64..2.0, omega in 0.1f64..4.0) {
        let sys = system("multi-stop.toml", &[("mu_m", mu_m), ("mu_k", mu_k), ("mu_c", mu_c), ("zeta", zeta), ("R", r), ("delta", delta), ("omega", omega)]);
        let acc = Accuracy::default().with(solver::Knob::MaxEvents, 2e4).unwrap();
        let mut sim = match solver::Simulator::new(&sys, acc, Method::Exact, &sys.model.initial_state()) {
            Ok(s) => s,
            Err(h) => return Err(TestCaseError::fail(format!("{h:?}"))),
        };
        let mut rec = crate::common::Recorder::default();
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

impl solver::EventObserver for FirstImpact {
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
        let acc = Accuracy::default().with(solver::Knob::MaxEvents, 2e5).unwrap();
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

/// `m x'' + c x' + k x = p sin(ωt)` from `x(0) = x0`, `x'(0) = v0`
/// (underdamped), by the textbook closed form: particular solution plus a
/// decaying free oscillation.
fn oscillator((m, c, k, p): (f64, f64, f64, f64), omega: f64, (x0, v0): (f64, f64), t: f64) -> f64 {
    let (w0, f) = ((k / m).sqrt(), p / m);
    let z = c / (2.0 * (k * m).sqrt());
    let d = (w0 * w0 - omega * omega).powi(2) + (2.0 * z * w0 * omega).powi(2);
    let (a, b) = (f * (w0 * w0 - omega * omega) / d, -f * 2.0 * z * w0 * omega / d);
    let wd = w0 * (1.0 - z * z).sqrt();
    let c1 = x0 - b;
    let c2 = (v0 - a * omega + z * w0 * c1) / wd;
    a * (omega * t).sin() + b * (omega * t).cos() + (-z * w0 * t).exp() * (c1 * (wd * t).cos() + c2 * (wd * t).sin())
}

/// The first time an observer hears of any event.
#[derive(Default)]
struct FirstEvent(Option<f64>);

impl solver::EventObserver for FirstEvent {
    fn event(&mut self, time: f64, _: &solver::DVector<f64>) {
        self.0.get_or_insert(time);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Issue 15: on random two-mass scenes (multi-stop: masses, stiffnesses,
    /// damping, force split and frequency random) one stop, chosen at random
    /// among A1, A2 and A12, is put a hair ε (1e-9 to 1e-3) inside the
    /// deepest approach of the free motion within the first forcing period
    /// (at most 30 time units), found by dense sampling (1e-4 apart) of the
    /// masses' closed forms (they move independently until a contact); the
    /// other stops are far away. Grazing contacts included, the exact solver's
    /// first event comes no later than the first sampled contact.
    #[test]
    fn no_contact_of_any_stop_is_missed(mu_m in 0.1f64..0.9, mu_k in 0.1f64..0.9, mu_c in 0.1f64..0.9,
                                         zeta in 0.02f64..0.3, f20 in 0.0f64..1.0, omega in 0.2f64..3.0,
                                         x1 in -0.5f64..0.5, x2 in -0.5f64..0.5, v1 in -0.5f64..0.5, v2 in -0.5f64..0.5,
                                         stop in 0usize..3, log_eps in -9.0f64..-3.0) {
        let (m2, k2, c2) = (mu_m / (1.0 - mu_m), mu_k / (1.0 - mu_k), 2.0 * zeta * mu_c / (1.0 - mu_c));
        let free = |t: f64| {
            (oscillator((1.0, 2.0 * zeta, 1.0, 1.0 - f20), omega, (x1, v1), t), oscillator((m2, c2, k2, f20), omega, (x2, v2), t))
        };
        // Each stop's gap without its clearance: A1 x1 + δ1, A2 x2 + δ2, A12 δ12 - (x1 - x2).
        let depth = |t: f64| {
            let (a, b) = free(t);
            [a, b, b - a][stop]
        };
        let window = (std::f64::consts::TAU / omega).min(30.0);
        let samples = (window / 1e-4) as usize;
        let i_low = (0..=samples).min_by(|&a, &b| depth(a as f64 * 1e-4).total_cmp(&depth(b as f64 * 1e-4))).unwrap();
        prop_assume!(i_low > 0 && i_low < samples);
        let clearance = -depth(i_low as f64 * 1e-4) - 10f64.powf(log_eps);
        prop_assume!(clearance > 1e-6 && clearance + depth(0.0) > 1e-3);
        let first = (0..=samples).map(|i| i as f64 * 1e-4).find(|&t| depth(t) + clearance <= 0.0).unwrap();
        let mut sets = vec![("mu_m", mu_m), ("mu_k", mu_k), ("mu_c", mu_c), ("zeta", zeta), ("f20", f20), ("omega", omega),
                            ("delta1", 50.0), ("delta2", 50.0), ("delta12", 50.0), ("delta", 0.0)];
        sets[6 + stop].1 = clearance;
        let sys = system("multi-stop.toml", &sets);
        let acc = Accuracy::default();
        let mut sim = solver::Simulator::new(&sys, acc, Method::Exact, &[x1, x2, v1, v2]).unwrap();
        let mut heard = FirstEvent::default();
        let _ = sim.run_period(&[], false, &mut heard);
        prop_assert!(heard.0.is_some_and(|t| t <= first + 1e-6), "stop {stop}, ε {:e}: contact at {first} missed (first event {:?})", 10f64.powf(log_eps), heard.0);
    }
}
