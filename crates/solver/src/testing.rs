//! Helpers of the unit tests: the systems of the shipped scenes and of
//! scenes given as text, and the textbook closed form they are checked
//! against.

use crate::system::System;

/// The system of the shipped scene `configs/<name>` with parameter overrides.
pub(crate) fn system(name: &str, sets: &[(&str, f64)]) -> System {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs").join(name);
    system_of(&std::fs::read_to_string(path).unwrap(), sets)
}

/// The system of a scene given as TOML text, with parameter overrides.
pub(crate) fn system_of(toml: &str, sets: &[(&str, f64)]) -> System {
    let scene = scene::Scene::parse(toml).unwrap();
    let overrides: Vec<(String, f64)> = sets.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    System::new(scene.evaluate(&overrides).unwrap()).unwrap()
}

/// `x'' + 2ζx' + x = cos ωt` from `x(0) = x0`, `x'(0) = v0` by the
/// textbook closed form (ζ < 1), independent of the modal flow.
pub(crate) fn forced_oscillator(zeta: f64, omega: f64, x0: f64, v0: f64, t: f64) -> f64 {
    let d = (1.0 - omega * omega).powi(2) + (2.0 * zeta * omega).powi(2);
    let (a, b) = ((1.0 - omega * omega) / d, 2.0 * zeta * omega / d);
    let wd = (1.0 - zeta * zeta).sqrt();
    let c1 = x0 - a;
    let c2 = (v0 + zeta * c1 - b * omega) / wd;
    a * (omega * t).cos() + b * (omega * t).sin() + (-zeta * t).exp() * (c1 * (wd * t).cos() + c2 * (wd * t).sin())
}

/// The highest `x` of the undamped [`forced_oscillator`] from `x0`, `v0`
/// over `periods` forcing periods, sampled `per_period` times a period.
pub(crate) fn undamped_top(omega: f64, x0: f64, v0: f64, periods: usize, per_period: usize) -> f64 {
    let step = std::f64::consts::TAU / omega / per_period as f64;
    (0..periods * per_period)
        .map(|i| forced_oscillator(0.0, omega, x0, v0, i as f64 * step))
        .fold(f64::NEG_INFINITY, f64::max)
}
