//! `vibroatlas study`: one atlas per value of a parameter, each with its map,
//! and a contact sheet comparing them.
//!
//! The whole study is checked before any atlas is computed, as `atlas` checks
//! its own: at most [`grid::MAX_VALUES`] values, every value's scene and
//! plane ([`Plan::check`]), and the memory of one atlas at a time beside the
//! contact sheet's panels ([`Plan::check_memory_beside`]). A finished atlas is
//! kept only as its panel ([`sheet_panel`]: the drawn sweep's labels, no states
//! or sections). An output folder the study created is removed when it fails
//! before its first atlas is written.

use crate::args::StudyArgs;
use crate::common::command_line;
use crate::out::outln;
use crate::progress::Shown;
use anyhow::{anyhow, bail, Context, Result};
use engine::{Plan, SceneSource, Sim};
use grid::{Along, Atlas, Axis, CellData, Map, Meta, Plane, Study, SweepKind};
use render::View;
use std::path::{Path, PathBuf};
use store::write_atomically;

/// Runs the command.
pub fn run(a: StudyArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    let text =
        std::fs::read_to_string(&a.study).with_context(|| format!("cannot read study file {}", a.study.display()))?;
    let study = Study::parse(&text).map_err(|e| anyhow!("{}: {e}", a.study.display()))?;
    let scene_path = a.study.parent().unwrap_or(std::path::Path::new(".")).join(&study.scene);
    let sweeps = SweepKind::parse_set(&study.sweep, "sweep")?;
    let plane = Plane::new(Axis::parse(&study.x, "x")?, Axis::parse(&study.y, "y")?, Along::parse(&study.along)?)?;
    if [&plane.x.name, &plane.y.name].contains(&&study.parameter) {
        bail!(
            "{}: parameter '{}' is also an axis of the study's plane; vary another parameter",
            a.study.display(),
            study.parameter
        );
    }
    if a.output.exists() && !a.output.is_dir() {
        bail!("{}: exists and is not a folder; give a folder for the study's files", a.output.display());
    }
    let mut plans = plans(&a, &study, &scene_path, &plane, &sweeps)?;
    // One atlas at a time, beside every panel of the contact sheet.
    if let Some((_, plan)) = plans.first() {
        let held = plans.len() as u64 * panel_bytes(&plan.meta);
        plan.check_memory_beside(held, &format!(" (and the contact sheet's {} maps)", plans.len()))?;
    }
    let created = create_folder(&a.output)?;
    let mut written = false;
    let result = (|| -> Result<()> {
        for (v, plan) in &mut plans {
            let out = a.output.join(format!("{}.h5", study.stem(*v)));
            store::check_output(&out, &[&scene_path, &a.study], false)?;
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

/// One checked plan per value of the study, every value validated before any
/// is computed (and before the folder exists).
fn plans(
    a: &StudyArgs,
    study: &Study,
    scene_path: &Path,
    plane: &Plane,
    sweeps: &[SweepKind],
) -> Result<Vec<(f64, Plan)>> {
    let threads = engine::threads(a.run.threads)?;
    study
        .values
        .iter()
        .map(|&v| {
            let mut sim = Sim::new(SceneSource::File(scene_path.to_path_buf()));
            sim.set = study.set.iter().map(|(k, x)| (k.clone(), *x)).collect();
            sim.set.push((study.parameter.clone(), v));
            sim.preset = Some(a.preset.preset());
            let s = sim.setup()?;
            let mut plan = Plan::new(&s, a.run.section_cap, plane.clone(), sweeps.to_vec(), threads)?;
            plan.command = command_line();
            plan.check()?;
            Ok((v, plan))
        })
        .collect()
}

/// Creates the folder `dir` (and its missing parents); returns the outermost
/// folder it created, if any (to be removed again when nothing is written).
fn create_folder(dir: &Path) -> Result<Option<PathBuf>> {
    let missing: Option<PathBuf> = dir
        .ancestors()
        .filter(|p| !p.as_os_str().is_empty())
        .take_while(|p| std::fs::symlink_metadata(p).is_err())
        .last()
        .map(Path::to_path_buf);
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    Ok(missing)
}

/// What the contact sheet needs of a finished atlas: the map of the sweep it
/// draws, each cell's class and labels; no states, sections or attractors,
/// and no scene text.
fn sheet_panel(atlas: Atlas, sweep: SweepKind) -> Atlas {
    let Atlas { mut meta, maps, .. } = atlas;
    meta.scene_toml = String::new();
    meta.sweeps = vec![sweep];
    let maps = maps
        .into_iter()
        .filter(|m| m.sweep == sweep)
        .map(|m| Map {
            sweep,
            cells: m
                .cells
                .into_iter()
                .map(|c| {
                    c.map(|c| CellData {
                        final_state: Vec::new(),
                        period_section: Vec::new(),
                        impact_sections: Vec::new(),
                        reason: None,
                        ..c
                    })
                })
                .collect(),
        })
        .collect();
    Atlas { meta, maps, attractors: None }
}

/// Bytes a panel of [`sheet_panel`] holds at most for an atlas of `meta`.
fn panel_bytes(meta: &Meta) -> u64 {
    let cell = std::mem::size_of::<Option<CellData>>() + meta.masses.len() * std::mem::size_of::<solver::Label>();
    (meta.plane.cells() * cell) as u64 + 16_384
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_is_created_and_its_outermost_new_parent_named() {
        let base = std::env::temp_dir().join(format!("vibroatlas-study-folder-{}", std::process::id()));
        let dir = base.join("a/b");
        std::fs::create_dir_all(&base).unwrap();
        assert_eq!(create_folder(&dir).unwrap(), Some(base.join("a")));
        assert!(dir.is_dir());
        assert_eq!(create_folder(&dir).unwrap(), None);
        std::fs::remove_dir_all(&base).unwrap();
    }
}
