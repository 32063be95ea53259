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
        let acc = Accuracy { max_events: 20_000, ..Accuracy::default() };
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
        let tol = 10.0 * acc.contact_tol;
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
