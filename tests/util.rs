//! Helpers shared by the integration tests.

use solver::{Accuracy, DVector, Method, Observer, Simulator, System};
use std::path::PathBuf;
use std::process::{Command, Output};

/// Path of a shipped config.
pub fn config(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("configs").join(name)
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

/// Observer keeping every impact and every event state.
#[derive(Debug, Default)]
pub struct Recorder {
    pub impacts: Vec<Impact>,
    pub events: Vec<(f64, DVector<f64>)>,
}

impl Observer for Recorder {
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

/// Runs the real binary.
pub fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vibroatlas")).args(args).current_dir(env!("CARGO_MANIFEST_DIR")).output().unwrap()
}

/// Runs `cell ... --json` and parses its one JSON object.
pub fn cell_json(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["cell"];
    all.extend_from_slice(args);
    all.push("--json");
    let out = run(&all);
    assert!(out.status.success(), "stderr: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// A fresh scratch folder for one test (`vibroatlas-NAME-PID` in the temp dir).
pub fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("vibroatlas-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the binary, which must succeed, and parses its one JSON object.
pub fn json_of(args: &[&str]) -> serde_json::Value {
    let out = run(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Runs the binary, which must succeed.
pub fn ok(args: &[&str]) {
    let out = run(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
}

/// The arguments of `curve` for the dry-friction pitchfork from
/// (ω, fk) = (6.845, 0.01) to fk = `to` in `steps` steps, then `extra`.
pub fn pitchfork<'a>(to: &'a str, steps: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["curve", "configs/dry-friction.toml", "--kind", "pf", "--start", "omega=6.845,fk=0.01"];
    args.extend(["--free", "omega,fk", "--to", to, "--steps", steps]);
    args.extend_from_slice(extra);
    args
}
