//! A parameter study ([`study`]): one atlas per value of a parameter, the
//! whole checked before any atlas is computed, as `atlas` checks its own: at
//! most [`grid::MAX_VALUES`] values, every value's scene and plane
//! ([`Plan::check`]), and the memory of one atlas at a time beside the
//! contact sheet's panels ([`Plan::check_memory_beside`]). A finished atlas
//! is kept only as its panel ([`sheet_panel`]: the drawn sweep's labels, no
//! states or sections).

use crate::error::{Error, Result};
use crate::plan::Plan;
use crate::sim::{SceneSource, Sim};

use grid::{Along, Atlas, Axis, CellData, Map, Meta, Plane, Study, SweepKind};
use std::path::{Path, PathBuf};

/// A study, checked: one plan per value.
#[derive(Debug)]
pub struct StudyPlan {
    /// The study file's contents.
    pub study: Study,
    /// The scene file (beside the study file).
    pub scene: PathBuf,
    /// The sweeps of every atlas (the first is drawn).
    pub sweeps: Vec<SweepKind>,
    /// Per value, its checked plan (no output yet).
    pub plans: Vec<(f64, Plan)>,
}

/// Reads and checks the study file `file` for runs with `preset`, sections
/// of `section_cap` points and `threads` workers; `command` is what made it.
pub fn study(
    file: &Path,
    preset: solver::Preset,
    section_cap: usize,
    threads: usize,
    command: &str,
) -> Result<StudyPlan> {
    let text =
        crate::sim::read_text(file).map_err(|cause| Error::Unreadable { what: "study", path: file.into(), cause })?;
    let study = Study::parse(&text).map_err(|e| Error::file(file, "", Some(e.into())))?;
    let scene = file.parent().unwrap_or(Path::new(".")).join(&study.scene);
    let sweeps = SweepKind::parse_set(&study.sweep, "sweep")?;
    let plane = Plane::new(
        Axis::parse(&study.x, "x")?,
        Axis::parse(&study.y, "y")?,
        grid::read::<Along>(&study.along, "along")?,
    )?;
    if [&plane.x.name, &plane.y.name].contains(&&study.parameter) {
        let why =
            format!("parameter '{}' is also an axis of the study's plane; vary another parameter", study.parameter);
        return Err(Error::file(file, why, None));
    }
    let plans = study
        .values
        .iter()
        .map(|&v| {
            let mut sim = Sim::new(SceneSource::File(scene.clone()));
            sim.set = study.set.iter().map(|(k, x)| (k.clone(), *x)).collect();
            sim.set.push((study.parameter.clone(), v));
            sim.preset = Some(preset);
            let mut plan = Plan::new(&sim.setup()?, section_cap, plane.clone(), sweeps.clone(), threads)?;
            plan.command = command.to_string();
            plan.check()?;
            Ok((v, plan))
        })
        .collect::<Result<Vec<_>>>()?;
    // One atlas at a time, beside every panel of the contact sheet.
    if let Some((_, plan)) = plans.first() {
        let held = plans.len() as u64 * panel_bytes(&plan.meta);
        plan.check_memory_beside(held, &format!(" (and the contact sheet's {} maps)", plans.len()))?;
    }
    Ok(StudyPlan { study, scene, sweeps, plans })
}

/// What the contact sheet needs of a finished atlas: the map of the sweep it
/// draws, each cell's class and labels; no states, sections or attractors,
/// and no scene text.
pub fn sheet_panel(atlas: Atlas, sweep: SweepKind) -> Atlas {
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
    Atlas { meta, maps, attractors: None, entries: grid::Entries::default() }
}

/// Bytes a panel of [`sheet_panel`] holds at most for an atlas of `meta`.
fn panel_bytes(meta: &Meta) -> u64 {
    let cell = std::mem::size_of::<Option<CellData>>() + meta.masses.len() * std::mem::size_of::<solver::Label>();
    (meta.plane.cells() * cell) as u64 + 16_384
}
