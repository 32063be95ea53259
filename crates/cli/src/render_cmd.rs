//! `vibroatlas render`: the coloured map of an atlas file.

use crate::args::RenderArgs;
use anyhow::{anyhow, Result};
use grid::SweepKind;
use render::View;

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
    let tmp = store::partial_path(&a.output);
    render::map(&l.atlas, view, mass, &tmp).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        anyhow!("{}: {e}", a.output.display())
    })?;
    std::fs::rename(&tmp, &a.output).map_err(|e| anyhow!("{}: {e}", a.output.display()))?;
    Ok(())
}
