//! `vibroatlas bench`: atlas throughput on 1 and 2 threads (fresh and both
//! sweeps, best of repeated runs, every run checked to give the same atlas)
//! and, with `--trade`, the measured speed and accuracy of every preset and of
//! RK4 against the `precise` reference (in rounds of every setting, best kept).

use crate::args::BenchArgs;
use crate::out::outln;
use anyhow::{anyhow, bail, Context, Result};
use engine::{Executed, Plan, Quiet, Setup};
use grid::{Along, Atlas, Axis, Plane, SweepKind};
use scene::Scene;
use serde_json::{json, Value};
use solver::{Accuracy, Class, Method, Preset};
use store::write_atomically;

/// The reference scene, shipped with the binary.
const REFERENCE_SCENE: &str = include_str!("../../../configs/multi-stop.toml");

/// A setting of the trade: preset, integrator, and the accuracy knobs it
/// overrides.
#[derive(Clone, Copy)]
struct Setting {
    name: &'static str,
    preset: Preset,
    method: Method,
    knobs: &'static [(&'static str, f64)],
}

/// A setting of the exact solver.
const fn exact(name: &'static str, preset: Preset, knobs: &'static [(&'static str, f64)]) -> Setting {
    Setting { name, preset, method: Method::Exact, knobs }
}

/// A setting of the RK4 integrator, at standard tolerances.
const fn rk4(name: &'static str, knobs: &'static [(&'static str, f64)]) -> Setting {
    Setting { name, preset: Preset::Standard, method: Method::Rk4, knobs }
}

/// The exact solver at the default preset.
const STANDARD: Setting = exact("standard", Preset::Standard, &[]);

/// The reference of the trade.
const PRECISE: Setting = exact("precise", Preset::Precise, &[]);

/// The literature's method, the setting all others are compared with for speed.
const RK4: Setting = rk4("rk4 h=0.01", &[("rk4_step", 0.01), ("newton", 0.0)]);

/// Settings of the trade, in table order. The RK4 rows are the literature's
/// method: RK4 with step-back refinement and a plainly simulated transient
/// (standard tolerances, no Newton); the last row shows what Newton adds to RK4.
/// `standard chaos_check=0` is standard without the early end of chaotic
/// records (the default of `standard` before it was measured to agree with
/// `precise` at least as well as RK4).
const SETTINGS: [Setting; 7] = [
    exact("fast", Preset::Fast, &[]),
    STANDARD,
    exact("standard chaos_check=0", Preset::Standard, &[("chaos_check", 0.0)]),
    PRECISE,
    RK4,
    rk4("rk4 h=0.001", &[("rk4_step", 0.001), ("newton", 0.0)]),
    rk4("rk4 h=0.01 newton", &[("rk4_step", 0.01)]),
];

/// One setting's measured speed and agreement with the reference.
struct TradeRow {
    setting: &'static str,
    cells_per_s: f64,
    label_agreement: f64,
    class_agreement: f64,
    median_state_error: f64,
    /// Forcing periods simulated over the grid.
    periods: u64,
    /// Thread time per forcing period, µs.
    us_per_period: f64,
    /// Periods simulated in cells without a period.
    nonperiodic_periods: u64,
}

impl TradeRow {
    /// The row's JSON object (the contract of `bench --trade --json`), with its
    /// cells/s over those of the RK4 baseline `base`.
    fn json(&self, base: Option<f64>) -> Value {
        let mut row = json!({"setting": self.setting, "cells_per_s": self.cells_per_s, "label_agreement": self.label_agreement, "class_agreement": self.class_agreement, "median_state_error": self.median_state_error, "periods": self.periods, "us_per_period": self.us_per_period, "nonperiodic_periods": self.nonperiodic_periods});
        if let Some(base) = base {
            row["speedup_vs_rk4"] = json!(self.cells_per_s / base);
        }
        row
    }
}

struct Measured {
    atlas: Atlas,
    secs: f64,
}

/// What a run costs outside its workers' cells, measured on one run with a
/// journal and a file (as `atlas -o` runs): seconds per line to seal it for
/// the journal, per journal write (one line and its sync), the cost probe,
/// the file's creation by the writer thread while the workers compute, and
/// its completion after the last line.
#[derive(Debug, Clone, Copy)]
struct Serial {
    seal: f64,
    append: f64,
    probe: f64,
    /// Creating the file with what does not depend on the results.
    create: f64,
    /// Per line: writing the chunks it completes (by the writer thread).
    stream: f64,
    /// Finishing the file: the part that stays serial and the part its
    /// threads share (chunk compression), from finishes on one and on all threads.
    finish: (f64, f64),
}

/// Measures [`Serial`] on `m` (a run with an output file), re-sealing and
/// re-appending its lines one by one into a journal beside `out`.
fn serial_costs(m: &Executed, out: &std::path::Path, probe: f64, threads: usize) -> Result<Serial> {
    let p = &m.atlas.meta.plane;
    let lines: Vec<grid::Line> = m
        .atlas
        .maps
        .iter()
        .flat_map(|map| {
            (0..p.lines()).map(move |l| grid::Line {
                sweep: map.sweep,
                index: l,
                cells: (0..p.line_len())
                    .filter_map(|pos| {
                        let (iy, ix) = p.cell(l, pos);
                        map.cells[iy * p.x.count + ix].clone()
                    })
                    .collect(),
            })
        })
        .collect();
    let mut journal = store::Journal::create(&store::journal_path(out), "bench")?;
    let sealer = journal.sealer();
    let clock = std::time::Instant::now();
    let sealed = lines.iter().map(|l| sealer.seal(l)).collect::<Result<Vec<_>, _>>()?;
    let seal = clock.elapsed().as_secs_f64();
    let clock = std::time::Instant::now();
    for s in &sealed {
        journal.append_sealed([s])?;
    }
    let append = clock.elapsed().as_secs_f64();
    journal.remove()?;
    let n = lines.len().max(1) as f64;
    // The file finished again on one thread, every line kept as in the run:
    // with the run's finish, the shared part.
    let info = store::RunInfo { command: "bench".into(), run_time_s: m.secs, shard: None, history: Vec::new() };
    let mut draft = store::Draft::create(&out.with_extension("one.h5"), &m.atlas.meta, 1)?;
    for l in &lines {
        draft.keep(&m.atlas, l.sweep, l.index)?;
    }
    let clock = std::time::Instant::now();
    draft.finish(&m.atlas, &info)?;
    let one = clock.elapsed().as_secs_f64();
    let shared =
        if threads > 1 { ((one - m.write_s) * threads as f64 / (threads - 1) as f64).clamp(0.0, one) } else { 0.0 };
    let (create, stream, finish) = (m.prelude_s, m.stream_s / n, (one - shared, shared));
    Ok(Serial { seal: seal / n, append: append / n, probe, create, stream, finish })
}

/// Replays the run `m` on `virtual_threads` workers: each cell's time is the
/// workers' thread time shared in proportion to the forcing periods it
/// simulated, the lines are kept by one writer thread, the cost probe comes
/// before (its thread time shared by the workers) and the file's completion
/// after (its compression shared by the workers, the rest serial). The
/// previous policy takes lines in order, both directions of a line together,
/// its writer seals and syncs every line, and the whole file is written after
/// the last line; the current one takes chains longest first by the probed
/// `estimate` (fresh lines in order), seals in the workers, syncs once per
/// batch, and its writer creates the file before it keeps the first line.
/// Efficiency is the replayed one-worker time over `P` times the replayed
/// time on `P`.
fn replay(
    sweep: &str,
    m: &Executed,
    threads: usize,
    estimate: &[f64],
    c: Serial,
    virtual_threads: &[usize],
) -> Vec<Value> {
    use grid::schedule::{longest_first, pipeline, Writer};
    let atlas = &m.atlas;
    let p = &atlas.meta.plane;
    let lines = atlas.maps.len() * p.lines();
    let thread_secs = (m.secs * threads as f64 - c.seal * lines as f64).max(0.0);
    let per_period = thread_secs / periods(atlas, |_| true).max(1) as f64;
    let line_cells = |map: &grid::Map, line: usize| -> Vec<f64> {
        (0..p.line_len())
            .map(|pos| {
                let (iy, ix) = p.cell(line, pos);
                map.cells[iy * p.x.count + ix].as_ref().map_or(0.0, |c| c.periods as f64 * per_period)
            })
            .collect()
    };
    let previous: Vec<(SweepKind, usize)> =
        (0..p.lines()).flat_map(|l| atlas.meta.sweeps.iter().map(move |&s| (s, l))).collect();
    // Chains longest first; fresh lines in order (their cells are shared).
    let current = if sweep == "fresh" { previous.clone() } else { longest_first(&previous, estimate) };
    // Jobs (seconds, line): a chain, or each cell of a fresh line; `seal` is
    // the sealing each line's worker does (the current policy).
    let jobs = |order: &[(SweepKind, usize)], seal: f64| -> Vec<(f64, usize)> {
        order
            .iter()
            .flat_map(|&(s, l)| {
                let id = atlas.maps.iter().position(|m| m.sweep == s).unwrap_or(0) * p.lines() + l;
                let cells = atlas.map(s).map(|m| line_cells(m, l)).unwrap_or_default();
                let n = cells.len().max(1) as f64;
                if s == SweepKind::Fresh {
                    cells.into_iter().map(|d| (d + seal / n, id)).collect()
                } else {
                    vec![(cells.iter().sum::<f64>() + seal, id)]
                }
            })
            .collect()
    };
    // The probe runs its lines in parallel: its thread time, shared.
    let probe = if sweep == "fresh" { 0.0 } else { c.probe * threads as f64 };
    let (finish, shared) = c.finish;
    let current_writer = Writer { start: c.create, per_write: c.append, per_line: c.stream, batched: true };
    let previous_writer = Writer { start: 0.0, per_write: c.append, per_line: c.seal, batched: false };
    let whole_file = c.create + c.stream * lines as f64 + finish;
    let policies = [
        ("current", jobs(&current, c.seal), current_writer, probe, finish),
        ("previous", jobs(&previous, 0.0), previous_writer, 0.0, whole_file),
    ];
    let mut rows = Vec::new();
    for &t in virtual_threads {
        for (policy, order, writer, before, after) in &policies {
            let time = |workers: usize| {
                let w = workers as f64;
                before / w + pipeline(order, workers, writer) + after + shared / w
            };
            let span = time(t);
            rows.push(json!({"sweep": sweep, "threads": t, "policy": policy, "makespan_s": span, "efficiency": time(1) / (t as f64 * span)}));
        }
    }
    rows
}

/// One run of `plane` as `atlas -o` runs it (journal, file with sections)
/// in a scratch folder, for the replay; the scratch folder is removed.
/// Also returns each line's estimated cost (the run's own probe, or one run
/// here when the run did not need it).
fn measured_run(
    scene: &Scene,
    plane: &Plane,
    sweeps: &[SweepKind],
    threads: usize,
    sync_ms: Option<f64>,
) -> Result<(Executed, Serial, Vec<f64>)> {
    let dir = std::env::temp_dir().join(format!("vibroatlas-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let out = dir.join("replay.h5");
    let s = Setup {
        scene: scene.clone(),
        overrides: Vec::new(),
        accuracy: Accuracy::preset(Preset::Standard),
        accuracy_overrides: Vec::new(),
        preset: Preset::Standard,
        method: Method::Exact,
    };
    let mut plan = Plan::new(&s, 16, plane.clone(), sweeps.to_vec(), threads)?;
    plan.output = Some(out.clone());
    let clock = std::time::Instant::now();
    plan.check()?;
    let probe = clock.elapsed().as_secs_f64();
    let m = plan.execute(&Quiet)?;
    let mut serial = serial_costs(&m, &out, probe, threads)?;
    if let Some(ms) = sync_ms {
        serial.append = ms / 1000.0;
    }
    std::fs::remove_dir_all(&dir)?;
    let estimate = match plan.cost {
        Some(cost) => cost,
        None => grid::schedule::probe(plane, &plan.setup, threads)?,
    };
    Ok((m, serial, estimate))
}

fn run_plane(scene: &Scene, plane: &Plane, sweeps: &[SweepKind], setting: Setting, threads: usize) -> Result<Measured> {
    let mut accuracy = Accuracy::preset(setting.preset);
    for &(knob, value) in setting.knobs {
        accuracy.set_named(knob, value)?;
    }
    let s = Setup {
        scene: scene.clone(),
        overrides: Vec::new(),
        accuracy,
        accuracy_overrides: Vec::new(),
        preset: setting.preset,
        method: setting.method,
    };
    let plan = Plan::new(&s, 0, plane.clone(), sweeps.to_vec(), threads)?;
    let m = plan.execute(&Quiet)?;
    Ok(Measured { atlas: m.atlas, secs: m.secs })
}

/// Keeps in `best` the faster of it and `m`, once `m`'s atlas is checked to
/// equal `best`'s: results are deterministic, however often they are computed.
fn keep_faster(best: &mut Option<Measured>, m: Measured) -> Result<()> {
    if let Some(b) = best.as_ref() {
        same_atlas(&b.atlas, &m.atlas)?;
    }
    if best.as_ref().is_none_or(|b| m.secs < b.secs) {
        *best = Some(m);
    }
    Ok(())
}

/// An error unless two runs of the same grid gave the same atlas, bit for bit.
fn same_atlas(a: &Atlas, b: &Atlas) -> Result<()> {
    if a != b {
        bail!("results differ between runs of the same grid: the solver is not deterministic");
    }
    Ok(())
}

/// The fastest of `repeat` (>= 1) runs, each checked to give the same atlas,
/// which must also equal `first` (set by the first call when `None`), whatever
/// the thread count.
fn best_of(repeat: usize, first: &mut Option<Atlas>, mut run: impl FnMut() -> Result<Measured>) -> Result<Measured> {
    let mut best = None;
    for _ in 0..repeat {
        keep_faster(&mut best, run()?)?;
    }
    let best = best.ok_or_else(|| anyhow!("no run"))?;
    same_atlas(first.get_or_insert_with(|| best.atlas.clone()), &best.atlas)?;
    Ok(best)
}

fn cells(a: &Atlas) -> usize {
    a.maps.iter().map(|m| m.cells.len()).sum()
}

/// Forcing periods simulated over the cells of `a` whose class passes `keep`
/// (Newton, stability and section work included).
fn periods(a: &Atlas, keep: impl Fn(Class) -> bool) -> u64 {
    a.maps.iter().flat_map(|m| m.cells.iter().flatten()).filter(|c| keep(c.class)).map(|c| c.periods).sum()
}

/// Label agreement, class agreement and median state error of `m` against `reference`.
fn compare(reference: &Atlas, m: &Atlas) -> (f64, f64, f64) {
    let pairs: Vec<_> = reference.maps[0]
        .cells
        .iter()
        .zip(&m.maps[0].cells)
        .filter_map(|(a, b)| Some((a.as_ref()?, b.as_ref()?)))
        .collect();
    let total = pairs.len().max(1) as f64;
    let labels = pairs.iter().filter(|(a, b)| a.class == b.class && a.labels == b.labels).count() as f64 / total;
    let classes = pairs.iter().filter(|(a, b)| a.class == b.class).count() as f64 / total;
    let mut errs: Vec<f64> = pairs
        .iter()
        .map(|(a, b)| a.final_state.iter().zip(&b.final_state).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max))
        .collect();
    errs.sort_by(f64::total_cmp);
    (labels, classes, errs.get(errs.len() / 2).copied().unwrap_or(0.0))
}

/// Runs the command.
pub fn run(a: BenchArgs) -> Result<()> {
    let threads: Vec<usize> = a
        .threads
        .split(',')
        .map(|t| t.trim().parse::<usize>().ok().filter(|&n| (1..=1024).contains(&n)))
        .collect::<Option<Vec<_>>>()
        .ok_or_else(|| anyhow!("--threads: expected a comma-separated list of counts 1..1024, got '{}'", a.threads))?;
    if !(2..=2000).contains(&a.grid) {
        bail!("--grid: must be in 2..=2000, got {}", a.grid);
    }
    if a.repeat == 0 {
        bail!("--repeat: must be >= 1");
    }
    if a.trade_repeat == 0 {
        bail!("--trade-repeat: must be >= 1");
    }
    let text = match &a.scene {
        Some(p) => std::fs::read_to_string(p).with_context(|| format!("cannot read scene file {}", p.display()))?,
        None => REFERENCE_SCENE.to_string(),
    };
    let scene = Scene::parse(&text).map_err(|e| anyhow!("scene: {e}"))?;
    for name in ["omega", "delta"] {
        scene.check_parameter(name, "--scene").map_err(|e| anyhow!("{e} (bench maps the omega-delta plane)"))?;
    }
    let n = a.grid;
    let plane = Plane::new(
        Axis::parse(&format!("omega=0.1:3.05:{n}"), "--grid")?,
        Axis::parse(&format!("delta=0.05:2:{n}"), "--grid")?,
        Along::X,
    )?;

    if let Some(ms) = a.simulate_sync_ms {
        if a.simulate_threads.is_none() {
            bail!("--simulate-sync-ms: only with --simulate-threads (it sets the replay's journal write)");
        }
        if !(ms.is_finite() && (0.0..=60_000.0).contains(&ms)) {
            bail!("--simulate-sync-ms: expected 0 to 60000 milliseconds, got {ms}");
        }
    }
    let virtual_threads: Vec<usize> = match &a.simulate_threads {
        Some(text) => text
            .split(',')
            .map(|t| t.trim().parse::<usize>().ok().filter(|&n| (1..=1_000_000).contains(&n)))
            .collect::<Option<Vec<_>>>()
            .ok_or_else(|| anyhow!("--simulate-threads: expected a comma-separated list of counts, got '{text}'"))?,
        None => Vec::new(),
    };
    let mut throughput = Vec::new();
    let mut simulated = Vec::new();
    for (name, sweeps) in [("fresh", vec![SweepKind::Fresh]), ("both", vec![SweepKind::Up, SweepKind::Down])] {
        let mut base = None;
        // Every run, on any thread count, must give the same atlas bit for bit.
        let mut first: Option<Atlas> = None;
        let mut last = None;
        for &t in &threads {
            let m = best_of(a.repeat, &mut first, || run_plane(&scene, &plane, &sweeps, STANDARD, t))?;
            last = Some((t, m.secs));
            let (best, count) = (m.secs, cells(&m.atlas));
            let rate = count as f64 / best;
            let (t0, r0) = *base.get_or_insert((t, rate));
            let efficiency = rate / r0 / (t as f64 / t0 as f64);
            if !a.json {
                outln!(
                    "throughput {name:<5} {t} thread(s): {count} cells in {best:.2} s, {rate:.0} cells/s, parallel efficiency {efficiency:.2}"
                );
            }
            throughput.push(json!({"sweep": name, "threads": t, "cells": count, "seconds": best, "cells_per_s": rate, "efficiency": efficiency}));
        }
        if let (Some((t, _)), false) = (last, virtual_threads.is_empty()) {
            let (m, serial, estimate) = measured_run(&scene, &plane, &sweeps, t, a.simulate_sync_ms)?;
            if !a.json {
                outln!(
                    "serial     {name:<5} per line: seal {:.2} ms, journal write {:.2} ms, file chunks {:.2} ms; probe {:.2} s; file created {:.3} s (while computing), finished {:.3} s serial + {:.3} s shared",
                    1e3 * serial.seal,
                    1e3 * serial.append,
                    1e3 * serial.stream,
                    serial.probe,
                    serial.create,
                    serial.finish.0,
                    serial.finish.1
                );
            }
            for row in replay(name, &m, t, &estimate, serial, &virtual_threads) {
                if !a.json {
                    outln!(
                        "simulated  {name:<5} {:>6} threads, {:<8} policy: makespan {:.3} s, efficiency {:.2}",
                        row["threads"],
                        row["policy"].as_str().unwrap_or_default(),
                        row["makespan_s"].as_f64().unwrap_or_default(),
                        row["efficiency"].as_f64().unwrap_or_default()
                    );
                }
                simulated.push(row);
            }
        }
    }
    if !a.json {
        outln!("every run on {} thread(s) gave the same atlas, bit for bit", a.threads);
    }

    let mut trade = Vec::new();
    if a.trade {
        let t = *threads.iter().max().unwrap_or(&1);
        let fresh = [SweepKind::Fresh];
        // Rounds of every setting once, best kept per setting: a slow spell of
        // a shared machine falls on all settings alike, not on every run of one.
        let mut runs: Vec<Option<Measured>> = SETTINGS.iter().map(|_| None).collect();
        for _ in 0..a.trade_repeat {
            for (best, &setting) in runs.iter_mut().zip(&SETTINGS) {
                keep_faster(best, run_plane(&scene, &plane, &fresh, setting, t)?)?;
            }
        }
        let measured: Vec<Measured> =
            runs.into_iter().map(|best| best.ok_or_else(|| anyhow!("no run"))).collect::<Result<_>>()?;
        let reference = SETTINGS
            .iter()
            .zip(&measured)
            .find(|(s, _)| s.name == PRECISE.name)
            .map(|(_, m)| &m.atlas)
            .ok_or_else(|| anyhow!("no reference setting"))?;
        if !a.json {
            outln!("\ntrade on {n} x {n} fresh cells, {t} thread(s), reference: precise (exact)");
            outln!(
                "{:<24} {:>11} {:>16} {:>16} {:>19} {:>10} {:>12} {:>17}",
                "setting",
                "cells/s",
                "label agreement",
                "class agreement",
                "median |d state|",
                "periods",
                "us/period",
                "no-period share"
            );
        }
        let mut rows = Vec::new();
        for (setting, m) in SETTINGS.iter().zip(&measured) {
            let (labels, classes, median) = compare(reference, &m.atlas);
            // Work per forcing period, in thread time: what the integrator costs.
            let total = periods(&m.atlas, |_| true);
            let row = TradeRow {
                setting: setting.name,
                cells_per_s: cells(&m.atlas) as f64 / m.secs,
                label_agreement: labels,
                class_agreement: classes,
                median_state_error: median,
                periods: total,
                us_per_period: 1e6 * m.secs * t as f64 / total.max(1) as f64,
                // Cells without a period: the records every method simulates in full.
                nonperiodic_periods: periods(&m.atlas, |c| c != Class::Periodic),
            };
            if !a.json {
                outln!(
                    "{:<24} {:>11.0} {:>15.2}% {:>15.2}% {:>19.2e} {:>10} {:>12.1} {:>16.1}%",
                    row.setting,
                    row.cells_per_s,
                    100.0 * row.label_agreement,
                    100.0 * row.class_agreement,
                    row.median_state_error,
                    row.periods,
                    row.us_per_period,
                    100.0 * row.nonperiodic_periods as f64 / total.max(1) as f64
                );
            }
            rows.push(row);
        }
        // Speed of every setting against the literature's method.
        let base = rows.iter().find(|r| r.setting == RK4.name).map(|r| r.cells_per_s);
        if let (Some(base), false) = (base, a.json) {
            let ratios: Vec<String> =
                rows.iter().map(|r| format!("{} {:.1}x", r.setting, r.cells_per_s / base)).collect();
            outln!("cells/s against {}: {}", RK4.name, ratios.join(", "));
        }
        trade = rows.iter().map(|r| r.json(base)).collect();
        if let Some(dir) = &a.output {
            std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
            let points: Vec<(String, f64, f64)> =
                rows.iter().map(|r| (r.setting.to_string(), r.cells_per_s, r.label_agreement)).collect();
            let png = dir.join("trade.png");
            write_atomically(&png, |tmp| render::trade(&points, tmp))?;
            if !a.json {
                outln!("wrote {}", png.display());
            }
        }
    }
    if a.json {
        outln!(
            "{}",
            serde_json::to_string(
                &json!({"grid": n, "trade": Value::Array(trade), "throughput": Value::Array(throughput), "simulated": Value::Array(simulated)})
            )?
        );
    }
    Ok(())
}
