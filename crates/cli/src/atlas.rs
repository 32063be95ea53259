//! `vibroatlas atlas`: map a parameter plane.

use crate::args::AtlasArgs;
use crate::common::setup;
use crate::out::outln;
use crate::plan::{threads, Plan};
use crate::summary::print_summary;
use anyhow::Result;
use grid::{Along, Axis, Plane, Shard, SweepKind};

/// Runs the command.
pub fn run(a: AtlasArgs) -> Result<()> {
    let s = setup(&a.sim)?;
    let plane = Plane::new(Axis::parse(&a.x, "--x")?, Axis::parse(&a.y, "--y")?, Along::parse(&a.along)?)?;
    let sweeps = SweepKind::parse_set(&a.sweep, "--sweep")?;
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    let mut plan = Plan::new(&s, a.run.section_cap, plane, sweeps, threads(a.run.threads)?)?;
    plan.shard = shard;
    plan.output = Some(a.output.clone());
    plan.resume = a.resume;
    plan.inputs = vec![a.sim.scene.clone()];
    plan.force = a.force;
    plan.quiet = a.run.quiet;
    plan.check()?;
    let (atlas, secs) = plan.execute("atlas")?;
    if !a.run.quiet {
        print_summary(&atlas, secs, plan.threads)?;
        outln!("wrote {}", a.output.display());
    }
    Ok(())
}
