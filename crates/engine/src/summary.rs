//! What an atlas holds, in numbers: its grid, per sweep the cells of each
//! class, label and reason, and its hysteresis ([`summary_json`], the
//! object `inspect --json` prints).

use grid::hysteresis::zones;
use grid::Atlas;
use solver::Class;

/// Why a sweep's unresolved cells are unresolved: each kind of reason (its
/// text with the numbers of each cell shown as `…`) and how many cells, the
/// most frequent first.
pub fn reasons(cells: &[Option<grid::CellData>]) -> Vec<(String, usize)> {
    let mut kinds: std::collections::BTreeMap<String, usize> = std::collections::BTreeMap::new();
    for r in cells.iter().flatten().filter_map(|c| c.reason.as_deref()) {
        *kinds.entry(without_numbers(r)).or_default() += 1;
    }
    let mut v: Vec<(String, usize)> = kinds.into_iter().collect();
    v.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
    v
}

/// `text` with every number (`-1.5e-3`, `400000`) written `…`.
fn without_numbers(text: &str) -> String {
    let mut out = String::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        let sign = c == '-' && chars.peek().is_some_and(char::is_ascii_digit);
        if c.is_ascii_digit() || sign {
            while chars.peek().is_some_and(|&d| d.is_ascii_digit() || ".eE".contains(d) || "+-".contains(d)) {
                chars.next();
            }
            out.push('…');
        } else {
            out.push(c);
        }
    }
    out
}

/// What an atlas holds, in numbers ([`Summary::of`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// Each sweep's, in the file's order.
    pub sweeps: Vec<SweepSummary>,
    /// Where up and down differ: the cells, and the size of each zone (the
    /// largest first), when the atlas has both.
    pub hysteresis: Option<(usize, Vec<usize>)>,
}

/// One sweep of an atlas, in numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepSummary {
    /// The sweep.
    pub sweep: grid::SweepKind,
    /// Cells computed.
    pub computed: usize,
    /// Cells per class: periodic, quasiperiodic, chaotic, unresolved.
    pub classes: [usize; 4],
    /// Per labelled mass, each label and its cells, the most frequent first.
    pub labels: Vec<Vec<(String, u64)>>,
    /// Why its unresolved cells are unresolved ([`reasons`]).
    pub reasons: Vec<(String, usize)>,
}

/// The classes of [`SweepSummary::classes`], in order.
pub const CLASSES: [Class; 4] = [Class::Periodic, Class::Quasiperiodic, Class::Chaotic, Class::Unresolved];

impl Summary {
    /// The summary of `atlas`.
    pub fn of(atlas: &Atlas) -> Summary {
        let p = &atlas.meta.plane;
        let sweeps = atlas
            .maps
            .iter()
            .map(|map| {
                let cells: Vec<_> = map.cells.iter().flatten().collect();
                SweepSummary {
                    sweep: map.sweep,
                    computed: cells.len(),
                    classes: CLASSES.map(|c| cells.iter().filter(|x| x.class == c).count()),
                    labels: (0..atlas.meta.masses.len()).map(|mi| atlas.legend(map.sweep, mi)).collect(),
                    reasons: reasons(&map.cells),
                }
            })
            .collect();
        let hysteresis =
            atlas.hysteresis().map(|h| (h.iter().map(|&v| v as usize).sum(), zones(&h, p.x.count, p.y.count)));
        Summary { sweeps, hysteresis }
    }

    /// Cells computed, every sweep together.
    pub fn computed(&self) -> usize {
        self.sweeps.iter().map(|s| s.computed).sum()
    }
}

/// The summary as one JSON object (`inspect --json`): grid, sweeps with class
/// and label counts per mass, hysteresis cells and zone sizes.
pub fn summary_json(atlas: &Atlas) -> serde_json::Value {
    use serde_json::json;
    let m = &atlas.meta;
    let p = &m.plane;
    let axis = |a: &grid::Axis| json!({"name": a.name, "start": a.start, "stop": a.stop, "count": a.count});
    let summary = Summary::of(atlas);
    let sweeps: Vec<serde_json::Value> = summary
        .sweeps
        .iter()
        .map(|s| {
            let labels: serde_json::Map<String, serde_json::Value> = m
                .masses
                .iter()
                .zip(&s.labels)
                .map(|(mass, legend)| {
                    let counts: serde_json::Map<String, serde_json::Value> =
                        legend.iter().map(|(l, c)| (l.clone(), (*c).into())).collect();
                    (mass.clone(), counts.into())
                })
                .collect();
            let [periodic, quasiperiodic, chaotic, unresolved] = s.classes;
            json!({
                "sweep": s.sweep.name(),
                "computed": s.computed,
                "classes": {
                    "periodic": periodic,
                    "quasiperiodic": quasiperiodic,
                    "chaotic": chaotic,
                    "unresolved": unresolved,
                },
                "labels": labels,
                "reasons": s.reasons.iter().map(|(kind, n)| json!({"reason": kind, "cells": n})).collect::<Vec<_>>(),
            })
        })
        .collect();
    let hysteresis = summary.hysteresis.map(|(cells, z)| json!({"cells": cells, "zones": z}));
    json!({
        "scene": m.scene_name,
        "preset": m.preset.name(),
        "integrator": m.integrator.name(),
        "x": axis(&p.x),
        "y": axis(&p.y),
        "along": p.along.name(),
        "cells": p.cells(),
        "masses": m.masses,
        "stops": m.stops,
        "sweeps": sweeps,
        "hysteresis": hysteresis,
    })
}

/// The object of `inspect --json` for the file `path` read as `loaded`: the
/// [`summary_json`] with the file's provenance (its path, when and by what
/// it was made, its history, run time and shard).
pub fn inspect_json(path: &std::path::Path, loaded: &store::Loaded) -> serde_json::Value {
    let mut o = summary_json(&loaded.atlas);
    o["file"] = path.display().to_string().into();
    o["created"] = loaded.created.clone().into();
    o["command"] = loaded.info.command.clone().into();
    o["history"] = loaded.info.history.clone().into();
    o["run_time_s"] = loaded.info.run_time_s.into();
    o["shard"] = loaded.info.shard.map(|s| s.to_string()).into();
    o
}
