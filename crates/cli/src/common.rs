//! Validation shared by commands: scene loading, `--set`, presets, integrators,
//! and writing output files atomically.

use crate::args::SimArgs;
use anyhow::{anyhow, bail, Context, Result};
use scene::Scene;
use solver::{Accuracy, Method, Preset};

/// A validated simulation setup.
pub struct Setup {
    pub scene: Scene,
    pub overrides: Vec<(String, f64)>,
    pub accuracy: Accuracy,
    /// The `--accuracy` overrides as given.
    pub accuracy_overrides: Vec<(String, f64)>,
    pub preset: Preset,
    pub method: Method,
}

/// Parses `NAME=VALUE` with a finite value; `flag` names the option in errors.
pub fn parse_assignment(text: &str, flag: &str) -> Result<(String, f64)> {
    let (name, value) = text.split_once('=').ok_or_else(|| anyhow!("{flag} {text}: expected NAME=VALUE"))?;
    let name = name.trim().to_string();
    let v: f64 = value.trim().parse().map_err(|_| anyhow!("{flag} {name}: '{}' is not a number", value.trim()))?;
    if !v.is_finite() {
        bail!("{flag} {name}: not a finite number, got {value}");
    }
    Ok((name, v))
}

/// Loads the scene and validates every option of [`SimArgs`].
pub fn setup(a: &SimArgs) -> Result<Setup> {
    let text =
        std::fs::read_to_string(&a.scene).with_context(|| format!("cannot read scene file {}", a.scene.display()))?;
    let scene = Scene::parse(&text).map_err(|e| anyhow!("{}: {e}", a.scene.display()))?;
    let overrides = a.set.iter().map(|s| parse_assignment(s, "--set")).collect::<Result<Vec<_>>>()?;
    for (name, _) in &overrides {
        scene.check_parameter(name, &format!("--set {name}"))?;
    }
    let preset = Preset::parse(&a.preset)
        .ok_or_else(|| anyhow!("--preset: expected fast, standard or precise, got '{}'", a.preset))?;
    let mut accuracy = Accuracy::preset(preset);
    let mut accuracy_overrides = Vec::new();
    for s in &a.accuracy {
        let (k, v) = parse_assignment(s, "--accuracy")?;
        accuracy.set(&k, v)?;
        accuracy_overrides.push((k, v));
    }
    let method = Method::parse(&a.integrator)
        .ok_or_else(|| anyhow!("--integrator: expected exact or rk4, got '{}'", a.integrator))?;
    Ok(Setup { scene, overrides, accuracy, accuracy_overrides, preset, method })
}

/// Checks an orbit period given with `--n`: 1 to 1000 forcing periods.
pub fn check_period(n: Option<usize>) -> Result<()> {
    match n {
        Some(n) if n == 0 || n > 1000 => bail!("--n: expected a period between 1 and 1000, got {n}"),
        _ => Ok(()),
    }
}

/// Labels as a JSON object `{"M1": "1-4-4", …}` (the contract of `cell`, `orbit`
/// and `continue`).
pub fn labels_json(labels: &[solver::MassLabel]) -> serde_json::Value {
    labels
        .iter()
        .map(|l| (l.mass.clone(), serde_json::Value::from(l.to_string())))
        .collect::<serde_json::Map<_, _>>()
        .into()
}

/// The grid's cell set-up for a validated [`Setup`].
pub fn cell_setup(s: &Setup, section_cap: usize) -> Result<grid::CellSetup> {
    if section_cap > 100_000 {
        bail!("--section-cap: at most 100000, got {section_cap}");
    }
    Ok(grid::CellSetup {
        scene: s.scene.clone(),
        base: s.overrides.clone(),
        accuracy: s.accuracy,
        method: s.method,
        section_cap,
    })
}
