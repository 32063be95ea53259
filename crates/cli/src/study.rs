//! `vibroatlas study`: one atlas per value of a parameter, each with its map,
//! and a contact sheet comparing them.
//!
//! The whole study is checked before any atlas is computed
//! ([`engine::study`]), then run ([`engine::StudyPlan::run`]: an output
//! folder the study created is removed when it fails before its first atlas
//! is written).

use crate::args::StudyArgs;
use crate::common::command_line;
use crate::out::outln;
use crate::progress::Shown;
use anyhow::Result;

/// Runs the command.
pub fn run(a: StudyArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let threads = engine::threads(a.run.threads)?;
    let plan = engine::study(&a.study, a.preset, a.run.section_cap, threads, &command_line())?;
    let quiet = a.run.quiet;
    // A line that cannot be printed (standard output full) does not stop the
    // atlases, whose files are the results: its error is returned after them.
    let mut printed = Ok(());
    let sheet = plan.run(&a.output, &page, &|stem| Box::new(Shown::new(stem, quiet)), &mut |done| {
        if !quiet && printed.is_ok() {
            printed = crate::out::line(&format!(
                "{}: {} cells in {:.1} s -> {}",
                done.stem,
                done.cells,
                done.secs,
                done.map.display()
            ));
        }
    })?;
    printed?;
    outln!("wrote {}", sheet.display());
    Ok(())
}
