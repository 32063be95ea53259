//! Text summaries of atlases (after a run, and `vibroatlas inspect`).

use crate::out::outln;
use grid::hysteresis::zones;
use grid::Atlas;
use solver::Class;

/// Prints grid, per-sweep class and label counts, hysteresis, and speed.
pub fn print_summary(atlas: &Atlas, secs: f64, threads: usize) -> anyhow::Result<()> {
    let m = &atlas.meta;
    let p = &m.plane;
    outln!("scene     {} (preset {}, integrator {})", m.scene_name, m.preset.name(), m.integrator.name());
    outln!("grid      {} x {} = {} cells, continuation along {}", p.x, p.y, p.cells(), p.along.name());
    let computed: usize = atlas.maps.iter().map(|mp| mp.cells.iter().flatten().count()).sum();
    if secs > 0.0 {
        let rate = crate::progress::thousands((computed as f64 / secs).round() as u64);
        outln!("time      {} on {threads} threads, {rate} cells/s", crate::progress::duration(secs));
    }
    for map in &atlas.maps {
        let cells: Vec<_> = map.cells.iter().flatten().collect();
        let count = |c: Class| cells.iter().filter(|x| x.class == c).count();
        outln!(
            "sweep     {}: {} cells computed; periodic {}, quasiperiodic {}, chaotic {}, unresolved {}",
            map.sweep.name(),
            cells.len(),
            count(Class::Periodic),
            count(Class::Quasiperiodic),
            count(Class::Chaotic),
            count(Class::Unresolved)
        );
        for (mi, mass) in m.masses.iter().enumerate() {
            let legend = atlas.legend(map.sweep, mi);
            let shown: Vec<String> = legend.iter().take(12).map(|(l, c)| format!("{l} {c}")).collect();
            let more = if legend.len() > 12 { format!(", … {} more", legend.len() - 12) } else { String::new() };
            outln!("  {mass:<6} {}{more}", shown.join(", "));
        }
        for (kind, n) in reasons(&map.cells).iter().take(5) {
            outln!("  why U  {n} x {kind}");
        }
    }
    if let Some(h) = atlas.hysteresis() {
        let z = zones(&h, p.x.count, p.y.count);
        let n: usize = h.iter().map(|&v| v as usize).sum();
        outln!("hysteresis {n} cells in {} zones (largest {:?})", z.len(), &z[..z.len().min(5)]);
    }
    Ok(())
}

/// Why a sweep's unresolved cells are unresolved: each kind of reason (its
/// text with the numbers of each cell shown as `…`) and how many cells, the
/// most frequent first.
fn reasons(cells: &[Option<grid::CellData>]) -> Vec<(String, usize)> {
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
