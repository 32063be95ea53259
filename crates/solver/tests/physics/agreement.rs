//! Agreement of the exact flow with the RK4 integrator (issue 2).

use crate::common::{record, system};
use solver::{Accuracy, Method};

/// Issue 2: impact times of exact flow and RK4 (h = 1e-3) agree to 1e-6 over
/// 50 periods of a non-chattering orbit.
#[test]
fn exact_and_rk4_impact_times_agree() {
    let sys = system("multi-stop.toml", &[("omega", 0.33), ("delta", 0.6)]);
    let acc = Accuracy::default().with(solver::Knob::Rk4Step, 1e-3).unwrap();
    let y0 = sys.model.initial_state();
    let (exact, _) = record(&sys, &acc, Method::Exact, &y0, 50);
    let (rk4, _) = record(&sys, &acc, Method::Rk4, &y0, 50);
    assert!(exact.impacts.len() > 300);
    assert_eq!(exact.impacts.len(), rk4.impacts.len());
    let worst = exact
        .impacts
        .iter()
        .zip(&rk4.impacts)
        .map(|(a, b)| {
            assert_eq!(a.stop, b.stop);
            (a.time - b.time).abs()
        })
        .fold(0.0, f64::max);
    assert!(worst < 1e-6, "largest impact time difference {worst:e}");
}
