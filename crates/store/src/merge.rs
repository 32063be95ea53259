//! Merging shard files (`--shard K/N`) back into one atlas equal to a
//! single-machine run.

use crate::error::StoreError;
use crate::read::read;
use grid::{Atlas, Meta};
use std::path::{Path, PathBuf};

/// Why two atlases cannot be merged: the first field of [`Meta`] that differs.
fn difference(a: &Meta, b: &Meta) -> Option<&'static str> {
    if a.scene_toml != b.scene_toml || a.scene_name != b.scene_name {
        Some("scene")
    } else if a.overrides != b.overrides {
        Some("parameter overrides (--set)")
    } else if a.plane != b.plane {
        Some("grid (axes or --along)")
    } else if a.sweeps != b.sweeps {
        Some("sweeps")
    } else if a.preset != b.preset || a.accuracy != b.accuracy || a.integrator != b.integrator {
        Some("accuracy settings")
    } else if a != b {
        Some("settings")
    } else {
        None
    }
}

/// Reads and merges `paths`; returns the atlas and the summed run time.
pub fn merge(paths: &[PathBuf]) -> Result<(Atlas, f64), StoreError> {
    let Some(first) = paths.first() else {
        return Err(StoreError::format(Path::new("merge"), "no input files"));
    };
    let base = read(first)?;
    let mut atlas = base.atlas;
    let mut run_time = base.info.run_time_s;
    for p in &paths[1..] {
        let part = read(p)?;
        if let Some(what) = difference(&atlas.meta, &part.atlas.meta) {
            return Err(StoreError::format(p, format!("cannot merge with {}: different {what}", first.display())));
        }
        run_time += part.info.run_time_s;
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
    Ok((atlas, run_time))
}
