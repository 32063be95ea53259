//! The command line's simulation options as the engine's requests.

use crate::args::{FromArgs, SimArgs};
use anyhow::{anyhow, Result};
use engine::{Sim, Start};

/// The simulation options of `a` (the scene a file).
pub fn sim(a: &SimArgs) -> Result<Sim> {
    sim_from(a, &FromArgs::default())
}

/// [`sim`] of a command that may start from a stored cell: without a scene
/// file, the scene stored in the `--from` file.
pub fn sim_from(a: &SimArgs, f: &FromArgs) -> Result<Sim> {
    let scene = match (&a.scene, &f.from) {
        (Some(scene), _) => engine::SceneSource::File(scene.clone()),
        (None, Some(file)) => engine::SceneSource::Stored(file.clone()),
        (None, None) => anyhow::bail!("a scene file is needed (or --from FILE.h5, whose stored scene is taken)"),
    };
    Ok(Sim {
        scene,
        set: a.set.iter().map(|s| parse_assignment(s, "--set")).collect::<Result<Vec<_>>>()?,
        preset: a.preset,
        accuracy: a.accuracy.iter().map(|s| knob(s)).collect::<Result<Vec<_>>>()?,
        integrator: a.integrator,
    })
}

/// An accuracy knob and its value, `KNOB=VALUE` (`--accuracy`).
fn knob(text: &str) -> Result<(solver::Knob, f64)> {
    let (name, value) = parse_assignment(text, "--accuracy")?;
    Ok((solver::Knob::named(&name).map_err(engine::Error::from)?, value))
}

/// Where a simulation starts (`--from … --at … [--sweep …]` or `--state`).
pub fn start(f: &FromArgs) -> Result<Start> {
    if let Some(file) = &f.from {
        let at = match &f.at {
            Some(at) => at.split(',').map(|t| parse_assignment(t, "--at")).collect::<Result<Vec<_>>>()?,
            None => Vec::new(),
        };
        return Ok(Start::Cell { file: file.clone(), at, sweep: f.from_sweep });
    }
    let Some(text) = &f.state else { return Ok(Start::Initial) };
    Ok(Start::State(parse_state(text)?))
}

/// The numbers of `--state X…,V…`.
pub fn parse_state(text: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|v| v.trim().parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| anyhow!("--state: expected comma-separated finite numbers, got '{text}'"))
}

/// Says on standard error what a start from a stored cell took: its
/// warning (the scene differs from the stored one), and which cell `--at`
/// took where it is off the values given.
pub fn tell(warning: Option<&String>, note: Option<&String>) {
    if let Some(w) = warning {
        crate::out::errln!("warning: {w}");
    }
    if let Some(n) = note {
        crate::out::errln!("note: --at: {n}");
    }
}

/// The command line as one string (for the file's `command` attribute).
pub fn command_line() -> String {
    std::env::args().collect::<Vec<_>>().join(" ")
}

/// Parses `NAME=VALUE` with a finite value; `option` names the flag in
/// errors (`--set`).
pub fn parse_assignment(text: &str, option: &str) -> Result<(String, f64)> {
    engine::parse_assignment(text, option).map_err(|e| anyhow!(e))
}
