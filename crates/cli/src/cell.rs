//! `vibroatlas cell`: simulate one cell and print its classification.

use crate::args::CellArgs;
use crate::common::{sim, start};
use crate::out::{errln, outln, outp};
use anyhow::{anyhow, Result};
use engine::{friction_names, Setup};
use solver::{CellResult, System};
use std::fmt::Write as _;
use store::write_atomically;

/// Largest `--trace-samples` (samples per forcing period): a trace of n periods
/// holds about n × 100 000 rows.
pub const MAX_TRACE_SAMPLES: usize = 100_000;
/// Largest number of rows of a trace (about 1 GB of CSV for two masses).
pub const MAX_TRACE_ROWS: usize = 10_000_000;

/// Runs the command.
pub fn run(a: CellArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    if a.trace_samples == 0 || a.trace_samples > MAX_TRACE_SAMPLES {
        return Err(anyhow!("--trace-samples: expected 1 to {MAX_TRACE_SAMPLES}, got {}", a.trace_samples));
    }
    let c = engine::cell(&sim(&a.sim)?, &start(&a.start)?)?;
    crate::common::warn(c.origin.as_ref().and_then(|o| o.warning.as_ref()));
    let (sys, s, cell) = (&c.system, &c.setup, &c.result);
    if let Some(path) = &a.trace {
        let periods = cell.n.unwrap_or(cell.section.len().max(1));
        if periods.saturating_mul(a.trace_samples) > MAX_TRACE_ROWS {
            return Err(anyhow!(
                "--trace-samples: {periods} periods x {} samples is more than {MAX_TRACE_ROWS} rows; take fewer samples",
                a.trace_samples
            ));
        }
        let w = engine::window(sys, s, cell, periods, a.trace_samples);
        let csv = engine::trace_csv(sys, &w.rows);
        write_atomically(path, |tmp| std::fs::write(tmp, csv.as_bytes()))?;
        if let Some(note) = w.note(periods) {
            errln!("warning: trace {}: {note}", path.display());
        }
    }
    if let Some(path) = &a.portrait {
        render::Format::of(path)?;
        let periods = cell.n.unwrap_or(cell.section.len().max(1));
        let rows = engine::window(sys, s, cell, periods, 400).rows;
        let p = portrait(sys, &rows, &describe_parameters(s));
        write_atomically(path, |tmp| render::portrait(&p, &page, tmp))?;
    }
    if let Some(path) = &a.section_png {
        if a.section_periods == 0 || a.section_periods > 1_000_000 {
            return Err(anyhow!("--section-periods: expected 1 to 1000000, got {}", a.section_periods));
        }
        let (panels, silent) = sections(sys, s, cell, a.section_periods)?;
        let labels: Vec<String> = cell.labels.iter().map(|l| format!("{} {l}", l.mass)).collect();
        let silent = if silent.is_empty() { String::new() } else { format!("; no impacts at {}", silent.join(", ")) };
        let title = format!(
            "{} ({}): {}, Poincaré sections over {} periods{silent}",
            sys.model.name,
            describe_parameters(s),
            labels.join(", "),
            a.section_periods
        );
        write_atomically(path, |tmp| render::sections(&panels, &title, &page, tmp))?;
    }
    if a.json {
        outln!("{}", serde_json::to_string(&c.to_json())?);
    } else {
        outp!("{}", to_text(sys, s, cell));
    }
    Ok(())
}

fn to_text(sys: &System, s: &Setup, c: &CellResult) -> String {
    let mut o = String::new();
    let params: Vec<String> = sys.model.parameters.iter().map(|(k, v)| format!("{k}={v}")).collect();
    let _ = writeln!(o, "scene     {} ({})", sys.model.name, params.join(" "));
    if let Some(about) = s.scene.description().lines().find(|l| !l.trim().is_empty()) {
        let _ = writeln!(o, "about     {}", about.trim());
    }
    let _ = writeln!(o, "settings  preset {}, integrator {}", s.preset.name(), s.method.name());
    let _ = write!(o, "class     {}", c.class.name());
    if let Some(n) = c.n {
        let _ = write!(o, ", n = {n}");
    }
    if let Some(sym) = c.symmetry {
        let _ = write!(o, ", symmetry {}", sym.name());
    }
    let _ = writeln!(o);
    if let Some(m) = c.multiplier {
        let verdict = match m {
            m if (m - 1.0).abs() <= 1e-9 => "neutral",
            m if m < 1.0 => "stable",
            _ => "unstable",
        };
        let _ = writeln!(o, "stability largest |multiplier| {m:.8} ({verdict})");
    }
    if let Some(l) = c.lyapunov {
        let _ = writeln!(o, "lyapunov  {l:.6} per unit time ({:.6} per forcing period)", l * sys.period);
    }
    if let Some(r) = &c.reason {
        let _ = writeln!(o, "reason    {r}");
    }
    for l in &c.labels {
        let _ = writeln!(o, "label     {:<6} {}", l.mass, l);
    }
    let _ = writeln!(o, "stop      impacts  chatter  sticking");
    for (k, st) in sys.model.stops.iter().enumerate() {
        let _ =
            writeln!(o, "  {:<8}{:>7}  {:<8} {}", st.name, c.impacts[k], c.chatter.contains(k), c.sticking.contains(k));
    }
    for (i, name) in friction_names(sys).iter().enumerate() {
        let _ = writeln!(
            o,
            "friction  {name:<8} {}",
            if c.friction_stick.contains(i) { "sticks" } else { "slips throughout" }
        );
    }
    let _ = writeln!(o, "final     {:?}", c.final_state);
    let _ = writeln!(o, "work      {} periods, {} events", c.periods, c.events);
    o
}

/// Panels `(x label, y label, points)` of the sections over `periods` periods
/// from the final state ([`engine::sections`]); and the stops without impacts.
fn sections(sys: &System, s: &Setup, c: &CellResult, periods: usize) -> Result<(Vec<render::Panel>, Vec<String>)> {
    let sec = engine::sections(sys, s, c, periods)?;
    let name = &sys.model.masses[sec.mass].name;
    let mut panels =
        vec![render::Panel { x: format!("x_{name} at t = kT"), y: format!("v_{name}"), points: sec.period }];
    let mut silent = Vec::new();
    for (stop, points) in sys.model.stops.iter().zip(sec.impacts) {
        if points.is_empty() {
            silent.push(stop.name.clone());
        } else {
            panels.push(render::Panel { x: format!("phase at {} (rad)", stop.name), y: "impact speed".into(), points });
        }
    }
    Ok((panels, silent))
}

/// The portrait of the window: per mass its (x, v) path, its frame stops, and
/// the events.
fn portrait(sys: &System, rows: &[engine::Row], parameters: &str) -> render::Portrait {
    let m = sys.dof();
    let masses: Vec<String> = sys.model.masses.iter().map(|x| x.name.clone()).collect();
    let stops = sys
        .model
        .stops
        .iter()
        .filter_map(|st| match st.geometry {
            scene::StopGeometry::Frame { mass, position, .. } => Some((mass, position, st.name.clone())),
            scene::StopGeometry::Pair { .. } => None,
        })
        .collect();
    render::Portrait {
        title: format!("{} ({parameters})", sys.model.name),
        masses,
        t: rows.iter().map(|r| r.0).collect(),
        x: (0..m).map(|k| rows.iter().map(|r| r.1[k]).collect()).collect(),
        v: (0..m).map(|k| rows.iter().map(|r| r.1[m + k]).collect()).collect(),
        events: rows.iter().enumerate().filter_map(|(i, r)| r.2.clone().map(|e| (i, e))).collect(),
        stops,
    }
}

/// The parameters set on the command line, by their symbols, for titles
/// (`ω = 0.33, δ = 0.6`), or `scene defaults`.
fn describe_parameters(s: &Setup) -> String {
    if s.overrides.is_empty() {
        return "scene defaults".to_string();
    }
    s.overrides.iter().map(|(k, v)| format!("{} = {v}", s.scene.symbol(k))).collect::<Vec<_>>().join(", ")
}
