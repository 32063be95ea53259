//! `vibroatlas study`: one atlas per value of a parameter, each with its map,
//! and a contact sheet comparing them.
//!
//! The whole study is checked before any atlas is computed
//! ([`engine::study`]), then run ([`engine::StudyPlan::run`]: an output
//! folder the study created is removed when it fails before its first atlas
//! is written).

use crate::args::StudyArgs;
use crate::common::command_line;
use crate::interrupt::Stoppable;
use crate::out::outln;
use crate::progress::Shown;
use anyhow::Result;

/// Runs the command.
pub fn run(a: StudyArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let threads = engine::threads(a.run.threads)?;
    let plan = engine::study(&a.study, a.preset, a.run.section_cap, threads, &command_line())?;
    let quiet = a.run.quiet;
    // A study has no journal to resume from: Ctrl-C cancels the atlas being
    // computed, leaving none of its files, and keeps those written before it.
    crate::interrupt::install();
    let observer = |stem: &str| -> Box<dyn engine::Observer> { Box::new(Stoppable(Shown::new(stem, quiet))) };
    // A line that cannot be printed (standard output full) does not stop the
    // atlases, whose files are the results: its error is returned after them.
    let mut printed = Ok(());
    let ran = plan.run(&a.output, &page, &observer, &mut |done| {
        if !quiet && printed.is_ok() {
            printed = crate::out::line(&format!(
                "{}: {} cells in {:.1} s -> {}",
                done.stem,
                done.cells,
                done.secs,
                done.map.display()
            ));
        }
    });
    let sheet = match ran {
        Err(_) if crate::interrupt::requested() => {
            crate::out::errln!("study: interrupted; the atlases finished before are kept, no contact sheet was drawn");
            std::process::exit(130);
        }
        ran => ran?,
    };
    printed?;
    outln!("wrote {}", sheet.display());
    Ok(())
}
