//! What an atlas holds, in numbers: its grid, per sweep the cells of each
//! class, label and reason, and its hysteresis ([`summary_json`], the
//! object `inspect --json` prints).

use grid::hysteresis::zones;
use grid::Atlas;
use solver::Class;

/// Why a sweep's unresolved cells are unresolved: each kind of reason and
/// how many cells, the most frequent first. A kind is a reason's text with
/// its numbers set apart; it is shown with each number as it varies over
/// its cells: the number where they all agree, else its range (`λT =
/// -2.103e-3 to -4.000e-4`), each end as one of the cells wrote it.
pub fn reasons(cells: &[Option<grid::CellData>]) -> Vec<(String, usize)> {
    let mut kinds: std::collections::BTreeMap<String, (usize, Vec<Range>)> = std::collections::BTreeMap::new();
    for r in cells.iter().flatten().filter_map(|c| c.reason.as_deref()) {
        let (template, numbers) = split_numbers(r);
        let (n, ranges) = kinds.entry(template).or_insert_with(|| (0, numbers.iter().map(Range::of).collect()));
        *n += 1;
        for (range, number) in ranges.iter_mut().zip(&numbers) {
            range.take(number);
        }
    }
    let mut v: Vec<(String, usize)> =
        kinds.into_iter().map(|(template, (n, ranges))| (filled(&template, &ranges), n)).collect();
    v.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
    v
}

/// A number of a reason as written (`-1.5e-3`) and its value.
type Number = (f64, String);

/// The least and the greatest of one number over the cells of a kind.
struct Range {
    low: Number,
    high: Number,
}

impl Range {
    fn of(n: &Number) -> Range {
        Range { low: n.clone(), high: n.clone() }
    }

    fn take(&mut self, n: &Number) {
        if n.0 < self.low.0 {
            self.low = n.clone();
        }
        if n.0 > self.high.0 {
            self.high = n.clone();
        }
    }

    fn text(&self) -> String {
        if self.low.1 == self.high.1 {
            self.low.1.clone()
        } else {
            format!("{} to {}", self.low.1, self.high.1)
        }
    }
}

/// `text` with every number (`-1.5e-3`, `400000`) written `…`, and the
/// numbers in order.
fn split_numbers(text: &str) -> (String, Vec<Number>) {
    let mut out = String::new();
    let mut numbers = Vec::new();
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        let sign = c == '-' && chars.peek().is_some_and(char::is_ascii_digit);
        if c.is_ascii_digit() || sign {
            let mut token = c.to_string();
            while let Some(&d) = chars.peek().filter(|&&d| d.is_ascii_digit() || ".eE".contains(d) || "+-".contains(d))
            {
                token.push(d);
                chars.next();
            }
            numbers.push((token.trim_end_matches(['.', 'e', 'E', '+', '-']).parse().unwrap_or(f64::NAN), token));
            out.push('…');
        } else {
            out.push(c);
        }
    }
    (out, numbers)
}

/// `template` with its `…` replaced by the ranges, in order.
fn filled(template: &str, ranges: &[Range]) -> String {
    let mut out = String::new();
    let mut ranges = ranges.iter();
    for c in template.chars() {
        match (c, c == '…') {
            (_, true) => out.push_str(&ranges.next().map_or("…".to_string(), Range::text)),
            (c, false) => out.push(c),
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
/// it was made, its history, run time and shard; a zoom's parent).
pub fn inspect_json(path: &std::path::Path, loaded: &store::Loaded) -> serde_json::Value {
    let mut o = summary_json(&loaded.atlas);
    o["file"] = path.display().to_string().into();
    o["created"] = loaded.created.clone().into();
    o["command"] = loaded.info.command.clone().into();
    o["history"] = loaded.info.history.clone().into();
    o["run_time_s"] = loaded.info.run_time_s.into();
    o["shard"] = loaded.info.shard.map(|s| s.to_string()).into();
    if let Some(p) = &loaded.info.parent {
        o["parent"] =
            serde_json::json!({"file": p.path, "labels_crc32": format!("{:08x}", p.labels_crc32), "box": p.region});
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unresolved(reason: &str) -> Option<grid::CellData> {
        Some(grid::CellData {
            class: Class::Unresolved,
            labels: Vec::new(),
            chatter: solver::Mask::EMPTY,
            sticking: solver::Mask::EMPTY,
            symmetry: None,
            lyapunov: None,
            multiplier: None,
            final_state: Vec::new(),
            periods: 0,
            events: 0,
            period_section: Vec::new(),
            impact_sections: Vec::new(),
            reason: Some(reason.to_string()),
        })
    }

    /// Issue 40: reasons are shown with their numbers (each as it varies over
    /// the cells of its kind), not as templates.
    #[test]
    fn reasons_show_their_numbers() {
        let cells = vec![
            unresolved("still contracts (λT = -1.5e-3) after 600 periods"),
            None,
            unresolved("still contracts (λT = -4.0e-2) after 600 periods"),
            unresolved("still contracts (λT = -2.0e-3) after 600 periods"),
            unresolved("event budget of 400000 events exhausted"),
        ];
        assert_eq!(
            reasons(&cells),
            vec![
                ("still contracts (λT = -4.0e-2 to -1.5e-3) after 600 periods".to_string(), 3),
                ("event budget of 400000 events exhausted".to_string(), 1),
            ]
        );
    }
}
