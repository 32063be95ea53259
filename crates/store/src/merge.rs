//! Merging shard files (`--shard K/N`) back into one atlas equal to a
//! single-machine run.

use crate::error::{Setting, StoreError};
use crate::read::read;
use maps::{Atlas, Meta, Shard};
use scene::Named;
use std::path::{Path, PathBuf};

/// Why two atlases cannot be merged: the first field of [`Meta`] that differs.
fn difference(a: &Meta, b: &Meta) -> Option<Setting> {
    if a.scene_toml != b.scene_toml || a.scene_name != b.scene_name {
        Some(Setting::Scene)
    } else if a.overrides != b.overrides {
        Some(Setting::Overrides)
    } else if a.plane != b.plane {
        Some(Setting::Grid)
    } else if a.sweeps != b.sweeps {
        Some(Setting::Sweeps)
    } else if a.preset != b.preset || a.accuracy != b.accuracy || a.integrator != b.integrator {
        Some(Setting::Accuracy)
    } else if a != b {
        Some(Setting::Other)
    } else {
        None
    }
}

/// Each setting in which two atlases differ, with both values (`a`'s
/// first): `section_cap 100 and 4`.
fn differences(a: &Meta, b: &Meta) -> Vec<String> {
    let mut out = Vec::new();
    let mut differ = |name: &str, x: String, y: String| {
        if x != y {
            out.push(format!("{name} {x} and {y}"));
        }
    };
    let none = |s: String| if s.is_empty() { "none".to_string() } else { s };
    let pairs = |p: &[(String, f64)]| none(crate::write::pairs(p));
    let knobs = |p: &[(solver::Knob, f64)]| none(crate::write::pairs(p));
    let sweeps = |m: &Meta| m.sweeps.iter().map(|s| s.name()).collect::<Vec<_>>().join(",");
    differ("scene", a.scene_name.clone(), b.scene_name.clone());
    if a.scene_name == b.scene_name && a.scene_toml != b.scene_toml {
        out.push(format!("scene {} (two texts of it)", a.scene_name));
    }
    let mut differ = |name: &str, x: String, y: String| {
        if x != y {
            out.push(format!("{name} {x} and {y}"));
        }
    };
    differ("overrides", pairs(&a.overrides), pairs(&b.overrides));
    differ("grid x", a.plane.x.to_string(), b.plane.x.to_string());
    differ("grid y", a.plane.y.to_string(), b.plane.y.to_string());
    differ("grid along", a.plane.along.name().into(), b.plane.along.name().into());
    differ("sweeps", sweeps(a), sweeps(b));
    differ("preset", a.preset.name().into(), b.preset.name().into());
    differ("accuracy", knobs(&a.accuracy), knobs(&b.accuracy));
    differ("integrator", a.integrator.name().into(), b.integrator.name().into());
    differ("section_cap", a.section_cap.to_string(), b.section_cap.to_string());
    out
}

/// The result of merging parts.
#[derive(Debug)]
pub struct Merged {
    /// The merged atlas (cells in none of the parts stay `None`).
    pub atlas: Atlas,
    /// Summed run time of the parts, seconds.
    pub run_time_s: f64,
    /// The history lines of the parts (`TIME: command`), each once, in the order given.
    pub history: Vec<String>,
    /// Shards that no part holds (empty when complete, or when the parts are
    /// not shards).
    pub missing: Vec<Shard>,
}

/// Reads and merges `paths`. A part given twice (the same shard, or the same
/// file), or a part of another run, is an error naming it.
pub fn merge(paths: &[PathBuf]) -> Result<Merged, StoreError> {
    let Some(first) = paths.first() else {
        return Err(StoreError::format(Path::new("merge"), "no input files"));
    };
    let base = read(first)?;
    // Every part whole (a dataset or group missing, or an attribute changed,
    // is refused) and a part: not a zoom's file, which is its whole box (a
    // zoom has no shards; merged, it would lose its parent and keep the
    // parent's lattice), and without curves (`curves --into`), which are of
    // that part alone: not carried, and not dropped unsaid.
    let mergeable = |p: &Path, loaded: &crate::Loaded| {
        let curves = crate::write::verified(p, loaded)?;
        if loaded.info.parent.is_some() {
            return Err(StoreError::format(p, "a zoom's file, which holds its whole box: there are no parts to merge"));
        }
        if curves {
            let why =
                "holds bifurcation curves (curves --into), which a merge does not carry; find them on the merged atlas";
            return Err(StoreError::format(p, why));
        }
        Ok(())
    };
    mergeable(first, &base)?;
    let mut atlas = base.atlas;
    let mut run_time = base.info.run_time_s;
    let mut history = base.info.history;
    let mut shards = vec![(base.info.shard, first.clone())];
    for (i, p) in paths.iter().enumerate().skip(1) {
        if let Some(other) = paths[..i].iter().find(|q| crate::lock::same_path(q, p)) {
            let what = if other == p {
                "is given twice".to_string()
            } else {
                format!("is given twice (also as {})", other.display())
            };
            return Err(StoreError::format(p, what));
        }
        let part = read(p)?;
        mergeable(p, &part)?;
        if let Some(setting) = difference(&atlas.meta, &part.atlas.meta) {
            let (path, first) = (p.display().to_string(), first.display().to_string());
            let differences = differences(&atlas.meta, &part.atlas.meta);
            return Err(StoreError::OtherRun { path, first, setting, differences });
        }
        // Shards of runs split into other numbers of parts deal other lines.
        let other_split = |s: &Option<Shard>| matches!((s, part.info.shard), (Some(a), Some(b)) if a.n != b.n);
        if let (Some((Some(s), other)), Some(ours)) = (shards.iter().find(|(s, _)| other_split(s)), part.info.shard) {
            let what = format!(
                "is shard {ours}, {} is shard {s}: the parts split the run into different numbers of shards",
                other.display()
            );
            return Err(StoreError::format(p, what));
        }
        if let Some((_, other)) = shards.iter().find(|(s, _)| s.is_some() && *s == part.info.shard) {
            let k = part.info.shard.map(|s| s.to_string()).unwrap_or_default();
            return Err(StoreError::format(p, format!("shard {k} is given twice (also {})", other.display())));
        }
        // Parts sampled for attractors differently (or one not at all) would
        // merge into a map that covers only some parts' cells.
        let sampling = |a: &Option<maps::AttractorMap>| a.as_ref().map(|m| (m.samples, m.seed));
        let (ours, theirs) = (sampling(&atlas.attractors), sampling(&part.atlas.attractors));
        if ours != theirs {
            let say = |s: Option<(usize, u64)>| {
                s.map_or("none".to_string(), |(k, seed)| format!("{k} samples per cell, seed {seed}"))
            };
            return Err(StoreError::format(
                p,
                format!(
                    "is not a part of the same run as {}: attractors {} against {}",
                    first.display(),
                    say(theirs),
                    say(ours)
                ),
            ));
        }
        shards.push((part.info.shard, p.clone()));
        for line in part.info.history {
            if !history.contains(&line) {
                history.push(line);
            }
        }
        run_time += part.info.run_time_s;
        if let (Some(into), Some(from)) = (&mut atlas.attractors, part.atlas.attractors) {
            for (i, c) in from.cells.into_iter().enumerate() {
                if c.is_some() {
                    into.cells[i] = c;
                }
            }
        }
        for (into, from) in atlas.maps.iter_mut().zip(part.atlas.maps) {
            for (i, cell) in from.cells.into_iter().enumerate() {
                if let Some(c) = cell {
                    match &into.cells[i] {
                        Some(existing) if *existing != c => {
                            return Err(StoreError::format(
                                p,
                                format!("cell {i} of sweep {} differs from another part", into.sweep.name()),
                            ))
                        }
                        _ => into.cells[i] = Some(c),
                    }
                }
            }
        }
    }
    let missing = match shards.iter().find_map(|(s, _)| *s) {
        Some(s) => (1..=s.n)
            .filter(|&k| !shards.iter().any(|(t, _)| t.is_some_and(|t| t.k == k)))
            .map(|k| Shard { k, n: s.n })
            .collect(),
        None => Vec::new(),
    };
    Ok(Merged { atlas, run_time_s: run_time, history, missing })
}
