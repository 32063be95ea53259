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

/// The summary as one JSON object (`inspect --json`): grid, sweeps with class
/// and label counts per mass, hysteresis cells and zone sizes.
pub fn summary_json(atlas: &Atlas) -> serde_json::Value {
    use serde_json::json;
    let m = &atlas.meta;
    let p = &m.plane;
    let axis = |a: &grid::Axis| json!({"name": a.name, "start": a.start, "stop": a.stop, "count": a.count});
    let sweeps: Vec<serde_json::Value> = atlas
        .maps
        .iter()
        .map(|map| {
            let cells: Vec<_> = map.cells.iter().flatten().collect();
            let count = |c: Class| cells.iter().filter(|x| x.class == c).count();
            let labels: serde_json::Map<String, serde_json::Value> = m
                .masses
                .iter()
                .enumerate()
                .map(|(mi, mass)| {
                    let counts: serde_json::Map<String, serde_json::Value> =
                        atlas.legend(map.sweep, mi).into_iter().map(|(l, c)| (l, c.into())).collect();
                    (mass.clone(), counts.into())
                })
                .collect();
            json!({
                "sweep": map.sweep.name(),
                "computed": cells.len(),
                "classes": {
                    "periodic": count(Class::Periodic),
                    "quasiperiodic": count(Class::Quasiperiodic),
                    "chaotic": count(Class::Chaotic),
                    "unresolved": count(Class::Unresolved),
                },
                "labels": labels,
                "reasons": reasons(&map.cells).into_iter().map(|(kind, n)| json!({"reason": kind, "cells": n})).collect::<Vec<_>>(),
            })
        })
        .collect();
    let hysteresis = atlas.hysteresis().map(|h| {
        let z = zones(&h, p.x.count, p.y.count);
        json!({"cells": h.iter().map(|&v| v as usize).sum::<usize>(), "zones": z})
    });
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
