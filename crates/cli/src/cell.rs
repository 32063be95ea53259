//! `vibroatlas cell`: simulate one cell and print its classification.

use crate::args::CellArgs;
use crate::common::{sim_from, start};
use crate::out::{errln, outln, outp};
use anyhow::{Context, Result};
use engine::{friction_names, Setup};
use scene::Named;
use solver::contact::Contact;
use solver::{CellResult, System};
use std::fmt::Write as _;
use store::write_atomically;

/// Runs the command.
pub fn run(a: CellArgs) -> Result<()> {
    let page = crate::figure::page(&a.figure)?;
    engine::check_trace_samples(a.trace_samples)?;
    let (sim, from) = (sim_from(&a.sim, &a.start)?, start(&a.start)?);
    // Each output checked against the inputs and the outputs before it.
    let mut taken = sim.inputs(&from);
    crate::figure::check("--portrait", a.portrait.as_ref(), &taken, &page)?;
    taken.extend(a.portrait.as_deref());
    crate::figure::check("--section-png", a.section_png.as_ref(), &taken, &page)?;
    taken.extend(a.section_png.as_deref());
    crate::figure::output("--trace", a.trace.as_ref(), &taken)?;
    let c = engine::cell(&sim, &from)?;
    crate::common::tell(
        c.origin.as_ref().and_then(|o| o.warning.as_ref()),
        c.origin.as_ref().and_then(|o| o.note.as_ref()),
    );
    let (sys, s, cell) = (&c.system, &c.setup, &c.result);
    if let Some(path) = &a.trace {
        let w = engine::trace(sys, s, cell, a.trace_samples)?;
        write_atomically(path, |tmp| std::fs::write(tmp, trace_csv(sys, &w.rows))).context("--trace")?;
        if let Some(note) = w.note(engine::window_periods(cell)) {
            errln!("warning: trace {}: {note}", path.display());
        }
    }
    if let Some(path) = &a.portrait {
        let p = engine::portrait(&c);
        write_atomically(path, |tmp| render::portrait(&p, &page, tmp)).context("--portrait")?;
    }
    if let Some(path) = &a.section_png {
        let (panels, title) = engine::section_panels(&c, a.section_periods)?;
        write_atomically(path, |tmp| render::sections(&panels, &title, &page, tmp)).context("--section-png")?;
    }
    if a.json {
        outln!("{}", serde_json::to_string(&c.to_json())?);
    } else {
        outp!("{}", to_text(sys, s, cell));
        // Every file written, named as every other command names its files.
        if let Some(path) = &a.trace {
            outln!("wrote {}", path.display());
        }
        for path in [&a.portrait, &a.section_png].into_iter().flatten() {
            crate::render_cmd::wrote(path, &page)?;
        }
    }
    Ok(())
}

/// The first sentence of a scene's description, its lines joined (the
/// whole description when it has no full stop followed by a space).
fn first_sentence(text: &str) -> String {
    let joined = text.split_whitespace().collect::<Vec<_>>().join(" ");
    match joined.find(". ") {
        Some(end) => joined[..=end].to_string(),
        None => joined,
    }
}

fn to_text(sys: &System, s: &Setup, c: &CellResult) -> String {
    let mut o = String::new();
    let params: Vec<String> = sys.model.parameters.iter().map(|(k, v)| format!("{k}={}", scene::number(*v))).collect();
    let _ = writeln!(o, "scene     {} ({})", sys.model.name, params.join(" "));
    let about = first_sentence(s.scene.description());
    if !about.is_empty() {
        let _ = writeln!(o, "about     {about}");
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
    // Soft stops count contacts begun, rigid ones impacts.
    let mut laws = sys.model.stops.iter().map(|s| s.law.events());
    let events = match laws.next() {
        Some(first) if laws.all(|e| e == first) => first,
        _ => "impacts",
    };
    let _ = writeln!(o, "stop      {events}  chatter  sticking");
    for (k, st) in sys.model.stops.iter().enumerate() {
        let (count, chatter, sticking) = (c.impacts[k], c.chatter.contains(k), c.sticking.contains(k));
        let _ = writeln!(o, "  {:<8}{count:>w$}  {chatter:<8} {sticking}", st.name, w = events.len());
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

/// The window as CSV: `t`, every coordinate and velocity, and the event.
pub fn trace_csv(sys: &solver::System, rows: &[engine::Row]) -> String {
    let mut out = String::from("t");
    for m in &sys.model.masses {
        let _ = write!(out, ",x_{}", m.name);
    }
    for m in &sys.model.masses {
        let _ = write!(out, ",v_{}", m.name);
    }
    out.push_str(",event\n");
    for (t, y, event) in rows {
        let _ = write!(out, "{t:.15e}");
        for v in y {
            let _ = write!(out, ",{v:.15e}");
        }
        let _ = writeln!(out, ",{}", event.as_deref().unwrap_or(""));
    }
    out
}
