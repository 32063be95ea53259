//! `vibroatlas study`: one atlas per value of a parameter, each with its map,
//! and a contact sheet comparing them.
//!
//! The whole study is checked before any atlas is computed
//! ([`engine::study`]). An output folder the study created is removed when it
//! fails before its first atlas is written.

use crate::args::StudyArgs;
use crate::common::command_line;
use crate::out::outln;
use crate::progress::Shown;
use anyhow::{anyhow, bail, Context, Result};
use engine::sheet_panel;
use render::View;
use store::write_atomically;

/// Runs the command.
pub fn run(a: StudyArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let threads = engine::threads(a.run.threads)?;
    let plan = engine::study(&a.study, a.preset, a.run.section_cap, threads, &command_line())?;
    if a.output.exists() && !a.output.is_dir() {
        bail!("{}: exists and is not a folder; give a folder for the study's files", a.output.display());
    }
    let engine::StudyPlan { study, scene, sweeps, mut plans } = plan;
    let created = store::create_folder(&a.output).with_context(|| format!("cannot create {}", a.output.display()))?;
    let mut written = false;
    let result = (|| -> Result<()> {
        for (v, plan) in &mut plans {
            let out = a.output.join(format!("{}.h5", study.stem(*v)));
            store::check_output(&out, &[&scene, &a.study])?;
            plan.output = Some(store::canonical_output(&out)?);
        }
        let mut panels = Vec::new();
        for (v, plan) in plans {
            let run = plan.execute(&Shown::new(&study.stem(v), a.run.quiet))?;
            let (atlas, secs) = (run.atlas, run.secs);
            written = true;
            let png = a.output.join(format!("{}.png", study.stem(v)));
            write_atomically(&png, |tmp| render::map(&atlas, View::Sweep(sweeps[0]), 0, &[], &page, tmp))?;
            if !a.run.quiet {
                outln!(
                    "{}: {} cells in {secs:.1} s -> {}",
                    study.stem(v),
                    plan.meta.plane.cells() * sweeps.len(),
                    png.display()
                );
            }
            panels.push((format!("{} = {v}", study.parameter), sheet_panel(atlas, sweeps[0])));
        }
        let sheet = a.output.join("contact-sheet.png");
        write_atomically(&sheet, |tmp| render::sheet(&panels, sweeps[0], 0, &page, tmp))?;
        outln!("wrote {}", sheet.display());
        Ok(())
    })();
    match (result, created) {
        (Err(e), Some(folder)) if !written => match std::fs::remove_dir_all(&folder) {
            Ok(()) => Err(anyhow!(
                "{e:#}; nothing was written: {}, which the study had created, is removed",
                folder.display()
            )),
            Err(_) => Err(e),
        },
        (result, _) => result,
    }
}
