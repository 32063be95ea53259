//! A parameter plane ([`atlas`]): fresh cells, or continuation chains up and
//! down, on threads, optionally one shard of it, with the coexisting
//! attractors of its cells; written to an HDF5 file through a journal.

use crate::observer::Observer;
use crate::plan::{Executed, Plan};
use crate::sim::Sim;
use anyhow::{bail, Result};
use grid::attractors::Sampling;
use grid::{Along, Axis, Plane, Shard, SweepKind};
use std::path::PathBuf;

/// Which cells get their coexisting attractors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AttractorCells {
    /// Every cell.
    All,
    /// The cells where the up and down sweeps differ.
    Hysteresis,
}

/// An atlas to compute.
#[derive(Debug, Clone)]
pub struct AtlasRequest {
    /// The simulation options.
    pub sim: Sim,
    /// The axis along the lines (the columns).
    pub x: Axis,
    /// The other axis (the rows).
    pub y: Axis,
    /// Which axis the continuation chains follow.
    pub along: Along,
    /// The sweeps (fresh, or up and/or down).
    pub sweeps: Vec<SweepKind>,
    /// This run's shard of the lines, if any.
    pub shard: Option<Shard>,
    /// The coexisting attractors to find once the lines are done.
    pub attractors: Option<(Sampling, AttractorCells)>,
    /// Section points kept per cell.
    pub section_cap: usize,
    /// Worker threads.
    pub threads: usize,
    /// The file to write. A symbolic link's target is written.
    pub output: Option<PathBuf>,
    /// Continue from the journal beside the output (or do nothing when the
    /// output is already this run's finished file).
    pub resume: bool,
    /// Allow a non-regular output file.
    pub force: bool,
    /// What made the run (the file's `command` attribute).
    pub command: String,
}

impl AtlasRequest {
    /// A request for `sweeps` of the plane `x` by `y` (chains along x), every
    /// other option at its default: no shard, attractors or output, sections
    /// of 16 points, one thread per core.
    pub fn new(sim: Sim, x: Axis, y: Axis, sweeps: Vec<SweepKind>) -> AtlasRequest {
        AtlasRequest {
            sim,
            x,
            y,
            along: Along::X,
            sweeps,
            shard: None,
            attractors: None,
            section_cap: 16,
            threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
            output: None,
            resume: false,
            force: false,
            command: String::new(),
        }
    }
}

/// The flags of the grid's fields.
const FLAGS: &[(&str, &str)] =
    &[("x", "--x"), ("y", "--y"), ("along", "--along"), ("shard", "--shard"), ("threads", "--threads")];

/// Computes an atlas, reporting to `observer` (and writes it when asked).
pub fn atlas(r: &AtlasRequest, observer: &dyn Observer) -> Result<Executed> {
    let s = r.sim.setup()?;
    let plane = Plane::new(r.x.clone(), r.y.clone(), r.along).map_err(|e| crate::in_flags(e, FLAGS))?;
    let mut plan = Plan::new(&s, r.section_cap, plane, r.sweeps.clone(), r.threads)?;
    plan.shard = r.shard;
    plan.output = r.output.as_deref().map(store::lock::canonical_output).transpose()?;
    plan.resume = r.resume;
    plan.inputs = r.sim.scene.file().map(|f| vec![f.to_path_buf()]).unwrap_or_default();
    plan.force = r.force;
    plan.command = r.command.clone();
    if let Some((sampling, cells)) = r.attractors {
        if sampling.samples == 0 || sampling.samples > 100_000 {
            bail!("--attractors: expected 1 to 100000 samples per cell, got {}", sampling.samples);
        }
        plan.attractors = Some((sampling, cells == AttractorCells::Hysteresis));
    }
    plan.check().map_err(|e| match e.downcast::<grid::GridError>() {
        Ok(g) => crate::in_flags(g, FLAGS),
        Err(e) => e,
    })?;
    plan.execute(observer)
}
