//! `vibroatlas cell`: simulate one cell and print its classification.

use crate::args::CellArgs;
use crate::common::{sim, start};
use crate::out::{errln, outln, outp};
use anyhow::{anyhow, Result};
use engine::{friction_names, Setup};
use solver::{CellResult, Simulator, System};
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
    if let Some(w) = c.origin.as_ref().and_then(|o| o.warning.as_ref()) {
        errln!("warning: {w}");
    }
    let (sys, s, cell) = (&c.system, &c.setup, &c.result);
    if let Some(path) = &a.trace {
        let periods = cell.n.unwrap_or(cell.section.len().max(1));
        if periods.saturating_mul(a.trace_samples) > MAX_TRACE_ROWS {
            return Err(anyhow!(
                "--trace-samples: {periods} periods x {} samples is more than {MAX_TRACE_ROWS} rows; take fewer samples",
                a.trace_samples
            ));
        }
        let w = window(sys, s, cell, periods, a.trace_samples);
        let csv = trace_csv(sys, &w.rows);
        write_atomically(path, |tmp| std::fs::write(tmp, csv.as_bytes()))?;
        if let Some(note) = w.note(periods) {
            errln!("warning: trace {}: {note}", path.display());
        }
    }
    if let Some(path) = &a.portrait {
        render::Format::of(path)?;
        let periods = cell.n.unwrap_or(cell.section.len().max(1));
        let rows = window(sys, s, cell, periods, 400).rows;
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
/// from the final state: the first labelled mass's (x, v) at t = kT, then per
/// stop with impacts (forcing phase mod 2π, impact speed); and the stops
/// without impacts.
fn sections(sys: &System, s: &Setup, c: &CellResult, periods: usize) -> Result<(Vec<render::Panel>, Vec<String>)> {
    struct Points<'a>(&'a System, Vec<Vec<(f64, f64)>>);
    impl solver::Observer for Points<'_> {
        fn impact(&mut self, t: f64, stop: usize, before: &solver::DVector<f64>, _: &solver::DVector<f64>) {
            self.1[stop].push((self.0.phase_at(t), -self.0.gap_rate(stop, before)));
        }
    }
    let mass = sys.model.labels.first().map_or(0, |l| l.mass);
    let m = sys.dof();
    let mut sim = Simulator::new(sys, s.accuracy, s.method, &c.final_state)
        .map_err(|h| anyhow!("sections: {}", halt_text(&h, s)))?;
    let mut obs = Points(sys, vec![Vec::new(); sys.stops.len()]);
    let mut period = Vec::with_capacity(periods);
    for _ in 0..periods {
        let rec = sim.run_period(&[], false, &mut obs).map_err(|h| anyhow!("sections: {}", halt_text(&h, s)))?;
        period.push((rec.end[mass], rec.end[m + mass]));
    }
    let name = &sys.model.masses[mass].name;
    let mut panels = vec![render::Panel { x: format!("x_{name} at t = kT"), y: format!("v_{name}"), points: period }];
    let mut silent = Vec::new();
    for (stop, points) in sys.model.stops.iter().zip(obs.1) {
        if points.is_empty() {
            silent.push(stop.name.clone());
        } else {
            panels.push(render::Panel { x: format!("phase at {} (rad)", stop.name), y: "impact speed".into(), points });
        }
    }
    Ok((panels, silent))
}

/// One row of the classified window: time, state, and the event it is (if any).
type Row = (f64, Vec<f64>, Option<String>);

/// Why a simulation halted, in the words of a cell's `reason`.
fn halt_text(h: &solver::Halt, s: &Setup) -> String {
    match h {
        solver::Halt::Budget => format!("event budget of {} events exhausted", s.accuracy.max_events()),
        solver::Halt::Stalled => "event location stalled at a degenerate contact".into(),
        solver::Halt::Error(e) => e.to_string(),
    }
}

/// The classified window, and what of it could not be traced (see [`window`]).
struct Window {
    rows: Vec<Row>,
    /// Periods replayed at their events only, and why sampling them halted.
    events_only: Vec<(usize, String)>,
    /// Where the trace ends early: the periods traced, and why.
    ended: Option<(usize, String)>,
}

impl Window {
    /// One line saying what the trace lacks, if anything.
    fn note(&self, periods: usize) -> Option<String> {
        let mut parts = Vec::new();
        if let Some((k, why)) = self.events_only.first() {
            let count = self.events_only.len();
            let which =
                if count == 1 { format!("period {}", k + 1) } else { format!("{count} periods (first: {})", k + 1) };
            parts.push(format!("{which} traced at the events only (stopping at the samples halted it: {why})"));
        }
        if let Some((done, why)) = &self.ended {
            parts.push(format!("it ends after {done} of {periods} periods: {why}"));
        }
        (!parts.is_empty()).then(|| parts.join("; "))
    }
}

/// Dense samples (and every event, named: `impact A1`, `stick A12`, …) of
/// `periods` periods from the window start, each period's end included. It is
/// as robust as the cell itself: a period whose samples halt the simulation
/// (stopping at a sample time can meet a degenerate contact the cell's own run
/// stepped over) is replayed from its start at its events only, the cell's
/// trajectory; a halt that remains ends the window there (the samples up to
/// it kept), with its reason (the cell's `reason` when it is unresolved for it).
fn window(sys: &System, s: &Setup, c: &CellResult, periods: usize, samples: usize) -> Window {
    struct Rows<'a>(Vec<Row>, &'a System);
    impl solver::Observer for Rows<'_> {
        fn named_event(&mut self, t: f64, kind: solver::EventKind, y: &solver::DVector<f64>) {
            self.0.push((t, y.as_slice().to_vec(), Some(kind.describe(self.1))));
        }
        fn sample(&mut self, t: f64, y: &solver::DVector<f64>) {
            self.0.push((t, y.as_slice().to_vec(), None));
        }
    }
    let mut rows = Rows(vec![(0.0, c.window_start.clone(), None)], sys);
    let mut events_only = Vec::new();
    let mut sim = match Simulator::new(sys, s.accuracy, s.method, &c.window_start) {
        Ok(sim) => sim,
        Err(h) => return Window { rows: rows.0, events_only, ended: Some((0, halt_text(&h, s))) },
    };
    let times: Vec<f64> = (1..samples).map(|i| sys.period * i as f64 / samples as f64).collect();
    for k in 0..periods {
        // The period's end is a sample (the observer's, after the period).
        let (before, kept) = (sim.clone(), rows.0.len());
        let Err(h) = sim.run_period(&times, false, &mut rows) else { continue };
        let sampled = rows.0.split_off(kept);
        sim = before;
        if let Err(again) = sim.run_period(&[], false, &mut rows) {
            // A halt of the cell's own trajectory: the samples up to it.
            rows.0.truncate(kept);
            rows.0.extend(sampled);
            return Window { rows: rows.0, events_only, ended: Some((k, halt_text(&again, s))) };
        }
        events_only.push((k, halt_text(&h, s)));
    }
    Window { rows: rows.0, events_only, ended: None }
}

/// The window as CSV: `t`, every coordinate and velocity, and the event.
fn trace_csv(sys: &System, rows: &[Row]) -> String {
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

/// The portrait of the window: per mass its (x, v) path, its frame stops, and
/// the events.
fn portrait(sys: &System, rows: &[Row], parameters: &str) -> render::Portrait {
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
