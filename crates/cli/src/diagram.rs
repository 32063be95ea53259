//! Options of a bifurcation diagram (`sweep --png`, `render` of a sweep file
//! or of one row of an atlas), checked against the file's masses.

use crate::args::ImpactArg;
use anyhow::{anyhow, Result};
use grid::Atlas;
use render::{component_name, Diagram, Impact};

/// The diagram of row `row` of `atlas`, plotting `variable` (a component name
/// such as `x_M1`; default: the position of the first labelled mass).
pub fn diagram(atlas: &Atlas, row: usize, variable: Option<&str>, impact: ImpactArg) -> Result<Diagram> {
    let m = &atlas.meta;
    let names: Vec<String> = (0..m.dim).map(|k| component_name(atlas, k)).collect();
    let component = match variable {
        Some(v) => names
            .iter()
            .position(|n| n == v)
            .ok_or_else(|| anyhow!("--variable: expected one of {}, got '{v}'", names.join(", ")))?,
        None => m.masses.first().and_then(|first| m.state_masses.iter().position(|n| n == first)).unwrap_or(0),
    };
    let impact = match impact {
        ImpactArg::Speed => Impact::Speed,
        ImpactArg::Phase => Impact::Phase,
    };
    Ok(Diagram { row, component, impact, first: None })
}
