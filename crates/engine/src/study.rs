//! A parameter study ([`study`]): one atlas per value of a parameter, the
//! whole checked before any atlas is computed, as `atlas` checks its own: at
//! most [`grid::MAX_VALUES`] values, every value's scene and plane
//! ([`Plan::check`]), and the memory of one atlas at a time beside the
//! contact sheet's panels ([`Plan::check_memory_beside`]); then run into a
//! folder ([`StudyPlan::run`]): each atlas, its map, and the contact sheet
//! of them all. A finished atlas is kept only as its panel ([`sheet_panel`]:
//! the drawn sweep's labels, no states or sections).

use crate::error::{Error, Result};
use crate::plan::Plan;
use crate::sim::{SceneSource, Sim};

use grid::{Along, Atlas, Axis, CellData, Map, Meta, Observer, Plane, Study, SweepKind};
use render::View;
use std::path::{Path, PathBuf};

/// A study, checked: one plan per value.
#[derive(Debug)]
pub struct StudyPlan {
    /// The study file's contents.
    pub study: Study,
    /// The study file.
    pub file: PathBuf,
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
    // The parameters the study names are the scene's (its file and field named).
    let base = Sim::new(SceneSource::File(scene.clone())).setup()?;
    let named = study.set.keys().map(|k| (k, format!("set.{k}"))).chain([(&study.parameter, "parameter".into())]);
    for (name, field) in named {
        base.scene.check_parameter(name, &field).map_err(|e| Error::file(file, "", Some(e.into())))?;
    }
    let plans = study
        .values
        .iter()
        .map(|&v| {
            let value = || -> Result<Plan> {
                let mut sim = Sim::new(SceneSource::File(scene.clone()));
                sim.set = study.set.iter().map(|(k, x)| (k.clone(), *x)).collect();
                sim.set.push((study.parameter.clone(), v));
                sim.preset = Some(preset);
                let mut plan = Plan::new(&sim.setup()?, section_cap, plane.clone(), sweeps.clone(), threads)?;
                plan.command = command.to_string();
                plan.check()?;
                Ok(plan)
            };
            // Which value of which file, where that value's scene or plan is refused.
            let plan = value()
                .map_err(|e| Error::file(file, format!("values: {} = {v}", study.parameter), Some(Box::new(e))))?;
            Ok((v, plan))
        })
        .collect::<Result<Vec<_>>>()?;
    // One atlas at a time, beside every panel of the contact sheet.
    if let Some((_, plan)) = plans.first() {
        let held = plans.len() as u64 * panel_bytes(&plan.meta);
        plan.check_memory_beside(held, &format!(" (and the contact sheet's {} maps)", plans.len()))?;
    }
    Ok(StudyPlan { study, file: file.to_path_buf(), scene, sweeps, plans })
}

/// One atlas of a study, written (as [`StudyPlan::run`] tells it).
#[derive(Debug)]
pub struct StudyAtlas<'a> {
    /// Its name in the folder ([`Study::stem`], `mu_k=0.1`): its file is
    /// `STEM.h5`, its map `STEM.png`.
    pub stem: &'a str,
    /// Cells computed, every sweep's.
    pub cells: usize,
    /// Seconds its run took.
    pub secs: f64,
    /// Its map.
    pub map: &'a Path,
}

/// The contact sheet's file name in a study's folder.
const SHEET: &str = "contact-sheet.png";

impl StudyPlan {
    /// Runs the study into the folder `output` (made where missing): per
    /// value its atlas `STEM.h5` and the map of its first sweep `STEM.png`,
    /// drawn on `page`, then `contact-sheet.png` of every map, whose path it
    /// returns. Each atlas reports to the observer that `observer` makes for
    /// its stem, and is told to `written` once its map is drawn. A folder the
    /// study created is removed when the study fails before its first atlas
    /// is written ([`Error::Unwritten`]).
    pub fn run(
        self,
        output: &Path,
        page: &render::Page,
        observer: &dyn Fn(&str) -> Box<dyn Observer>,
        written: &mut dyn FnMut(&StudyAtlas<'_>),
    ) -> Result<PathBuf> {
        if output.exists() && !output.is_dir() {
            return Err(Error::file(output, "exists and is not a folder; give a folder for the study's files", None));
        }
        let created =
            store::create_folder(output).map_err(|cause| Error::Uncreatable { path: output.to_path_buf(), cause })?;
        // Whether an atlas was written: from then on the folder is kept.
        let mut any = false;
        let done = (|| -> Result<PathBuf> {
            let StudyPlan { study, file, scene, sweeps, mut plans } = self;
            // Every file the study writes, its maps and contact sheet too,
            // checked before any work (none may replace the study or its scene).
            for (v, plan) in &mut plans {
                let stem = study.stem(*v);
                let out = output.join(format!("{stem}.h5"));
                store::check_output(&out, &[&scene, &file])?;
                store::check_output(&output.join(format!("{stem}.png")), &[&scene, &file])?;
                plan.output = Some(store::canonical_output(&out)?);
            }
            store::check_output(&output.join(SHEET), &[&scene, &file])?;
            let mut panels = Vec::new();
            for (v, plan) in plans {
                let stem = study.stem(v);
                let run = plan.execute(observer(&stem).as_ref())?;
                any = true;
                let map = output.join(format!("{stem}.png"));
                store::write_atomically(&map, |tmp| {
                    render::map(&run.atlas, View::Sweep(sweeps[0]), 0, &[], page, tmp)
                })?;
                let cells = plan.meta.plane.cells() * sweeps.len();
                written(&StudyAtlas { stem: &stem, cells, secs: run.secs, map: &map });
                panels.push((format!("{} = {v}", study.parameter), sheet_panel(run.atlas, sweeps[0])));
            }
            let sheet = output.join(SHEET);
            store::write_atomically(&sheet, |tmp| render::sheet(&panels, sweeps[0], 0, page, tmp))?;
            Ok(sheet)
        })();
        match (done, created) {
            (Err(cause), Some(folder)) if !any => match std::fs::remove_dir_all(&folder) {
                Ok(()) => Err(Error::Unwritten { cause: Box::new(cause), folder }),
                Err(_) => Err(cause),
            },
            (done, _) => done,
        }
    }
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
                        period_section: solver::Points::default(),
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
