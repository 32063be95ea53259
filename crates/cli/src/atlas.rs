//! `vibroatlas atlas`: map a parameter plane.

use crate::args::{AlongArg, AtlasArgs, AtlasSweep, AttractorsWhere};
use crate::common::{in_flags, setup};
use crate::out::outln;
use crate::plan::{threads, Plan};
use crate::summary::print_summary;
use anyhow::Result;
use grid::{Along, Axis, Plane, Shard, SweepKind};

/// The flags of the grid's fields.
const FLAGS: &[(&str, &str)] =
    &[("x", "--x"), ("y", "--y"), ("along", "--along"), ("shard", "--shard"), ("threads", "--threads")];

/// Runs the command.
pub fn run(a: AtlasArgs) -> Result<()> {
    let s = setup(&a.sim)?;
    let along = match a.along {
        AlongArg::X => Along::X,
        AlongArg::Y => Along::Y,
    };
    let plane =
        Plane::new(Axis::parse(&a.x, "--x")?, Axis::parse(&a.y, "--y")?, along).map_err(|e| in_flags(e, FLAGS))?;
    let sweeps = match a.sweep {
        AtlasSweep::Fresh => vec![SweepKind::Fresh],
        AtlasSweep::Up => vec![SweepKind::Up],
        AtlasSweep::Down => vec![SweepKind::Down],
        AtlasSweep::Both => vec![SweepKind::Up, SweepKind::Down],
    };
    let shard = a.shard.as_deref().map(Shard::parse).transpose().map_err(|e| in_flags(e, FLAGS))?;
    let mut plan = Plan::new(&s, a.run.section_cap, plane, sweeps, threads(a.run.threads)?)?;
    plan.shard = shard;
    // The file written: a symbolic link's target (the link stays), locked
    // under that name whatever name it is given by.
    let target = store::lock::canonical_output(&a.output)?;
    let through_link = std::fs::symlink_metadata(&a.output).is_ok_and(|m| m.file_type().is_symlink());
    plan.output = Some(target.clone());
    plan.resume = a.resume;
    plan.inputs = vec![a.sim.scene.clone()];
    plan.force = a.force;
    if let Some(k) = a.attractors {
        if k == 0 || k > 100_000 {
            anyhow::bail!("--attractors: expected 1 to 100000 samples per cell, got {k}");
        }
        let sampling = grid::attractors::Sampling { samples: k, seed: a.seed, x: 2.0, v: 2.0 };
        plan.attractors = Some((sampling, a.attractors_where == AttractorsWhere::Hysteresis));
    }
    plan.quiet = a.run.quiet;
    plan.check().map_err(|e| match e.downcast::<grid::GridError>() {
        Ok(g) => in_flags(g, FLAGS),
        Err(e) => e,
    })?;
    let run = plan.execute_measured("atlas")?;
    if !a.run.quiet {
        print_summary(&run.atlas, run.secs, plan.threads)?;
        outln!(
            "file      finished in {:.2} s once the cells were done (the rest was written while they computed)",
            run.write_s
        );
        if through_link {
            outln!("wrote {} (the file the link {} names)", target.display(), a.output.display());
        } else {
            outln!("wrote {}", a.output.display());
        }
    }
    Ok(())
}
