//! `vibroatlas render`: the coloured map of an atlas file.

use crate::args::RenderArgs;
use anyhow::{anyhow, Result};
use grid::SweepKind;
use render::{Quantity, View};
use store::write_atomically;

/// Runs the command.
pub fn run(a: RenderArgs) -> Result<()> {
    let l = store::read(&a.file)?;
    let m = &l.atlas.meta;
    let mass = match &a.mass {
        Some(name) => m
            .masses
            .iter()
            .position(|x| x == name)
            .ok_or_else(|| anyhow!("--mass: no labelled mass '{name}' (the file has {})", m.masses.join(", ")))?,
        None => 0,
    };
    let view = match a.sweep.as_deref() {
        None => View::Sweep(m.sweeps[0]),
        Some("hysteresis") => View::Hysteresis,
        Some(s) => View::Sweep(SweepKind::parse(s).filter(|k| m.sweeps.contains(k)).ok_or_else(|| {
            anyhow!(
                "--sweep: the file has {}, or hysteresis with up and down; got '{s}'",
                m.sweeps.iter().map(|k| k.name()).collect::<Vec<_>>().join(", ")
            )
        })?),
    };
    let quantity = match a.view.as_str() {
        "labels" => None,
        "lyapunov" => Some(Quantity::Lyapunov),
        "multiplier" => Some(Quantity::Multiplier),
        other => return Err(anyhow!("--view: expected labels, lyapunov or multiplier, got '{other}'")),
    };
    match (quantity, view) {
        (None, _) => Ok(write_atomically(&a.output, |tmp| render::map(&l.atlas, view, mass, tmp))?),
        (Some(q), View::Sweep(sweep)) => {
            Ok(write_atomically(&a.output, |tmp| render::scalar_map(&l.atlas, sweep, q, tmp))?)
        }
        (Some(_), View::Hysteresis) => Err(anyhow!("--view {}: needs --sweep fresh, up or down", a.view)),
    }
}
