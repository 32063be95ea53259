//! `vibroatlas atlas`: map a parameter plane.

use crate::args::AtlasArgs;
use crate::common::{command_line, sim};
use crate::out::outln;
use crate::progress::Shown;
use crate::summary::print_summary;
use anyhow::Result;
use engine::AtlasRequest;
use grid::Axis;

/// Runs the command.
pub fn run(a: AtlasArgs) -> Result<()> {
    let mut r = AtlasRequest::new(sim(&a.sim)?, Axis::parse(&a.x, "--x")?, Axis::parse(&a.y, "--y")?, Vec::new());
    a.options.apply(&mut r)?;
    r.section_cap = a.run.section_cap;
    r.threads = engine::threads(a.run.threads)?;
    r.output = Some(a.output.clone());
    r.command = command_line();
    let run = engine::atlas(&r, &Shown::new("atlas", a.run.quiet))?;
    // The file written: a symbolic link's target (the link stays).
    let target = store::canonical_output(&a.output)?;
    if a.run.quiet {
        return Ok(());
    }
    if run.already {
        outln!("{} is already this run's finished file: nothing to do", target.display());
        return Ok(());
    }
    {
        print_summary(&run.atlas, run.secs, r.threads)?;
        outln!(
            "file      finished in {:.2} s once the cells were done (the rest was written while they computed)",
            run.write_s
        );
        if target != a.output && std::fs::symlink_metadata(&a.output).is_ok_and(|m| m.file_type().is_symlink()) {
            outln!("wrote {} (the file the link {} names)", target.display(), a.output.display());
        } else {
            outln!("wrote {}", a.output.display());
        }
    }
    Ok(())
}
