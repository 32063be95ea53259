//! `vibroatlas atlas`: map a parameter plane.

use crate::args::AtlasArgs;
use crate::common::{cell_setup, setup};
use crate::plan::{command_line, meta, threads, Plan};
use crate::summary::print_summary;
use anyhow::{bail, Result};
use grid::{Along, Axis, Plane, Shard, SweepKind};

/// Runs the command.
pub fn run(a: AtlasArgs) -> Result<()> {
    let s = setup(&a.sim)?;
    let cs = cell_setup(&s, a.run.section_cap)?;
    let plane = Plane::new(Axis::parse(&a.x, "--x")?, Axis::parse(&a.y, "--y")?, Along::parse(&a.along)?)?;
    let sweeps = SweepKind::parse_set(&a.sweep, "--sweep")?;
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    if a.output.as_os_str().is_empty() {
        bail!("--output: empty path");
    }
    let plan = Plan {
        meta: meta(&cs, &s, plane, sweeps, s.accuracy_overrides.clone())?,
        setup: cs,
        threads: threads(a.run.threads)?,
        shard,
        output: Some(a.output.clone()),
        resume: a.resume,
        quiet: a.run.quiet,
        command: command_line(),
    };
    plan.check_memory()?;
    plan.meta.plane.validate(&plan.setup)?;
    let (atlas, secs) = plan.execute("atlas")?;
    if !a.run.quiet {
        print_summary(&atlas, secs, plan.threads);
        println!("wrote {}", a.output.display());
    }
    Ok(())
}
