//! Helpers of the unit tests: the systems of the shipped scenes.

use crate::system::System;

/// The system of the shipped scene `configs/<name>` with parameter overrides.
pub(crate) fn system(name: &str, sets: &[(&str, f64)]) -> System {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs").join(name);
    let scene = scene::Scene::parse(&std::fs::read_to_string(path).unwrap()).unwrap();
    let overrides: Vec<(String, f64)> = sets.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    System::new(scene.evaluate(&overrides).unwrap()).unwrap()
}
