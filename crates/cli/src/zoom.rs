//! `vibroatlas zoom`: a box of a stored atlas, computed again.

use crate::args::ZoomArgs;
use crate::common::{command_line, parse_assignment};
use crate::out::outln;
use crate::progress::Shown;
use crate::summary::print_summary;
use anyhow::Result;
use engine::ZoomRequest;
use grid::Axis;

/// Runs the command.
pub fn run(a: ZoomArgs) -> Result<()> {
    let mut r = ZoomRequest::new(&a.parent, Axis::parse(&a.x, "--x")?, Axis::parse(&a.y, "--y")?);
    r.sweeps = a.sweep.map(grid::Sweeps::kinds);
    r.set = a.set.iter().map(|t| parse_assignment(t, "--set")).collect::<Result<_>>()?;
    r.threads = engine::threads(a.threads)?;
    r.output = Some(a.output.clone());
    r.command = command_line();
    // A zoom has no journal to resume from: Ctrl-C cancels it, leaving nothing.
    crate::interrupt::install();
    let shown = Shown::new("zoom", a.quiet);
    let run = match engine::zoom(&r, &crate::interrupt::Stoppable(shown)) {
        Err(_) if crate::interrupt::requested() => {
            crate::out::errln!("zoom: interrupted; nothing was written");
            std::process::exit(130);
        }
        run => run?,
    };
    if a.quiet {
        return Ok(());
    }
    print_summary(&run.atlas, run.secs, r.threads)?;
    outln!("wrote {} (a box of {})", a.output.display(), a.parent.display());
    Ok(())
}
