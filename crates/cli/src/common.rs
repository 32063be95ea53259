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
    let preset = a.preset.map_or(Preset::Standard, |p| p.preset());
    let method = a.integrator.map_or(Method::Exact, |m| m.method());
    setup_with(a, preset, method)
}

/// [`setup`] with the preset and integrator given.
fn setup_with(a: &SimArgs, preset: Preset, method: Method) -> Result<Setup> {
    let text =
        std::fs::read_to_string(&a.scene).with_context(|| format!("cannot read scene file {}", a.scene.display()))?;
    let scene = Scene::parse(&text).map_err(|e| anyhow!("{}: {e}", a.scene.display()))?;
    let overrides = a.set.iter().map(|s| parse_assignment(s, "--set")).collect::<Result<Vec<_>>>()?;
    for (name, _) in &overrides {
        scene.check_parameter(name, &format!("--set {name}"))?;
    }
    let mut accuracy = Accuracy::preset(preset);
    let mut accuracy_overrides = Vec::new();
    for s in &a.accuracy {
        let (k, v) = parse_assignment(s, "--accuracy")?;
        accuracy.set(&k, v)?;
        accuracy_overrides.push((k, v));
    }
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

/// Where a simulation starts (see [`crate::args::FromArgs`]).
pub struct Origin {
    /// The state the stored cell started from (the final state of the cell
    /// before it along its sweep), or `None` (the scene's initial state).
    pub cell_start: Option<Vec<f64>>,
    /// The state to start a new simulation from (the stored cell's final
    /// state, at a whole forcing period; or the given `--state`).
    pub state: Vec<f64>,
    /// What was taken, for the output (`{"file", "sweep", "cell": {…}}`).
    pub about: serde_json::Value,
    /// The section cap of the stored run (its cells' work includes their
    /// sections), `None` for `--state`.
    pub section_cap: Option<usize>,
}

/// Validates the simulation options and where the simulation starts: with
/// `--from`, the cell's parameters are added to the overrides and, unless
/// given, the file's preset, knobs and integrator are used.
pub fn setup_from(a: &SimArgs, f: &crate::args::FromArgs) -> Result<(Setup, Option<Origin>)> {
    let Some(file) = &f.from else {
        let s = setup(a)?;
        let Some(text) = &f.state else { return Ok((s, None)) };
        let state: Vec<f64> = text
            .split(',')
            .map(|v| v.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect::<Option<_>>()
            .ok_or_else(|| anyhow!("--state: expected comma-separated finite numbers, got '{text}'"))?;
        let model = s.scene.evaluate(&s.overrides)?;
        let dim = 2 * model.masses.len();
        if state.len() != dim {
            bail!("--state: the scene's state has {dim} numbers (x of every mass, then v), got {}", state.len());
        }
        let x: Vec<f64> = state[..dim / 2].to_vec();
        for (k, stop) in model.stops.iter().enumerate() {
            let g = model.gap(k, &x);
            if g < -solver::ADMISSIBLE_PENETRATION {
                bail!("--state: penetrates stop {} by {}", stop.name, -g);
            }
        }
        let about = serde_json::json!({"state": state});
        return Ok((s, Some(Origin { cell_start: None, state, about, section_cap: None })));
    };
    let at = f.at.as_deref().ok_or_else(|| anyhow!("--from: give the cell with --at NAME=VALUE,NAME=VALUE"))?;
    let loaded = store::read(file)?;
    let atlas = &loaded.atlas;
    let m = &atlas.meta;
    let sweep = match f.from_sweep.map(|s| s.kind()) {
        Some(kind) if !m.sweeps.contains(&kind) => {
            let have: Vec<&str> = m.sweeps.iter().map(|k| k.name()).collect();
            bail!("--sweep: {} has {}, not {}", file.display(), have.join(", "), kind.name());
        }
        Some(kind) => kind,
        None => m.sweeps[0],
    };
    let wanted = at.split(',').map(|t| parse_assignment(t, "--at")).collect::<Result<Vec<_>>>()?;
    let (iy, ix) = atlas.nearest(&wanted).map_err(|e| anyhow!("--at: {e}"))?;
    let cell = atlas
        .map(sweep)
        .and_then(|map| map.cells[iy * m.plane.x.count + ix].as_ref())
        .ok_or_else(|| anyhow!("--at: the cell was not computed in {} (a shard?)", file.display()))?;
    // The file's settings, unless given on the command line.
    let stored = |what: &str, name: &str| anyhow!("--from: {} has an unknown {what} '{name}'", file.display());
    let preset = match a.preset {
        Some(p) => p.preset(),
        None => Preset::parse(&m.preset).ok_or_else(|| stored("preset", &m.preset))?,
    };
    let method = match a.integrator {
        Some(i) => i.method(),
        None => Method::parse(&m.integrator).ok_or_else(|| stored("integrator", &m.integrator))?,
    };
    let mut sim = a.clone();
    let mut knobs: Vec<String> = m.accuracy.iter().map(|(k, v)| format!("{k}={v}")).collect();
    knobs.extend(a.accuracy.iter().cloned());
    sim.accuracy = knobs;
    let mut s = setup_with(&sim, preset, method)?;
    let params = m.plane.params(iy, ix);
    if let Some((k, _)) = s.overrides.iter().find(|(k, _)| params.iter().any(|(p, _)| p == k)) {
        bail!("--set {k}: the cell of --from fixes {k} (an axis of {}); choose the cell with --at", file.display());
    }
    let mut overrides = m.overrides.clone();
    overrides.extend(params.iter().cloned());
    overrides.extend(s.overrides.iter().filter(|(k, _)| !params.iter().any(|(p, _)| p == k)).cloned());
    s.overrides = overrides;
    let model = s.scene.evaluate(&s.overrides)?;
    if 2 * model.masses.len() != m.dim {
        bail!("--from: {} has states of {} numbers, the scene {}", file.display(), m.dim, 2 * model.masses.len());
    }
    if s.scene.source() != m.scene_toml {
        crate::out::errln!("warning: the scene differs from the one stored in {}", file.display());
    }
    let coords: serde_json::Map<String, serde_json::Value> =
        params.iter().map(|(k, v)| (k.clone(), serde_json::json!(v))).collect();
    let about = serde_json::json!({
        "file": file.display().to_string(),
        "sweep": sweep.name(),
        "cell": coords,
        "labels": m.masses.iter().enumerate().map(|(i, n)| (n.clone(), serde_json::json!(cell.labels[i].to_string()))).collect::<serde_json::Map<_, _>>(),
    });
    let origin = Origin {
        cell_start: atlas.start_of(sweep, iy, ix).map(<[f64]>::to_vec),
        state: cell.final_state.clone(),
        about,
        section_cap: Some(m.section_cap),
    };
    Ok((s, Some(origin)))
}

/// A library error in the words of the command line: the field it names
/// (`x`, `x omega`, `shard`) becomes the flag (`--x`, `--x omega`, `--shard`)
/// that `flags` maps it to.
pub fn in_flags(e: grid::GridError, flags: &[(&str, &str)]) -> anyhow::Error {
    match e {
        grid::GridError::Field { field, message } => {
            let (head, rest) = field.split_once(' ').map_or((field.as_str(), ""), |(h, r)| (h, r));
            let flag = flags.iter().find(|(f, _)| *f == head).map_or(head, |(_, flag)| flag);
            let sep = if rest.is_empty() { "" } else { " " };
            anyhow!("{flag}{sep}{rest}: {message}")
        }
        other => anyhow!(other),
    }
}

/// The system of the set-up with the parameters `set` replacing their overrides.
pub fn system_with(s: &Setup, set: &[(&str, f64)]) -> Result<solver::System> {
    let mut over = s.overrides.clone();
    over.retain(|(k, _)| !set.iter().any(|(n, _)| n == k));
    over.extend(set.iter().map(|&(n, v)| (n.to_string(), v)));
    Ok(solver::System::new(s.scene.evaluate(&over)?)?)
}
