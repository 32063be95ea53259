//! Helpers of the tests that drive the solver as a library: the systems of
//! the shipped scenes and a recording observer. The workspace's integration
//! tests (`tests/util.rs`) include this file too, so that both test targets
//! share one copy.

use solver::{Accuracy, DVector, EventObserver, Method, Simulator, System};
use std::path::{Path, PathBuf};

/// Path of a shipped scene, `configs/<name>` at the workspace's root (found
/// above the crate that runs the test).
pub fn config(name: &str) -> PathBuf {
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    let root = here.ancestors().find(|d| d.join("configs").is_dir()).unwrap_or(here);
    root.join("configs").join(name)
}

/// The evaluated system of a shipped scene with parameter overrides.
pub fn system(name: &str, sets: &[(&str, f64)]) -> System {
    let text = std::fs::read_to_string(config(name)).unwrap();
    let scene = scene::Scene::parse(&text).unwrap();
    let overrides: Vec<(String, f64)> = sets.iter().map(|(k, v)| (k.to_string(), *v)).collect();
    System::new(scene.evaluate(&overrides).unwrap()).unwrap()
}

/// One recorded impact.
#[derive(Debug, Clone)]
pub struct Impact {
    pub time: f64,
    pub stop: usize,
    pub before: DVector<f64>,
    pub after: DVector<f64>,
}

/// EventObserver keeping every impact and every event state.
#[derive(Debug, Default)]
pub struct Recorder {
    pub impacts: Vec<Impact>,
    pub events: Vec<(f64, DVector<f64>)>,
}

impl EventObserver for Recorder {
    fn impact(&mut self, time: f64, stop: usize, before: &DVector<f64>, after: &DVector<f64>) {
        self.impacts.push(Impact { time, stop, before: before.clone(), after: after.clone() });
    }
    fn event(&mut self, time: f64, y: &DVector<f64>) {
        self.events.push((time, y.clone()));
    }
}

/// Simulates `periods` periods from `y0` and records what happened.
pub fn record<'s>(
    sys: &'s System,
    acc: &Accuracy,
    method: Method,
    y0: &[f64],
    periods: usize,
) -> (Recorder, Simulator<'s>) {
    let mut sim = Simulator::new(sys, *acc, method, y0).unwrap();
    let mut rec = Recorder::default();
    for _ in 0..periods {
        sim.run_period(&[], false, &mut rec).unwrap();
    }
    (rec, sim)
}
