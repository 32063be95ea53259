//! `vibroatlas sweep`: continuation along one parameter. Computed as a plane of
//! one row (the other axis is a plain parameter held at its value), so the file,
//! the renderer and the hysteresis logic are those of the atlas.

use crate::args::{Direction, SweepArgs};
use crate::common::{in_flags, setup_from};
use crate::out::outln;
use crate::plan::{threads, Plan};
use anyhow::{anyhow, Result};
use grid::{Along, Atlas, Axis, CellData, Line, Plane, SweepKind};
use serde_json::{json, Map, Value};
use store::write_atomically;

/// The legs of a sweep: independent directions (each from the same start), or
/// a hysteresis loop whose second leg starts from the first leg's end state.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Legs {
    Separate,
    Loop(SweepKind),
}

/// Runs the command.
pub fn run(a: SweepArgs) -> Result<()> {
    let (mut s, origin) = setup_from(&a.sim, &a.start)?;
    let axis = Axis::parse(&a.axis, "--axis")?;
    // From a stored cell, the swept parameter is the axis, not the cell's value.
    s.overrides.retain(|(k, _)| *k != axis.name || origin.is_none());
    let given = if axis.start <= axis.stop { SweepKind::Up } else { SweepKind::Down };
    let (sweeps, legs) = match a.direction {
        None => (vec![given], Legs::Separate),
        Some(Direction::Up) => (vec![SweepKind::Up], Legs::Separate),
        Some(Direction::Down) => (vec![SweepKind::Down], Legs::Separate),
        Some(Direction::Both) => (vec![SweepKind::Up, SweepKind::Down], Legs::Separate),
        Some(Direction::DownUp) => (vec![SweepKind::Up, SweepKind::Down], Legs::Loop(SweepKind::Down)),
        Some(Direction::UpDown) => (vec![SweepKind::Up, SweepKind::Down], Legs::Loop(SweepKind::Up)),
    };
    let x = if given == SweepKind::Up { axis.clone() } else { axis.reversed() };
    let model = s.scene.evaluate(&s.overrides)?;
    let (held, value) = model
        .parameters
        .iter()
        .find(|(n, _)| *n != x.name && s.scene.is_plain(n))
        .cloned()
        .ok_or_else(|| anyhow!("--axis: the scene needs a second plain parameter to hold fixed"))?;
    let plane = Plane::new(x, Axis { name: held, start: value, stop: value, count: 1 }, Along::X)
        .map_err(|e| in_flags(e, &[("x", "--axis")]))?;
    let page = crate::figure::page(&a.figure)?;
    if let Some(png) = &a.png {
        render::Format::of(png)?;
    }
    let cap = a.points.unwrap_or(a.run.section_cap);
    let mut plan = Plan::new(&s, cap, plane, sweeps.clone(), threads(a.run.threads)?)?;
    plan.output = a.output.clone();
    plan.inputs = vec![a.sim.scene.clone()];
    plan.force = a.force;
    plan.quiet = a.run.quiet || a.json;
    plan.check().map_err(|e| match e.downcast::<grid::GridError>() {
        Ok(g) => in_flags(g, &[("x", "--axis"), ("threads", "--threads")]),
        Err(e) => e,
    })?;
    let atlas = match (legs, &origin) {
        (Legs::Separate, None) => plan.execute("sweep")?.0,
        _ => legs_from(&plan, legs, origin.as_ref().map(|o| o.state.as_slice()))?,
    };
    if let Some(png) = &a.png {
        let mut d = crate::diagram::diagram(&atlas, 0, a.variable.as_deref(), a.impact)?;
        if let Legs::Loop(first) = legs {
            d.first = Some(first);
        }
        write_atomically(png, |tmp| render::bifurcation(&atlas, &d, &page, tmp))?;
    }
    let first = match legs {
        Legs::Loop(first) => first,
        Legs::Separate if sweeps.contains(&given) => given,
        Legs::Separate => sweeps[0],
    };
    if a.json {
        let mut o = json!({
            "axis": axis.name,
            "direction": a.direction.map_or(first.name(), direction_name),
            "points": points(&atlas, first, first == SweepKind::Down),
        });
        if sweeps.len() == 2 {
            o["up"] = points(&atlas, SweepKind::Up, false);
            o["down"] = points(&atlas, SweepKind::Down, true);
            o["hysteresis"] = hysteresis(&atlas);
        }
        if let Some(origin) = &origin {
            o["from"] = origin.about.clone();
        }
        outln!("{}", serde_json::to_string(&o)?);
    } else {
        print_text(&atlas, &sweeps)?;
    }
    Ok(())
}

/// The name of a direction, as given on the command line.
fn direction_name(d: Direction) -> &'static str {
    match d {
        Direction::Up => "up",
        Direction::Down => "down",
        Direction::Both => "both",
        Direction::DownUp => "down-up",
        Direction::UpDown => "up-down",
    }
}

/// Runs the legs of a sweep that do not start from the scene's initial state:
/// from a given state, and the second leg of a loop from the first leg's end
/// state (the protocol of experiments and of published hysteresis zones).
/// Writes the file (under the output's lock) when the plan has an output.
fn legs_from(plan: &Plan, legs: Legs, start: Option<&[f64]>) -> Result<Atlas> {
    let p = &plan.meta.plane;
    let _lock = plan.output.as_deref().map(store::OutputLock::acquire).transpose()?;
    let clock = std::time::Instant::now();
    let ascending: Vec<Vec<(String, f64)>> = (0..p.x.count).map(|ix| p.params(0, ix)).collect();
    let descending: Vec<Vec<(String, f64)>> = ascending.iter().rev().cloned().collect();
    let total = (p.x.count * plan.meta.sweeps.len()) as u64;
    let bar = crate::progress::Bar::new("sweep", total, 0, plan.quiet);
    let leg = |sweep: SweepKind, from: Option<&[f64]>| -> Result<Line> {
        let mut cells = match sweep {
            SweepKind::Down => grid::chain_from(&plan.setup, &descending, from, &bar)?,
            _ => grid::chain_from(&plan.setup, &ascending, from, &bar)?,
        };
        if sweep == SweepKind::Down {
            cells.reverse();
        }
        Ok(Line { sweep, index: 0, cells })
    };
    let mut atlas = Atlas::new(plan.meta.clone());
    match legs {
        Legs::Loop(first) => {
            let one = leg(first, start)?;
            // The first leg ends at the far end of the axis from where it began.
            let end = match first {
                SweepKind::Down => one.cells.first(),
                _ => one.cells.last(),
            }
            .map(|c| c.final_state.clone());
            let second = if first == SweepKind::Down { SweepKind::Up } else { SweepKind::Down };
            let two = leg(second, end.as_deref())?;
            atlas.insert(one);
            atlas.insert(two);
        }
        Legs::Separate => {
            for &sweep in &plan.meta.sweeps {
                atlas.insert(leg(sweep, start)?);
            }
        }
    }
    bar.finish();
    if let Some(out) = &plan.output {
        let info = store::RunInfo {
            command: plan.command.clone(),
            run_time_s: clock.elapsed().as_secs_f64(),
            shard: None,
            history: Vec::new(),
        };
        store::write(out, &atlas, &info, plan.threads)?;
    }
    Ok(atlas)
}

fn labels(atlas: &Atlas, c: &CellData) -> Value {
    let m: Map<String, Value> = atlas
        .meta
        .masses
        .iter()
        .enumerate()
        .map(|(i, name)| (name.clone(), Value::from(c.labels[i].to_string())))
        .collect();
    Value::Object(m)
}

fn point(atlas: &Atlas, ix: usize, c: &CellData) -> Value {
    json!({
        "value": atlas.meta.plane.x.value(ix),
        "class": c.class.name(),
        "n": c.labels.first().and_then(|l| l.npq()).map(|(n, _, _)| n),
        "labels": labels(atlas, c),
        "symmetry": c.symmetry.map(|s| s.name()),
        "lyapunov": c.lyapunov,
        "max_multiplier": c.multiplier,
    })
}

/// The points of one sweep in the order they were computed.
fn points(atlas: &Atlas, sweep: SweepKind, descending: bool) -> Value {
    let Some(map) = atlas.map(sweep) else { return Value::Array(Vec::new()) };
    let mut v: Vec<Value> =
        map.cells.iter().enumerate().filter_map(|(ix, c)| c.as_ref().map(|c| point(atlas, ix, c))).collect();
    if descending {
        v.reverse();
    }
    Value::Array(v)
}

/// Values where up and down end on different periodic motions.
fn hysteresis(atlas: &Atlas) -> Value {
    let (Some(h), Some(up), Some(down)) = (atlas.hysteresis(), atlas.map(SweepKind::Up), atlas.map(SweepKind::Down))
    else {
        return Value::Array(Vec::new());
    };
    Value::Array(
        h.iter()
            .enumerate()
            .filter(|(_, &v)| v == 1)
            .filter_map(|(ix, _)| {
                let (u, d) = (up.cells[ix].as_ref()?, down.cells[ix].as_ref()?);
                Some(json!({"value": atlas.meta.plane.x.value(ix), "up": labels(atlas, u), "down": labels(atlas, d)}))
            })
            .collect(),
    )
}

fn print_text(atlas: &Atlas, sweeps: &[SweepKind]) -> Result<()> {
    let p = &atlas.meta.plane;
    let header: Vec<String> = sweeps.iter().map(|s| format!("{:<24}", s.name())).collect();
    outln!("{:<12} {}", p.x.name, header.join(""));
    for ix in 0..p.x.count {
        let cols: Vec<String> = sweeps
            .iter()
            .map(|&s| {
                let c = atlas.map(s).and_then(|m| m.cells[ix].as_ref());
                let text = c.map_or(String::new(), |c| {
                    (0..atlas.meta.masses.len()).map(|i| c.labels[i].to_string()).collect::<Vec<_>>().join(" ")
                });
                format!("{text:<24}")
            })
            .collect();
        outln!("{:<12.6} {}", p.x.value(ix), cols.join(""));
    }
    Ok(())
}
